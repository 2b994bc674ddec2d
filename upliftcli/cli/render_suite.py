"""Terminal tables of a record suite's results (engines/suite_result.SuiteResult): the statistics
of every scalar and quantity, one summary row per record, and the simplified engine on the
target spectrum beside the design statistic. Table-driven from engines/quantities.py."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from rich.markup import escape
from rich.table import Table

from ..engines.quantities import QUANTITIES, SCALARS
from ..engines.result import AnalysisResult
from ..engines.suite_result import STATISTICS, SuiteResult, simplified_ratios

#: how the scalars and the compared values are shown: name -> (heading, factor from SI, format)
SCALAR_DISPLAY = {"base_shear": ("V_b [kN]", 1e-3, ".1f"), "base_shear_coefficient": ("V_b/W", 1.0, ".4f"),
                  "base_moment": ("M_b [kN m]", 1e-3, ".1f"), "base_moment_coefficient": ("M_b/Wh", 1.0, ".4f")}
COMPARED_DISPLAY = {"base_shear": ("V_b [kN]", 1e-3, ".1f"), "base_moment": ("M_b [kN m]", 1e-3, ".1f"),
                    "drift_ratio": ("largest drift ratio [%]", 100.0, ".3f"),
                    "roof_displacement": ("roof displacement [mm]", 1e3, ".2f")}
STATISTIC_HEADINGS = {"mean": "mean", "median": "median", "p84": "84th percentile", "max": "maximum"}
CAPTION = ("W = m_t g, Wh = m_t g h_1*; the quantities: their largest value over the floors, stories or "
           "elements (all of them in the JSON and CSV files)")


def _rows(result: AnalysisResult, scalars=tuple(SCALAR_DISPLAY)) -> list[tuple[str, float, tuple[float, str]]]:
    """(heading, SI value, (display factor, format)) of the scalars and of the largest value of each
    quantity that the summaries carry (those with a sweep column, engines/quantities.py)."""
    rows = [(SCALAR_DISPLAY[name][0], result.value(name), SCALAR_DISPLAY[name][1:]) for name in scalars
            if name in SCALARS]
    for q in QUANTITIES.values():
        if q.column and q.name in result.peaks and result.peaks[q.name].size:
            rows.append((q.heading, result.value(q.name), q.display[1:]))
    return rows


def _show(value: float, display: tuple[float, str]) -> str:
    return format(value * display[0], display[1]) if np.isfinite(value) else "-"


def statistics_table(result: SuiteResult) -> Table:
    """Rows: the scalars and the largest value of each quantity; columns: every statistic over the
    records, the design statistic marked with *."""
    table = Table(title=escape(f"{result.engine} engine, {result.support} support: statistics of {result.count} "
                               f"records ({result.rule_label}: design value = {result.statistic})"))
    table.add_column("quantity", justify="left")
    for name in STATISTICS:
        table.add_column(escape(STATISTIC_HEADINGS[name] + (" *" if name == result.statistic else "")),
                         justify="right")
    per_statistic = {name: _rows(stat) for name, stat in result.statistics.items()}
    for i, (heading, _, display) in enumerate(per_statistic[result.statistic]):
        table.add_row(escape(heading), *[_show(per_statistic[name][i][1], display) for name in STATISTICS])
    table.caption = escape(f"uplift under {result.uplift_count} of {result.count} records; {CAPTION}; "
                           f"{STATISTICS['p84'][0]}")
    return table


def records_table(result: SuiteResult) -> Table:
    """One row per record: name, amplitude factor, coefficients, largest quantities, uplift."""
    table = Table(title=escape(f"{result.engine} engine, {result.support} support: each record"))
    scalars = ("base_shear_coefficient", "base_moment_coefficient")
    headings = [heading for heading, _, _ in _rows(result.record_results[0], scalars)]
    widest = min(20, max(len(info.name) for info in result.records))
    for heading in ["#", "record", "factor [-]", *headings, "uplift"]:
        if heading == "record":
            table.add_column(heading, justify="left", min_width=widest, max_width=20, no_wrap=True,
                             overflow="ellipsis")
        else:
            table.add_column(escape(heading), justify="right")
    for k, (info, record) in enumerate(zip(result.records, result.record_results, strict=True)):
        values = {heading: _show(value, display) for heading, value, display in _rows(record, scalars)}
        table.add_row(str(k + 1), escape(info.name), f"{info.factor:.4f}", *[values.get(h, "-") for h in headings],
                      "yes" if record.uplift else "no")
    table.caption = escape(CAPTION)
    return table


def comparison_table(results: Sequence[AnalysisResult]) -> Table | None:
    """The simplified engine on the target spectrum beside each suite's design statistic, per
    support, with the ratio simplified / statistic (None when there is no suite result)."""
    suites = [r for r in results if isinstance(r, SuiteResult) and r.simplified is not None]
    if not suites:
        return None
    table = Table(title="Simplified engine on the target spectrum against the suite")
    split = all("procedure_ratio" in item for r in suites for item in simplified_ratios(r).values())
    headings = ["engine", "support", "quantity", "simplified", "suite", "simplified / suite"]
    headings += ["target / records", "procedure"] if split else []
    for heading in headings:
        table.add_column(escape(heading), justify="left" if heading in ("engine", "quantity") else "right")
    for r in suites:
        for name, item in simplified_ratios(r).items():
            heading, factor, spec = COMPARED_DISPLAY[name]
            cells = [f"{item['spectrum_ratio']:.3f}", f"{item['procedure_ratio']:.3f}"] if split else []
            table.add_row(escape(r.label), r.support, escape(heading), format(item["simplified"] * factor, spec),
                          format(item["statistic"] * factor, spec), f"{item['ratio']:.3f}", *cells)
    table.caption = escape("suite: the design statistic of the records' peaks (the code's rule); a ratio below 1: "
                           "the simplified procedure gives less"
                           + ("; simplified / suite = (target / records) x procedure: target / records = the "
                              "simplified engine on the target against it on each record's own spectrum (below 1: "
                              "the records are above the target), procedure = it on each record's spectrum against "
                              "the exact engine on that record (the procedure's own error)" if split else ""))
    return table


def suite_check_table(results: Sequence[AnalysisResult]) -> Table | None:
    """The accuracy check on a suite (suite_check.py) split into the suite's standing against the
    target and the procedure's own error, per support (None without such a check)."""
    from ..accuracy import CHECKED

    checks = [r.details["accuracy"] for r in results if r.details.get("accuracy", {}).get("reference") == "exact-suite"
              and "procedure_ratio" in r.details["accuracy"]]
    if not checks:
        return None
    suite = checks[0]["suite"]
    made = (f"{suite['count']} records generated for the spectrum (seed {suite['seed']}, cached)"
            if suite["source"] == "generated" else f"the deck's {suite['count']} records")
    table = Table(title=escape(f"Accuracy check split: simplified / exact {suite['statistic']} of {made}"))
    for header in ("support", "quantity", "simplified / exact", "target / records", "procedure"):
        table.add_column(escape(header), justify="left" if header in ("support", "quantity") else "right")
    for check in checks:
        for name, (unit, meaning, _) in CHECKED.items():
            cells = [check[key][name] for key in ("ratio", "spectrum_ratio", "procedure_ratio")]
            table.add_row(check["support"], escape(f"{meaning} [{unit}]"),
                          *["-" if value is None else f"{value:.3f}" for value in cells])
    table.caption = escape("simplified / exact = (target / records) x procedure; target / records: the simplified "
                           "engine on the target against it on each record's own spectrum (the records' excess over "
                           "the target); procedure: it on each record's spectrum against the exact engine on that "
                           "record (the procedure's own error)")
    return table
