"""The pattern-independent arguments of the compiled soil loops, built once per model and kept for the
few models in use (a run asks for one contact state at a time, hundreds of times: docs/theory.md 14.3),
by the model's identity: a model that is gone is never matched by a new one at the same address; and the
operator arrays of the runs of a yielding mat of many elements, kept for the next run (reused); and how
operators.Operators reserves its arrays and grows them (reserve, doubled)."""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import TypeVar

import numpy as np

from .statespace import StateSpace

T = TypeVar("T")

#: how many (model, builder) entries are kept: the runs of a sweep's batch stepped together
KEPT = 64
#: how many arrays reused keeps, in use or free (the runs of a sweep's batch each hold one)
REUSED = 8

_kept: dict[tuple[int, str], tuple[StateSpace, object]] = {}
_reused: list[np.ndarray] = []


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


def reused(shape: tuple[int, ...]) -> np.ndarray:
    """An array of floats of this shape and of any contents: one an earlier call gave that nothing holds any
    more (neither it nor a view of it), else a new one, kept (at most REUSED; the free ones of other shapes
    are let go). Its memory stays mapped: the operators of a yielding 20-element mat's run are 200 MB, which a
    new array (a mapping of its own) faults in again at every run (0.03 s of system time, and their building
    57 ms instead of 71 ms: benchmarks/bench_yielding.py, measured)."""
    free = _free_arrays()
    for array in free:
        if array.shape == shape:
            return array
    return _kept_new(np.empty(shape), free)


def _kept_new(array: np.ndarray, free: list[np.ndarray]) -> np.ndarray:
    """The new array, kept by reused in place of the free ones (of other shapes: their memory handed back; at
    most REUSED kept)."""
    gone = {id(other) for other in free}
    _reused[:] = [other for other in _reused if id(other) not in gone]
    if len(_reused) < REUSED:
        _reused.append(array)
    return array


def _free_arrays() -> list[np.ndarray]:
    """The arrays of _reused that nothing else holds: a reference count no higher than that of an array only a
    list holds, counted the same way (_counts: what the interpreter counts of its own references while it
    counts differs between Python versions)."""
    return [array for array, count in zip(_reused, _counts(_reused), strict=True) if count <= _ALONE]


def _counts(arrays: list[np.ndarray]) -> list[int]:
    return [sys.getrefcount(array) for array in arrays]


#: the reference count _counts gives an array only its list holds
_ALONE = _counts([np.empty(0)])[0]


def reserve(shape: tuple[int, ...], fill: float | None, kept: bool = False) -> np.ndarray:
    """A new array of `shape`: zeros (fill 0), or left as allocated (None); kept: one an earlier run left."""
    if kept:
        return reused(shape)  # its 200 MB mapped and not zeroed: the operators of a yielding mat's run
    return np.empty(shape) if fill is None else np.zeros(shape)


def doubled(array: np.ndarray, fill: float | None = None) -> np.ndarray:
    """The array with as many rows again after its own, those set to `fill` (None: left unset; 0:
    zeros, whose pages are mapped only as they are written)."""
    shape = (2 * array.shape[0], *array.shape[1:])
    if fill is None:
        out = np.empty(shape, dtype=array.dtype)
    else:
        out = np.zeros(shape, dtype=array.dtype) if fill == 0.0 else np.full(shape, fill, dtype=array.dtype)
    out[:array.shape[0]] = array
    return out
