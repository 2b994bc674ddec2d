"""Terminal tables (rich) for modes and analysis results. Falls back to plain text when
there is no terminal (CI=true, pipes): rich handles that itself.

Every table fits the console's width (80 columns and up): the story tables abbreviate their
headings with a legend, the summary states once what every row shares, and a table that is
still too wide is split in parts that repeat its leading label columns (fit_table; the
console of console() does it for every table it prints). A number is never cut. Without a
terminal the width is $COLUMNS, else 120.
"""

from __future__ import annotations

import os
import re

from rich.cells import cell_len
from rich.console import Console
from rich.markup import escape
from rich.measure import Measurement
from rich.table import Table
from rich.text import Text

from ..display import VERDICT_LEGEND, WEIGHT_LEGEND, intermediate_kind, label, show, summary_columns, verdicts
from ..engines.quantities import COMPARED, FLOOR, INTERMEDIATES, STORY, quantities
from ..engines.result import AnalysisResult
from ..engines.suite_result import SuiteResult
from ..model.system import System, fixed_base_mode_rows

#: floor and story quantities in table order
STORY_QUANTITIES = quantities(FLOOR, STORY)
#: short headings of the story tables (name -> (heading, legend entry)); the others: Quantity.heading
SHORT_HEADINGS = {"displacement": ("disp.", "disp. = floor displacement relative to the mat"),
                  "drift_ratio": ("drift ratio", "drift ratio = story drift / story height"),
                  "moment": ("moment", "moment = overturning moment at the bottom of the story"),
                  "floor_acceleration": ("floor acc.", "floor acc. = absolute floor acceleration")}
#: width of the output when it is not a terminal and $COLUMNS does not say
PIPE_WIDTH = 120


def console_width(environ=os.environ) -> int | None:
    """$COLUMNS when it is a positive integer, else None."""
    text = environ.get("COLUMNS", "").strip()
    return int(text) if text.isdigit() and int(text) > 0 else None


class FittedConsole(Console):
    """A Console that draws every table within its width (fit_table); a reader that closes the
    pipe early (`| head`) silences it and the command goes on (cli/stdout.py; rich would exit 1)."""

    def print(self, *objects, **kwargs) -> None:
        parts = [part for item in objects for part in (fit_table(item, self.width) if isinstance(item, Table)
                                                        else [item])]
        super().print(*parts, **kwargs)

    def on_broken_pipe(self) -> None:
        from .stdout import silence

        silence()
        self.quiet = True


def console(stderr: bool = False) -> Console:
    """A console that never needs a terminal: on a terminal its width, else $COLUMNS or
    PIPE_WIDTH; tables too wide for it are split (FittedConsole). Texts are printed as they
    are: no ":name:" emoji codes replaced (a deck title "Block B :warning:" stays that)."""
    probe = Console(stderr=stderr)
    width = None if probe.is_terminal else console_width() or PIPE_WIDTH
    return FittedConsole(stderr=stderr, width=width, highlight=False, emoji=False)


def _measure(table: Table) -> Measurement:
    probe = Console(width=100_000, emoji=False)
    return Measurement.get(probe, probe.options, table)


def minimum_width(table: Table) -> int:
    """The fewest columns the table can be drawn in without cutting a cell (headings and
    texts wrapped at their blanks, numbers whole)."""
    return _measure(table).minimum


_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?%?|-")


def _labels(table: Table) -> int:
    """Leading label columns that every part of a split table repeats: the first, and after it
    those that are left-justified or hold a text that is not a number (engine, support ...)."""
    count = 1
    for column in table.columns[1:-1]:
        texts = [_text(cell).strip() for cell in column.cells]
        if column.justify != "left" and all(_NUMBER.fullmatch(text) for text in texts if text):
            break
        count += 1
    return count


def _text(cell) -> str:
    return cell.plain if isinstance(cell, Text) else str(cell)


def _stacked_header(column) -> str | Text:
    """A number column's heading in lines no wider than its widest cell (or its longest word; a
    unit in brackets, "[kN m]", is one word)."""
    header = column.header
    if not isinstance(header, str):
        return header
    header = Text.from_markup(header).plain
    words = re.findall(r"\[[^\]]*\]|[^\s\[]+", header)
    widest = max((len(line) for cell in column.cells for line in _text(cell).splitlines()), default=0)
    limit = max(widest, *(len(word) for word in words)) if words else widest
    lines: list[str] = []
    for word in words:
        if lines and len(lines[-1]) + 1 + len(word) <= limit:
            lines[-1] += " " + word
        else:
            lines.append(word)
    return Text("\n".join(lines))


