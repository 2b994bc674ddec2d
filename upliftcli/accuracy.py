"""The simplified engine checked against the exact engine on the same deck.

When the deck has a record, every simplified result gets the exact engine's values of the
same support (already run, or run here: about 10 ms each) and the ratio simplified / exact
for the quantities a designer takes away (docs/accuracy.md gives the measured spread of
those ratios). The check lives in result.details["accuracy"]; `uplift analyze --no-check`
skips it. A suite deck has its own comparison (the simplified engine on the target spectrum
beside the suite statistic, engines/suite_result.py); a design-spectrum deck has no record
to check against.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from .deck import Deck
from .engines.quantities import unit_of
from .engines.result import AnalysisResult
from .errors import AnalysisError, InputError
from .motion.records import Record

#: the quantities compared: name -> (unit, meaning, value of a result); the units are those of
#: the quantities table (engines/quantities.py)
CHECKED: dict[str, tuple[str, str, Callable[[AnalysisResult], float]]] = {
    "base_shear": (unit_of("base_shear"), "base shear V_b", lambda r: r.base_shear),
    "base_moment": (unit_of("base_moment"), "base overturning moment M_b", lambda r: r.base_moment),
    "max_drift_ratio": (unit_of("drift_ratio"), "largest story drift ratio", lambda r: r.value("drift_ratio")),
    "roof_displacement": (unit_of("displacement"), "roof displacement relative to the mat",
                          lambda r: float(abs(r.peaks["displacement"][-1]))),
}


def accuracy(simplified: AnalysisResult, exact: AnalysisResult | Exception) -> dict:
    """{reference, support, simplified, exact, ratio} (SI values; ratio = simplified / exact),
    or {reference, support, error} when the exact engine could not run."""
    head = {"reference": "exact", "support": simplified.support}
    if isinstance(exact, Exception):
        return {**head, "error": str(exact)}
    values = {name: value(simplified) for name, (_, _, value) in CHECKED.items()}
    reference = {name: value(exact) for name, (_, _, value) in CHECKED.items()}
    ratio = {name: values[name] / reference[name] if reference[name] else None for name in CHECKED}
    return {**head, "simplified": values, "exact": reference, "ratio": ratio}


def check_accuracy(deck: Deck, results: Sequence[AnalysisResult]) -> None:
    """Attach details["accuracy"] to each simplified result of a deck with a record, running the
    exact engine for the supports it has not run (its results are reused otherwise)."""
    if not isinstance(deck.ground_motion, Record):
        return
    from .analysis import run_one  # analysis imports nothing of this module

    exact = {r.support: r for r in results if r.engine == "exact"}
    for result in results:
        if result.engine != "simplified":
            continue
        if result.support not in exact:
            try:
                exact[result.support] = run_one(deck, "exact", result.support)
            except (AnalysisError, InputError) as error:
                exact[result.support] = error
        result.details["accuracy"] = accuracy(result, exact[result.support])
