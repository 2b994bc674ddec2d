"""The deck's acceptance criteria ([criteria]) applied to results: one home for the tests that
`uplift analyze` turns into its exit code, a sweep into its `violations` column and the report
into its criteria table.

A criterion is a limit on the largest |value| of a response quantity or a scalar
(engines/quantities.py), `uplift = false`, or `simplified_error = e`: every ratio simplified /
exact of the accuracy check (accuracy.py) within [1/(1 + e), 1 + e] (applied to the checks given;
none without a record or with --no-check). On a suite (SuiteResult) the limits apply to the
design statistic (the mean, or EC8's maximum below 7 records) and uplift = false to every record.
A limit on a rocking quantity (quantities.ROCKING: rotation, residual rotation, settlement; the
values of ASCE 41-17 section 8.4 for the chosen performance level, given by the user) applies to
the results that report it: the exact engine's uplift analyses of a foundation with a bearing
capacity (the deck asks for one: deck.py).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from .engines.quantities import ROCKING, unit_of
from .engines.result import AnalysisResult
from .engines.suite_result import SuiteResult


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

    @property
    def ok(self) -> bool:
        if self.name == "uplift":
            return bool(self.limit) or not self.value
        return self.value <= self.limit

    def message(self) -> str:
        """The one line that reports a violation."""
        result = self.result
        label = f"{result.engine}/{result.support}"
        if isinstance(result, SuiteResult):
            label += f" ({result.statistic} of {result.count} records)"
        if self.name == "uplift":
            under = f" under {result.uplift_count} records" if isinstance(result, SuiteResult) else ""
            return f"{label}: the mat lifts off{under} (criteria.uplift = false)"
        detail = f" ({self.detail})" if self.detail else ""
        return f"{label}: {self.name} = {self.value:.4g} exceeds the limit {self.limit:.4g} [{self.unit}]{detail}"


def outcomes(results: Sequence[AnalysisResult], criteria: Mapping, checks: Sequence = ()) -> list[Outcome]:
    """Every criterion applied to every result, in the order of the results, then the criteria;
    simplified_error applied to each accuracy check (accuracy.Check) of a simplified result."""
    found = []
    for result in results:
        for name, limit in criteria.items():
            if name == "uplift":
                found.append(Outcome(result, name, bool(result.uplift), bool(limit), "-"))
            elif name in ROCKING and name not in result.peaks:
                continue  # not reported by this engine or support (the deck has the one that reports it)
            elif name == "simplified_error":
                found += [_simplified_error(result, check, limit) for check in checks
                          if result.engine == "simplified" and check.support == result.support]
            else:
                found.append(Outcome(result, name, abs(result.value(name)), limit, unit_of(name)))
    return found


def _simplified_error(result: AnalysisResult, check, limit: float) -> Outcome:
    """The largest relative error of a check (max(ratio, 1/ratio) - 1) against the limit."""
    error, worst = check.largest_error()
    detail = "" if worst is None else worst.describe()
    if check.error is not None:
        error, detail = float("inf"), f"the {check.reference} could not run: {check.error}"
    return Outcome(result, "simplified_error", error, limit, "-", detail)


def check_criteria(results: Sequence[AnalysisResult], criteria: Mapping, checks: Sequence = ()) -> list[str]:
    """One message per violated acceptance criterion; empty when all pass (checks: the accuracy
    checks of accuracy.check_accuracy, for simplified_error)."""
    return [outcome.message() for outcome in outcomes(results, criteria, checks) if not outcome.ok]