def _part(table: Table, indices: list[int], number: int = 0, parts: int = 1, compact: bool = False) -> Table:
    """The table with the columns `indices`; compact: the number (right-justified) columns with
    their headings stacked to the width of their cells and never wrapped (_stacked_header)."""
    title = table.title
    if parts > 1 and title is not None:
        suffix = f" ({number + 1}/{parts})"
        title = title + suffix if isinstance(title, str) else Text.assemble(title, suffix)
    part = Table(title=title, caption=table.caption if number == parts - 1 else None, box=table.box,
                 show_header=table.show_header, show_lines=table.show_lines, title_justify=table.title_justify,
                 caption_justify=table.caption_justify, padding=table.padding)
    cells = []
    for index in indices:
        column = table.columns[index]
        number_column = compact and column.justify == "right"
        part.add_column(_stacked_header(column) if number_column else column.header, justify=column.justify,
                        no_wrap=column.no_wrap or number_column, overflow=column.overflow,
                        min_width=column.min_width, style=column.style, header_style=column.header_style)
        cells.append(list(column.cells))
    for row in zip(*cells, strict=True):
        part.add_row(*row)
    return part


def fit_table(table: Table, width: int) -> list[Table]:
    """The table, if it fits `width` as it is; else with the headings of its number columns
    stacked (_part compact), and if that is still too wide, in parts, each with the leading
    label columns (_labels) and as many of the others, in order, as fit (one at least),
    titled "(1/2)" ... A number is never cut."""
    if _widest(table) <= width or _measure(table).maximum <= width:
        return [table]
    every = list(range(len(table.columns)))
    # rich draws a table as wide as its columns' minimums plus its frame (_frame_width): each
    # column is measured once, alone, instead of every candidate part
    columns = [_column_width(_part(table, [index], compact=True)) - _frame_width(table, 1) for index in every]
    if sum(columns) + _frame_width(table, len(every)) <= width or len(every) < 2:
        return [_part(table, every, compact=True)]
    keys = every[:_labels(table)]
    groups: list[list[int]] = [[]]
    for index in every[len(keys):]:
        candidate = keys + groups[-1] + [index]
        if groups[-1] and sum(columns[c] for c in candidate) + _frame_width(table, len(candidate)) > width:
            groups.append([])
        groups[-1].append(index)
    return [_part(table, keys + group, k, len(groups), compact=True) for k, group in enumerate(groups)]


def _column_width(part: Table) -> int:
    """The narrowest a one-column table is drawn: its minimum, or for a column that may not wrap
    (no_wrap: rich never narrows it below its widest line, though it measures it by its longest
    word) its maximum."""
    measured = _measure(part)
    return measured.maximum if part.columns[0].no_wrap else measured.minimum


def _widest(table: Table) -> float:
    """An upper bound of the table's natural width, from the lengths of its texts as given
    (markup and escapes only shorten them): most tables fit, and rich measures a table by
    rendering every cell. Infinite when a cell is not text."""
    _, right, _, left = table.padding
    total = _frame_width(table, len(table.columns)) + len(table.columns) * (left + right)
    for column in table.columns:
        texts = [column.header, *column.cells]
        if not all(isinstance(text, (str, Text)) for text in texts):
            return float("inf")
        widest = max(cell_len(line) for text in texts for line in (_text(text).splitlines() or [""]))
        total += max(widest, column.min_width or 0) if column.width is None else column.width
    return total


def _frame_width(table: Table, count: int) -> int:
    """Columns a table of `count` columns adds to its cells (padding included): its outer
    edges and the rules between the columns (as rich.table.Table lays it out)."""
    if table.box is None:
        return 0
    return (2 if table.show_edge else 0) + count - 1


def modes_table(system: System, n_modes: int | None = None, units: str = "si") -> Table:
    """Periods, w_n/w_1, m_n*/m_t (and cumulative), h_n* and h_n*/b (docs/theory.md sections 5, 6)."""
    rows = fixed_base_mode_rows(system)[:n_modes]
    m_t = system.total_mass
    table = Table(title=escape(f"Fixed-base modes (m_t = {show(m_t, 'kg', units)} {label('kg', units)}, "
                               f"b = {show(system.half_width, 'm', units)} {label('m', units)})"))
    for header in ("mode", "T_n [s]", "w_n/w_1", "m_n*/m_t", "cumulative", f"h_n* [{label('m', units)}]", "h_n*/b"):
        table.add_column(escape(header), justify="right")
    if system.mat_mass > 0.0:
        table.caption = escape(f"m_t includes the mat mass m_0 = {show(system.mat_mass, 'kg', units)} "
                               f"{label('kg', units)}: the m_n* add up to the building mass, "
                               f"{1 - system.mat_mass / m_t:.4f} m_t")
    for row in rows:
        table.add_row(str(row["mode"]), f"{row['period']:.4f}", f"{row['frequency_ratio']:.3f}",
                      f"{row['effective_mass_ratio']:.4f}", f"{row['cumulative_mass_ratio']:.4f}",
                      show(row["effective_height"], "m", units), f"{row['effective_height_over_b']:.3f}")
    return table


