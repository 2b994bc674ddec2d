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
        """Analyse several systems under one ground motion and support (see the module docstring)."""
        module = importlib.import_module(self.module, __package__)
        yield from module.iter_batch(list(systems), ground_motion, support, options)

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
