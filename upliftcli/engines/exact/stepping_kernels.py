"""Compiled stepping loop of the exact engine (numba).

For each contact state s the caller supplies the exact step operators
ops[s, j] = expm(A_s h / 2^j)^T, j = 0..L, of the augmented autonomous system (see
statespace.py), the event rows G_s, their rates G_s A_s and A_s^T (operators and
matrices are passed transposed: see _matvec). A step of length h is one
matrix-vector product. When an event function turns positive at the end of a chunk,
the crossing is bracketed by bisection with the finer operators (one product per
halving, exact at every level) down to h / 2^L, then placed by linear interpolation
inside that last sliver; the state switches there and the rest of the step is
integrated in the new state, itself checked for events. Nothing is rounded to a step
boundary (docs/theory.md section 4).

Status codes returned: DONE, NEED_STATE (a contact pattern without operators was
reached: the caller builds them and calls again), FULL (the sample buffer is full),
FLIGHT (both edges lifted and flight is refused), NONFINITE, CHATTER (more than
MAX_EVENTS_PER_STEP transitions inside one step). On NEED_STATE, x and offset are at the
event (transition applied): the caller adds the state, stores the event sample and calls
again with the new state.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import njit

DONE, NEED_STATE, FULL, FLIGHT, NONFINITE, CHATTER = 0, 1, 2, 3, 4, 5
#: samples kept free at the start of every step; more events than this inside one step is chatter
MAX_EVENTS_PER_STEP = 256
EVENT_TOLERANCE = 1e-12
#: a chunk whose event functions may make a brief positive excursion is halved down to h / 2^this
REFINE_LEVELS = 5


@njit(cache=True, inline="always")
def copy_into(destination, source):
    """destination[j] = source[j] for a 1-D source: an explicit loop, because a slice assignment
    from an array makes numba compile its shape-mismatch message (string formatting: about 3 s of
    the first run after installing)."""
    for j in range(source.size):
        destination[j] = source[j]


@njit(cache=True, inline="always")
def _matvec(matrix_t, x, out):
    """out = M x from the transposed matrix M^T, column by column: the inner loop runs along
    contiguous memory without a reduction, so it vectorises (3x faster than row dot products)."""
    n = x.size
    for i in range(n):
        out[i] = 0.0
    for j in range(n):
        xj = x[j]
        if xj != 0.0:
            for i in range(n):
                out[i] += matrix_t[j, i] * xj


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
def _excursion(events, rates, x, y, length):
    """True if some event function, not positive at either end of a chunk (states x, y,
    length [s]), has a positive interior maximum on its cubic Hermite interpolant (values
    G x, G y and exact rates G A x, G A y): a brief excursion the chunk ends would miss."""
    for i in range(events.shape[0]):
        g0 = 0.0
        g1 = 0.0
        d0 = 0.0
        d1 = 0.0
        for j in range(x.size):
            g0 += events[i, j] * x[j]
            g1 += events[i, j] * y[j]
            d0 += rates[i, j] * x[j]
            d1 += rates[i, j] * y[j]
        if d0 <= 0.0 and d1 >= 0.0:
            continue  # falling at the start and rising at the end: no interior maximum
        d0 *= length
        d1 *= length
        a = 2.0 * (g0 - g1) + d0 + d1
        b = 3.0 * (g1 - g0) - 2.0 * d0 - d1
        # p'(s) = 3 a s^2 + 2 b s + d0 = 0
        if abs(a) > 1e-14 * (abs(b) + abs(d0)):
            disc = b * b - 3.0 * a * d0
            if disc < 0.0:
                continue
            root = np.sqrt(disc)
            for s in ((-b + root) / (3.0 * a), (-b - root) / (3.0 * a)):
                if 0.0 < s < 1.0 and ((a * s + b) * s + d0) * s + g0 > EVENT_TOLERANCE:
                    return True
        elif b != 0.0:
            s = -d0 / (2.0 * b)
            if 0.0 < s < 1.0 and ((a * s + b) * s + d0) * s + g0 > EVENT_TOLERANCE:
                return True
    return False


@njit(cache=True)
def _find_state(patterns, n_states, pattern):
    for s in range(n_states):
        if patterns[s] == pattern:
            return s
    return -1


#: the contact states built so far: step operators ops[s, j] = expm(A_s h / 2^j)^T, event rows
#: G_s, their rates G_s A_s, A_s^T, the contact pattern of each and how many there are
States = namedtuple("States", "ops events event_rates matrices patterns count")
#: the elements: state index of each element top z_i, rows of its displacement v_i, whether it
#: has a dashpot, the pattern with every element lifted, and whether flight is allowed
Elements = namedtuple("Elements", "z_index lift_rows damped all_lifted allow_flight")
#: the ground acceleration at every internal step [m/s^2], its slope in each step [m/s^3], the
#: step h [s], the bisection levels L and where a_g and its slope sit in the augmented state
Grid = namedtuple("Grid", "ground slopes h levels index_acceleration index_slope")
#: the state x (updated in place) and the sample buffers (times, states, state ids)
Samples = namedtuple("Samples", "x out_x out_t out_state")


@njit(cache=True, inline="always")
def _crossing(ops_s, events_s, x, level, chunk, n_levels, left, trial, right):
    """Bracket the first crossing inside the chunk x -> trial by bisection with the finer exact
    operators down to h / 2^L (left, right: its ends), then place it by linear interpolation
    of each event function inside that last sliver. Returns (start, fraction): the crossing
    is at start + fraction * chunk[L] from x."""
    copy_into(left, x)
    start = 0.0
    for j in range(level + 1, n_levels + 1):
        _matvec(ops_s[j], left, trial)
        if _max_event(events_s, trial) <= EVENT_TOLERANCE:
            copy_into(left, trial)
            start += chunk[j]
    _matvec(ops_s[n_levels], left, right)
    # earliest crossing inside the last sliver, linear interpolation of each g_i
    fraction = 1.0
    for i in range(events_s.shape[0]):
        gl = 0.0
        gr = 0.0
        for j in range(x.size):
            gl += events_s[i, j] * left[j]
            gr += events_s[i, j] * right[j]
        if gr > EVENT_TOLERANCE:
            f = 0.0
            if gr > gl:
                f = (EVENT_TOLERANCE - gl) / (gr - gl)
            if f < 0.0:
                f = 0.0
            if f < fraction:
                fraction = f
    return start, fraction


@njit(cache=True, inline="always")
def _switch(pattern, events_s, x, right, elements):
    """The new contact pattern at the crossing x: every element whose event function has
    reached zero there (and is positive at the sliver's end) switches; a lifting element's
    top starts where the edge is (k z + c z' = 0 from there). Updates x."""
    for i in range(events_s.shape[0]):
        g = 0.0
        for j in range(x.size):
            g += events_s[i, j] * x[j]
        if g >= -1e-9:
            gr = 0.0
            for j in range(x.size):
                gr += events_s[i, j] * right[j]
            if gr > EVENT_TOLERANCE:
                pattern ^= np.int64(1) << np.int64(i)
                if (pattern >> np.int64(i)) & np.int64(1):
                    value = 0.0
                    if elements.damped[i]:
                        for j in range(x.size):
                            value += elements.lift_rows[i, j] * x[j]
                    x[elements.z_index[i]] = value
    return pattern


@njit(cache=True)
def integrate(states, elements, grid, samples, state, step, offset, n_out):
    """Advance from (step, offset) to the end of the ground-motion grid.

    Returns (status, step, offset, state, n_out, pattern) and updates samples.x and the
    sample buffers in place; pattern is the pending contact pattern for NEED_STATE.
    """
    ground, slopes, h, n_levels = grid.ground, grid.slopes, grid.h, grid.levels
    x, out_x, out_t, out_state = samples.x, samples.out_x, samples.out_t, samples.out_state
    n_steps = ground.size - 1
    n_aug = x.size
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
            return FULL, step, offset, state, n_out, states.patterns[state]
        events_in_step = 0
        if offset == 0.0:
            x[grid.index_acceleration] = ground[step]
            x[grid.index_slope] = slopes[step]
        while True:
            remaining = h - offset
            if remaining < smallest * (1.0 - 1e-9):
                if remaining > 0.0:
                    # sub-sliver close: second-order Taylor step (error ~ (|A| h 2^-L)^3)
                    _matvec(states.matrices[state], x, tmp)
                    _matvec(states.matrices[state], tmp, trial)
                    for i in range(n_aug):
                        x[i] += remaining * tmp[i] + 0.5 * remaining * remaining * trial[i]
                break
            level = 0
            while level < n_levels and chunk[level] > remaining * (1.0 + 1e-12):
                level += 1
            ops_s, events_s = states.ops[state], states.events[state]
            _matvec(ops_s[level], x, trial)
            crossed = _max_event(events_s, trial) > EVENT_TOLERANCE
            # an event function may rise above zero and fall back inside the chunk: halve it
            # while its cubic interpolant says so (down to h / 2^REFINE_LEVELS)
            while (not crossed and level < REFINE_LEVELS
                   and _excursion(events_s, states.event_rates[state], x, trial, chunk[level])):
                level += 1
                _matvec(ops_s[level], x, trial)
                crossed = _max_event(events_s, trial) > EVENT_TOLERANCE
            if not crossed:
                copy_into(x, trial)
                offset += chunk[level]
                continue
            start, fraction = _crossing(ops_s, events_s, x, level, chunk, n_levels, left, trial, right)
            for j in range(n_aug):
                x[j] = left[j] + fraction * (right[j] - left[j])
            offset += start + fraction * smallest
            pattern = _switch(states.patterns[state], events_s, x, right, elements)
            if pattern == elements.all_lifted and not elements.allow_flight:
                return FLIGHT, step, offset, state, n_out, pattern
            new_state = _find_state(states.patterns, states.count, pattern)
            if new_state < 0:
                return NEED_STATE, step, offset, state, n_out, pattern
            state = new_state
            events_in_step += 1
            if events_in_step >= MAX_EVENTS_PER_STEP:
                return CHATTER, step, offset, state, n_out, pattern
            out_t[n_out] = step * h + offset
            copy_into(out_x[n_out], x)
            out_state[n_out] = state
            n_out += 1
        step += 1
        offset = 0.0
        x[grid.index_acceleration] = ground[step]
        if step < n_steps:
            # the sample opens the next interval: it carries that interval's ground slope
            x[grid.index_slope] = slopes[step]
        finite = True
        for i in range(n_aug):
            if not np.isfinite(x[i]):
                finite = False
        if not finite:
            return NONFINITE, step, offset, state, n_out, states.patterns[state]
        out_t[n_out] = step * h
        copy_into(out_x[n_out], x)
        out_state[n_out] = state
        n_out += 1
    return DONE, step, offset, state, n_out, states.patterns[state]