def story_table(result: AnalysisResult, units: str = "si") -> Table:
    """Per story (top first): elevation and the peak of every floor and story quantity the
    engine gives (engines/quantities.py), in the display units (display.py)."""
    title = f"{result.engine} engine, {result.support} support"
    if isinstance(result, SuiteResult):
        title += f": {result.statistic} of {result.count} records ({result.rule_label})"
    table = Table(title=escape(title))
    shown = [q for q in STORY_QUANTITIES if q.name in result.peaks]
    headings = [f"{SHORT_HEADINGS[q.name][0]} [{label(q.display, units)}]" if q.name in SHORT_HEADINGS
                else q.heading(units) for q in shown]
    for header in ["story", f"elevation [{label('m', units)}]", *headings]:
        table.add_column(escape(header), justify="right")
    legend = [SHORT_HEADINGS[q.name][1] for q in shown if q.name in SHORT_HEADINGS]
    table.caption = escape("; ".join(legend)) if legend else None
    for j in range(result.elevations.size - 1, -1, -1):
        table.add_row(str(j + 1), show(result.elevations[j], "m", units),
                      *[show(result.peaks[q.name][j], q.display, units) for q in shown])
    return table


#: the columns of the summary table (display.SUMMARY); the critical ones go into the caption
#: when every row has the same (one building)
SUMMARY_COLUMNS = ("base_shear", "base_shear_coefficient", "base_moment", "base_moment_coefficient")
CRITICAL_COLUMNS = ("critical_base_shear", "critical_base_moment", "critical_coefficient")


def summary_table(results: list[AnalysisResult], units: str = "si") -> Table:
    """One row per result: base shear and moment, their coefficients (W = m_t g), uplift; the
    critical values V_c [16a], M_c [16b] and b/h_1* in the caption when every row has the same
    (one building), else in columns (display.SUMMARY)."""
    critical = summary_columns(CRITICAL_COLUMNS)
    values = [tuple(column.cell(r, units) for column in critical) for r in results]
    shared = len(set(values)) == 1
    columns = summary_columns(SUMMARY_COLUMNS + (() if shared else CRITICAL_COLUMNS) + verdicts(results))
    table = Table(title="Summary")
    for header in ("engine", "support"):
        table.add_column(header, justify="left")
    for column in columns:
        table.add_column(escape(column.heading(units)), justify="right")
    for r in results:
        table.add_row(escape(engine_label(r)), r.support, *[column.cell(r, units) for column in columns])
    legend = WEIGHT_LEGEND + (f"; {VERDICT_LEGEND}" if "yielded" in verdicts(results) else "")
    if shared and results:
        legend += (f"; every row: {', '.join(column.stated(results[0], units) for column in critical)} [16a, 16b] "
                   "(b/h_1*: the critical value of both coefficients)")
    table.caption = escape(legend)
    return table


def engine_label(result: AnalysisResult) -> str:
    """The engine, and for a suite's result its design statistic ('exact, mean of 11 records')."""
    return result.label if isinstance(result, SuiteResult) else result.engine


MODAL_LISTS = ("T_n", "Sa_n", "m_n*/m_t", "h_n*", "V_n")


def modal_table(result: AnalysisResult, units: str = "si") -> Table:
    """Per mode what the engine combined: period, S_a, m_n*/m_t, h_n* and V_n; for the
    flexible supports mode 1 is the bonded system's: T1bar [21] and S_a(T1bar, xi1bar) [23]
    (marked 1*), the higher modes fixed-base."""
    inter = result.intermediates
    flexible = "T1bar" in inter and "Sa1bar" in inter
    table = Table(title=escape(f"Modal base shears ({engine_label(result)}, {result.support})"))
    for header in ("mode", "T [s]", "S_a [g]", "m_n*/m_t", f"h_n* [{label('m', units)}]",
                   f"V_n [{label('N', units)}]"):
        table.add_column(escape(header), justify="right")
    for i, period in enumerate(inter["T_n"]):
        sa = inter["Sa_n"][i]
        if i == 0 and flexible:
            period, sa = inter["T1bar"], inter["Sa1bar"]
        table.add_row("1*" if i == 0 and flexible else str(i + 1), f"{period:.4f}", show(sa, "g", units),
                      f"{inter['m_n*/m_t'][i]:.4f}", show(inter["h_n*"][i], "m", units),
                      show(inter["V_n"][i], "N", units))
    if flexible:
        note = (f"1*: the bonded system's T1bar [21] and S_a(T1bar, xi1bar = {inter['xi1bar']:.4g}) [23] "
                f"(fixed-base T_1 = {inter['T_n'][0]:.4f} s)")
        if "V1_uplift" in inter:
            slender = result.details.get("options", {}).get("uplift_formula") == "slender"
            note += "; the mat lifts off: V_1 by " + (
                f"the improved procedure (docs/accuracy.md; S_a averaged over T1bar-T_u = {inter['T_u']:.4f} s)"
                if "T_u" in inter else "[29]" if slender else "[28a]")
        table.caption = escape(note + "; modes 2 and up: fixed-base T_n, S_a(T_n, xi_n)")
    else:
        table.caption = escape("S_a = S_a(T_n, xi_n), fixed base")
    return table


