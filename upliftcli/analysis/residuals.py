"""The stability check of the residuals (issue 35; docs/theory.md 15.8).

Residual drifts of yielding stories and the residual rotation and settlement of a mat on yielding soil
are the end of a path: a tiny change of the input can send the last yield excursion the other way. An
exact run of such a deck is rerun with the record scaled by 1 + PERTURBATION (a change far below any
uncertainty of a ground motion), and a residual that differs by more than TOLERANCE between the two
runs is named in a warning; the result keeps the twin's values in details["residual_check"].

Only runs that leave residuals get a twin: exact runs whose stories or soil yielded (an elastic run
returns to rest, its results are not touched). `analysis.exact.residual_check` chooses where: "auto"
(default) in a single analysis (`uplift analyze`, `uplift report`, the API's run and run_one: each
record of a suite), "on" also in the batches of a sweep, "off" never.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from ..deck.load import Deck
from ..engines.exact.reuse import yielded
from ..engines.quantities import MAT_PLACES
from ..engines.result import AnalysisResult
from ..engines.suite_result import SuiteResult
from ..motion.records import is_suite

#: the twin's record is the record times 1 + PERTURBATION
PERTURBATION = 1e-6
_PERTURBED = "1e-6"  # as the warnings write it
#: a residual that differs by more than this fraction of the larger of the two is sensitive
TOLERANCE = 0.2
#: below these (both runs), a residual is too small to matter to a design, and no warning is given
#: (docs/theory.md 15.8): a tenth of FEMA P-58's smallest residual drift damage state (0.2 %), a tenth
#: of the tilt occupants notice (3/1000 rad), a tenth of the 25 mm settlement shallow foundations
#: are commonly allowed
FLOORS = {"residual_drift_ratio": 2e-4, "residual_rotation": 3e-4, "residual_settlement": 2.5e-3}
#: how a warning names each residual, the unit it is shown in and the factor from SI
SHOWN = {"residual_drift_ratio": ("residual drift ratio", "%", 100.0),
         "residual_rotation": ("residual mat rotation", "mrad", 1e3),
         "residual_settlement": ("residual settlement", "mm", 1e3)}

Rerun = Callable[[list[Deck]], Sequence[Any]]


def wanted(deck: Deck, single: bool) -> bool:
    """Whether the deck's analyses get the check: analysis.exact.residual_check "on", or "auto" in a
    single analysis (not a sweep's batch)."""
    mode = deck.analysis.exact.residual_check
    return mode == "on" or (mode == "auto" and single)


def asked(engine: str, decks: Sequence[Deck], single: bool) -> bool:
    """Whether some of the decks' analyses by `engine` may get the check (the exact engine's only)."""
    return engine == "exact" and any(wanted(deck, single) for deck in decks)


def _yielded(result: AnalysisResult) -> bool:
    """Whether an exact run's stories or soil yielded."""
    return result.engine == "exact" and yielded(result)


def leaves_residuals(result: Any) -> bool:
    """Whether an exact run's stories or soil yielded (a suite: on some record)."""
    if isinstance(result, SuiteResult):
        return any(_yielded(r) for r in result.record_results)
    return isinstance(result, AnalysisResult) and _yielded(result)


def perturbed_motion(motion: Any) -> Any:
    """The record times 1 + PERTURBATION (a suite: every factor)."""
    if is_suite(motion):
        return replace(motion, factors=tuple(f * (1.0 + PERTURBATION) for f in motion.factors))
    return replace(motion, acceleration=motion.acceleration * (1.0 + PERTURBATION),
                   scale=motion.scale * (1.0 + PERTURBATION))


def _without_histories(deck: Deck) -> Any:
    """The deck's analysis settings with the histories not kept (a twin's residuals need none)."""
    if not deck.analysis.exact.histories:
        return deck.analysis
    return replace(deck.analysis, exact=replace(deck.analysis.exact, histories=False))


def twin_decks(decks: Sequence[Deck]) -> list[Deck]:
    """The decks with their motions perturbed, one perturbed motion per motion (decks that shared a
    motion share its twin, and run in one batch as they did), and no histories kept."""
    motions: dict[int, Any] = {}
    for deck in decks:
        motions.setdefault(id(deck.ground_motion), perturbed_motion(deck.ground_motion))
    return [replace(deck, ground_motion=motions[id(deck.ground_motion)], analysis=_without_histories(deck))
            for deck in decks]


def checked(decks: Sequence[Deck], results: list[Any], rerun: Rerun, single: bool) -> list[Any]:
    """The results, those that left residuals (and whose deck wants the check) compared with their
    twins (rerun: the same analysis of other decks, without the check)."""
    chosen = _to_check(decks, results, single)
    if not chosen:
        return results
    twins = rerun(twin_decks([decks[k] for k in chosen]))
    out = list(results)
    for k, twin in zip(chosen, twins, strict=True):
        out[k] = with_check(results[k], twin)
    return out


def _to_check(decks: Sequence[Deck], results: list[Any], single: bool) -> list[int]:
    """The indices of the results that left residuals and whose deck wants the check."""
    return [k for k, (deck, result) in enumerate(zip(decks, results, strict=True))
            if wanted(deck, single) and leaves_residuals(result)]


def compare(result: AnalysisResult, twin: AnalysisResult) -> dict[str, dict[str, list]]:
    """Per residual of FLOORS in the result: its values, the twin's, their relative difference
    |a - b| / max(|a|, |b|) and whether each is sensitive (above TOLERANCE, and above the floor)."""
    out = {}
    for name, floor in FLOORS.items():
        if name not in result.peaks or name not in twin.peaks:
            continue
        a, b = np.abs(result.peaks[name]), np.abs(twin.peaks[name])
        larger = np.maximum(a, b)
        difference = np.abs(a - b) / np.where(larger > 0.0, larger, 1.0)
        out[name] = {"values": a.tolist(), "twin": b.tolist(), "difference": difference.tolist(),
                     "sensitive": ((difference > TOLERANCE) & (larger >= floor)).tolist()}
    return out


def _place(name: str, index: int, count: int) -> str:
    """Which story or point of the mat value `index` of residual `name` is."""
    if name == "residual_drift_ratio":
        return f" of story {index + 1}" + (f" (and {count - 1} more)" if count > 1 else "")
    if name == "residual_settlement":
        return f" of the {MAT_PLACES[index][1]}"
    return ""


def warning(name: str, entry: dict[str, list]) -> str | None:
    """One line for a sensitive residual (the component that changed most), None if none is."""
    sensitive = np.asarray(entry["sensitive"], dtype=bool)
    if not sensitive.any():
        return None
    difference = np.where(sensitive, entry["difference"], -1.0)
    i = int(np.argmax(difference))
    label, unit, factor = SHOWN[name]
    return (f"{label}{_place(name, i, int(sensitive.sum()))} is sensitive to the record: "
            f"{entry['values'][i] * factor:.3g} {unit}, and {entry['twin'][i] * factor:.3g} {unit} with the record "
            f"scaled by 1 + {_PERTURBED} (they differ by {difference[i]:.0%}; docs/theory.md 15.8)")


def _record_check(result: AnalysisResult, twin: Any) -> tuple[dict, list[str]]:
    """The check of one run and its warnings."""
    if not isinstance(twin, AnalysisResult):
        return {"twin_error": str(twin), "sensitive": False}, \
            [f"the residuals were not checked: the perturbed twin failed ({twin})"]
    quantities = compare(result, twin)
    lines = [line for name, entry in quantities.items() if (line := warning(name, entry))]
    return {"sensitive": bool(lines), "quantities": quantities}, lines


def _record_twins(result: SuiteResult, twin: Any) -> tuple:
    """Each record's twin result (the twin suite's record_results: analysis/suite.RecordTwins; the twin's
    error for every record if the twin suite failed)."""
    return (twin,) * result.count if isinstance(twin, Exception) else twin.record_results


def _suite_check(result: SuiteResult, twin: Any) -> tuple[dict, list[str]]:
    """The check of every record of a suite that left residuals, each warning naming its record."""
    records, lines = [], []
    for named, own, other in zip(result.records, result.record_results, _record_twins(result, twin), strict=True):
        if not leaves_residuals(own):
            continue
        entry, warned = _record_check(own, other)
        records.append({"record": named.name, **entry})
        lines += [f"record {named.name}: {line}" for line in warned]
    return {"sensitive": any(r["sensitive"] for r in records), "records": records}, lines


def with_check(result: AnalysisResult, twin: Any) -> AnalysisResult:
    """The result with details["residual_check"] (the perturbation, the tolerance, the floors, whether a
    residual is sensitive, and each residual with the twin's) and a warning per sensitive residual."""
    check = _suite_check if isinstance(result, SuiteResult) else _record_check
    entry, lines = check(result, twin)
    details = {**result.details, "residual_check": {"perturbation": PERTURBATION, "tolerance": TOLERANCE,
                                                     "floors": dict(FLOORS), **entry},
               "warnings": [*result.details.get("warnings", []), *lines]}
    return replace(result, details=details)
