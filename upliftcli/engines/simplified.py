"""Simplified engine: response spectrum analysis with interaction and uplift in mode 1.

docs/theory.md section 7 (paper Eqs. 21-35). The engine chooses the procedure
(options.procedure): the improved one (engines/improved.py) for the uplift support, else the
paper's (engines/paper.py); then it adds the plausibility warnings (engines/plausibility.py).
Every intermediate an engineer checks by hand is returned in result.intermediates
(names and units: engines/quantities.INTERMEDIATES).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace

from ..errors import AnalysisError, InputError
from ..model.interaction import effective_properties
from ..model.system import System
from . import improved, plausibility
from .options import SimplifiedOptions
from .paper import paper_analyze
from .registry import check_support
from .result import AnalysisResult

#: effective_properties is read from here by the deck and the sweeps (T1bar, xi1bar of the engine)
__all__ = ["analyze", "effective_properties", "iter_batch", "paper_analyze"]


def analyze(system: System, spectrum, support: str, options: SimplifiedOptions = SimplifiedOptions()) -> AnalysisResult:
    """Peak response by the simplified procedure (options.procedure: "improved", engines/improved.py,
    or "paper") for support "rigid", "bonded" or "uplift", with the warnings of
    engines/plausibility.py in result.details["warnings"]. A building whose stories yield is refused
    (InputError naming building.story_strengths: docs/theory.md 15.6)."""
    check_support(support)
    if system.building.yields:
        raise InputError("building", "story_strengths", "the simplified engine does not model yielding stories "
                         "(docs/theory.md 15.6): use analysis.engine = \"exact\", or remove the story strengths")
    if support == "uplift" and options.procedure == "improved":
        result = improved.analyze_uplift(system, spectrum, options)
    else:
        result = paper_analyze(system, spectrum, support, options)
    found = plausibility.warnings(system, spectrum, support, options, result)
    return replace(result, details={**result.details, "warnings": [*result.details["warnings"], *found]})


def iter_batch(systems: list[System], spectrum, support: str, options: SimplifiedOptions = SimplifiedOptions()
               ) -> Iterator[tuple[int, AnalysisResult | AnalysisError | InputError]]:
    """analyze for each system (engines/registry.py: the engines' common interface)."""
    for k, system in enumerate(systems):
        try:
            yield k, analyze(system, spectrum, support, options)
        except (AnalysisError, InputError) as error:
            yield k, error
