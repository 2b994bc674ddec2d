"""Report sections on what came out: the results of every engine and support (the tables of
engines/quantities.py, in the display units of display.py), the accuracy check (simplified
against exact), the warnings and the [criteria] verdict with the exit code of `uplift analyze`."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..deck.criteria import outcomes
from ..display import (
    ROCKING_HEADINGS,
    SUMMARY,
    VERDICT_LEGEND,
    WEIGHT_LEGEND,
    heading,
    intermediate_kind,
    label,
    rocking_rows,
    show,
    verdicts,
)
from ..engines.quantities import (
    COMPARED,
    FLOOR,
    INTERMEDIATES,
    ROCKING,
    STORY,
    display_kind,
    element_quantities,
    quantities,
    rocking_entries,
)
from ..engines.result import AnalysisResult
from .document import Section, Table, Text, number

EXIT_OK, EXIT_CRITERIA = 0, 3
STORY_QUANTITIES = quantities(FLOOR, STORY)


def _slug(result: AnalysisResult) -> str:
    return f"{result.engine}-{result.support}"


def summary_table(results: Sequence[AnalysisResult], units: str = "si") -> Table:
    """One row per analysis, every column of the display record of the scalar results (display.SUMMARY;
    `yielded` where a result tells it: display.verdicts)."""
    columns = [c for name, c in SUMMARY.items() if name != "yielded" or "yielded" in verdicts(results)]
    rows = [[getattr(r, "label", r.engine), r.support, *(column.cell(r, units) for column in columns)] for r in results]
    return Table("table-summary", "Summary: base shear V_b [14a] and base moment M_b [14b] of every analysis",
                 ["engine", "support", *(column.heading(units) for column in columns)], rows,
                 f"{WEIGHT_LEGEND}; the critical value of both coefficients is b/h_1* [16a, 16b]"
                 + (f"; {VERDICT_LEGEND}." if "yielded" in verdicts(results) else "."))


def detail_unit(table: str, name: str) -> str:
    """SI unit of an entry of the uplift summary or the energy balance of the history engines."""
    if table == "energy":
        return "-" if name.startswith("relative") else "J"
    for part, unit in (("rotation", "rad"), ("time", "s"), ("episodes", "-"), ("uplift", "m"),
                       ("displacement", "m"), ("reaction", "N")):
        if part in name:
            return unit
    return INTERMEDIATES.get(name, ("", ""))[0]


def records_table(result, units: str = "si") -> Table:
    """A suite's records (engines/suite_result.SuiteResult): factor and peak response of each."""
    shear, moment, drift = SUMMARY["base_shear"], SUMMARY["base_moment"], display_kind("drift_ratio")

    def peaks(r) -> list[str]:
        return [shear.cell(r, units), moment.cell(r, units), show(r.value("drift_ratio"), drift, units)]

    told = "yielded" in verdicts(result.record_results)
    rows = [[str(k + 1), record.name, number(record.factor, 4), *peaks(r), number(r.uplift),
             *([SUMMARY["yielded"].cell(r)] if told else [])]
            for k, (record, r) in enumerate(zip(result.records, result.record_results, strict=True))]
    yielded = sum(bool(r.yielded) for r in result.record_results)
    rows.append(["", f"{result.statistic} (design value)", "", *peaks(result),
                 f"{result.uplift_count} of {result.count}", *([f"{yielded} of {result.count}"] if told else [])])
    return Table(f"table-{_slug(result)}-records", f"Each record of the suite, {result.engine} engine, "
                 f"{result.support} support ({result.rule_label or result.rule}: the {result.statistic})",
                 ["record", "name", "factor [-]", shear.heading(units), moment.heading(units),
                  heading("largest drift ratio", drift, units), "uplift", *(["yielded"] if told else [])], rows)


