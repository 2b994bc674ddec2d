"""Terminal tables (rich) for modes and analysis results. Falls back to plain text when
there is no terminal (CI=true, pipes): rich handles that itself.

Every table fits the console's width (cli/fitting.py: console() and fit_table): the story tables
abbreviate their headings with a legend, the summary states once what every row shares, and a
table that is still too wide is split in parts that repeat its leading label columns.
"""

from __future__ import annotations

from collections.abc import Iterator

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from ..analysis.comparison import MEASURED
from ..analysis.level import answer_line, level_text, levels_legend
from ..display import (
    BUILDING_LEGEND,
    WEIGHT_LEGEND,
    building_verdicts,
    intermediate_kind,
    label,
    show,
    summary_columns,
    verdicts,
)
from ..engines.quantities import COMPARED, FLOOR, INTERMEDIATES, STORY, YIELDING, quantities
from ..engines.result import AnalysisResult
from ..engines.suite_result import SuiteResult
from . import render_design, render_rocking, render_suite
from .fitting import console  # noqa: F401 - the commands' console, render.console()
from .render_modes import modes_table  # noqa: F401 - part of this module's interface
from .tables import add_columns, add_rows, engine_label, print_tables, summary_cells, verdict_legend

#: floor and story quantities in table order
STORY_QUANTITIES = quantities(FLOOR, STORY)
#: the yielding stories' quantities (quantities.YIELDING), shown after them where a result has them
YIELDING_STORY = [q for q in YIELDING.values() if q.where == STORY]
#: short headings of the story tables (name -> (heading, legend entry)); the others: Quantity.heading
SHORT_HEADINGS = {"displacement": ("disp.", "disp. = floor displacement relative to the mat"),
                  "drift_ratio": ("drift ratio", "drift ratio = story drift / story height"),
                  "moment": ("moment", "moment = overturning moment at the bottom of the story"),
                  "floor_acceleration": ("floor acc.", "floor acc. = absolute floor acceleration"),
                  "ductility": ("ductility", "ductility = peak drift / yield drift"),
                  "residual_drift_ratio": ("resid. drift ratio", "resid. = at the end of the analysis"),
                  "hysteretic_energy": ("hyst. energy", "hyst. energy = energy dissipated by yielding"),
                  "story_yielded": ("yielded", "yielded: the story yielded")}


def story_table(result: AnalysisResult, units: str = "si") -> Table:
    """Per story (top first): elevation and the peak of every floor and story quantity the
    engine gives (engines/quantities.py), in the display units (display.py)."""
    table = Table(title=escape(_story_title(result)))
    shown = [q for q in STORY_QUANTITIES + YIELDING_STORY if q.name in result.peaks]
    add_columns(table, ["story", f"elevation [{label('m', units)}]", *(_short_heading(q, units) for q in shown)])
    table.caption = _story_legend(shown)
    stories = range(result.elevations.size - 1, -1, -1)
    return add_rows(table, (_story_cells(result, j, shown, units) for j in stories))


def _story_title(result: AnalysisResult) -> str:
    """Engine and support; a suite's result: its design statistic of its records."""
    title = f"{result.engine} engine, {result.support} support"
    if isinstance(result, SuiteResult):
        title += f": {result.statistic} of {result.count} records ({result.rule_label})"
    return title + (f", {level_text(result)}" if level_text(result) else "")


def _short_heading(quantity, units: str) -> str:
    """The quantity's short heading (SHORT_HEADINGS) with its unit, else its own heading."""
    if quantity.name not in SHORT_HEADINGS:
        return quantity.heading(units)
    if quantity.display == "-":
        return SHORT_HEADINGS[quantity.name][0]
    return f"{SHORT_HEADINGS[quantity.name][0]} [{label(quantity.display, units)}]"


def _story_legend(shown: list) -> str | None:
    """The legend of the short headings among the quantities shown (None without one)."""
    legend = [SHORT_HEADINGS[q.name][1] for q in shown if q.name in SHORT_HEADINGS]
    return escape("; ".join(legend)) if legend else None


