"""The numpy twin of the compiled stepping loop (_stepping.c): the same functions with the same
arguments (stepping_kernels.py has the method, the arguments and the status codes), the same
steps, crossings and samples to round-off (tests/test_stepping_numpy.py,
tests/test_backend_agreement.py).

Whole steps in one contact state run many at once. With the ground acceleration a_i and its
slope s_i set at the start of every step (as the C loop sets them) and y the other components
of the state, a step is y' = A y + b_a a_i + b_s s_i, so within a block of BLOCK steps

    y_j = A^j y_0 + sum_{i<j} A^(j-1-i) (b_a a_i + b_s s_i),   j = 1..BLOCK

(`_Block`: the forced part of every block of a run is one product with the block's inputs, the
block starts follow one matrix-vector product each, the states one product more). The event
functions and their rates at both ends of every step come from one product too, and the steps
are checked together: an event function crosses, or its cubic interpolant may rise above zero
inside the step (`excursion_between`, after a bound that clears almost every step at once), or
the state stops being finite. The first such step, a step entered part-way (after a transition)
and the record's last step are stepped as the C loop steps them (`_Loop.finish_step`, line by
line: crossings bracketed with the finer operators and placed by linear interpolation, the
contact pattern switched, the rest of the step in the new state). A run of blocks starts one
block long after such a step and doubles while no step needs more, up to RUN_BLOCKS.
"""

from __future__ import annotations

import numpy as np

from .stepping_kernels import (
    CHATTER,
    DONE,
    EVENT_TOLERANCE,
    FLIGHT,
    FULL,
    MAX_EVENTS_PER_STEP,
    NEED_STATE,
    NONFINITE,
    REFINE_LEVELS,
)

#: steps of one block recurrence (its operators grow as BLOCK^2)
BLOCK = 32
#: blocks in the longest run computed at once
RUN_BLOCKS = 16


def matvec(matrix_t, x, out) -> None:
    """out = M x from the transposed matrix M^T."""
    out[:] = x @ matrix_t


def excursion_between(g0, d0, g1, d1, length: float):
    """True where some event function (first axis), not positive at either end of a chunk of
    `length` [s], has a positive interior maximum on its cubic Hermite interpolant through its
    values g and exact rates d at the ends (events.h, excursion_between; one answer per column
    of 2-D arrays)."""
    d0, d1 = d0 * length, d1 * length
    if np.ndim(g0) == 1:
        return _excursion(g0, d0, g1, d1)
    # p lies below its largest Bernstein coefficient, g0, g0 + d0/3, g1 - d1/3, g1: the exact test
    # only where that bound (with room for round-off) reaches the tolerance
    bound = np.maximum(np.maximum(g0, g1), np.maximum(g0 + d0 / 3.0, g1 - d1 / 3.0))
    bound += 1e-12 * (np.abs(g0) + np.abs(g1) + np.abs(d0) + np.abs(d1))
    columns = np.flatnonzero(np.logical_or.reduce(bound > EVENT_TOLERANCE, axis=0))
    found = np.zeros(g0.shape[1], dtype=bool)
    if columns.size:
        found[columns] = _excursion(g0[:, columns], d0[:, columns], g1[:, columns], d1[:, columns])
    return found


def _excursion(g0, d0, g1, d1):
    """excursion_between with the slopes already times the chunk's length."""
    a = 2.0 * (g0 - g1) + d0 + d1
    b = 3.0 * (g1 - g0) - 2.0 * d0 - d1
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = b * b - 3.0 * a * d0
        root = np.sqrt(disc)
        cubic = np.abs(a) > 1e-14 * (np.abs(b) + np.abs(d0))
        candidates = (np.where(cubic, (-b + root) / (3.0 * a), -d0 / (2.0 * b)),
                      np.where(cubic, (-b - root) / (3.0 * a), np.nan))
        possible = ~((d0 <= 0.0) & (d1 >= 0.0)) & np.where(cubic, disc >= 0.0, b != 0.0)
        found = np.zeros(np.shape(g0), dtype=bool)
        for s in candidates:
            found |= (s > 0.0) & (s < 1.0) & (((a * s + b) * s + d0) * s + g0 > EVENT_TOLERANCE)
    return np.logical_or.reduce(possible & found, axis=0)


