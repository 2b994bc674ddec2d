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
    told = "yielded" in verdicts(results)
    columns = _summary_columns(told)
    rows = [[getattr(r, "label", r.engine), r.support, *_cells(r, columns, units)] for r in results]
    return Table("table-summary", "Summary: base shear V_b [14a] and base moment M_b [14b] of every analysis",
                 ["engine", "support", *(column.heading(units) for column in columns)], rows,
                 f"{WEIGHT_LEGEND}; the critical value of both coefficients is b/h_1* [16a, 16b]"
                 + (f"; {VERDICT_LEGEND}." if told else "."))


def _summary_columns(told: bool) -> list:
    """The columns of display.SUMMARY; `yielded` only when a result tells it."""
    return [c for name, c in SUMMARY.items() if name != "yielded" or told]


def _cells(result: AnalysisResult, columns: list, units: str) -> list[str]:
    return [column.cell(result, units) for column in columns]


def detail_unit(table: str, name: str) -> str:
    """SI unit of an entry of the uplift summary or the energy balance of the history engines."""
    if table == "energy":
        return "-" if name.startswith("relative") else "J"
    for part, unit in (("rotation", "rad"), ("time", "s"), ("episodes", "-"), ("uplift", "m"),
                       ("displacement", "m"), ("reaction", "N")):
        if part in name:
            return unit
    return INTERMEDIATES.get(name, ("", ""))[0]


def _peaks(result, units: str) -> list[str]:
    """The peak base shear, base moment and drift ratio of a result, in the display units."""
    return [SUMMARY["base_shear"].cell(result, units), SUMMARY["base_moment"].cell(result, units),
            show(result.value("drift_ratio"), display_kind("drift_ratio"), units)]


def _record_rows(result, told: bool, units: str) -> list[list[str]]:
    """A row per record of a suite: number, name, factor, peaks, uplift (and whether it yielded)."""
    return [[str(k + 1), record.name, number(record.factor, 4), *_peaks(r, units), number(r.uplift),
             *([SUMMARY["yielded"].cell(r)] if told else [])]
            for k, (record, r) in enumerate(zip(result.records, result.record_results, strict=True))]


def _design_row(result, told: bool, units: str) -> list[str]:
    """The suite's design statistic: its peaks and how many records lifted (and yielded)."""
    yielded = sum(bool(r.yielded) for r in result.record_results)
    return ["", f"{result.statistic} (design value)", "", *_peaks(result, units),
            f"{result.uplift_count} of {result.count}", *([f"{yielded} of {result.count}"] if told else [])]


def records_table(result, units: str = "si") -> Table:
    """A suite's records (engines/suite_result.SuiteResult): factor and peak response of each."""
    told = "yielded" in verdicts(result.record_results)
    rows = [*_record_rows(result, told, units), _design_row(result, told, units)]
    return Table(f"table-{_slug(result)}-records", f"Each record of the suite, {result.engine} engine, "
                 f"{result.support} support ({result.rule_label or result.rule}: the {result.statistic})",
                 ["record", "name", "factor [-]", SUMMARY["base_shear"].heading(units),
                  SUMMARY["base_moment"].heading(units), heading("largest drift ratio", display_kind("drift_ratio"),
                                                                 units),
                  "uplift", *(["yielded"] if told else [])], rows)


#: the detail tables of the history engines: key of result.details -> caption
DETAILS = {"uplift_summary": "Uplift summary", "energy": "Energy balance"}


def result_tables(result: AnalysisResult, units: str = "si") -> list[Table]:
    """Story table, foundation elements, intermediates and the history engines' extras (for a
    suite: of its design statistic, and each record's peaks), in the display units."""
    what = f"{getattr(result, 'label', result.engine)} engine, {result.support} support"
    tables = [story_table(result, what, units), elements_table(result, what, units), rocking_table(result, units),
              intermediates_table(result, what, units),
              *(detail_table(result, key, f"{caption}, {what}", units) for key, caption in DETAILS.items()),
              _suite_records(result, units)]
    return [table for table in tables if table is not None]


def story_table(result: AnalysisResult, what: str, units: str = "si") -> Table:
    """Peak response per story, top story first; what: the analysis in words."""
    shown = [q for q in STORY_QUANTITIES if q.name in result.peaks]
    rows = [_story_row(result, j, shown, units) for j in range(result.elevations.size - 1, -1, -1)]
    return Table(f"table-{_slug(result)}-stories", f"Peak response per story, {what} (top story first)",
                 ["story", heading("elevation", "m", units)] + [q.heading(units) for q in shown], rows,
                 "Floor quantities are those of the floor at the top of the story.")


