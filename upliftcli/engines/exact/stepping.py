"""Response history of a piecewise-linear modal model (statespace.py) by exact step operators.

In each contact state the system X' = A X is linear and autonomous (the ground
acceleration is piecewise linear between samples and is part of X), so
X(t + h) = expm(A h) X(t) exactly: no integration error at any step size; the step only
sets how finely the history is sampled and how finely crossings are searched for.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ...errors import AnalysisError
from ...runtime.limits import MAX_CONTACT_ELEMENTS, MAX_PATTERN_BITS, MAX_YIELDING_ELEMENTS, too_many_bits
from ..registry import too_many_yielding
from . import stepping_kernels as kernel
from .operators import LEVELS, Operators, add_states, expected_states, soil_rows, state_bytes
from .statespace import ContactState, StateSpace
from .stories import resets
from .story_requests import adopt, loop_builds
from .yielding import event_resets


@dataclass
class History:
    """Samples of the augmented state at every step and at every contact transition.

    space: the state-space model integrated (its maps serve the responses and the energy);
    times [s] (n,), states X (n, n_aug), state_ids (n,): the contact state valid from
    each sample to the next; contact: the ContactState list indexed by state id; lifted
    (n, n_e): True where the element is lifted (valid from the sample on); yielding (n, n_e):
    True where it yields (a foundation with a bearing capacity, docs/theory.md 14; else None).
    """

    space: StateSpace
    times: np.ndarray
    states: np.ndarray
    state_ids: np.ndarray
    contact: list[ContactState]
    time_step: float
    criterion: str
    lifted: np.ndarray
    yielding: np.ndarray | None = None
    story_sign: np.ndarray | None = None  # (n, n_y) +1 / -1 / 0 per yielding story (docs/theory.md 15)

    @cached_property
    def lengths(self) -> np.ndarray:
        """Lengths of the intervals between samples [s] (computed once: every digest step uses them)."""
        return np.diff(self.times)


class Run:
    """One simulation from rest (static under gravity) through the ground acceleration
    ground [m/s^2] at every internal step h [s] (ground_grid), slopes [m/s^3] in each step.
    uplift: False keeps every element in contact (bonded support).

    `advance` integrates until the end of the record (returns None) or until a contact
    pattern without operators is reached (returns the pattern); after add_states,
    `enter(index)` switches to it. simulate_many drives several. operators: the step operators to
    start from (a twin's: reuse.py; they must be those of this space, h, criterion and support), else
    new ones."""

    def __init__(self, space: StateSpace, ground: np.ndarray, slopes: np.ndarray, h: float,
                 criterion: str = "reaction", uplift: bool = True, allow_flight: bool = True,
                 on_chunk: Callable[[History], None] | None = None, operators: Operators | None = None):
        lay = space.layout
        n_e = lay.n_elements
        if n_e > MAX_CONTACT_ELEMENTS:  # the deck's field is checked against it (a model built in code is not)
            raise AnalysisError(f"at most {MAX_CONTACT_ELEMENTS} contact elements are supported (got {n_e}): lower "
                                "foundation.elements")
        if too_many_yielding(lay.n_settlements):  # the rule of registry.capacity_refusal, for a model built in code
            raise AnalysisError(f"at most {MAX_YIELDING_ELEMENTS} contact elements with a bearing capacity are "
                                f"supported (got {n_e}): lower foundation.elements")
        if soil_rows(lay) + 2 * lay.n_plastic > MAX_PATTERN_BITS:  # the deck refuses it first (registry)
            raise AnalysisError(too_many_bits(soil_rows(lay), lay.n_plastic))
        self.space, self.layout, self.h, self.criterion = space, lay, h, criterion
        self.uplift = uplift
        # operators: those of this model, step, criterion and support to start from (reuse.OperatorStore)
        self.operators = _operators(space, h, criterion, uplift, operators)
        self.elements = kernel.Elements(*all_resets(space), np.int64((1 << n_e) - 1) if n_e else np.int64(-2),
                                        bool(allow_flight))
        self.grid = kernel.Grid(ground, slopes, float(h), LEVELS, lay.index_acceleration, lay.index_slope)
        # a long run is stepped in chunks: a full buffer goes to on_chunk (post-processed and
        # dropped) and stepping goes on from its last sample; without on_chunk the buffer grows
        self.on_chunk = on_chunk
        self.capacity = ground.size + 1024 if on_chunk is None else min(ground.size + 1024, CHUNK_SAMPLES)
        self.out_x = self.out_t = self.out_s = None  # allocated by first_request
        self.samples: kernel.Samples | None = None  # the state and the sample buffers (first_request, _buffer_full)
        self.integrate = kernel.integrator()  # the loop that runs this run (backend.loops asked once)
        self.x = space.rest.copy()
        self.x[lay.index_acceleration] = ground[0]
        self.x[lay.index_slope] = slopes[0]
        self.state, self.n_out, self.step, self.offset = -1, 0, 0, 0.0

    @property
    def buffer_bytes(self) -> int:
        """Memory of the sample buffers at their initial size [bytes], and of the operators of the
        contact states the run is expected to meet (operators.expected_states: with more than two
        elements with a bearing capacity n_e^2; a yielding Winkler mat of 20 elements met 441 under
        El Centro, 200 MB: docs/theory.md 14.3), so that few such runs are stepped together."""
        lay = self.layout
        return self.capacity * (lay.n_aug + 2) * 8 + expected_states(lay) * state_bytes(lay)

    def first_request(self) -> tuple[Operators, int, bool]:
        """Allocate the sample buffers; the request for the initial state (all elements in contact)."""
        self.out_x = np.empty((self.capacity, self.layout.n_aug))
        self.out_t = np.empty(self.capacity)
        self.out_s = np.empty(self.capacity, dtype=np.int64)
        self.samples = kernel.Samples(self.x, self.out_x, self.out_t, self.out_s)
        return self.operators, 0, (self.uplift and self.layout.n_elements > 0) or self.layout.n_plastic > 0

    def first_lifts(self) -> list[int]:
        """The contact patterns a run that lifts off reaches first: an edge element lifted (the
        others in contact); built with the initial state, in one stacked exponentiation, instead
        of one round each when the run reaches them (about 0.6 ms of an uplift analysis). On two
        elements with a bearing capacity also the states of an edge yielding, the other in contact
        or lifted: every state a yielding run meets, in one round instead of up to five (0.5 ms
        each); a run that never yields pays about 0.6 ms for them (CPU time, measured;
        benchmarks/bench_yielding.py, docs/theory.md 14.3). Not on more elements: a Winkler mat
        meets hundreds of yielding states, and a run that never yields would pay for them."""
        n_e = self.layout.n_elements
        if not (self.uplift and n_e):
            return []
        patterns = {1, 1 << (n_e - 1)}
        if self.layout.n_settlements and n_e <= AHEAD_ELEMENTS:
            for edge, opposite in ((0, n_e - 1), (n_e - 1, 0)):
                patterns.add(1 << (n_e + edge))
                if opposite != edge:
                    patterns.add((1 << (n_e + edge)) | (1 << opposite))
        return sorted(patterns)

    def enter(self, index: int) -> None:
        """Switch to state `index` (just added) and store the sample where it starts."""
        self.state = index
        self.out_t[self.n_out], self.out_x[self.n_out], self.out_s[self.n_out] = \
            self.step * self.h + self.offset, self.x, index
        self.n_out += 1

    def advance(self) -> int | None:
        """Step on (stepping_kernels.integrate) until the end of the record (None) or a contact pattern
        without operators (returned); a full sample buffer goes to on_chunk or grows (_buffer_full); a
        run that cannot go on raises the AnalysisError saying why (_stopped)."""
        ops = self.operators
        while True:
            builds = loop_builds(ops)  # the states of yielding stories the compiled loop builds itself
            status, self.step, self.offset, self.state, self.n_out, pattern = self.integrate(
                kernel.States(ops.ops, ops.slots, ops.events, ops.event_rates, ops.matrices, ops.patterns,
                              len(ops.contact)),
                self.elements, self.grid, self.samples, self.state, self.step, self.offset, self.n_out, builds,
            )
            adopt(ops, builds)
            if status == kernel.DONE:
                return None
            if status == kernel.NEED_STATE:
                return int(pattern)
            if status != kernel.FULL:
                raise self._stopped(status)
            self._buffer_full()

    def _buffer_full(self) -> None:
        """A full sample buffer: passed to on_chunk and restarted from its last sample, or grown."""
        if self.on_chunk is not None:
            self.on_chunk(self.history())
            self.out_x[0], self.out_t[0], self.out_s[0] = self.out_x[self.n_out - 1], self.out_t[self.n_out - 1], \
                self.out_s[self.n_out - 1]
            self.n_out = 1
            return
        extra = max(self.capacity // 2, 4096)
        self.out_x = np.concatenate((self.out_x, np.empty((extra, self.layout.n_aug))))
        self.out_t = np.concatenate((self.out_t, np.empty(extra)))
        self.out_s = np.concatenate((self.out_s, np.empty(extra, dtype=np.int64)))
        self.samples = kernel.Samples(self.x, self.out_x, self.out_t, self.out_s)
        self.capacity += extra

    def _stopped(self, status: int) -> AnalysisError:
        """Why the run stopped (kernel.FLIGHT, NONFINITE or CHATTER), in words."""
        h = self.h
        if status == kernel.FLIGHT:
            return AnalysisError(
                f"both edges of the mat left the foundation (flight) at t = {self.step * h + self.offset:.4f} s "
                "and flight = \"error\" was asked for"
            )
        if status == kernel.NONFINITE:
            return AnalysisError(f"the state became non-finite at t = {self.step * h:.4f} s")
        return AnalysisError(
            f"contact chatter: more than {kernel.MAX_EVENTS_PER_STEP} transitions inside one step "
            f"at t = {self.step * h:.4f} s; reduce the time step"
        )

    def history(self) -> History:
        """The samples in the buffer (views of it: use them before stepping on)."""
        n = self.n_out
        contact = self.operators.contact
        table = np.array([c.lifted for c in contact], dtype=bool).reshape(len(contact), -1)
        yielding = None
        if self.layout.n_settlements:
            yield_table = np.array([c.yielding for c in contact], dtype=bool).reshape(len(contact), -1)
            yielding = np.take(yield_table, self.out_s[:n], axis=0)
        signs = None
        if self.layout.n_plastic:
            sign_table = np.array([c.story_sign for c in contact], dtype=np.int8).reshape(len(contact), -1)
            signs = np.take(sign_table, self.out_s[:n], axis=0)
        # np.take, not table[ids]: the same rows, 15x faster for a table this narrow
        return History(self.space, self.out_t[:n], self.out_x[:n], self.out_s[:n], contact, self.h, self.criterion,
                       np.take(table, self.out_s[:n], axis=0), yielding, signs)


def all_resets(space: StateSpace) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The resets of every event row (stepping_kernels.Elements): the foundation's (yielding.event_resets),
    then the yielding stories' (stories.resets)."""
    index, rows, with_row = event_resets(space)
    lay = space.layout
    if not lay.n_plastic:
        return index, rows, with_row
    more = resets(space.model.stories, space.drift_rows, lay.plastic_indices, lay.index_one)
    return (np.concatenate((index, more[0])).astype(np.int64), np.vstack((rows.reshape(-1, lay.n_aug), more[1])),
            np.concatenate((with_row, more[2])))


def ground_grid(acceleration: np.ndarray, substeps: int, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Ground acceleration at every internal step [m/s^2] and its slope in each step [m/s^3]."""
    acceleration = np.asarray(acceleration, dtype=float)
    fine = np.arange((acceleration.size - 1) * substeps + 1) / substeps
    ground = np.interp(fine, np.arange(acceleration.size), acceleration)
    slopes = np.repeat(np.diff(acceleration) / dt, substeps)
    return ground, slopes


#: on at most this many elements with a bearing capacity, the yielding states are built with the
#: initial state (Run.first_lifts)
AHEAD_ELEMENTS = 2
#: memory allowed for the sample buffers of the runs stepped together [bytes]
BATCH_MEMORY = 256 * 2**20
#: runs of buildings whose stories yield stepped together at most. Each touches step operators of its own (about
#: 40 MB for the ten-story example at El Centro x2, against 2 MB elastic) and they share none: five together
#: (a sweep's chunk of 16 cases on three supports) cost 0.2-0.4 s of page faults more than two in a 100-case
#: sweep, sixteen 0.8 s, a third of the sweep (benchmarks/bench_sweep_split.py). Elastic runs share their
#: operators' work and are not counted.
YIELDING_GROUP = 2
#: samples of a run held at once when it is stepped in chunks (about 30 MB of states and
#: signals for ten stories; a run of the paper's example under El Centro is one chunk)
CHUNK_SAMPLES = 16384


def simulate(spaces: list[StateSpace], substeps: list[int], acceleration: np.ndarray, dt: float, criterion: str,
             uplift: bool, allow_flight: bool, on_chunk: list[Callable[[History], None]] | None = None,
             operators: list[Operators | None] | None = None) -> Iterator[tuple[int, History | AnalysisError]]:
    """Histories of several models under one ground acceleration [m/s^2] sampled at dt [s],
    model k integrated with substeps[k] internal steps per record step: (index, History or
    the AnalysisError that stopped it) as each run ends. With on_chunk[k], run k is stepped in
    chunks of at most CHUNK_SAMPLES samples, each full one passed to on_chunk[k] (the History
    yielded is then the last chunk); operators[k]: the step operators run k starts from (Run). The
    fine ground grid is built once per step size; runs
    are stepped together (simulate_many) in groups whose sample buffers fit in BATCH_MEMORY."""
    grids: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    pending: list[tuple[int, Run]] = []
    for k, (space, count) in enumerate(zip(spaces, substeps, strict=True)):
        if count not in grids:
            grids[count] = ground_grid(acceleration, count, dt)
        try:
            run = Run(space, *grids[count], dt / count, criterion, uplift=uplift, allow_flight=allow_flight,
                      on_chunk=_item(on_chunk, k), operators=_item(operators, k))
        except AnalysisError as error:  # this run only (e.g. too many contact elements)
            yield k, error
            continue
        pending.append((k, run))
    while pending:
        size = _fitting(pending)
        order = [k for k, _ in pending[:size]]
        group = [run for _, run in pending[:size]]
        del pending[:size]  # the runs live in simulate_many only: each one's buffers go when it ends
        for j, history in simulate_many(group):
            yield order[j], history


def simulate_many(runs: list[Run]) -> Iterator[tuple[int, History | AnalysisError]]:
    """Drive several runs in rounds: each advances until it finishes or needs a new contact
    state; the states asked for in a round are built together (add_states), in the first round
    with those each run reaches first when it lifts off or yields (Run.first_lifts). Yields
    (index, History or the AnalysisError that stopped it) as each run ends."""
    runs = list(runs)  # a finished run is dropped from here, so its buffers go with its history
    active = list(range(len(runs)))
    requests = [runs[k].first_request() for k in active]
    # built ahead with the initial states; one that cannot be built fails the run only if reached
    ahead = [(runs[k].operators, pattern, True) for k in active for pattern in runs[k].first_lifts()]
    while active:
        built = _added(requests + ahead)[:len(requests)]
        ahead = []
        going = []
        for k, index in zip(active, built, strict=False):
            outcome = _advanced(runs[k], index)
            if isinstance(outcome, (History, AnalysisError)):
                runs[k] = None
                yield k, outcome
            else:
                going.append((k, outcome))
        active = [k for k, _ in going]
        requests = [(runs[k].operators, pattern, True) for k, pattern in going]


def _added(requests: list[tuple[Operators, int, bool]]) -> list[int | AnalysisError]:
    """add_states of the requests, those whose pattern is stored already (operators a run started from:
    reuse.py) given its index instead (the requests of runs without such operators go to add_states as they are:
    a yielding run makes one request at a time, hundreds of times)."""
    if not any(getattr(operators, "inherited", 0) for operators, _, _ in requests):
        return add_states(requests)
    stored = [_stored(operators, pattern) for operators, pattern, _ in requests]
    built = iter(add_states(_unstored(requests, stored)))
    return [next(built) if index is None else index for index in stored]


def _unstored(requests: list[tuple[Operators, int, bool]], stored: list[int | None]
              ) -> list[tuple[Operators, int, bool]]:
    """The requests whose pattern has no state stored (stored[k] None)."""
    return [request for request, index in zip(requests, stored, strict=True) if index is None]


def _stored(operators: Operators, pattern: int) -> int | None:
    """The index of the state of `pattern` among those stored, None if there is none (only operators that
    inherited states, reuse.fork, can hold one a run asks for: the stepping loop asks for the others)."""
    if not getattr(operators, "inherited", 0):
        return None
    found = np.flatnonzero(operators.patterns[:len(operators.contact)] == pattern)
    return int(found[0]) if found.size else None


def _item(items: list | None, k: int):
    """items[k], None without items."""
    return items[k] if items else None


def _operators(space: StateSpace, h: float, criterion: str, uplift: bool, given: Operators | None) -> Operators:
    """The operators a run starts from: those it was given (a twin's: reuse.py), else new ones."""
    return Operators(space, h, criterion, uplift) if given is None else given


def _fitting(pending: list[tuple[int, Run]]) -> int:
    """How many of the pending runs, from the first, are stepped together: at least one, and as many as
    have their sample buffers within BATCH_MEMORY, with at most YIELDING_GROUP of them yielding stories."""
    size, used, yielding = 1, pending[0][1].buffer_bytes, _yields(pending[0][1])
    while size < len(pending):
        run = pending[size][1]
        if used + run.buffer_bytes > BATCH_MEMORY or yielding + _yields(run) > YIELDING_GROUP:
            break
        used, yielding, size = used + run.buffer_bytes, yielding + _yields(run), size + 1
    return size


def _yields(run: Run) -> int:
    """1 for a run of a building whose stories may yield, else 0."""
    return int(run.layout.n_plastic > 0)


def _advanced(run: Run, index: int | AnalysisError) -> int | History | AnalysisError:
    """Run `run` from its new state `index` (or the error that kept that state from being built) until
    it ends or needs another state: the pattern it needs, its History, or the AnalysisError that stopped it."""
    if isinstance(index, AnalysisError):
        return index
    run.enter(index)
    try:
        pattern = run.advance()
    except AnalysisError as error:
        return error
    return run.history() if pattern is None else pattern
