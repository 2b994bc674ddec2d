"""Report sections on what the checks said: the accuracy check (the simplified engine against the
exact one, in the display units of display.py), the warnings, and the [criteria] verdict with the
exit code of `uplift analyze`."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..analysis.comparison import MEASURED
from ..deck.criteria import outcomes
from ..display import heading, label, show
from ..engines.quantities import COMPARED, ROCKING, display_kind
from ..engines.result import AnalysisResult
from .document import Section, Table, Text, number

EXIT_OK, EXIT_CRITERIA = 0, 3


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
                 "(docs/theory.md sections 7 and 11); the procedure's accuracy, " + MEASURED + ". "
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
    if not criteria and not outcomes(results, criteria, checks):  # [design]'s drift check is one (deck/criteria.py)
        verdict = "The deck sets no acceptance criteria ([criteria]): `uplift analyze` exits with code 0."
        return Section("criteria", "Acceptance criteria", [Text([verdict])]), verdict, EXIT_OK
    rows, violated = criteria_rows(results, criteria, units, checks)
    code = EXIT_CRITERIA if violated else EXIT_OK
    verdict = _criteria_verdict(violated, code, _limits_named(criteria, results))
    sourced = any(len(row) > 7 for row in rows)
    table = Table("table-criteria", "Acceptance criteria: the largest |value| of each quantity against its limit",
                  ["engine", "support", "criterion", "value", "limit", "unit", "verdict",
                   *(["source"] if sourced else [])], rows, _criteria_note(rows, sourced))
    return Section("criteria", "Acceptance criteria", [Text([verdict]), table]), verdict, code


def _limits_named(criteria: Mapping, results: Sequence[AnalysisResult]) -> str:
    """Where the limits come from: the deck's [criteria], [design] (Table 12.12-1's allowable drift) or both."""
    design = any("allowable_drift_ratio" in result.peaks for result in results)
    tables = [name for name, given in (("[criteria]", bool(criteria)), ("[design]", design)) if given]
    return "the deck's " + " and ".join(tables or ["[criteria]"])


def _criteria_verdict(violated: int, code: int, named: str = "the deck's [criteria]") -> str:
    if violated:
        return (f"{violated} acceptance limit{'s' if violated > 1 else ''} of {named} exceeded: "
                f"`uplift analyze` exits with code {code}.")
    return f"Every acceptance limit of {named} holds: `uplift analyze` exits with code {code}."


def _criteria_note(rows: list[list[str]], sourced: bool) -> str:
    """The note on settlement limits and sources, where a row has a source or a rocking criterion."""
    return CRITERIA_NOTE if sourced or any(row[2] in ROCKING for row in rows) else ""
