"""The deck's acceptance criteria ([criteria]) applied to results: one home for the tests that
`uplift analyze` turns into its exit code, a sweep into its `violations` column and the report
into its criteria table.

A criterion is a limit on the largest |value| of a response quantity or a scalar
(engines/quantities.py), `uplift = false`, or `simplified_error = e`: every ratio simplified /
exact of the accuracy check (analysis/accuracy.py) within [1/(1 + e), 1 + e] (applied to the checks given:
a deck without the simplified engine is refused by deck/load.py, --no-check by cli/options.py). On a
suite (SuiteResult) the limits apply to the design statistic (the mean, or EC8's maximum below 7
records) and uplift = false to every record.
A limit on a rocking quantity (quantities.ROCKING: rotation, residual rotation, settlement and
residual settlement; the values of ASCE 41-17 section 8.4 for the chosen performance level, given
by the user) applies to the results that report it: the exact engine's uplift analyses (deck/load.py
asks for one). A settlement limit bounds the largest downward value (a mat that rose is not
judged by it), a rotation limit |theta|. Each limit may carry its source as the user states it
(`[criteria.sources]`, Criteria.sources), repeated with its verdict.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from ..engines.design import drift_exceedances
from ..engines.quantities import ROCKING, rocking_value, unit_of
from ..engines.result import AnalysisResult, is_suite_result


class Criteria(dict):
    """The deck's acceptance limits {name: limit} (a dict) with `sources` {name: text}: where each
    limit comes from, as the deck states it ([criteria.sources]; a mapping without it has none)."""

    def __init__(self, limits=(), sources: Mapping[str, str] | None = None):
        super().__init__(limits)
        self.sources = dict(sources or {})


def source_of(criteria: Mapping, name: str) -> str:
    """The source the deck gives for the limit `name` ("" when none)."""
    return getattr(criteria, "sources", {}).get(name, "")


@dataclass(frozen=True)
class Outcome:
    """One criterion applied to one result. value: the largest |value| (in `unit`), or for
    `uplift` whether the mat lifts off; limit: the deck's (for `uplift`: whether it may)."""

    result: AnalysisResult
    name: str
    value: float | bool
    limit: float | bool
    unit: str
    detail: str = ""
    source: str = ""

    @property
    def ok(self) -> bool:
        if self.name == "uplift":
            return bool(self.limit) or not self.value
        return self.value <= self.limit

    def message(self) -> str:
        """The one line that reports a violation."""
        label = _label(self.result)
        source = f" (source: {self.source})" if self.source else ""
        if self.name == "uplift":
            return f"{label}: the mat lifts off{_under(self.result)} (criteria.uplift = false){source}"
        detail = f" ({self.detail})" if self.detail else ""
        return (f"{label}: {self.name} = {self.value:.4g} exceeds the limit {self.limit:.4g} [{self.unit}]"
                f"{source}{detail}")


def _label(result: AnalysisResult) -> str:
    """'engine/support', and for a suite the statistic and the number of records."""
    label = f"{result.engine}/{result.support}"
    if is_suite_result(result):
        label += f" ({result.statistic} of {result.count} records)"
    return label


def _under(result: AnalysisResult) -> str:
    """' under k records' of a suite's uplift ('' for one analysis)."""
    return f" under {result.uplift_count} records" if is_suite_result(result) else ""


def outcomes(results: Sequence[AnalysisResult], criteria: Mapping, checks: Sequence = ()) -> list[Outcome]:
    """Every criterion applied to every result, in the order of the results, then the criteria;
    simplified_error applied to each accuracy check (accuracy.Check) of a simplified result."""
    found = []
    for result in results:
        for name, limit in criteria.items():
            found += _outcomes(result, name, limit, source_of(criteria, name), checks)
        found += _design_drift(result)
    return found


