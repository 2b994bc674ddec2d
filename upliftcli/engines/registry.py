"""The engines and support conditions by name: the one place that knows them.

An engine module is imported the first time it is used, so that naming the engines (the
deck schema, `--help`) costs nothing and a command that runs only the simplified engine
never imports the exact engine.

Every engine module has `iter_batch(systems, ground_motion, support, options)`, which
yields (index, result or the InputError/AnalysisError that stopped it) as each system's
analysis ends; systems of one batch share the ground motion and the options.
"""

from __future__ import annotations

import importlib
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import AnalysisError, InputError
from .result import AnalysisResult

#: support conditions compared throughout the paper (docs/theory.md, support conditions)
SUPPORTS = ("rigid", "bonded", "uplift")
SUPPORT_LABELS = {"rigid": "rigid support", "bonded": "flexible support, bonded mat",
                  "uplift": "flexible support, uplift permitted"}


@dataclass(frozen=True)
class Engine:
    """name; label: what it computes, in words; needs_record: whether it needs a record (a
    response-history engine) or takes any spectrum (.sa); options: the attribute of the
    deck's AnalysisSettings holding its options; module: where its iter_batch lives."""

    name: str
    label: str
    needs_record: bool
    options: str
    module: str

    def iter_batch(self, systems: Sequence[Any], ground_motion: Any, support: str, options: Any,
                   operators: Any = None) -> Iterator[tuple[int, AnalysisResult | InputError | AnalysisError]]:
        """Analyse several systems under one ground motion and support (see the module docstring);
        a system this engine cannot analyse on yielding soil (capacity_refusal) gets an InputError.
        operators: the exact engine's store of step operators for a check of the residuals
        (exact/reuse.py), passed on when given."""
        module = importlib.import_module(self.module, __package__)
        systems = list(systems)
        kept = []
        for k, system in enumerate(systems):
            refusal = capacity_refusal(self.name, system, support)
            strength = strength_refusal(self.name, system, support)
            if refusal is None and strength is None:
                kept.append(k)
            elif refusal is not None:
                yield k, InputError("foundation", "elements", refusal)
            else:
                yield k, InputError(*strength)
        extra = {} if operators is None else {"operators": operators}
        for j, result in module.iter_batch([systems[k] for k in kept], ground_motion, support, options, **extra):
            yield kept[j], result

    def analyze(self, system: Any, ground_motion: Any, support: str, options: Any) -> AnalysisResult:
        """One analysis; raises the error that stopped it."""
        ((_, result),) = tuple(self.iter_batch([system], ground_motion, support, options))
        if not isinstance(result, AnalysisResult):
            raise result
        return result


ENGINES: dict[str, Engine] = {
    "simplified": Engine("simplified", "simplified (response spectrum, Eqs. 21-35)", False, "simplified",
                         ".simplified"),
    "approximate": Engine("approximate", "approximate (mode 1 coupled, Eq. 17)", True, "exact", ".approximate"),
    "exact": Engine("exact", "exact (Eq. 11, all modes coupled)", True, "exact", ".exact"),
}


def capacity_refusal(name: str, system: Any, support: str) -> str | None:
    """Why the engine `name` cannot analyse `system` with `support` on yielding soil, in words
    (what is expected); None when it can. Every engine models a bearing capacity (docs/theory.md
    section 14); the history engines (exact, approximate) step a contact pattern of two bits per
    element with a capacity, so they take at most limits.MAX_YIELDING_ELEMENTS of them in an
    uplift analysis (14.3: too_many_yielding). The simplified engine (the closed-form M_c of 14.4)
    and the rigid and bonded supports (linear references, built without the capacity) have no such
    bound. The one rule: the deck, the analysis and Engine.iter_batch ask it."""
    from ..runtime.limits import MAX_YIELDING_ELEMENTS

    if name == "simplified" or support != "uplift" or getattr(system.foundation, "capacity", None) is None:
        return None
    count = int(getattr(system.foundation, "elements", 2))
    if not too_many_yielding(count):
        return None
    return (f"at most {MAX_YIELDING_ELEMENTS} contact elements with a bearing capacity for the {name} engine's "
            f"uplift analysis (two bits each of its contact pattern, docs/theory.md 14.3), got {count}: lower "
            "foundation.elements (the simplified engine alone has no such bound)")


def strength_refusal(name: str, system: Any, support: str) -> tuple[str, str, str] | None:
    """Why the engine `name` cannot analyse a building whose stories yield (docs/theory.md 15.6), as
    (table, field, what is expected); None when it can (or the building is elastic). Only the exact engine models
    yielding stories; its contact pattern holds two bits per yielding story beside the foundation's
    (limits.MAX_PATTERN_BITS). (table, field, what is expected)."""
    from ..runtime.limits import MAX_PATTERN_BITS, too_many_bits

    building = system.building
    if not building.yields:
        return None
    if name != "exact":
        return ("building", "story_strengths", f"the {name} engine does not model yielding stories (docs/theory.md "
                "15.6): use analysis.engine = \"exact\", or remove the story strengths")
    stories = int(np.count_nonzero(np.isfinite(building.story_strength)))
    elements = _element_bits(system, support)
    if elements + 2 * stories <= MAX_PATTERN_BITS:
        return None
    message = too_many_bits(elements, stories)
    if 2 * stories > MAX_PATTERN_BITS:
        return "building", "story_strengths", message
    return "foundation", "elements", message


def _element_bits(system: Any, support: str) -> int:
    """Bits of the foundation in the exact engine's contact pattern: none on a rigid base, one per contact
    element, two per element with a bearing capacity in an uplift analysis."""
    if support == "rigid":
        return 0
    elements = int(getattr(system.foundation, "elements", 2))
    return 2 * elements if support == "uplift" and getattr(system.foundation, "capacity", None) is not None \
        else elements


def too_many_yielding(count: int) -> bool:
    """Whether `count` contact elements with a bearing capacity are more than a history engine steps:
    two bits each of its 64-bit contact pattern (limits.MAX_YIELDING_ELEMENTS, docs/theory.md 14.3).
    capacity_refusal asks it of a system, the stepping (exact/stepping.Run) of a model built in code."""
    from ..runtime.limits import MAX_YIELDING_ELEMENTS

    return count > MAX_YIELDING_ELEMENTS


def engine(name: str) -> Engine:
    """The engine of that name (a deck's names are checked when it is read; this is for Python callers)."""
    try:
        return ENGINES[name]
    except KeyError:
        raise ValueError(f"engine must be one of {', '.join(ENGINES)}, got {name!r}") from None


def check_support(support: str) -> str:
    """The support name, or ValueError (a deck's names are checked when it is read)."""
    if support not in SUPPORTS:
        raise ValueError(f"support must be one of {', '.join(SUPPORTS)}, got {support!r}")
    return support
