"""The cases of a planned sweep in chunks, the batches handed to one worker at a time (picklable):
the cases that share a structure together, so that one chunk is one batch for the exact engine.
"""

from __future__ import annotations

import itertools
import json
import math
from collections.abc import Container, Iterator, Sequence
from dataclasses import dataclass, field

from .cases import Case, Cases, is_structure_field
from .plan import SweepPlan


@dataclass
class Chunk:
    """A batch of cases handed to one worker at a time (picklable)."""

    raw: dict
    source: str
    base_overrides: tuple
    cases: list[Case]
    #: the plan's fingerprint (the contents of every file its ground motions read)
    inputs: str = ""
    #: the SHA-256 of every record file as the plan read it (absolute path -> digest)
    records: dict = field(default_factory=dict)

    def unfinished(self, done: set[str]) -> list[Case]:
        """The chunk's cases whose key is not in `done`, in order."""
        return [case for case in self.cases if case.key not in done]


def _structure_order(case: Case) -> tuple:
    """Sort key putting together the cases that differ only in foundation fields (same
    building, record and engine options), then by engine and support: a chunk of them is
    one batch for the exact engine (analysis.run_batch)."""
    others = [(path, value) for path, value in case.overrides if not is_structure_field(path)]
    return json.dumps(others, default=str), case.engine, case.support


def make_chunks(plan: SweepPlan, cases: Sequence[Case], size: int) -> list[Chunk]:
    """The cases in chunks of `size`, those that share a structure together (_structure_order;
    stable, so otherwise in case order)."""
    size = max(1, int(size))
    ordered = sorted(cases, key=_structure_order)
    return [Chunk(plan.raw, plan.source, (*plan.base_overrides, *plan.chosen), ordered[i:i + size],
                  plan.fingerprint, plan.records) for i in range(0, len(ordered), size)]


def stream_chunks(plan: SweepPlan, done: Container[str], size: int) -> Iterator[Chunk]:
    """The plan's cases whose key is not in `done`, in chunks of `size` made as they are asked for,
    those that share a structure together (Cases.in_structure_order; a list of cases: sorted as by
    make_chunks): the first chunk runs before the last case is made."""
    cases = plan.cases
    ordered = cases.in_structure_order() if isinstance(cases, Cases) else sorted(cases, key=_structure_order)
    todo = (case for case in ordered if case.key not in done)
    while batch := list(itertools.islice(todo, max(1, int(size)))):
        yield Chunk(plan.raw, plan.source, (*plan.base_overrides, *plan.chosen), batch, plan.fingerprint,
                    plan.records)


def chunk_size(n_cases: int, workers: int) -> int:
    """About four chunks per worker, at most 16 cases a chunk (a chunk lost to a dead worker is small)."""
    return max(1, min(16, math.ceil(n_cases / (4 * max(1, workers)))))
