"""The terminal table of the global acceptance of ASCE 7-22 16.4.1 of a suite's result
(analysis/acceptance.py): per story the mean peak drift ratio against the limit of 16.4.1.2, the
residual drift ratios beside it, and the unacceptable responses of 16.4.1.1 in the caption."""

from __future__ import annotations

from rich.markup import escape
from rich.table import Table

from ..analysis.acceptance import CLAUSE, CLAUSE_DRIFT, CLAUSE_UNACCEPTABLE, DRIFT_FACTOR, Acceptance
from ..engines.result import AnalysisResult
from .tables import add_columns, add_rows

HEADINGS = ("story", "mean peak drift ratio", "limit", "verdict", "residual drift ratio: mean", "max")


def _percent(value: float | None) -> str:
    """A ratio in %, '-' for none."""
    return "-" if value is None else f"{100.0 * value:.3g} %"


def _rows(found: Acceptance) -> list[tuple[str, ...]]:
    """One row per story: its number, mean peak drift ratio, the limit, the verdict, the residuals."""
    exceeding = set(found.exceeding_stories)
    return [(str(j + 1), _percent(mean), _percent(found.limit), "exceeds" if j + 1 in exceeding else "ok",
             _percent(found.residual_mean[j]), _percent(found.residual_max[j]))
            for j, mean in enumerate(found.mean_drift_ratio)]


def _caption(found: Acceptance) -> str:
    """The unacceptable responses (16.4.1.1), the limit's origin (16.4.1.2) and the residuals' status."""
    names = f" ({', '.join(found.unacceptable)})" if found.unacceptable else ""
    return (f"unacceptable responses: {len(found.unacceptable)} of {len(found.records)} ground motions{names}, "
            f"{found.permitted} permitted for Risk Category {found.risk_category} ({CLAUSE_UNACCEPTABLE}); limit: "
            f"{DRIFT_FACTOR:g} x the allowable story drift ratio of Table 12.12-1 on the mean over the records of each "
            f"story's peak drift ratio ({CLAUSE_DRIFT}, as read in docs/theory.md 16.5); the residual drift ratios "
            "have no limit there and are shown beside it")


def acceptance_table(result: AnalysisResult) -> Table | None:
    """The acceptance of a suite's result that carries one, else None."""
    found = getattr(result, "acceptance", None)
    if found is None:
        return None
    verdict = "accepted" if found.accepted else "NOT accepted"
    table = Table(title=escape(f"{result.engine} engine, {result.support} support: global acceptance of {CLAUSE} "
                               f"(Risk Category {found.risk_category}): {verdict}"))
    add_columns(table, list(HEADINGS), left=("story",))
    add_rows(table, _rows(found))
    table.caption = escape(_caption(found))
    return table
