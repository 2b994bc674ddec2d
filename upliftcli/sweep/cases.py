"""The cases of a sweep, made on demand: Cases is the cartesian product of the varied values
(first --vary outermost), then engine, then support, as a sequence that holds none of them
(a 10^5-case sweep kept 10^5 Case objects and their keys before its first row). A case's index,
varied values and key are those of the product's position; in_structure_order walks the same
cases with those that differ only in foundation fields together (one batch for the exact engine:
analysis.run_batch), without sorting them all first.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, replace
from typing import Any

from .values import Vary


@dataclass(frozen=True)
class Case:
    """One analysis of a sweep: index in the sweep, stable key, varied values, engine, support."""

    index: int
    key: str
    overrides: tuple  # ((path, value), ...) of the varied fields
    engine: str
    support: str


def case_key(deck_fingerprint: str, overrides: Sequence[tuple[str, Any]], engine: str, support: str) -> str:
    text = json.dumps([deck_fingerprint, [list(o) for o in overrides], engine, support], default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def is_structure_field(path: str) -> bool:
    """A foundation field: the cases differing only in these share a structure (one batch)."""
    return path.startswith("foundation.")


class Cases(Sequence):
    """The cases of the product varies x engines x supports, each made when asked for (by
    index, by slice, in order, or in_structure_order)."""

    def __init__(self, varies: Sequence[Vary], engines: Sequence[str], supports: Sequence[str],
                 deck_fingerprint: str):
        self.varies = tuple(varies)
        self.engines = tuple(engines)
        self.supports = tuple(supports)
        self.deck_fingerprint = deck_fingerprint
        self._sizes = (*(len(v.values) for v in self.varies), len(self.engines), len(self.supports))

    def __len__(self) -> int:
        return math.prod(self._sizes)

    def __getitem__(self, index):
        if isinstance(index, slice):
            return [self._case(i) for i in range(*index.indices(len(self)))]
        position = index + len(self) if index < 0 else index
        if not 0 <= position < len(self):
            raise IndexError(f"case {index} of {len(self)}")
        return self._case(position)

    def __iter__(self) -> Iterator[Case]:
        return (self._case(index) for index in range(len(self)))

    def _case(self, index: int) -> Case:
        digits = _digits(index, self._sizes)
        overrides = tuple((v.path, v.values[d]) for v, d in zip(self.varies, digits, strict=False))
        engine, support = self.engines[digits[-2]], self.supports[digits[-1]]
        return Case(index, case_key(self.deck_fingerprint, overrides, engine, support), overrides, engine, support)

    def in_structure_order(self) -> Iterator[Case]:
        """The cases, those sharing every varied field but the foundation's (and the engine and
        support) together, in case order within; the groups in the order of their first case."""
        inner, outer = _split(self.varies, len(self._sizes))
        for head, tail in itertools.product(_positions(outer, self._sizes), _positions(inner, self._sizes)):
            yield self._case(_index({**head, **tail}, self._sizes))


def _split(varies: Sequence[Vary], dimensions: int) -> tuple[list[int], list[int]]:
    """The dimensions of the product that are foundation fields, and the others (engine, support too)."""
    inner = [k for k, v in enumerate(varies) if is_structure_field(v.path)]
    return inner, [k for k in range(dimensions) if k not in inner]


def _positions(dimensions: list[int], sizes: Sequence[int]) -> list[dict[int, int]]:
    """Every position (dimension -> digit) over `dimensions`, the last one fastest."""
    ranges = [range(sizes[k]) for k in dimensions]
    return [dict(zip(dimensions, digits, strict=True)) for digits in itertools.product(*ranges)]


def _digits(index: int, sizes: Sequence[int]) -> list[int]:
    """The position of `index` in the product of ranges of `sizes` (the last one fastest)."""
    digits = []
    for size in reversed(sizes):
        index, digit = divmod(index, size)
        digits.append(digit)
    return digits[::-1]


def _index(digits: dict[int, int], sizes: Sequence[int]) -> int:
    """The index of a position (dimension -> digit) in the product of ranges of `sizes`."""
    index = 0
    for dimension, size in enumerate(sizes):
        index = index * size + digits[dimension]
    return index


def combos(varies: Sequence[Vary]) -> Iterator[tuple]:
    """The combinations of the varied values, ((path, value), ...), first --vary outermost."""
    return itertools.product(*[[(v.path, value) for value in v.values] for v in varies])


#: a sweep of more combinations of its varied values than this is checked before it runs
#: (sweep/plan.py) on the combinations of checked_combos (each value of a building or foundation
#: field with the other fields at their first value, and every combination of the other fields:
#: the ground motion may follow them), not on each: building 10^5 decks took 27-210 s before the
#: first row. Each case's deck is built and checked by its worker all the same (a combination the
#: deck refuses is a 'failed' row naming the field). 1,000 decks take 1-3 s.
CHECKED_COMBINATIONS = 1_000


def motion_free(path: str) -> bool:
    """A field the ground motion does not depend on (a building or foundation field)."""
    return path.startswith(("building.", "foundation."))


def checked_combos(varies: Sequence[Vary], every: bool) -> Iterator[tuple]:
    """The combinations a plan builds before the run: all of them (every, or at most
    CHECKED_COMBINATIONS), else those of CHECKED_COMBINATIONS' comment, each once."""
    if every or math.prod(len(v.values) for v in varies) <= CHECKED_COMBINATIONS:
        return combos(varies)
    return iter(dict.fromkeys(itertools.chain(combos([_motion_only(v) for v in varies]), _each_alone(varies))))


def _motion_only(vary: Vary) -> Vary:
    """A building or foundation field at its first value only; another field as it is."""
    return replace(vary, values=vary.values[:1]) if motion_free(vary.path) else vary


def _each_alone(varies: Sequence[Vary]) -> Iterator[tuple]:
    """Each value of each building or foundation field, the other fields at their first value."""
    first = [(v.path, v.values[0]) for v in varies]
    for k, vary in enumerate(varies):
        values = vary.values[1:] if motion_free(vary.path) else ()
        yield from (tuple([*first[:k], (vary.path, value), *first[k + 1:]]) for value in values)


def expand_cases(varies: Sequence[Vary], engines: Sequence[str], supports: Sequence[str],
                 deck_fingerprint: str) -> list[Case]:
    """Cartesian product of the varied values (first --vary outermost), then engine, then support,
    so that the cases sharing one deck are adjacent (Cases, as a list)."""
    return list(Cases(varies, engines, supports, deck_fingerprint))
