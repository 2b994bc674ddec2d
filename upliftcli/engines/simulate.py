"""Response history of a piecewise-linear modal model (statespace.py) by exact step operators.

In each contact state the system X' = A X is linear and autonomous (the ground
acceleration is piecewise linear between samples and is part of X), so
X(t + h) = expm(A h) X(t) exactly: no integration error at any step size; the step only
sets how finely the history is sampled and how finely crossings are searched for.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm

from ..errors import AnalysisError
from . import kernel
from .statespace import (
    ContactState, Layout, ModalModel, contact_state, element_directions, layout, position_map, static_state,
)

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
    transposed, as kernel.integrate takes them)."""

    def __init__(self, model: ModalModel, lay: Layout, h: float, criterion: str):
        self.model, self.layout, self.h, self.criterion = model, lay, h, criterion
        n_aug, n_e = lay.n_aug, max(lay.n_elements, 0)
        self.capacity = 4
        self.ops = np.zeros((self.capacity, LEVELS + 1, n_aug, n_aug))
        self.events = np.zeros((self.capacity, n_e, n_aug))
        self.event_rates = np.zeros((self.capacity, n_e, n_aug))
        self.matrices = np.zeros((self.capacity, n_aug, n_aug))
        self.patterns = np.full(self.capacity, -1, dtype=np.int64)
        self.contact: list[ContactState] = []

    def add(self, pattern: int, events: bool = True) -> int:
        lay = self.layout
        lifted = np.array([(pattern >> i) & 1 for i in range(lay.n_elements)], dtype=bool)
        try:
            state = contact_state(self.model, lay, lifted, self.criterion)
        except ZeroDivisionError:
            raise AnalysisError(
                "the mat rotation has neither inertia nor damping in this contact state "
                "(all damping ratios 0 and no element damping): give the mat a rotary inertia I_0 > 0"
            ) from None
        index = len(self.contact)
        if index == self.capacity:
            self.capacity *= 2
            grow = lambda a, fill=0.0: np.concatenate((a, np.full_like(a, fill)))  # noqa: E731
            self.ops, self.events, self.matrices = grow(self.ops), grow(self.events), grow(self.matrices)
            self.event_rates = grow(self.event_rates)
            self.patterns = grow(self.patterns, -1)
        # transposed (the kernel's _matvec runs down columns); (E^T)^2 = (E^2)^T
        a = state.matrix
        self.ops[index, LEVELS] = expm(a.T * (self.h / 2.0**LEVELS))
        for j in range(LEVELS - 1, 0, -1):
            self.ops[index, j] = self.ops[index, j + 1] @ self.ops[index, j + 1]
        self.ops[index, 0] = expm(a.T * self.h)
        if events:
            self.events[index] = state.events
            self.event_rates[index] = state.events @ a
        self.matrices[index] = a.T
        self.patterns[index] = pattern
        self.contact.append(state)
        return index


def simulate(
    model: ModalModel,
    acceleration: np.ndarray,
    dt: float,
    substeps: int,
    criterion: str = "reaction",
    uplift: bool = True,
    allow_flight: bool = True,
) -> History:
    """Integrate from rest (static under gravity) through the ground acceleration [m/s^2].

    dt: record step [s]; substeps: internal steps per record step (h = dt / substeps).
    uplift: False keeps every element in contact (bonded support).
    """
    lay = layout(model)
    h = dt / substeps
    acceleration = np.asarray(acceleration, dtype=float)
    fine = np.arange((acceleration.size - 1) * substeps + 1) / substeps
    ground = np.interp(fine, np.arange(acceleration.size), acceleration)
    slopes = np.repeat(np.diff(acceleration) / dt, substeps)
    operators = _Operators(model, lay, h, criterion)
    state = operators.add(0, events=uplift and lay.n_elements > 0)
    n_e = lay.n_elements
    z_index = np.array([lay.z_index(i) for i in range(n_e)], dtype=np.int64)
    lift_rows = np.zeros((n_e, lay.n_aug))
    element_damped = np.zeros(n_e, dtype=np.bool_)
    if n_e:
        lift_rows = element_directions(model) @ position_map(model, lay)
        element_damped = model.elements.damping > 0.0
    if n_e > 62:
        raise AnalysisError(f"at most 62 contact elements are supported (got {n_e}): lower foundation.elements")
    all_lifted = np.int64((1 << n_e) - 1) if n_e else np.int64(-2)

    x = static_state(model, lay)
    capacity = ground.size + 1024
    out_x = np.empty((capacity, lay.n_aug))
    out_t = np.empty(capacity)
    out_s = np.empty(capacity, dtype=np.int64)
    x[lay.index_acceleration] = ground[0]
    x[lay.index_slope] = slopes[0]
    out_x[0], out_t[0], out_s[0] = x, 0.0, state
    n_out, step, offset = 1, 0, 0.0
    while True:
        status, step, offset, state, n_out, pattern = kernel.integrate(
            operators.ops, operators.events, operators.event_rates, operators.matrices, operators.patterns,
            len(operators.contact),
            z_index, lift_rows, element_damped, all_lifted, allow_flight,
            ground, slopes, h, LEVELS, lay.index_acceleration, lay.index_slope,
            x, state, step, offset, out_x, out_t, out_s, n_out,
        )
        if status == kernel.DONE:
            break
        if status == kernel.NEED_STATE:
            state = operators.add(int(pattern))
            out_t[n_out], out_x[n_out], out_s[n_out] = step * h + offset, x, state
            n_out += 1
        elif status == kernel.FULL:
            extra = max(capacity // 2, 4096)
            out_x = np.concatenate((out_x, np.empty((extra, lay.n_aug))))
            out_t = np.concatenate((out_t, np.empty(extra)))
            out_s = np.concatenate((out_s, np.empty(extra, dtype=np.int64)))
            capacity += extra
        elif status == kernel.FLIGHT:
            raise AnalysisError(
                f"both edges of the mat left the foundation (flight) at t = {step * h + offset:.4f} s "
                "and flight = \"error\" was asked for"
            )
        elif status == kernel.NONFINITE:
            raise AnalysisError(f"the state became non-finite at t = {step * h:.4f} s")
        elif status == kernel.CHATTER:
            raise AnalysisError(
                f"contact chatter: more than {kernel.MAX_EVENTS_PER_STEP} transitions inside one step "
                f"at t = {step * h:.4f} s; reduce the time step"
            )
    return History(model, lay, out_t[:n_out], out_x[:n_out], out_s[:n_out],
                   operators.contact, h, criterion)