def excursion(events, rates, x, y, length: float) -> bool:
    """The interior-excursion test between the states x, y (stepping_kernels.excursion)."""
    return bool(excursion_between(events @ x, rates @ x, events @ y, rates @ y, float(length)))


class _Block:
    """The block recurrence of one contact state. `forcing` maps a block's inputs [a_0..a_{B-1},
    s_0..s_{B-1}] to its free components after 1..B steps from zero, `powers` the block's start
    y_0 to their homogeneous part [A y_0, ..., A^B y_0]; `checks` maps a full state at a step's
    start to the event values and rates there and at the step's end (G, G A, G M, G A M for the
    step operator M)."""

    def __init__(self, operator: np.ndarray, events: np.ndarray, rates: np.ndarray, free: np.ndarray,
                 index_acceleration: int, index_slope: int):
        n_f, size = free.size, BLOCK
        a = operator[np.ix_(free, free)]
        inputs = operator[free][:, [index_acceleration, index_slope]]  # b_a, b_s
        powers = np.empty((size + 1, n_f, n_f))
        powers[0] = np.eye(n_f)
        for j in range(1, size + 1):
            powers[j] = a @ powers[j - 1]
        responses = powers[:size] @ inputs  # A^m b: (size, n_f, 2)
        forcing = np.zeros((2 * size, size, n_f))
        for i in range(size):
            forcing[i, i:] = responses[:size - i, :, 0]
            forcing[size + i, i:] = responses[:size - i, :, 1]
        self.forcing = forcing.reshape(2 * size, size * n_f)
        self.powers = np.ascontiguousarray(powers[1:].transpose(2, 0, 1).reshape(n_f, size * n_f))
        self.last = powers[size].T  # y_0 -> A^B y_0, transposed (row vectors)
        self.checks = np.vstack((events, rates, events @ operator, rates @ operator))