def intermediates_table(result: AnalysisResult, units: str = "si") -> Table:
    """Scalar intermediates in their display units, with meaning (engines/quantities.INTERMEDIATES)."""
    table = Table(title=escape(f"Intermediate values ({engine_label(result)}, {result.support})"))
    for header in ("quantity", "value", "unit", "meaning"):
        table.add_column(escape(header), justify="left")
    for name, value in result.intermediates.items():
        if name in MODAL_LISTS:
            continue
        unit, meaning = INTERMEDIATES.get(name, ("", ""))
        kind = intermediate_kind(name, unit)
        table.add_row(escape(name), show(value, kind, units), escape(label(kind, units)), escape(meaning))
    return table


def print_results(out: Console, results: list[AnalysisResult], title: str | None = None, units: str = "si",
                  checks=()) -> None:
    """Every table of every result, then the summary (a suite's result: its statistics and its
    records too, and the simplified engine beside it: cli/render_suite.py) and the accuracy checks
    (accuracy.Check) given."""
    from . import render_rocking, render_suite

    if title:
        out.print(f"[bold]{escape(title)}[/bold]")
    for result in results:
        out.print(story_table(result, units))
        for table in render_rocking.foundation_tables(result, units):
            out.print(table)
        if all(name in result.intermediates for name in MODAL_LISTS):
            out.print(modal_table(result, units))
        if result.intermediates:
            out.print(intermediates_table(result, units))
        if isinstance(result, SuiteResult):
            out.print(render_suite.statistics_table(result, units))
            out.print(render_suite.records_table(result, units))
    out.print(summary_table(results, units))
    comparison = render_suite.comparison_table(results, units)
    if comparison is not None:
        out.print(comparison)
    checked = accuracy_table(checks, units)
    if checked is not None:
        out.print(checked)
    split = render_suite.suite_check_table(checks, units)
    if split is not None:
        out.print(split)


def accuracy_table(checks=(), units: str = "si") -> Table | None:
    """The simplified engine against the exact engine, per support (accuracy.Check), in the display
    units (display.py), or None."""
    if not checks:
        return None
    references = list(dict.fromkeys(check.reference for check in checks))
    shared = len(references) == 1  # named in the title, else in a column
    table = Table(title=escape("Accuracy check: the simplified engine against the "
                               + (references[0] if shared else "exact engine")
                               + (", same deck and record" if checks[0].suite is None else "")))
    band, motion = checks[0].band, checks[0].motion_band
    table.caption = escape(f"ratio = simplified / exact; '!': outside [{band[0]:g}, {band[1]:g}] "
                           f"(analysis.check_band; edge uplift and mat rotation: [{motion[0]:g}, {motion[1]:g}], "
                           "analysis.check_band_motion), also a warning; the measured spread of these ratios: "
                           "docs/accuracy.md; --no-check skips this check")
    headers = ("support", *(() if shared else ("reference",)), "quantity", "simplified", "exact", "ratio")
    for header in headers:
        table.add_column(escape(header), justify="left" if header in ("support", "reference", "quantity") else "right")
    for check in checks:
        lead = (check.support,) if shared else (check.support, escape(check.reference))
        if check.error is not None:
            table.add_row(*lead, "-", "-", "-", escape(f"failed: {check.error}"))
            continue
        for c in check.comparisons:
            compared = COMPARED[c.name]
            ratio = "-" if c.ratio is None else f"{c.ratio:.3f}" + (" !" if c.outside(check.band_of(c.name)) else "")
            table.add_row(*lead, escape(compared.heading(units)), show(c.simplified, compared.display, units),
                          show(c.exact, compared.display, units), ratio)
        for name in check.left_out:
            table.add_row(*lead, escape(COMPARED[name].heading(units)), "-", "-", "left out")
    reasons = {f"{COMPARED[n].symbol} left out: {why}" for check in checks for n, why in check.left_out.items()}
    table.caption += escape("".join(f"; {reason}" for reason in sorted(reasons)))
    return table