def result_tables(result: AnalysisResult, units: str = "si") -> list[Table]:
    """Story table, foundation elements, intermediates and the history engines' extras (for a
    suite: of its design statistic, and each record's peaks), in the display units."""
    what = f"{getattr(result, 'label', result.engine)} engine, {result.support} support"
    shown = [q for q in STORY_QUANTITIES if q.name in result.peaks]
    rows = [[str(j + 1), show(result.elevations[j], "m", units)]
            + [show(result.peaks[q.name][j], q.display, units) for q in shown]
            for j in range(result.elevations.size - 1, -1, -1)]
    tables = [Table(f"table-{_slug(result)}-stories", f"Peak response per story, {what} (top story first)",
                    ["story", heading("elevation", "m", units)] + [q.heading(units) for q in shown], rows,
                    "Floor quantities are those of the floor at the top of the story.")]
    elements = [q for q in element_quantities() if q.name in result.peaks and result.peaks[q.name].size]
    if elements:
        rows = [[str(i + 1), show(x, "m", units)] + [show(result.peaks[q.name][i], q.display, units) for q in elements]
                for i, x in enumerate(result.element_positions)]
        plastic = ", plastic settlement" if "plastic_settlement" in result.peaks else ""
        tables.append(Table(f"table-{_slug(result)}-elements",
                            f"Foundation elements, {what}: largest compression{plastic}",
                            ["element", heading("position x", "m", units), *(q.heading(units) for q in elements)],
                            rows))
    rocking = rocking_table(result, units)
    if rocking is not None:
        tables.append(rocking)
    if result.intermediates:
        rows = []
        for name, value in result.intermediates.items():
            unit, meaning = INTERMEDIATES.get(name, ("", ""))
            kind = intermediate_kind(name, unit)
            rows.append([name, show(value, kind, units), label(kind, units), meaning])
        tables.append(Table(f"table-{_slug(result)}-intermediates", f"Intermediate values, {what}",
                            ["quantity", "value", "unit", "meaning"], rows))
    for key, caption in (("uplift_summary", "Uplift summary"), ("energy", "Energy balance")):
        values = result.details.get(key)
        if values:
            kinds = {name: ("mm" if detail_unit(key, name) == "m" else detail_unit(key, name)) for name in values}
            rows = [[name, show(value, kinds[name], units), label(kinds[name], units)]
                    for name, value in values.items()]
            tables.append(Table(f"table-{_slug(result)}-{key.replace('_', '-')}", f"{caption}, {what}",
                                ["quantity", "value", "unit"], rows))
    if getattr(result, "record_results", ()):
        tables.append(records_table(result, units))
    return tables


def rocking_table(result: AnalysisResult, units: str = "si") -> Table | None:
    """The mat's peak and residual rotation and settlement and, on yielding soil, the yielded
    elements and the plastic work (quantities.ROCKING: the exact engine's uplift runs), or None."""
    entries = rocking_entries(result)
    if not entries:
        return None
    return Table(f"table-{_slug(result)}-rocking", f"Rocking of the mat, {result.engine} engine, {result.support} "
                 "support: rotation and settlement (ASCE 41-17 section 8.4)", list(ROCKING_HEADINGS),
                 rocking_rows(entries, units),
                 "Rotation |theta|; settlement: downward displacement from the rest position under gravity (< 0: "
                 "above it); residual: at the end of the analysis (docs/theory.md 14.7). With a bearing capacity, "
                 "the plastic work is the energy the yielding soil dissipated (14.5).")


def results_section(results: Sequence[AnalysisResult], units: str = "si") -> Section:
    blocks: list = [summary_table(results, units)]
    for result in results:
        blocks += result_tables(result, units)
    return Section("results", "Results", blocks)


def accuracy_pairs(results: Sequence[AnalysisResult]) -> list[tuple[AnalysisResult, AnalysisResult]]:
    """(simplified, exact) result pairs of the same support; on a suite the simplified engine on
    the target spectrum against the exact design statistic (the one the suite result carries
    when the simplified engine was not run beside it)."""
    exact = {r.support: r for r in results if r.engine == "exact"}
    pairs = [(r, exact[r.support]) for r in results if r.engine == "simplified" and r.support in exact]
    done = {e.support for _, e in pairs}
    pairs += [(e.simplified, e) for e in exact.values()
              if e.support not in done and getattr(e, "simplified", None) is not None]
    return pairs


def accuracy_section(results: Sequence[AnalysisResult], units: str = "si", checks: Sequence = ()) -> Section | None:
    """The accuracy check in the display units (display.py): the checks given (upliftcli/analysis/accuracy.py:
    the simplified engine against the exact engine with all modes, per support) or else, for each
    support both engines ran (on a suite: the simplified engine on the target against the suite's
    design statistic), accuracy.compare of the two; None when neither is available."""
    from ..analysis.accuracy import compare

    checks = list(checks) or [compare(simplified, exact) for simplified, exact in accuracy_pairs(results)]
    note = ("The exact engine solves the same model without the simplified procedure's approximations "
            "(docs/theory.md sections 7 and 11); docs/accuracy.md gives the measured spread of these ratios. "
            "A ratio outside the band of analysis.check_band (edge uplift and mat rotation: "
            "analysis.check_band_motion) is a warning.")
    rows = []
    for check in checks:
        if check.error is not None:
            rows.append([check.support, check.reference, "-", "-", f"not run: {check.error}", "-"])
            continue
        for c in check.comparisons:
            quantity = COMPARED[c.name]
            rows.append([check.support, heading(quantity.meaning, quantity.display, units),
                         show(c.simplified, quantity.display, units), show(c.exact, quantity.display, units),
                         number(np.nan if c.ratio is None else c.ratio, 4),
                         "no (warning)" if c.outside(check.band_of(c.name)) else "yes"])
        rows += [[check.support, heading(COMPARED[name].meaning, COMPARED[name].display, units), "-", "-", "-",
                  "left out"] for name in check.left_out]
    if not rows:
        return None
    reasons = dict.fromkeys(f"{COMPARED[n].meaning} left out: {why}." for c in checks for n, why in c.left_out.items())
    note = f"Exact values: {'; '.join(dict.fromkeys(c.reference for c in checks))}. {note} {' '.join(reasons)}".rstrip()
    table = Table("table-accuracy", "Accuracy of the simplified procedure: simplified / exact",
                  ["support", "quantity [unit]", "simplified", "exact", "simplified/exact [-]", "in band"], rows,
                  note)
    split = split_table(checks)
    return Section("accuracy", "Accuracy check", [table] + ([split] if split is not None else []))