def _story_row(result: AnalysisResult, j: int, shown: list, units: str) -> list[str]:
    """Story j + 1: its elevation and the peak of each quantity shown."""
    peaks = [show(result.peaks[q.name][j], q.display, units) for q in shown]
    return [str(j + 1), show(result.elevations[j], "m", units), *peaks]


def elements_table(result: AnalysisResult, what: str, units: str = "si") -> Table | None:
    """The peaks of each foundation element (largest compression, plastic settlement), or None."""
    elements = _element_quantities(result)
    if not elements:
        return None
    rows = [_element_row(result, i, x, elements, units) for i, x in enumerate(result.element_positions)]
    plastic = ", plastic settlement" if "plastic_settlement" in result.peaks else ""
    return Table(f"table-{_slug(result)}-elements", f"Foundation elements, {what}: largest compression{plastic}",
                 ["element", heading("position x", "m", units), *(q.heading(units) for q in elements)], rows)


def _element_quantities(result: AnalysisResult) -> list:
    """The quantities of the foundation elements the result gives a value for."""
    return [q for q in element_quantities() if q.name in result.peaks and result.peaks[q.name].size]


def _element_row(result: AnalysisResult, i: int, x: float, elements: list, units: str) -> list[str]:
    """Element i at position x: its peak of each quantity."""
    return [str(i + 1), show(x, "m", units)] + [show(result.peaks[q.name][i], q.display, units) for q in elements]


def _intermediate_row(name: str, value, units: str) -> list[str]:
    unit, meaning = INTERMEDIATES.get(name, ("", ""))
    kind = intermediate_kind(name, unit)
    return [name, show(value, kind, units), label(kind, units), meaning]


def intermediates_table(result: AnalysisResult, what: str, units: str = "si") -> Table | None:
    """The intermediate values of an engine (quantities.INTERMEDIATES), or None."""
    if not result.intermediates:
        return None
    rows = [_intermediate_row(name, value, units) for name, value in result.intermediates.items()]
    return Table(f"table-{_slug(result)}-intermediates", f"Intermediate values, {what}",
                 ["quantity", "value", "unit", "meaning"], rows)


def _detail_kind(key: str, name: str) -> str:
    """The display kind of a detail entry: its SI unit, lengths in mm (display.py)."""
    unit = detail_unit(key, name)
    return "mm" if unit == "m" else unit


def detail_table(result: AnalysisResult, key: str, caption: str, units: str = "si") -> Table | None:
    """A detail of the history engines (DETAILS: the uplift summary, the energy balance), or None."""
    values = result.details.get(key)
    if not values:
        return None
    rows = [[name, show(value, _detail_kind(key, name), units), label(_detail_kind(key, name), units)]
            for name, value in values.items()]
    return Table(f"table-{_slug(result)}-{key.replace('_', '-')}", caption, ["quantity", "value", "unit"], rows)


def _suite_records(result: AnalysisResult, units: str) -> Table | None:
    """The records table of a suite result, None for a single analysis."""
    return records_table(result, units) if getattr(result, "record_results", ()) else None


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
    return pairs + _carried_pairs(exact.values(), done)


def _carried_pairs(exact, done: set[str]) -> list[tuple[AnalysisResult, AnalysisResult]]:
    """(simplified, exact) of the exact results of the supports not yet paired that carry the
    simplified engine's result (a suite's, on the target spectrum)."""
    return [(e.simplified, e) for e in exact if e.support not in done and _carries_simplified(e)]


def _carries_simplified(result: AnalysisResult) -> bool:
    """Whether a (suite) result carries the simplified engine's result on the target spectrum."""
    return getattr(result, "simplified", None) is not None


ACCURACY_NOTE = ("The exact engine solves the same model without the simplified procedure's approximations "
                 "(docs/theory.md sections 7 and 11); docs/accuracy.md gives the measured spread of these ratios. "
                 "A ratio outside the band of analysis.check_band (edge uplift and mat rotation: "
                 "analysis.check_band_motion) is a warning.")