class _Loop:
    """One call of integrate: the model, the C loop's step (finish_step) and runs of blocks (run_blocks)."""

    def __init__(self, states, elements, grid, samples):
        self.ops, self.slots, self.events, self.rates, self.matrices, self.patterns, self.count = states
        self.z_index, self.lift_rows, self.damped, self.all_lifted, self.allow_flight = elements
        self.ground, self.slopes, self.h, self.levels, self.ia, self.islope = grid
        self.x, self.out_x, self.out_t, self.out_state = samples
        self.n = self.x.size
        self.chunk = self.h / 2.0 ** np.arange(self.levels + 1)
        self.smallest = self.chunk[-1]
        # np.delete, not np.setdiff1d or np.unique: they import numpy.ma (8 ms)
        self.free = np.delete(np.arange(self.n), sorted({self.ia, self.islope}))
        self.blocks: dict[int, _Block] = {}

    def state_events(self, state: int) -> tuple[np.ndarray, np.ndarray]:
        """The event rows and their rates of a state (none in a state whose rows are all zero: bonded)."""
        events = self.events[state]
        if not events.any():
            events = events[:0]
        return events, self.rates[state][:events.shape[0]]

    def step_with(self, state: int, level: int, x: np.ndarray) -> np.ndarray:
        return x @ self.ops[self.slots[state], level]

    # ------------------------------------------------------------------ the C loop's step
    def crossing(self, state, x, level, events):
        """Bracket the first crossing inside the chunk from x by bisection with the finer operators
        (left, right: the last sliver's ends), then interpolate linearly inside that sliver: (start,
        fraction, left, right), the crossing at start + fraction * smallest from x."""
        left, start = x, 0.0
        for j in range(level + 1, self.levels + 1):
            trial = self.step_with(state, j, left)
            if (events @ trial).max() <= EVENT_TOLERANCE:
                left = trial
                start += self.chunk[j]
        right = self.step_with(state, self.levels, left)
        best = 1.0
        for gl, gr in zip(events @ left, events @ right, strict=True):
            if gr > EVENT_TOLERANCE:
                f = (EVENT_TOLERANCE - gl) / (gr - gl) if gr > gl else 0.0
                best = min(best, max(f, 0.0))
        return start, best, left, right

    def switch_pattern(self, state, pattern, x, right) -> int:
        """Every element whose event function has reached zero at x and is positive at the sliver's
        end switches; a lifting element's top starts where the edge is. Updates x."""
        events = self.events[state]
        for i in range(events.shape[0]):
            if events[i] @ x >= -1e-9 and events[i] @ right > EVENT_TOLERANCE:
                pattern ^= 1 << i
                if (pattern >> i) & 1:
                    x[self.z_index[i]] = self.lift_rows[i] @ x if self.damped[i] else 0.0
        return pattern

    def finish_step(self, state, step, offset, n_out):
        """Step from `offset` to the end of step `step` as the C loop does: (status or None, state,
        offset, n_out, pattern); the state self.x is updated in place, transitions stored."""
        h, x, events_in_step = self.h, self.x, 0
        while True:
            remaining = h - offset
            if remaining < self.smallest * (1.0 - 1e-9):
                if remaining > 0.0:  # sub-sliver close
                    self.taylor_step(state, remaining)
                return None, state, offset, n_out, 0
            level, trial, crossed, events = self.trial_step(state, remaining)
            if not crossed:
                x[:] = trial
                offset += self.chunk[level]
                continue
            start, fraction, left, right = self.crossing(state, x, level, events)
            x[:] = left + fraction * (right - left)
            offset += start + fraction * self.smallest
            pattern = self.switch_pattern(state, int(self.patterns[state]), x, right)
            events_in_step += 1
            status, state = self.enter(state, pattern, events_in_step)
            if status is not None:
                return status, state, offset, n_out, pattern
            self.store(n_out, step * h + offset, x, state)
            n_out += 1

    def taylor_step(self, state: int, remaining: float) -> None:
        """Close a step shorter than the finest level by a second-order Taylor step (self.x in place)."""
        matrix_t = self.matrices[state]
        x = self.x
        tmp = x @ matrix_t
        x += remaining * tmp + 0.5 * remaining * remaining * (tmp @ matrix_t)

    def trial_step(self, state: int, remaining: float):
        """The chunk the C loop tries from self.x: the longest level within `remaining`, halved while an
        event function may cross and come back inside it (excursion_between): (level, the state at its
        end, whether an event row crossed, the state's event rows)."""
        level = 0
        while level < self.levels and self.chunk[level] > remaining * (1.0 + 1e-12):
            level += 1
        x = self.x
        events, rates = self.state_events(state)
        g_x, d_x = events @ x, rates @ x
        trial = self.step_with(state, level, x)
        g_t = events @ trial
        crossed = g_t.size > 0 and g_t.max() > EVENT_TOLERANCE
        while not crossed and level < REFINE_LEVELS and excursion_between(g_x, d_x, g_t, rates @ trial,
                                                                         self.chunk[level]):
            level += 1
            trial = self.step_with(state, level, x)
            g_t = events @ trial
            crossed = g_t.max() > EVENT_TOLERANCE
        return level, trial, crossed, events

    def enter(self, state: int, pattern: int, events_in_step: int) -> tuple[int | None, int]:
        """(status or None, state) after a transition to `pattern`, the events_in_step-th of the step:
        FLIGHT if flight is not allowed, NEED_STATE if the pattern has no state yet, CHATTER (in the new
        state) at MAX_EVENTS_PER_STEP."""
        if (pattern & self.all_lifted) == self.all_lifted and not self.allow_flight:  # story bits aside
            return FLIGHT, state
        found = np.flatnonzero(self.patterns[:self.count] == pattern)
        if found.size == 0:
            return NEED_STATE, state
        state = int(found[0])
        return (CHATTER if events_in_step >= MAX_EVENTS_PER_STEP else None), state

    def store(self, n_out: int, time: float, x: np.ndarray, state: int) -> None:
        self.out_t[n_out], self.out_x[n_out], self.out_state[n_out] = time, x, state

    # ------------------------------------------------------------------ blocks of whole steps
    def run_blocks(self, state: int, step: int, n_out: int, size: int) -> int:
        """Up to `size` whole steps from step `step` (offset 0) at once; stores the samples of the
        steps that need nothing more and returns their count (the next step, if any of the
        `size`, needs finish_step)."""
        if state not in self.blocks:
            events, rates = self.state_events(state)
            operator = self.ops[self.slots[state], 0].T
            self.blocks[state] = _Block(operator, events, rates, self.free, self.ia, self.islope)
        block, x = self.blocks[state], self.x
        count = -(-size // BLOCK)
        inputs = np.zeros((2, count * BLOCK))
        inputs[0, :size], inputs[1, :size] = self.ground[step:step + size], self.slopes[step:step + size]
        inputs = inputs.reshape(2, count, BLOCK).transpose(1, 0, 2).reshape(count, 2 * BLOCK)
        forced = (inputs @ block.forcing).reshape(count, BLOCK, -1)
        starts = np.empty((count, self.free.size))
        starts[0] = x[self.free]
        for k in range(1, count):
            starts[k] = starts[k - 1] @ block.last + forced[k - 1, -1]
        moved = (starts @ block.powers).reshape(count, BLOCK, -1) + forced
        states = np.empty((size + 1, self.n))
        states[0] = x
        states[1:, self.free] = moved.reshape(count * BLOCK, -1)[:size]
        states[1:, self.ia] = self.ground[step + 1:step + size + 1]
        states[1:, self.islope] = self.slopes[step + 1:step + size + 1]
        n_e = block.checks.shape[0] // 4
        # a sum is finite where every term is (or a spurious flag: finish_step checks each)
        needs = ~np.isfinite(states[1:] @ np.ones(self.n))
        if n_e:  # one row per event function, one column per step
            g_x, d_x, g_t, d_t = (block.checks[k * n_e:(k + 1) * n_e] @ states[:size].T for k in range(4))
            needs |= np.logical_or.reduce(g_t > EVENT_TOLERANCE, axis=0)
            before = int(np.argmax(needs)) if needs.any() else size  # the steps up to the first flagged
            needs[:before] = excursion_between(g_x[:, :before], d_x[:, :before], g_t[:, :before], d_t[:, :before],
                                               self.chunk[0])
        done = int(np.argmax(needs)) if needs.any() else size
        if done:
            self.out_x[n_out:n_out + done] = states[1:done + 1]
            self.out_t[n_out:n_out + done] = np.arange(step + 1, step + done + 1) * self.h
            self.out_state[n_out:n_out + done] = state
            x[:] = states[done]
        return done


def integrate(states, elements, grid, samples, state: int, step: int, offset: float,
              n_out: int, builds=None) -> tuple[int, int, float, int, int, int]:
    """Advance from (step, offset) to the end of the ground-motion grid (stepping_kernels.integrate; builds is
    not read: the twin builds no state, NEED_STATE for every pattern without one, the caller builds it)."""
    loop = _Loop(states, elements, grid, samples)
    n_steps, capacity, x = loop.ground.size - 1, loop.out_t.size, loop.x
    run = BLOCK  # steps of the next run of blocks
    while step < n_steps:
        if n_out + MAX_EVENTS_PER_STEP + 1 > capacity:
            return FULL, step, offset, state, n_out, int(loop.patterns[state])
        if offset == 0.0:
            x[loop.ia], x[loop.islope] = loop.ground[step], loop.slopes[step]
            # whole steps before the last one, as long as the sample buffer holds them
            size = min(run, n_steps - 1 - step, capacity - MAX_EVENTS_PER_STEP - n_out)
            if size > 0:
                done = loop.run_blocks(state, step, n_out, size)
                step, n_out = step + done, n_out + done
                run = min(2 * run, RUN_BLOCKS * BLOCK) if done == size else BLOCK
                if done:
                    continue
        status, state, offset, n_out, pattern = loop.finish_step(state, step, offset, n_out)
        if status is not None:
            return status, step, offset, state, n_out, pattern
        step += 1
        offset = 0.0
        x[loop.ia] = loop.ground[step]
        if step < n_steps:  # the sample opens the next interval: it carries that interval's ground slope
            x[loop.islope] = loop.slopes[step]
        if not np.isfinite(x).all():
            return NONFINITE, step, offset, state, n_out, int(loop.patterns[state])
        loop.store(n_out, step * loop.h, x, state)
        n_out += 1
    return DONE, step, offset, state, n_out, int(loop.patterns[state])
