"""The cases of a planned sweep in chunks, the batches handed to one worker at a time (picklable):
the cases that share a structure together, so that one chunk is one batch for the exact engine.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from .plan import Case, SweepPlan


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
    others = [(path, value) for path, value in case.overrides if not path.startswith("foundation.")]
    return json.dumps(others, default=str), case.engine, case.support


def make_chunks(plan: SweepPlan, cases: Sequence[Case], size: int) -> list[Chunk]:
    """The cases in chunks of `size`, those that share a structure together (_structure_order;
    stable, so otherwise in case order)."""
    size = max(1, int(size))
    ordered = sorted(cases, key=_structure_order)
    return [Chunk(plan.raw, plan.source, (*plan.base_overrides, *plan.chosen), ordered[i:i + size],
                  plan.fingerprint, plan.records) for i in range(0, len(ordered), size)]


def chunk_size(n_cases: int, workers: int) -> int:
    """About four chunks per worker, at most 16 cases a chunk (a chunk lost to a dead worker is small)."""
    return max(1, min(16, math.ceil(n_cases / (4 * max(1, workers)))))
