"""Terminal tables of a record suite's results (engines/suite_result.SuiteResult): the statistics
of every scalar and quantity, one summary row per record, and the simplified engine on the
target spectrum beside the design statistic. Table-driven from engines/quantities.py."""

from __future__ import annotations

from collections.abc import Sequence

from rich.markup import escape
from rich.table import Table

from ..display import SUMMARY, WEIGHT_LEGEND, show, summary_columns, verdicts
from ..engines.quantities import COMPARED, QUANTITIES, SCALARS
from ..engines.result import AnalysisResult
from ..engines.suite_result import STATISTICS, SuiteResult, simplified_ratios

#: the scalars of the statistics (display.SUMMARY)
SCALAR_COLUMNS = ("base_shear", "base_shear_coefficient", "base_moment", "base_moment_coefficient")
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
    rows = [(SUMMARY[name].heading(units), result.value(name), SUMMARY[name].kind) for name in scalars
            if name in SCALARS]
    for q in QUANTITIES.values():
        if q.column and q.name in result.peaks and result.peaks[q.name].size:
            rows.append((q.heading(units), result.value(q.name), q.display))
    return rows


def statistics_table(result: SuiteResult, units: str = "si") -> Table:
    """Rows: the scalars and the largest value of each quantity; columns: every statistic over the
    records, the design statistic marked with *."""
    table = Table(title=escape(f"{result.engine} engine, {result.support} support: statistics of {result.count} "
                               f"records ({result.rule_label}: design value = {result.statistic})"))
    table.add_column("quantity", justify="left")
    for name in STATISTICS:
        table.add_column(escape(STATISTIC_HEADINGS[name] + (" *" if name == result.statistic else "")),
                         justify="right")
    per_statistic = {name: _rows(stat, units) for name, stat in result.statistics.items()}
    for i, (text, _, kind) in enumerate(per_statistic[result.statistic]):
        table.add_row(escape(text), *[show(per_statistic[name][i][1], kind, units) for name in STATISTICS])
    table.caption = escape(f"uplift under {result.uplift_count} of {result.count} records; {CAPTION}; "
                           f"{STATISTICS['p84'][0]}")
    return table


def records_table(result: SuiteResult, units: str = "si") -> Table:
    """One row per record: name, amplitude factor, coefficients, largest quantities, uplift."""
    table = Table(title=escape(f"{result.engine} engine, {result.support} support: each record"))
    scalars = ("base_shear_coefficient", "base_moment_coefficient")
    headings = [text for text, _, _ in _rows(result.record_results[0], units, scalars)]
    widest = min(20, max(len(info.name) for info in result.records))
    verdict = summary_columns(verdicts(result.record_results))
    for text in ["#", "record", "factor [-]", *headings, *(column.symbol for column in verdict)]:
        if text == "record":
            table.add_column(text, justify="left", min_width=widest, max_width=20, no_wrap=True,
                             overflow="ellipsis")
        else:
            table.add_column(escape(text), justify="right")
    for k, (info, record) in enumerate(zip(result.records, result.record_results, strict=True)):
        values = {text: show(value, kind, units) for text, value, kind in _rows(record, units, scalars)}
        table.add_row(str(k + 1), escape(info.name), f"{info.factor:.4f}", *[values.get(h, "-") for h in headings],
                      *(column.cell(record) for column in verdict))
    table.caption = escape(CAPTION)
    return table


def comparison_table(results: Sequence[AnalysisResult], units: str = "si") -> Table | None:
    """The simplified engine on the target spectrum beside each suite's design statistic, per
    support, with the ratio simplified / statistic (None when there is no suite result)."""
    suites = [r for r in results if isinstance(r, SuiteResult) and r.simplified is not None]
    if not suites:
        return None
    table = Table(title="Simplified engine on the target spectrum against the suite")
    split = all("procedure_ratio" in item for r in suites for item in simplified_ratios(r).values())
    headings = ["engine", "support", "quantity", "simplified", "suite", "simplified / suite"]
    headings += ["target / records", "procedure"] if split else []
    for text in headings:
        table.add_column(escape(text), justify="left" if text in ("engine", "quantity") else "right")
    for r in suites:
        for name, item in simplified_ratios(r).items():
            kind = COMPARED[name].display
            cells = [f"{item['spectrum_ratio']:.3f}", f"{item['procedure_ratio']:.3f}"] if split else []
            table.add_row(escape(r.label), r.support, escape(COMPARED[name].heading(units)),
                          show(item["simplified"], kind, units), show(item["statistic"], kind, units),
                          f"{item['ratio']:.3f}", *cells)
    table.caption = escape("suite: the design statistic of the records' peaks (the code's rule); a ratio below 1: "
                           "the simplified procedure gives less" + (f"; {SPLIT_CAPTION}" if split else ""))
    return table


def suite_check_table(checks: Sequence, units: str = "si") -> Table | None:
    """The accuracy check on a suite (analysis/suite_check.py: accuracy.Check with a suite and the split
    ratios) split into the records' standing against the target and the procedure's own error,
    per support and compared value (None without such a check)."""
    checks = [check for check in checks if check.suite is not None and check.procedure_ratio]
    if not checks:
        return None
    suite = checks[0].suite
    made = (f"{suite['count']} records generated for the spectrum (seed {suite['seed']}, cached)"
            if suite["source"] == "generated" else f"the deck's {suite['count']} records")
    table = Table(title=escape(f"Accuracy check split: simplified / exact {suite['statistic']} of {made}"))
    for header in ("support", "quantity", "simplified / exact", "target / records", "procedure"):
        table.add_column(escape(header), justify="left" if header in ("support", "quantity") else "right")
    for check in checks:
        for c in check.comparisons:
            cells = [c.ratio, check.spectrum_ratio.get(c.name), check.procedure_ratio.get(c.name)]
            table.add_row(check.support, escape(COMPARED[c.name].heading(units)),
                          *["-" if value is None else f"{value:.3f}" for value in cells])
    table.caption = escape(SPLIT_CAPTION.replace("simplified / suite", "simplified / exact"))
    return table
