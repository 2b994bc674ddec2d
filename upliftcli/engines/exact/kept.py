"""The pattern-independent arguments of the compiled soil loops, built once per model and kept for the
few models in use (a run asks for one contact state at a time, hundreds of times: docs/theory.md 14.3),
by the model's identity: a model that is gone is never matched by a new one at the same address."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from .statespace import StateSpace

T = TypeVar("T")

#: how many (model, builder) entries are kept: the runs of a sweep's batch stepped together
KEPT = 64

_kept: dict[tuple[int, str], tuple[StateSpace, object]] = {}


def kept(space: StateSpace, build: Callable[[StateSpace], T]) -> T:
    """build(space), from the last call with this model and builder if there was one (emptied when full)."""
    key = (id(space), build.__qualname__)
    found = _kept.get(key)
    if found is not None and found[0] is space:
        return found[1]  # type: ignore[return-value]
    value = build(space)
    if len(_kept) >= KEPT:
        _kept.clear()
    _kept[key] = (space, value)
    return value
