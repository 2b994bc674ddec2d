"""Terminal tables of a record suite's results (engines/suite_result.SuiteResult): the statistics
of every scalar and quantity, one summary row per record, and the simplified engine on the
target spectrum beside the design statistic. Table-driven from engines/quantities.py."""

from __future__ import annotations

from collections.abc import Iterator, Sequence

from rich.markup import escape
from rich.table import Table

from ..analysis.accuracy import MOTION
from ..display import SUMMARY, WEIGHT_LEGEND, show, summary_columns, verdicts
from ..engines.quantities import COMPARED, QUANTITIES, SCALARS
from ..engines.result import AnalysisResult
from ..engines.suite_result import STATISTICS, SuiteResult, simplified_ratios
from .tables import add_columns, add_rows, has_peak, ratio_cell

#: the scalars of the statistics (display.SUMMARY)
SCALAR_COLUMNS = ("base_shear", "base_shear_coefficient", "base_moment", "base_moment_coefficient")
#: the scalars of each record's row (records_table)
RECORD_SCALARS = ("base_shear_coefficient", "base_moment_coefficient")
#: the columns of the comparison table; split: the ratio's two factors too
COMPARISON_HEADINGS = ("engine", "support", "quantity", "simplified", "suite", "simplified / suite")
SPLIT_HEADINGS = ("target / records", "procedure")
STATISTIC_HEADINGS = {"mean": "mean", "median": "median", "p84": "84th percentile", "max": "maximum"}
CAPTION = (f"{WEIGHT_LEGEND}; the quantities: their largest value over the floors, stories or "
           "elements (all of them in the JSON and CSV files)")
#: how a ratio simplified / exact on a suite splits into its two factors (engines/suite_result.simplified_ratios)
SPLIT_CAPTION = ("simplified / suite = (target / records) x procedure: target / records = the simplified engine "
                 "on the target against it on each record's own spectrum (below 1: the records are above the "
                 "target), procedure = it on each record's spectrum against the exact engine on that record (the "
                 "procedure's own error)")


def _rows(result: AnalysisResult, units: str = "si", scalars=SCALAR_COLUMNS) -> list[tuple[str, float, str]]:
    """(heading, SI value, display kind) of the scalars (display.SUMMARY) and of the largest value
    of each quantity that the summaries carry (those with a sweep column, engines/quantities.py)."""
    return _scalar_rows(result, units, scalars) + _quantity_rows(result, units)


def _scalar_rows(result: AnalysisResult, units: str, scalars) -> list[tuple[str, float, str]]:
    """(heading, SI value, display kind) of each of the `scalars` that is a result's scalar (SCALARS)."""
    return [(SUMMARY[name].heading(units), result.value(name), SUMMARY[name].kind) for name in scalars
            if name in SCALARS]


def _quantity_rows(result: AnalysisResult, units: str) -> list[tuple[str, float, str]]:
    """(heading, SI value, display kind) of the largest value of each quantity with a sweep column
    that the result holds."""
    return [(q.heading(units), result.value(q.name), q.display) for q in QUANTITIES.values()
            if q.column and has_peak(result, q.name)]


def statistics_table(result: SuiteResult, units: str = "si") -> Table:
    """Rows: the scalars and the largest value of each quantity; columns: every statistic over the
    records, the design statistic marked with *."""
    table = Table(title=escape(f"{result.engine} engine, {result.support} support: statistics of {result.count} "
                               f"records ({result.rule_label}: design value = {result.statistic})"))
    add_columns(table, ["quantity", *(_statistic_heading(name, result.statistic) for name in STATISTICS)],
                left=("quantity",))
    per_statistic = {name: _rows(stat, units) for name, stat in result.statistics.items()}
    design = per_statistic[result.statistic]
    add_rows(table, ((escape(text), *_statistic_cells(per_statistic, i, kind, units))
                     for i, (text, _, kind) in enumerate(design)))
    table.caption = escape(f"uplift under {result.uplift_count} of {result.count} records; {CAPTION}; "
                           f"{STATISTICS['p84'][0]}")
    return table


def _statistic_heading(name: str, design: str) -> str:
    """The statistic's heading, marked * when it is the design statistic."""
    return STATISTIC_HEADINGS[name] + (" *" if name == design else "")


def _statistic_cells(per_statistic: dict, i: int, kind: str, units: str) -> list[str]:
    """Row i of every statistic, in its display unit."""
    return [show(per_statistic[name][i][1], kind, units) for name in STATISTICS]


def records_table(result: SuiteResult, units: str = "si") -> Table:
    """One row per record: name, amplitude factor, coefficients, largest quantities, uplift."""
    table = Table(title=escape(f"{result.engine} engine, {result.support} support: each record"))
    headings = [text for text, _, _ in _rows(result.record_results[0], units, RECORD_SCALARS)]
    verdict = summary_columns(verdicts(result.record_results))
    table.add_column("#", justify="right")
    _add_record_column(table, result.records)
    add_columns(table, ["factor [-]", *headings, *(column.symbol for column in verdict)])
    pairs = enumerate(zip(result.records, result.record_results, strict=True))
    add_rows(table, (_record_cells(k, info, record, headings, verdict, units) for k, (info, record) in pairs))
    table.caption = escape(CAPTION)
    return table


