"""The step operators of a run handed to its twin (analysis/residuals.py; docs/theory.md 15.8).

A state's step operators, event rows and base depend on the model (the system, the support, the
engine options and the model builder), the internal step and the uplift criterion, never on the
record's amplitude: the twin of a yielding run (the record times 1 + 1e-6) meets nearly the same states
and would build them all again. An OperatorStore, made by one check of the residuals and dropped with
it, keeps the operators of the runs that yielded (within STORE_BYTES) under the key of everything that
determines them (store_key); the twin's run of the same key then starts from a fork of them
(OperatorStore.twins, take) and builds only the states the original did not meet. Each state's arrays
are the bits it would be built with (operators.add_states gives every item the bits it gets alone), so
the twin's results are those of a twin built from nothing, bit for bit (tests/test_operator_reuse.py).
Nothing is kept between two checks, two analyses or two cases of a sweep: the store lives in the call
that made it (analysis/run.run_batch). The twins fold their residuals and energy balance only
(residual_digest.py: `digest_for`), all the check reads of them.
"""

from __future__ import annotations

import copy
from dataclasses import replace
from typing import Any

import numpy as np

from ...model.system import System
from ..options import ExactOptions
from .digest import Digest
from .operators import Operators
from .residual_digest import ResidualDigest

#: the most memory of step operators a store keeps [bytes] (the README example's yielding rigid run holds 151
#: states, 106 slots of operators of 115 kB, 12 MB: used_bytes; a suite of eleven such records about 130 MB);
#: a run beyond it is not kept, and its twin builds its states itself
STORE_BYTES = 256 * 2**20


def store_key(system: System, support: str, options: ExactOptions, model: Any, h: float) -> tuple:
    """What a run's step operators are determined by: the system (by identity: the store holds it), the
    support (and with it whether the mat may lift), the engine options that build the model (all but
    `histories`, which only the digest reads), the model builder and the internal step h [s]."""
    return id(system), support, replace(options, histories=False), model, h


def used_bytes(operators: Operators) -> int:
    """Memory of the states stored in `operators` [bytes]: their event rows, rates and A^T, and the slots of
    operators they step with (Operators.slots: a slot a state shares is counted once; the arrays' rows beyond
    them are never touched: virtual memory only)."""
    n = len(operators.contact)
    shared = np.unique(operators.slots[:n]).size * operators.ops[0].nbytes
    return shared + sum(array[:n].nbytes for array in (operators.events, operators.event_rates, operators.matrices))


def fork(operators: Operators) -> Operators:
    """Operators that start with the states of `operators` and build more on their own: the stored arrays
    shared (a new state is written after the inherited ones, where `operators` never reads, or into
    grown copies), the lists and tables copied (the histories of the original's result keep its states)."""
    out = copy.copy(operators)
    out.contact = list(operators.contact)
    out.bases = dict(operators.bases)
    out.by_matrix = dict(operators.by_matrix)
    out.inherited = len(operators.contact)
    return out


class OperatorStore:
    """The step operators of the yielding runs of one check of the residuals (the originals: each run
    starts from nothing, start gives None, and done keeps those of a run that yielded), handed to their
    twins through twins(), each once, in the order they were kept; `reused` and `built` count the states
    the twins inherited and those they built themselves."""

    #: the originals are ordinary runs, with all their results
    residuals_only = False

    def __init__(self, max_bytes: int | None = None):
        self.max_bytes = STORE_BYTES if max_bytes is None else max_bytes
        self.kept: dict[tuple, list[tuple[System, Operators, int]]] = {}
        self.bytes = 0
        self.reused = self.built = 0

    def start(self, key: tuple, system: System) -> Operators | None:
        """What an original run starts from: nothing (None)."""
        return None

    def done(self, key: tuple, system: System, operators: Operators, result: Any) -> None:
        """An original run has ended with `result`: its operators kept if it yielded (only such runs get a
        twin) and they fit in max_bytes."""
        size = used_bytes(operators)
        if yielded(result) and self.bytes + size <= self.max_bytes:
            self.kept.setdefault(key, []).append((system, operators, size))
            self.bytes += size

    def take(self, key: tuple, system: System) -> Operators | None:
        """A fork of the first operators kept under `key` for `system` (None: none kept), no longer kept."""
        entries = self.kept.get(key)
        if not entries or entries[0][0] is not system:
            return None
        _, operators, size = entries.pop(0)
        if not entries:
            del self.kept[key]
        self.bytes -= size
        self.reused += len(operators.contact)
        return fork(operators)

    def twins(self) -> Twins:
        """The store as the twins' runs use it: each starts from its original's operators."""
        return Twins(self)


class Twins:
    """An OperatorStore as its twins use it: a run starts from a fork of the operators kept under its key
    (OperatorStore.take) and keeps nothing; the states it builds are counted (store.built). Its runs give
    their residuals and energy balance only (residuals_only: digest_for; a suite's twin, its records' results
    only: analysis/suite.iter_suite_batch)."""

    residuals_only = True

    def __init__(self, store: OperatorStore):
        self.store = store

    def start(self, key: tuple, system: System) -> Operators | None:
        """The fork of the original's operators a twin starts from (None: none kept)."""
        return self.store.take(key, system)

    def done(self, key: tuple, system: System, operators: Operators, result: Any) -> None:
        """A twin has ended: the states it built itself counted."""
        self.store.built += len(operators.contact) - getattr(operators, "inherited", 0)


def yielded(result: Any) -> bool:
    """Whether a run's stories or soil yielded (an error: False); only such runs get a twin (the one
    test, also analysis/residuals.py's)."""
    return bool(getattr(result, "yielded", False) or getattr(result, "building_yielded", False))


def digest_for(store: OperatorStore | Twins | None) -> type[Digest] | type[ResidualDigest]:
    """What a run of engine.iter_batch folds its chunks into: a twin's residuals and energy balance
    (ResidualDigest), else everything (Digest)."""
    return ResidualDigest if getattr(store, "residuals_only", False) else Digest