def _story_cells(result: AnalysisResult, j: int, shown: list, units: str) -> list[str]:
    """Story j+1: its number, the elevation of its floor and each quantity's peak there."""
    return [str(j + 1), show(result.elevations[j], "m", units),
            *[_cell(q, result.peaks[q.name][j], units) for q in shown]]


def _cell(quantity, value, units: str) -> str:
    """A story's value of a quantity in its display unit; a story's yielded flag as yes/no."""
    return show(bool(value) if quantity.name == "story_yielded" else value, quantity.display, units)


#: the columns of the summary table (display.SUMMARY); the critical ones go into the caption
#: when every row has the same (one building)
SUMMARY_COLUMNS = ("base_shear", "base_shear_coefficient", "base_moment", "base_moment_coefficient")
CRITICAL_COLUMNS = ("critical_base_shear", "critical_base_moment", "critical_coefficient")


def summary_table(results: list[AnalysisResult], units: str = "si") -> Table:
    """One row per result: base shear and moment, their coefficients (W = m_t g), uplift; the
    critical values V_c [16a], M_c [16b] and b/h_1* in the caption when every row has the same
    (one building), else in columns (display.SUMMARY)."""
    critical = summary_columns(CRITICAL_COLUMNS)
    shared = _same_cells(results, critical, units)
    columns = summary_columns(SUMMARY_COLUMNS + (() if shared else CRITICAL_COLUMNS) + verdicts(results)
                              + building_verdicts(results))
    table = Table(title="Summary")
    add_columns(table, ("engine", "support", *(column.heading(units) for column in columns)),
                left=("engine", "support"))
    add_rows(table, ((escape(engine_label(r)), r.support, *summary_cells(r, columns, units)) for r in results))
    table.caption = escape(_summary_legend(results, critical, shared, units))
    return table


def _same_cells(results: list[AnalysisResult], columns: list, units: str) -> bool:
    """Every result (one at least) shows the same cells in these columns."""
    return len({tuple(summary_cells(r, columns, units)) for r in results}) == 1


def _summary_legend(results: list[AnalysisResult], critical: list, shared: bool, units: str) -> str:
    """W = m_t g, the verdicts and, when every row shares them, the critical values, stated once."""
    legend = WEIGHT_LEGEND + verdict_legend(verdicts(results)) + levels_legend(results)
    legend += f"; {BUILDING_LEGEND}" * bool(building_verdicts(results))
    if not shared:
        return legend
    return (legend + f"; every row: {', '.join(column.stated(results[0], units) for column in critical)} [16a, 16b] "
            "(b/h_1*: the critical value of both coefficients)")


MODAL_LISTS = ("T_n", "Sa_n", "m_n*/m_t", "h_n*", "V_n")


def modal_table(result: AnalysisResult, units: str = "si") -> Table:
    """Per mode what the engine combined: period, S_a, m_n*/m_t, h_n* and V_n; for the
    flexible supports mode 1 is the bonded system's: T1bar [21] and S_a(T1bar, xi1bar) [23]
    (marked 1*), the higher modes fixed-base."""
    inter = result.intermediates
    flexible = "T1bar" in inter and "Sa1bar" in inter
    table = Table(title=escape(f"Modal base shears ({engine_label(result)}, {result.support})"))
    add_columns(table, ("mode", "T [s]", "S_a [g]", "m_n*/m_t", f"h_n* [{label('m', units)}]",
                        f"V_n [{label('N', units)}]"))
    add_rows(table, (_modal_cells(inter, i, flexible and i == 0, units) for i in range(len(inter["T_n"]))))
    table.caption = escape(_flexible_note(result) if flexible else "S_a = S_a(T_n, xi_n), fixed base")
    return table


