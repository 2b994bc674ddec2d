"""The report's section on the global acceptance of ASCE 7-22 16.4.1 (analysis/acceptance.py): per
suite result that carries it, the mean peak story drift ratios against the limit of 16.4.1.2 with the
residual drift ratios beside them, the unacceptable responses of 16.4.1.1, and its part in the
verdict and the exit code (3 when it is not met)."""

from __future__ import annotations

from collections.abc import Sequence

from ..analysis.acceptance import CLAUSE, CLAUSE_DRIFT, CLAUSE_UNACCEPTABLE, DRIFT_FACTOR
from ..engines.result import AnalysisResult
from .checks import EXIT_CRITERIA
from .document import Section, Table, Text

HEADERS = ["story", "mean peak drift ratio [%]", "limit [%]", "verdict", "residual drift ratio, mean [%]",
           "residual drift ratio, max [%]"]


def _judged(results: Sequence[AnalysisResult]) -> list[AnalysisResult]:
    """The results that carry an acceptance (a suite's result under the exact engine, with a [design] table)."""
    return [r for r in results if getattr(r, "acceptance", None) is not None]


def _percent(value: float | None) -> str:
    return "-" if value is None else f"{100.0 * value:.3g}"


def _rows(found) -> list[list[str]]:
    """One row per story: number, mean peak drift ratio, limit, verdict, residual drift ratios (mean, max)."""
    exceeding = set(found.exceeding_stories)
    return [[str(j + 1), _percent(mean), _percent(found.limit), "exceeds" if j + 1 in exceeding else "ok",
             _percent(found.residual_mean[j]), _percent(found.residual_max[j])]
            for j, mean in enumerate(found.mean_drift_ratio)]


def _table(result: AnalysisResult) -> Table:
    """The table of one result's acceptance, its unacceptable responses in the note."""
    found = result.acceptance
    names = f" ({', '.join(f'{k}: {v}' for k, v in found.unacceptable.items())})" if found.unacceptable else ""
    note = (f"Unacceptable responses ({CLAUSE_UNACCEPTABLE}): {len(found.unacceptable)} of {len(found.records)} "
            f"ground motions{names}, {found.permitted} permitted for Risk Category {found.risk_category}. Limit "
            f"({CLAUSE_DRIFT}): {DRIFT_FACTOR:g} x the allowable story drift ratio of Table 12.12-1 on the mean over "
            "the records of each story's peak drift ratio (docs/theory.md 16.5). The residual drift ratios have no "
            "limit there.")
    verdict = "accepted" if found.accepted else "not accepted"
    return Table(f"table-acceptance-{result.support}", f"Global acceptance of {CLAUSE}, {result.engine} engine, "
                 f"{result.support} support: {verdict}", HEADERS, _rows(found), note)


def acceptance_section(results: Sequence[AnalysisResult]) -> Section | None:
    """The section (None when no result carries an acceptance)."""
    judged = _judged(results)
    if not judged:
        return None
    return Section("acceptance", f"Nonlinear response history: global acceptance ({CLAUSE})",
                   [Text([acceptance_verdict(judged)]), *(_table(r) for r in judged)])


def acceptance_verdict(results: Sequence[AnalysisResult]) -> str:
    """One sentence: whether every result that carries an acceptance meets it ('' when none does)."""
    judged = _judged(results)
    if not judged:
        return ""
    failed = [f"{r.engine}/{r.support}" for r in judged if not r.acceptance.accepted]
    if failed:
        return (f"The global acceptance of {CLAUSE} is not met ({', '.join(failed)}): `uplift analyze` exits with "
                f"code {EXIT_CRITERIA}.")
    return f"The global acceptance of {CLAUSE} is met on every support analysed."


def with_acceptance(results: Sequence[AnalysisResult], verdict: str, code: int) -> tuple[str, int]:
    """The report's verdict and exit code with the acceptance's: its sentence after the verdict, 3 when not met."""
    sentence = acceptance_verdict(results)
    failed = any(not r.acceptance.accepted for r in _judged(results))
    return (f"{verdict} {sentence}".strip(), EXIT_CRITERIA if failed else code)
