"""The global acceptance of a nonlinear response history analysis, ASCE 7-22 16.4.1 (issue 35, item 4;
docs/theory.md section 16.5): a suite deck whose stories have strengths, analysed by the exact engine.

- 16.4.1.1 (unacceptable response): for Risk Category I and II structures an unacceptable response
  is permitted under at most one of the (at least 11) ground motions, for III and IV under none
  (PERMITTED_UNACCEPTABLE, as we read the clause). What the model can tell of the clause's list: a
  record under which the mat flew (both edges off the foundation, ROCKING flight_time > 0), which
  leaves the valid range of the model (no sliding, no impact losses: docs/exact-engine.md). A record
  on which the exact engine fails stops the run (exit code 4); it is not counted here.
- 16.4.1.2 (story drift): in each story, the mean over the ground motions of the peak story drift
  ratio shall not exceed 2.0 x the allowable story drift ratio of Table 12.12-1 (model/design.py), as
  we read the clause.

The residual drift ratios (mean and largest over the records, per story) are reported beside it;
the clause sets no limit on them. Pure functions of plain values, and suite_acceptance that reads
them from a deck and its SuiteResult. Knows nothing of the terminal or files.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

CLAUSE = "ASCE 7-22 16.4.1"
CLAUSE_UNACCEPTABLE = "ASCE 7-22 16.4.1.1"
CLAUSE_DRIFT = "ASCE 7-22 16.4.1.2"
#: the mean peak story drift ratio's limit over the allowable story drift of Table 12.12-1 (16.4.1.2)
DRIFT_FACTOR = 2.0
#: unacceptable responses permitted (among at least 11 ground motions) by risk category (16.4.1.1)
PERMITTED_UNACCEPTABLE = {"I": 1, "II": 1, "III": 0, "IV": 0}


def permitted_unacceptable(risk_category: str) -> int:
    """The number of ground motions allowed an unacceptable response (16.4.1.1)."""
    if risk_category not in PERMITTED_UNACCEPTABLE:
        raise ValueError(f"risk category {risk_category!r}: one of {', '.join(PERMITTED_UNACCEPTABLE)}")
    return PERMITTED_UNACCEPTABLE[risk_category]


def drift_limit(allowable: float | None) -> float | None:
    """The limit of 16.4.1.2 on the mean peak story drift ratio: 2.0 x Table 12.12-1's (None: no limit)."""
    return None if allowable is None else DRIFT_FACTOR * allowable


def _per_record(values, name: str) -> np.ndarray:
    """A (records, stories) array of non-negative ratios, or a ValueError naming `name`."""
    array = np.abs(np.asarray(values, dtype=float))
    if array.ndim != 2 or array.shape[0] == 0 or not np.all(np.isfinite(array)):
        raise ValueError(f"{name}: one row of finite story values per record is needed")
    return array


@dataclass(frozen=True)
class Acceptance:
    """The global acceptance of ASCE 7-22 16.4.1 of one suite: the records, the reasons of those
    with an unacceptable response (name -> reason), how many are permitted, the mean peak story drift
    ratio of each story against the limit (None: no limit), and the residual drift ratios (mean and
    largest over the records, per story) reported beside it."""

    risk_category: str
    records: tuple[str, ...]
    unacceptable: dict[str, str]
    permitted: int
    mean_drift_ratio: tuple[float, ...]
    limit: float | None
    residual_mean: tuple[float, ...]
    residual_max: tuple[float, ...]

    @property
    def unacceptable_ok(self) -> bool:
        """16.4.1.1: no more unacceptable responses than permitted."""
        return len(self.unacceptable) <= self.permitted

    @property
    def exceeding_stories(self) -> list[int]:
        """The stories (1-based) whose mean peak drift ratio exceeds the limit of 16.4.1.2."""
        if self.limit is None:
            return []
        return [j + 1 for j, value in enumerate(self.mean_drift_ratio) if value > self.limit]

    @property
    def accepted(self) -> bool:
        """Both parts of 16.4.1 met."""
        return self.unacceptable_ok and not self.exceeding_stories

    def violations(self, label: str = "") -> list[str]:
        """One line per part of 16.4.1 not met (empty when accepted), after `label`."""
        head = f"{label}: " if label else ""
        lines = []
        if not self.unacceptable_ok:
            lines.append(f"{head}{len(self.unacceptable)} of {len(self.records)} ground motions gave an unacceptable "
                         f"response ({', '.join(self.unacceptable)}), {self.permitted} permitted for Risk Category "
                         f"{self.risk_category} ({CLAUSE_UNACCEPTABLE})")
        for story in self.exceeding_stories:
            lines.append(f"{head}story {story}: the mean peak drift ratio {self.mean_drift_ratio[story - 1]:.4g} "
                         f"exceeds {DRIFT_FACTOR:g} x the Table 12.12-1 limit = {self.limit:.4g} ({CLAUSE_DRIFT})")
        return lines

    def to_dict(self) -> dict[str, Any]:
        """The acceptance as plain JSON-ready values."""
        return {"clause": CLAUSE, "accepted": self.accepted, "risk_category": self.risk_category,
                "records": len(self.records), "unacceptable": dict(self.unacceptable),
                "permitted_unacceptable": self.permitted, "unacceptable_ok": self.unacceptable_ok,
                "drift_limit": self.limit, "drift_factor": DRIFT_FACTOR,
                "mean_drift_ratio": list(self.mean_drift_ratio), "exceeding_stories": self.exceeding_stories,
                "residual_drift_ratio_mean": list(self.residual_mean),
                "residual_drift_ratio_max": list(self.residual_max)}