def _modal_cells(inter: dict, i: int, bonded: bool, units: str) -> tuple[str, ...]:
    """Mode i+1; bonded: mode 1 of a flexible support, T1bar and S_a(T1bar, xi1bar), marked 1*."""
    mode, period, sa = str(i + 1), inter["T_n"][i], inter["Sa_n"][i]
    if bonded:
        mode, period, sa = "1*", inter["T1bar"], inter["Sa1bar"]
    return (mode, f"{period:.4f}", show(sa, "g", units), f"{inter['m_n*/m_t'][i]:.4f}",
            show(inter["h_n*"][i], "m", units), show(inter["V_n"][i], "N", units))


def _flexible_note(result: AnalysisResult) -> str:
    """The caption of a flexible support's modal table: mode 1*, and how V_1 was found when the mat lifts."""
    inter = result.intermediates
    note = (f"1*: the bonded system's T1bar [21] and S_a(T1bar, xi1bar = {inter['xi1bar']:.4g}) [23] "
            f"(fixed-base T_1 = {inter['T_n'][0]:.4f} s)")
    if "V1_uplift" in inter:
        note += "; the mat lifts off: V_1 by " + _uplift_method(result)
    return note + "; modes 2 and up: fixed-base T_n, S_a(T_n, xi_n)"


def _uplift_method(result: AnalysisResult) -> str:
    """How the uplift base shear V_1 was found: the improved procedure, [29] (slender) or [28a]."""
    inter = result.intermediates
    if "T_u" in inter:
        return f"the improved procedure (docs/accuracy.md; S_a averaged over T1bar-T_u = {inter['T_u']:.4f} s)"
    slender = result.details.get("options", {}).get("uplift_formula") == "slender"
    return "[29]" if slender else "[28a]"


def intermediates_table(result: AnalysisResult, units: str = "si") -> Table:
    """Scalar intermediates in their display units, with meaning (engines/quantities.INTERMEDIATES)."""
    table = Table(title=escape(f"Intermediate values ({engine_label(result)}, {result.support})"))
    add_columns(table, ("quantity", "value", "unit", "meaning"), justify="left")
    scalars = {name: value for name, value in result.intermediates.items() if name not in MODAL_LISTS}
    return add_rows(table, (_intermediate_cells(name, value, units) for name, value in scalars.items()))


def _intermediate_cells(name: str, value, units: str) -> tuple[str, ...]:
    """Name, value in its display unit, the unit and the meaning (engines/quantities.INTERMEDIATES)."""
    unit, meaning = INTERMEDIATES.get(name, ("", ""))
    kind = intermediate_kind(name, unit)
    return escape(name), show(value, kind, units), escape(label(kind, units)), escape(meaning)


def print_results(out: Console, results: list[AnalysisResult], title: str | None = None, units: str = "si",
                  checks=()) -> None:
    """Every table of every result, then the summary (a suite's result: its statistics and its
    records too, and the simplified engine beside it: cli/render_suite.py) and the accuracy checks
    (accuracy.Check) given."""
    if title:
        out.print(f"[bold]{escape(title)}[/bold]")
    for result in results:
        print_tables(out, _result_tables(result, units))
    print_tables(out, _closing_tables(results, units, checks))
    if answer_line(results, checks):
        out.print(escape(answer_line(results, checks)))


def _result_tables(result: AnalysisResult, units: str) -> Iterator[Table | None]:
    """The tables of one result, in order, each made when it is printed (None: a table it has not)."""
    yield story_table(result, units)
    yield render_rocking.elements_table(result, units)
    yield render_rocking.rocking_table(result, units)
    yield render_design.design_table(result, units)  # with [design] (engines/design.py)
    if all(name in result.intermediates for name in MODAL_LISTS):
        yield modal_table(result, units)
    if result.intermediates:
        yield intermediates_table(result, units)
    if isinstance(result, SuiteResult):
        yield render_suite.statistics_table(result, units)
        yield render_suite.records_table(result, units)
        from . import render_acceptance  # a suite's: its acceptance (analysis/acceptance.py)

        yield render_acceptance.acceptance_table(result)