def _design_drift(result: AnalysisResult) -> list[Outcome]:
    """The design story drift ratio of a result with [design] values against the allowable one of ASCE 7-22
    Table 12.12-1 (engines/design.py; none without them): the largest over the stories, the stories that
    exceed it named (else the story of the largest)."""
    if "allowable_drift_ratio" not in result.peaks or "design_drift_ratio" not in result.peaks:
        return []
    drifts = result.peaks["design_drift_ratio"]
    design = result.details.get("design", {})
    source = (f"ASCE 7-22 Table 12.12-1, {design.get('structure')}, risk category {design.get('risk_category')}; "
              f"C_d = {design.get('Cd'):g}, R = {design.get('R'):g}")
    allowable = float(result.peaks["allowable_drift_ratio"][0])
    return [Outcome(result, "design_drift_ratio", float(np.max(drifts)), allowable, "-", _stories(result), source)]


def _stories(result: AnalysisResult) -> str:
    """'story 3' (the one that exceeds the allowable drift, or the largest), 'stories 2, 3 exceed it'."""
    over = drift_exceedances(result)
    if len(over) > 1:
        return f"stories {', '.join(map(str, over))} exceed it"
    return f"story {over[0] if over else int(np.argmax(result.peaks['design_drift_ratio'])) + 1}"


def _outcomes(result: AnalysisResult, name: str, limit, source: str, checks: Sequence) -> list[Outcome]:
    """One criterion applied to one result: none for a rocking limit the result does not report (the
    deck has the engine and support that report it), one per accuracy check for simplified_error."""
    if name == "uplift":
        return [Outcome(result, name, bool(result.uplift), bool(limit), "-", source=source)]
    if name in ROCKING and name not in result.peaks:
        return []
    if name == "simplified_error":
        return _simplified_errors(result, checks, limit, source)
    return [Outcome(result, name, _value(result, name), limit, unit_of(name), source=source)]


def _simplified_errors(result: AnalysisResult, checks: Sequence, limit: float, source: str) -> list[Outcome]:
    """simplified_error applied to each accuracy check of a simplified result."""
    return [replace(_simplified_error(result, check, limit), source=source) for check in _checks_of(result, checks)]


def _checks_of(result: AnalysisResult, checks: Sequence) -> list:
    """The accuracy checks of a simplified result (those of its support)."""
    if result.engine != "simplified":
        return []
    return [check for check in checks if check.support == result.support]


def _value(result: AnalysisResult, name: str) -> float:
    """The value a limit bounds: a rocking quantity's (quantities.rocking_value: a settlement's
    largest downward value), else the largest |value|."""
    return rocking_value(result, name) if name in ROCKING else abs(result.value(name))


def _simplified_error(result: AnalysisResult, check, limit: float) -> Outcome:
    """The largest relative error (max(ratio, 1/ratio) - 1) of the ratios the check flags against the
    limit (0 when it flags none): the check's bands follow the limit (accuracy.deck_bands), so the
    criterion fails exactly when a ratio is flagged."""
    worst = max(check.out_of_band, key=lambda c: c.error, default=None)
    error, detail = (0.0, "") if worst is None else (worst.error, worst.describe())
    if check.error is not None:
        error, detail = float("inf"), f"the {check.reference} could not run: {check.error}"
    return Outcome(result, "simplified_error", error, limit, "-", detail)


def check_criteria(results: Sequence[AnalysisResult], criteria: Mapping, checks: Sequence = ()) -> list[str]:
    """One message per violated acceptance criterion; empty when all pass (checks: the accuracy
    checks of accuracy.check_accuracy, for simplified_error); then each violation of the global
    acceptance of ASCE 7-22 16.4.1 a suite's result carries (analysis/acceptance.py)."""
    return [*(outcome.message() for outcome in outcomes(results, criteria, checks) if not outcome.ok),
            *(line for result in results for line in _acceptance_violations(result))]


def _acceptance_violations(result: AnalysisResult) -> list[str]:
    """The violations of ASCE 7-22 16.4.1 of a suite's result that carries its acceptance, else none."""
    found = getattr(result, "acceptance", None)
    return [] if found is None else found.violations(_label(result))