def acceptance(records: Sequence[str], peak_drift_ratios, residual_drift_ratios, reasons: Sequence[str | None],
               risk_category: str, allowable: float | None) -> Acceptance:
    """The acceptance of 16.4.1 from plain values: the records' names, their peak and residual story
    drift ratios (rows: records, columns: stories), the reason of each record's unacceptable response
    (None: acceptable), the risk category and the allowable story drift ratio of Table 12.12-1."""
    peaks = _per_record(peak_drift_ratios, "peak story drift ratios")
    residuals = _per_record(residual_drift_ratios, "residual story drift ratios")
    if not (len(records) == len(reasons) == peaks.shape[0] and residuals.shape == peaks.shape):
        raise ValueError("one name, one reason and one row of peak and residual drift ratios per record are needed")
    unacceptable = {name: reason for name, reason in zip(records, reasons, strict=True) if reason}
    return Acceptance(risk_category, tuple(records), unacceptable, permitted_unacceptable(risk_category),
                      tuple(peaks.mean(axis=0).tolist()), drift_limit(allowable),
                      tuple(residuals.mean(axis=0).tolist()), tuple(residuals.max(axis=0).tolist()))


def flight_reason(result: Any) -> str | None:
    """Why a record's exact result is an unacceptable response (16.4.1.1), or None: the mat flew."""
    flight = result.details.get("uplift_summary", {}).get("flight_time", 0.0)
    if flight > 0.0:
        return f"the mat flew for {flight:.3g} s (both edges off the foundation): outside the model's valid range"
    return None


def applies(deck: Any, result: Any) -> bool:
    """Whether 16.4.1 is judged: the exact engine on a suite, a [design] table and stories with a strength."""
    return (getattr(result, "record_results", ()) != () and result.engine == "exact"
            and getattr(deck, "design", None) is not None and deck.system.building.yields)


def record_values(result: Any) -> tuple[list[str], list, list, list[str | None]]:
    """The names, peak and residual story drift ratios and unacceptable responses of a suite's records."""
    records = result.record_results
    return ([record.name for record in result.records], [r.peaks["drift_ratio"] for r in records],
            [r.peaks["residual_drift_ratio"] for r in records], [flight_reason(r) for r in records])


def suite_acceptance(deck: Any, result: Any) -> Acceptance | None:
    """The acceptance of a deck's SuiteResult (None where it does not apply: `applies`)."""
    if not applies(deck, result):
        return None
    design = deck.design
    return acceptance(*record_values(result), design.risk_category,
                      design.allowable_drift_ratio(deck.system.building.n_stories))


def acceptance_violations(results: Sequence[Any]) -> list[str]:
    """The violations of 16.4.1 of every result that carries an acceptance (a SuiteResult's `acceptance`)."""
    return [line for r in results if getattr(r, "acceptance", None) is not None
            for line in r.acceptance.violations(f"{r.engine}/{r.support}")]
