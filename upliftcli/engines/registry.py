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

    def iter_batch(self, systems: Sequence[Any], ground_motion: Any, support: str, options: Any
                   ) -> Iterator[tuple[int, AnalysisResult | InputError | AnalysisError]]:
        """Analyse several systems under one ground motion and support (see the module docstring);
        a system this engine cannot model (capacity_refusal) gets an InputError."""
        module = importlib.import_module(self.module, __package__)
        systems = list(systems)
        kept = []
        for k, system in enumerate(systems):
            refusal = capacity_refusal(self.name, system, support)
            if refusal is None:
                kept.append(k)
            else:
                yield k, InputError("foundation", "capacity", refusal)
        for j, result in module.iter_batch([systems[k] for k in kept], ground_motion, support, options):
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


#: the engines that model a bearing capacity of the foundation (docs/theory.md section 14); the
#: others refuse an uplift analysis of a foundation that has one (rigid and bonded supports are
#: linear references, which a capacity does not change)
CAPACITY_ENGINES = ("simplified", "approximate", "exact")


def capacity_refusal(name: str, system: Any, support: str) -> str | None:
    """Why the engine `name` cannot analyse `system` with `support`: a bearing capacity it does
    not model, in words (what is expected); None when it can."""
    if name in CAPACITY_ENGINES or support != "uplift" or getattr(system.foundation, "capacity", None) is None:
        return None
    return (f"no bearing capacity for the {name} engine, which does not model yielding soil yet (docs/theory.md "
            "section 14; the simplified engine does): remove the capacity or run the simplified engine")


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