def accuracy_section(results: Sequence[AnalysisResult], units: str = "si", checks: Sequence = ()) -> Section | None:
    """The accuracy check in the display units (display.py): the checks given (upliftcli/analysis/accuracy.py:
    the simplified engine against the exact engine with all modes, per support) or else, for each
    support both engines ran (on a suite: the simplified engine on the target against the suite's
    design statistic), accuracy.compare of the two; None when neither is available."""
    from ..analysis.accuracy import compare

    checks = list(checks) or [compare(simplified, exact) for simplified, exact in accuracy_pairs(results)]
    rows = [row for check in checks for row in _check_rows(check, units)]
    if not rows:
        return None
    table = Table("table-accuracy", "Accuracy of the simplified procedure: simplified / exact",
                  ["support", "quantity [unit]", "simplified", "exact", "simplified/exact [-]", "in band"], rows,
                  _accuracy_note(checks))
    split = split_table(checks)
    return Section("accuracy", "Accuracy check", [table] + ([split] if split is not None else []))


def _check_rows(check, units: str) -> list[list[str]]:
    """The rows of one accuracy check: one per compared value and per value left out, or one
    saying why the check did not run."""
    if check.error is not None:
        return [[check.support, check.reference, "-", "-", f"not run: {check.error}", "-"]]
    return ([_comparison_row(check, c, units) for c in check.comparisons]
            + [[check.support, _quantity(name, units), "-", "-", "-", "left out"] for name in check.left_out])


def _quantity(name: str, units: str) -> str:
    """A compared quantity's meaning with its display unit."""
    return heading(COMPARED[name].meaning, COMPARED[name].display, units)


def _comparison_row(check, c, units: str) -> list[str]:
    """Simplified, exact, their ratio and whether it lies in the check's band."""
    kind = COMPARED[c.name].display
    return [check.support, _quantity(c.name, units), show(c.simplified, kind, units), show(c.exact, kind, units),
            number(_ratio(c.ratio), 4), "no (warning)" if c.outside(check.band_of(c.name)) else "yes"]


def _ratio(value: float | None) -> float:
    """A ratio, nan where there is none (printed as such)."""
    return np.nan if value is None else value


def _accuracy_note(checks: Sequence) -> str:
    """Where the exact values come from, what the ratios mean, and why values were left out."""
    reasons = dict.fromkeys(f"{COMPARED[n].meaning} left out: {why}." for c in checks for n, why in c.left_out.items())
    references = "; ".join(dict.fromkeys(c.reference for c in checks))
    return f"Exact values: {references}. {ACCURACY_NOTE} {' '.join(reasons)}".rstrip()


def split_table(checks: Sequence) -> Table | None:
    """The accuracy check on a spectrum-compatible suite (analysis/suite_check.py) split into its two
    factors, per support and compared value (None without such a check)."""
    rows = [_split_row(check, c) for check in _split_checks(checks) for c in check.comparisons]
    if not rows:
        return None
    return Table("table-accuracy-split", "The ratio on the suite split: records against the target, and the "
                 "procedure's own error", ["support", "quantity", "simplified/exact [-]", "target/records [-]",
                                           "procedure [-]"], rows,
                 "simplified/exact = (target/records) x procedure. target/records: the simplified engine on the "
                 "target spectrum against it on each record's own spectrum (the suite's statistic; below 1: the "
                 "records stand above the target); procedure: it on each record's own spectrum against the exact "
                 "engine on that record (the procedure's own error). docs/suites.md, \"The exact answer by default\".")


def _split_checks(checks: Sequence) -> list:
    """The checks on a suite that split their ratio (a procedure ratio per value)."""
    return [check for check in checks if check.suite is not None and check.procedure_ratio]


def _split_row(check, c) -> list[str]:
    ratios = (c.ratio, check.spectrum_ratio.get(c.name), check.procedure_ratio.get(c.name))
    return [check.support, COMPARED[c.name].meaning, *(number(_ratio(value), 4) for value in ratios)]


def warnings_section(results: Sequence[AnalysisResult], deck=None, checks: Sequence = ()) -> Section:
    rows = _analysis_warnings(results) + _check_warnings(results, checks) + _suite_warnings(results, deck)
    if not rows:
        return Section("warnings", "Warnings", [Text(["No warnings."])])
    return Section("warnings", "Warnings", [Table("table-warnings", "Warnings of the analyses",
                                                  ["engine", "support", "warning"], rows)])