def _add_record_column(table: Table, records) -> None:
    """The record's name, as wide as the longest (at most 20 characters: longer ones end in '...')."""
    widest = min(20, max(len(info.name) for info in records))
    table.add_column("record", justify="left", min_width=widest, max_width=20, no_wrap=True, overflow="ellipsis")


def _record_cells(k: int, info, record: AnalysisResult, headings: list[str], verdict: list, units: str) -> list[str]:
    """Record k+1: name, amplitude factor, the values under `headings` ('-': it has none) and the verdicts."""
    values = {text: show(value, kind, units) for text, value, kind in _rows(record, units, RECORD_SCALARS)}
    return [str(k + 1), escape(info.name), f"{info.factor:.4f}", *[values.get(h, "-") for h in headings],
            *(column.cell(record) for column in verdict)]


def comparison_table(results: Sequence[AnalysisResult], units: str = "si") -> Table | None:
    """The simplified engine on the target spectrum beside each suite's design statistic, per
    support, with the ratio simplified / statistic (None when there is no suite result)."""
    suites = [r for r in results if _compared_suite(r)]
    if not suites:
        return None
    split = _split_known(suites)
    table = Table(title="Simplified engine on the target spectrum against the suite")
    add_columns(table, COMPARISON_HEADINGS + (SPLIT_HEADINGS if split else ()), left=("engine", "quantity"))
    add_rows(table, _comparison_rows(suites, split, units))
    table.caption = escape(_comparison_caption(split))
    return table


def _comparison_caption(split: bool) -> str:
    """What 'suite' is, what a ratio below 1 means and, split, what its two factors are (SPLIT_CAPTION)."""
    return ("suite: the design statistic of the records' peaks (the code's rule); a ratio below 1: "
            "the simplified procedure gives less; '!': outside the accuracy check's band (analysis.check_band, "
            "check_band_motion)" + (f"; {SPLIT_CAPTION}" if split else ""))


def _compared_suite(result: AnalysisResult) -> bool:
    """A suite's result with the simplified engine on the target spectrum beside it."""
    return isinstance(result, SuiteResult) and result.simplified is not None


def _split_known(suites: list[SuiteResult]) -> bool:
    """Every ratio of every suite splits into its two factors (engines/suite_result.simplified_ratios)."""
    return all("procedure_ratio" in item for r in suites for item in simplified_ratios(r).values())


def _comparison_rows(suites: list[SuiteResult], split: bool, units: str) -> Iterator[list[str]]:
    """A row per suite and compared value (engines/suite_result.simplified_ratios)."""
    for r in suites:
        for name, item in simplified_ratios(r).items():
            yield _comparison_cells(r, name, item, split, units)


def _comparison_cells(result: SuiteResult, name: str, item: dict, split: bool, units: str) -> list[str]:
    """One compared value: the simplified one, the suite's, their ratio and, split, its two factors."""
    kind = COMPARED[name].display
    factors = [f"{item['spectrum_ratio']:.3f}", f"{item['procedure_ratio']:.3f}"] if split else []
    return [escape(result.label), result.support, escape(COMPARED[name].heading(units)),
            show(item["simplified"], kind, units), show(item["statistic"], kind, units),
            f"{item['ratio']:.3f}" + _flag(result, name, item["ratio"]), *factors]


def _flag(result: SuiteResult, name: str, ratio: float) -> str:
    """' !' for a ratio outside the deck's check band (analysis/suite.flagged), '' inside it."""
    low, high = result.suite.get("check_band_motion" if name in MOTION else "check_band", (0.0, float("inf")))
    return "" if low <= ratio <= high else " !"


def suite_check_table(checks: Sequence, units: str = "si") -> Table | None:
    """The accuracy check on a suite (analysis/suite_check.py: accuracy.Check with a suite and the split
    ratios) split into the records' standing against the target and the procedure's own error,
    per support and compared value (None without such a check)."""
    checks = _split_checks(checks)
    if not checks:
        return None
    table = Table(title=escape(_suite_check_title(checks[0].suite)))
    add_columns(table, ("support", "quantity", "simplified / exact", "target / records", "procedure"),
                left=("support", "quantity"))
    add_rows(table, (_split_cells(check, c, units) for check in checks for c in check.comparisons))
    table.caption = escape(SPLIT_CAPTION.replace("simplified / suite", "simplified / exact"))
    return table


def _split_checks(checks: Sequence) -> list:
    """The accuracy checks on a suite, with their ratios split."""
    return [check for check in checks if check.suite is not None and check.procedure_ratio]


def _suite_check_title(suite: dict) -> str:
    """The statistic and the records checked: generated for the spectrum, or the deck's."""
    made = (f"{suite['count']} records generated for the spectrum (seed {suite['seed']}, cached)"
            if suite["source"] == "generated" else f"the deck's {suite['count']} records")
    return f"Accuracy check split: simplified / exact {suite['statistic']} of {made}"


def _split_cells(check, comparison, units: str) -> list[str]:
    """Support, quantity, the ratio simplified / exact and its two factors."""
    ratios = [comparison.ratio, check.spectrum_ratio.get(comparison.name), check.procedure_ratio.get(comparison.name)]
    return [check.support, escape(COMPARED[comparison.name].heading(units)), *(ratio_cell(r) for r in ratios)]