def split_table(checks: Sequence) -> Table | None:
    """The accuracy check on a spectrum-compatible suite (analysis/suite_check.py) split into its two
    factors, per support and compared value (None without such a check)."""
    rows = [[check.support, COMPARED[c.name].meaning,
             *(number(np.nan if value is None else value, 4)
               for value in (c.ratio, check.spectrum_ratio.get(c.name), check.procedure_ratio.get(c.name)))]
            for check in checks if check.suite is not None and check.procedure_ratio for c in check.comparisons]
    if not rows:
        return None
    return Table("table-accuracy-split", "The ratio on the suite split: records against the target, and the "
                 "procedure's own error", ["support", "quantity", "simplified/exact [-]", "target/records [-]",
                                           "procedure [-]"], rows,
                 "simplified/exact = (target/records) x procedure. target/records: the simplified engine on the "
                 "target spectrum against it on each record's own spectrum (the suite's statistic; below 1: the "
                 "records stand above the target); procedure: it on each record's own spectrum against the exact "
                 "engine on that record (the procedure's own error). docs/suites.md, \"The exact answer by default\".")


def warnings_section(results: Sequence[AnalysisResult], deck=None, checks: Sequence = ()) -> Section:
    from ..output import check_of

    rows = [[r.engine, r.support, str(w)] for r in results for w in r.details.get("warnings", [])]
    rows += [[r.engine, r.support, w] for r in results if (check := check_of(r, checks)) for w in check.warnings()]
    suite = [str(w) for r in results for w in getattr(r, "warnings", ())]
    suite += [str(w) for w in getattr(getattr(deck, "ground_motion", None), "warnings", ()) or ()]
    rows += [["suite", "-", w] for w in dict.fromkeys(suite)]
    if not rows:
        return Section("warnings", "Warnings", [Text(["No warnings."])])
    return Section("warnings", "Warnings", [Table("table-warnings", "Warnings of the analyses",
                                                  ["engine", "support", "warning"], rows)])


def criteria_rows(results: Sequence[AnalysisResult], criteria: Mapping, units: str = "si", checks: Sequence = ()
                  ) -> tuple[list[list[str]], int]:
    """One row per result and criterion (value, limit in the display units, verdict, and the
    limit's source when the deck gives any: [criteria.sources]) and the number violated (the tests
    of deck/criteria.py; checks: the accuracy checks, for simplified_error)."""
    rows, violated = [], 0
    found = outcomes(results, criteria, checks)
    sourced = any(outcome.source for outcome in found)
    for outcome in found:
        result = outcome.result
        if outcome.name == "uplift":
            value, limit, unit = number(outcome.value), "allowed" if outcome.limit else "not allowed", "-"
        else:
            kind = "coefficient" if outcome.name == "simplified_error" else display_kind(outcome.name)
            value, limit, unit = show(outcome.value, kind, units), show(outcome.limit, kind, units), label(kind, units)
        rows.append([result.engine, result.support, outcome.name, value, limit, unit,
                     "ok" if outcome.ok else "VIOLATED", *([outcome.source or "-"] if sourced else [])])
        violated += not outcome.ok
    return rows, violated


def criteria_section(results: Sequence[AnalysisResult], criteria: Mapping, units: str = "si", checks: Sequence = ()
                     ) -> tuple[Section, str, int]:
    """(section, verdict, exit code): 0 when every limit holds (or none is set), 3 otherwise."""
    if not criteria:
        verdict = "The deck sets no acceptance criteria ([criteria]): `uplift analyze` exits with code 0."
        return Section("criteria", "Acceptance criteria", [Text([verdict])]), verdict, EXIT_OK
    rows, violated = criteria_rows(results, criteria, units, checks)
    code = EXIT_CRITERIA if violated else EXIT_OK
    verdict = (f"{violated} acceptance limit{'s' if violated > 1 else ''} of the deck's [criteria] exceeded: "
               f"`uplift analyze` exits with code {code}." if violated else
               f"Every acceptance limit of the deck's [criteria] holds: `uplift analyze` exits with code {code}.")
    sourced = any(len(row) > 7 for row in rows)
    table = Table("table-criteria", "Acceptance criteria: the largest |value| of each quantity against its limit",
                  ["engine", "support", "criterion", "value", "limit", "unit", "verdict",
                   *(["source"] if sourced else [])], rows,
                  "A settlement limit judges the largest settlement (downward) of the left edge, the centre and the "
                  "right edge of the mat; source: as the deck gives it ([criteria.sources])." if sourced or any(
                      row[2] in ROCKING for row in rows) else "")
    return Section("criteria", "Acceptance criteria", [Text([verdict]), table]), verdict, code
