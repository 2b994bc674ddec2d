"""Compiled stepping loop of the exact engine (numba).

For each contact state s the caller supplies the exact step operators
ops[s, j] = expm(A_s h / 2^j), j = 0..L, of the augmented autonomous system (see
statespace.py), the event rows G_s and A_s itself. A step of length h is one
matrix-vector product. When an event function turns positive at the end of a chunk,
the crossing is bracketed by bisection with the finer operators (one product per
halving, exact at every level) down to h / 2^L, then placed by linear interpolation
inside that last sliver; the state switches there and the rest of the step is
integrated in the new state, itself checked for events. Nothing is rounded to a step
boundary (THEORY.md section 4).

Status codes returned: DONE, NEED_STATE (a contact pattern without operators was
reached: the caller builds them and calls again), FULL (the sample buffer is full),
FLIGHT (both edges lifted and flight is refused), NONFINITE, CHATTER (more than
MAX_EVENTS_PER_STEP transitions inside one step). On NEED_STATE, x and offset are at the
event (transition applied): the caller adds the state, stores the event sample and calls
again with the new state.
"""

from __future__ import annotations

import numpy as np
from numba import njit

DONE, NEED_STATE, FULL, FLIGHT, NONFINITE, CHATTER = 0, 1, 2, 3, 4, 5
#: samples kept free at the start of every step; more events than this inside one step is chatter
MAX_EVENTS_PER_STEP = 256
EVENT_TOLERANCE = 1e-12


@njit(cache=True, inline="always")
def _matvec(matrix, x, out):
    n = x.size
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += matrix[i, j] * x[j]
        out[i] = acc


@njit(cache=True)
def _max_event(events, x):
    best = -np.inf
    for i in range(events.shape[0]):
        acc = 0.0
        for j in range(x.size):
            acc += events[i, j] * x[j]
        if acc > best:
            best = acc
    return best


@njit(cache=True)
def _find_state(patterns, n_states, pattern):
    for s in range(n_states):
        if patterns[s] == pattern:
            return s
    return -1


@njit(cache=True)
def integrate(
    ops, events, matrices, patterns, n_states,
    z_index, lift_rows, element_damped, all_lifted_pattern, allow_flight,
    ground, slopes, h, n_levels, index_acceleration, index_slope,
    x, state, step, offset, out_x, out_t, out_state, n_out,
):
    """Advance from (step, offset) to the end of the ground-motion grid.

    Returns (status, step, offset, state, n_out, pattern) and updates x and the
    output buffers in place; pattern is the pending contact pattern for NEED_STATE.
    """
    n_steps = ground.size - 1
    n_aug = x.size
    n_e = events.shape[1]
    trial = np.empty(n_aug)
    left = np.empty(n_aug)
    right = np.empty(n_aug)
    tmp = np.empty(n_aug)
    chunk = np.empty(n_levels + 1)
    for j in range(n_levels + 1):
        chunk[j] = h / 2.0**j
    smallest = chunk[n_levels]
    capacity = out_t.size
    while step < n_steps:
        if n_out + MAX_EVENTS_PER_STEP + 1 > capacity:
            return FULL, step, offset, state, n_out, patterns[state]
        events_in_step = 0
        if offset == 0.0:
            x[index_acceleration] = ground[step]
            x[index_slope] = slopes[step]
        while True:
            remaining = h - offset
            if remaining < smallest * (1.0 - 1e-9):
                if remaining > 0.0:
                    # sub-sliver close: second-order Taylor step (error ~ (|A| h 2^-L)^3)
                    _matvec(matrices[state], x, tmp)
                    _matvec(matrices[state], tmp, trial)
                    for i in range(n_aug):
                        x[i] += remaining * tmp[i] + 0.5 * remaining * remaining * trial[i]
                break
            level = 0
            while level < n_levels and chunk[level] > remaining * (1.0 + 1e-12):
                level += 1
            _matvec(ops[state, level], x, trial)
            if _max_event(events[state], trial) <= EVENT_TOLERANCE:
                x[:] = trial
                offset += chunk[level]
                continue
            # bracket the first crossing by bisection with the finer exact operators
            left[:] = x
            start = 0.0
            for j in range(level + 1, n_levels + 1):
                _matvec(ops[state, j], left, trial)
                if _max_event(events[state], trial) <= EVENT_TOLERANCE:
                    left[:] = trial
                    start += chunk[j]
            _matvec(ops[state, n_levels], left, right)
            # earliest crossing inside the last sliver, linear interpolation of each g_i
            fraction = 1.0
            ev = events[state]
            for i in range(n_e):
                gl = 0.0
                gr = 0.0
                for j in range(n_aug):
                    gl += ev[i, j] * left[j]
                    gr += ev[i, j] * right[j]
                if gr > EVENT_TOLERANCE:
                    f = 0.0
                    if gr > gl:
                        f = (EVENT_TOLERANCE - gl) / (gr - gl)
                    if f < 0.0:
                        f = 0.0
                    if f < fraction:
                        fraction = f
            for j in range(n_aug):
                x[j] = left[j] + fraction * (right[j] - left[j])
            offset += start + fraction * smallest
            # every element whose function has reached zero at that point switches
            pattern = patterns[state]
            for i in range(n_e):
                g = 0.0
                for j in range(n_aug):
                    g += ev[i, j] * x[j]
                if g >= -1e-9:
                    gr = 0.0
                    for j in range(n_aug):
                        gr += ev[i, j] * right[j]
                    if gr > EVENT_TOLERANCE:
                        pattern ^= np.int64(1) << np.int64(i)
                        if (pattern >> np.int64(i)) & np.int64(1):
                            # lift-off: the element top starts where the edge is (k z + c z' = 0)
                            value = 0.0
                            if element_damped[i]:
                                for j in range(n_aug):
                                    value += lift_rows[i, j] * x[j]
                            x[z_index[i]] = value
            if pattern == all_lifted_pattern and not allow_flight:
                return FLIGHT, step, offset, state, n_out, pattern
            new_state = _find_state(patterns, n_states, pattern)
            if new_state < 0:
                return NEED_STATE, step, offset, state, n_out, pattern
            state = new_state
            events_in_step += 1
            if events_in_step >= MAX_EVENTS_PER_STEP:
                return CHATTER, step, offset, state, n_out, pattern
            out_t[n_out] = step * h + offset
            out_x[n_out, :] = x
            out_state[n_out] = state
            n_out += 1
        step += 1
        offset = 0.0
        x[index_acceleration] = ground[step]
        finite = True
        for i in range(n_aug):
            if not np.isfinite(x[i]):
                finite = False
        if not finite:
            return NONFINITE, step, offset, state, n_out, patterns[state]
        out_t[n_out] = step * h
        out_x[n_out, :] = x
        out_state[n_out] = state
        n_out += 1
    return DONE, step, offset, state, n_out, patterns[state]