def _closing_tables(results: list[AnalysisResult], units: str, checks) -> Iterator[Table | None]:
    """The summary, the suites' comparison and the accuracy checks (None: a table the run has not)."""
    yield summary_table(results, units)
    yield render_suite.comparison_table(results, units)
    yield accuracy_table(checks, units)
    yield render_suite.suite_check_table(checks, units)


def accuracy_table(checks=(), units: str = "si") -> Table | None:
    """The simplified engine against the exact engine, per support (accuracy.Check), in the display
    units (display.py), or None."""
    if not checks:
        return None
    references = list(dict.fromkeys(check.reference for check in checks))
    shared = len(references) == 1  # named in the title, else in a column
    table = Table(title=escape(_accuracy_title(checks[0], references)))
    table.caption = escape(_band_caption(checks[0]))
    add_columns(table, _accuracy_headings(shared), left=("support", "reference", "quantity"))
    for check in checks:
        add_rows(table, _check_rows(check, shared, units))
    table.caption += escape(_left_out_reasons(checks))
    return table


def _accuracy_title(first, references: list[str]) -> str:
    """Against the one reference, else 'the exact engine'; on one record: 'same deck and record'."""
    reference = references[0] if len(references) == 1 else "exact engine"
    same = ", same deck and record" if first.suite is None else ""
    return "Accuracy check: the simplified engine against the " + reference + same


def _accuracy_headings(shared: bool) -> tuple[str, ...]:
    """The columns; a column of the reference engine when the checks have several."""
    return ("support", *(() if shared else ("reference",)), "quantity", "simplified", "exact", "ratio")


def _band_caption(first) -> str:
    """The ratio, and the bands outside which it is flagged (analysis.check_band, check_band_motion)."""
    band, motion = first.band, first.motion_band
    return (f"ratio = simplified / exact; '!': outside [{band[0]:g}, {band[1]:g}] "
            f"(analysis.check_band; edge uplift and mat rotation: [{motion[0]:g}, {motion[1]:g}], "
            f"analysis.check_band_motion), also a warning; {MEASURED}; --no-check skips this check")


def _check_rows(check, shared: bool, units: str) -> list[tuple[str, ...]]:
    """The rows of one check: a failed check in one row, else one per compared and left-out value."""
    lead = _check_lead(check, shared)
    if check.error is not None:
        return [(*lead, "-", "-", "-", escape(f"failed: {check.error}"))]
    compared = [(*lead, *_compared_cells(check, c, units)) for c in check.comparisons]
    return compared + [(*lead, escape(COMPARED[name].heading(units)), "-", "-", "left out") for name in check.left_out]


def _check_lead(check, shared: bool) -> tuple[str, ...]:
    """The leading cells of a check's rows: its support, and its reference when they are not shared."""
    return (check.support,) if shared else (check.support, escape(check.reference))


def _compared_cells(check, comparison, units: str) -> tuple[str, ...]:
    """Quantity, simplified and exact value, and their ratio ('!' when outside the check's band)."""
    compared = COMPARED[comparison.name]
    return (escape(compared.heading(units)), show(comparison.simplified, compared.display, units),
            show(comparison.exact, compared.display, units), _flagged_ratio(check, comparison))


def _flagged_ratio(check, comparison) -> str:
    """The ratio simplified / exact, ' !' when outside the check's band ('-' without one)."""
    if comparison.ratio is None:
        return "-"
    return f"{comparison.ratio:.3f}" + (" !" if comparison.outside(check.band_of(comparison.name)) else "")


def _left_out_reasons(checks) -> str:
    """'; <symbol> left out: <why>' for each value a check left out, sorted, once each."""
    reasons = {f"{COMPARED[n].symbol} left out: {why}" for check in checks for n, why in check.left_out.items()}
    return "".join(f"; {reason}" for reason in sorted(reasons))
