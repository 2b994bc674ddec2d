"""Response history of a piecewise-linear modal model (statespace.py) by exact step operators.

In each contact state the system X' = A X is linear and autonomous (the ground
acceleration is piecewise linear between samples and is part of X), so
X(t + h) = expm(A h) X(t) exactly: no integration error at any step size; the step only
sets how finely the history is sampled and how finely crossings are searched for.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm

from ...errors import AnalysisError
from . import stepping_kernels as kernel
from .statespace import ContactState, Layout, ModalModel, contact_states, layout, model_terms, static_state

#: levels of bisection operators: crossings are bracketed to h / 2^LEVELS, then interpolated
LEVELS = 12


@dataclass
class History:
    """Samples of the augmented state at every step and at every contact transition.

    times [s] (n,), states X (n, n_aug), state_ids (n,): the contact state valid from
    each sample to the next; contact: the ContactState list indexed by state id.
    """

    model: ModalModel
    layout: Layout
    times: np.ndarray
    states: np.ndarray
    state_ids: np.ndarray
    contact: list[ContactState]
    time_step: float
    criterion: str


class _Operators:
    """Exact step operators of the contact states met so far, grown on demand (stored
    transposed, as kernel.integrate takes them). States are built by add_states."""

    def __init__(self, model: ModalModel, lay: Layout, h: float, criterion: str):
        self.model, self.layout, self.h, self.criterion = model, lay, h, criterion
        self.terms = model_terms(model, lay)
        n_aug, n_e = lay.n_aug, max(lay.n_elements, 0)
        self.capacity = 4
        self.ops = np.zeros((self.capacity, LEVELS + 1, n_aug, n_aug))
        self.events = np.zeros((self.capacity, n_e, n_aug))
        self.event_rates = np.zeros((self.capacity, n_e, n_aug))
        self.matrices = np.zeros((self.capacity, n_aug, n_aug))
        self.patterns = np.full(self.capacity, -1, dtype=np.int64)
        self.contact: list[ContactState] = []

    def lifted(self, pattern: int) -> np.ndarray:
        return np.array([(pattern >> i) & 1 for i in range(self.layout.n_elements)], dtype=bool)

    def store(self, pattern: int, state: ContactState, ops: np.ndarray, events: bool) -> int:
        """Keep a built state: ops[j] = expm(A^T h / 2^j) for j = 0..LEVELS."""
        index = len(self.contact)
        if index == self.capacity:
            self.capacity *= 2
            grow = lambda a, fill=0.0: np.concatenate((a, np.full_like(a, fill)))  # noqa: E731
            self.ops, self.events, self.matrices = grow(self.ops), grow(self.events), grow(self.matrices)
            self.event_rates = grow(self.event_rates)
            self.patterns = grow(self.patterns, -1)
        self.ops[index] = ops
        if events:
            self.events[index] = state.events
            self.event_rates[index] = state.events @ state.matrix
        self.matrices[index] = state.matrix.T
        self.patterns[index] = pattern
        self.contact.append(state)
        return index


_NO_INERTIA = ("the mat rotation has neither inertia nor damping in this contact state "
               "(all damping ratios 0 and no element damping): give the mat a rotary inertia I_0 > 0")


def add_states(requests: list[tuple[_Operators, int, bool]]) -> list[int | AnalysisError]:
    """Build and store the contact states asked for, (operators, pattern, with event rows)
    each, vectorised over the requests that share a layout: one batched assembly
    (statespace.contact_states), one stacked expm and stacked squarings. Each item gets the
    same bits as built alone. Returns the new state index, or the error, per request."""
    out: list[int | AnalysisError] = [AnalysisError(_NO_INERTIA)] * len(requests)
    groups: dict[tuple, list[int]] = {}
    for k, (operators, _, _) in enumerate(requests):
        lay = operators.layout
        key = (lay.n_p, tuple(lay.massive), tuple(lay.massless), lay.n_x, lay.n_elements, operators.criterion)
        groups.setdefault(key, []).append(k)
    for members in groups.values():
        try:
            states = _states([requests[k] for k in members])
        except ZeroDivisionError:
            if len(members) == 1:
                continue
            states = []
            for k in members:  # find the item(s) at fault; the others go on
                try:
                    states.append(_states([requests[k]])[0])
                except ZeroDivisionError:
                    states.append(None)
        built = [(k, state) for k, state in zip(members, states) if state is not None]
        if not built:
            continue
        # transposed (the kernel's _matvec runs down columns); (E^T)^2 = (E^2)^T
        a_t = np.stack([state.matrix.T for _, state in built])
        h = np.array([requests[k][0].h for k, _ in built])[:, None, None]
        ops = np.empty((len(built), LEVELS + 1) + a_t.shape[1:])
        ops[:, LEVELS] = expm(a_t * (h / 2.0**LEVELS))
        for j in range(LEVELS - 1, 0, -1):
            ops[:, j] = ops[:, j + 1] @ ops[:, j + 1]
        ops[:, 0] = expm(a_t * h)
        for r, (k, state) in enumerate(built):
            operators, pattern, events = requests[k]
            out[k] = operators.store(pattern, state, ops[r], events)
    return out


def _states(requests: list[tuple[_Operators, int, bool]]) -> list[ContactState]:
    first = requests[0][0]
    lifted = np.array([operators.lifted(pattern) for operators, pattern, _ in requests], dtype=bool)
    lifted = lifted.reshape(len(requests), first.layout.n_elements)
    return contact_states([operators.terms for operators, _, _ in requests], first.layout, lifted, first.criterion)


class Run:
    """One simulation from rest (static under gravity) through the ground acceleration
    ground [m/s^2] at every internal step h [s] (ground_grid), slopes [m/s^3] in each step.
    uplift: False keeps every element in contact (bonded support).

    `advance` integrates until the end of the record (returns None) or until a contact
    pattern without operators is reached (returns the pattern); after add_states,
    `enter(index)` switches to it. simulate_many drives several."""

    def __init__(self, model: ModalModel, ground: np.ndarray, slopes: np.ndarray, h: float,
                 criterion: str = "reaction", uplift: bool = True, allow_flight: bool = True):
        lay = layout(model)
        n_e = lay.n_elements
        if n_e > 62:
            raise AnalysisError(f"at most 62 contact elements are supported (got {n_e}): lower foundation.elements")
        self.model, self.layout, self.h, self.criterion = model, lay, h, criterion
        self.ground, self.slopes, self.allow_flight = ground, slopes, allow_flight
        self.uplift = uplift
        self.operators = _Operators(model, lay, h, criterion)
        self.z_index = np.array([lay.z_index(i) for i in range(n_e)], dtype=np.int64)
        self.lift_rows = self.operators.terms.displacement_rows  # element displacements v_i = rows @ X
        self.element_damped = self.operators.terms.element_damping > 0.0
        self.all_lifted = np.int64((1 << n_e) - 1) if n_e else np.int64(-2)
        self.capacity = ground.size + 1024
        self.out_x = self.out_t = self.out_s = None  # allocated by first_request
        self.x = static_state(model, lay)
        self.x[lay.index_acceleration] = ground[0]
        self.x[lay.index_slope] = slopes[0]
        self.state, self.n_out, self.step, self.offset = -1, 0, 0, 0.0

    @property
    def buffer_bytes(self) -> int:
        """Memory of the sample buffers at their initial size [bytes]."""
        return self.capacity * (self.layout.n_aug + 2) * 8

    def first_request(self) -> tuple[_Operators, int, bool]:
        """Allocate the sample buffers; the request for the initial state (all elements in contact)."""
        self.out_x = np.empty((self.capacity, self.layout.n_aug))
        self.out_t = np.empty(self.capacity)
        self.out_s = np.empty(self.capacity, dtype=np.int64)
        return self.operators, 0, self.uplift and self.layout.n_elements > 0

    def enter(self, index: int) -> None:
        """Switch to state `index` (just added) and store the sample where it starts."""
        self.state = index
        self.out_t[self.n_out], self.out_x[self.n_out], self.out_s[self.n_out] = \
            self.step * self.h + self.offset, self.x, index
        self.n_out += 1

    def advance(self) -> int | None:
        ops, lay, h = self.operators, self.layout, self.h
        while True:
            status, self.step, self.offset, self.state, self.n_out, pattern = kernel.integrate(
                ops.ops, ops.events, ops.event_rates, ops.matrices, ops.patterns, len(ops.contact),
                self.z_index, self.lift_rows, self.element_damped, self.all_lifted, self.allow_flight,
                self.ground, self.slopes, h, LEVELS, lay.index_acceleration, lay.index_slope,
                self.x, self.state, self.step, self.offset, self.out_x, self.out_t, self.out_s, self.n_out,
            )
            if status == kernel.DONE:
                return None
            if status == kernel.NEED_STATE:
                return int(pattern)
            if status == kernel.FULL:
                extra = max(self.capacity // 2, 4096)
                self.out_x = np.concatenate((self.out_x, np.empty((extra, lay.n_aug))))
                self.out_t = np.concatenate((self.out_t, np.empty(extra)))
                self.out_s = np.concatenate((self.out_s, np.empty(extra, dtype=np.int64)))
                self.capacity += extra
            elif status == kernel.FLIGHT:
                raise AnalysisError(
                    f"both edges of the mat left the foundation (flight) at t = {self.step * h + self.offset:.4f} s "
                    "and flight = \"error\" was asked for"
                )
            elif status == kernel.NONFINITE:
                raise AnalysisError(f"the state became non-finite at t = {self.step * h:.4f} s")
            elif status == kernel.CHATTER:
                raise AnalysisError(
                    f"contact chatter: more than {kernel.MAX_EVENTS_PER_STEP} transitions inside one step "
                    f"at t = {self.step * h:.4f} s; reduce the time step"
                )

    def history(self) -> History:
        n = self.n_out
        return History(self.model, self.layout, self.out_t[:n], self.out_x[:n], self.out_s[:n],
                       self.operators.contact, self.h, self.criterion)


def ground_grid(acceleration: np.ndarray, substeps: int, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Ground acceleration at every internal step [m/s^2] and its slope in each step [m/s^3]."""
    acceleration = np.asarray(acceleration, dtype=float)
    fine = np.arange((acceleration.size - 1) * substeps + 1) / substeps
    ground = np.interp(fine, np.arange(acceleration.size), acceleration)
    slopes = np.repeat(np.diff(acceleration) / dt, substeps)
    return ground, slopes


def simulate_many(runs: list[Run]) -> Iterator[tuple[int, History | AnalysisError]]:
    """Drive several runs in rounds: each advances until it finishes or needs a new contact
    state; the states asked for in a round are built together (add_states). Yields
    (index, History or the AnalysisError that stopped it) as each run ends."""
    runs = list(runs)  # a finished run is dropped from here, so its buffers go with its history
    active = list(range(len(runs)))
    requests = [runs[k].first_request() for k in active]
    while active:
        built = add_states(requests)
        going = []
        for k, index in zip(active, built):
            if isinstance(index, AnalysisError):
                runs[k] = None
                yield k, index
                continue
            runs[k].enter(index)
            try:
                pattern = runs[k].advance()
            except AnalysisError as error:
                runs[k] = None
                yield k, error
                continue
            if pattern is None:
                history, runs[k] = runs[k].history(), None
                yield k, history
            else:
                going.append((k, pattern))
        active = [k for k, _ in going]
        requests = [(runs[k].operators, pattern, True) for k, pattern in going]