def _analysis_warnings(results: Sequence[AnalysisResult]) -> list[list[str]]:
    """The warnings each analysis gave (details["warnings"])."""
    return [[r.engine, r.support, str(w)] for r in results for w in r.details.get("warnings", [])]


def _check_warnings(results: Sequence[AnalysisResult], checks: Sequence) -> list[list[str]]:
    """The warnings of the accuracy check of each analysis (output.check_of)."""
    from ..output import check_of

    return [[r.engine, r.support, w] for r in results if (check := check_of(r, checks)) for w in check.warnings()]


def _suite_warnings(results: Sequence[AnalysisResult], deck) -> list[list[str]]:
    """The warnings of the suites of the results and of the deck's ground motion, each once."""
    suite = [str(w) for r in results for w in getattr(r, "warnings", ())] + _motion_warnings(deck)
    return [["suite", "-", w] for w in dict.fromkeys(suite)]


def _motion_warnings(deck) -> list[str]:
    """The warnings of the deck's ground motion (a suite's), none without a deck."""
    return [str(w) for w in getattr(getattr(deck, "ground_motion", None), "warnings", ()) or ()]


def criteria_rows(results: Sequence[AnalysisResult], criteria: Mapping, units: str = "si", checks: Sequence = ()
                  ) -> tuple[list[list[str]], int]:
    """One row per result and criterion (value, limit in the display units, verdict, and the
    limit's source when the deck gives any: [criteria.sources]) and the number violated (the tests
    of deck/criteria.py; checks: the accuracy checks, for simplified_error)."""
    found = outcomes(results, criteria, checks)
    sourced = any(outcome.source for outcome in found)
    rows = [_criterion_row(outcome, sourced, units) for outcome in found]
    return rows, sum(not outcome.ok for outcome in found)


def _criterion_row(outcome, sourced: bool, units: str) -> list[str]:
    """Analysis, criterion, value, limit, unit, verdict (and the limit's source)."""
    result = outcome.result
    return [result.engine, result.support, outcome.name, *_criterion_values(outcome, units),
            "ok" if outcome.ok else "VIOLATED", *([outcome.source or "-"] if sourced else [])]


def _criterion_values(outcome, units: str) -> tuple[str, str, str]:
    """(value, limit, unit) of a criterion in the display units; uplift: allowed or not."""
    if outcome.name == "uplift":
        return number(outcome.value), "allowed" if outcome.limit else "not allowed", "-"
    kind = "coefficient" if outcome.name == "simplified_error" else display_kind(outcome.name)
    return show(outcome.value, kind, units), show(outcome.limit, kind, units), label(kind, units)


CRITERIA_NOTE = ("A settlement limit judges the largest settlement (downward) of the left edge, the centre and the "
                 "right edge of the mat; source: as the deck gives it ([criteria.sources]).")


def criteria_section(results: Sequence[AnalysisResult], criteria: Mapping, units: str = "si", checks: Sequence = ()
                     ) -> tuple[Section, str, int]:
    """(section, verdict, exit code): 0 when every limit holds (or none is set), 3 otherwise."""
    if not criteria:
        verdict = "The deck sets no acceptance criteria ([criteria]): `uplift analyze` exits with code 0."
        return Section("criteria", "Acceptance criteria", [Text([verdict])]), verdict, EXIT_OK
    rows, violated = criteria_rows(results, criteria, units, checks)
    code = EXIT_CRITERIA if violated else EXIT_OK
    verdict = _criteria_verdict(violated, code)
    sourced = any(len(row) > 7 for row in rows)
    table = Table("table-criteria", "Acceptance criteria: the largest |value| of each quantity against its limit",
                  ["engine", "support", "criterion", "value", "limit", "unit", "verdict",
                   *(["source"] if sourced else [])], rows, _criteria_note(rows, sourced))
    return Section("criteria", "Acceptance criteria", [Text([verdict]), table]), verdict, code


def _criteria_verdict(violated: int, code: int) -> str:
    if violated:
        return (f"{violated} acceptance limit{'s' if violated > 1 else ''} of the deck's [criteria] exceeded: "
                f"`uplift analyze` exits with code {code}.")
    return f"Every acceptance limit of the deck's [criteria] holds: `uplift analyze` exits with code {code}."


def _criteria_note(rows: list[list[str]], sourced: bool) -> str:
    """The note on settlement limits and sources, where a row has a source or a rocking criterion."""
    return CRITERIA_NOTE if sourced or any(row[2] in ROCKING for row in rows) else ""
