"""The signals of a history at its samples (response.signals): their layout, and their rows in each contact state.

Each signal is a linear functional of the augmented state X, its rate one of X' = A X and its second rate one of
X'' = A X': the rows R of the values, R A of the rates and R A^2 of the second rates, built for every contact
state the samples use (a yielding run meets a hundred or more: response_kernels.state_rows), then multiplied by X
at each sample (response_kernels.evaluate_signals).
"""

from __future__ import annotations

import functools

import numpy as np

from . import response_kernels
from .statespace import StateSpace
from .stepping import History

#: signals with rates: those the work integrals use first (energy.py), then Y*'' and the mat's
#: rotation and vertical displacement (the rocking peaks between samples, mat_motion.py)
WITH_RATES = ("Ydot", "a", "input", "element_velocity", "z", "Yddot", "theta", "v", "Pdot")
VALUES_ONLY = ("Y", "element_displacement", "P")


@functools.cache
def signal_layout(n_modes: int, n_elements: int, n_plastic: int = 0) -> dict[str, slice]:
    """The columns of each signal (WITH_RATES first, in order, then VALUES_ONLY); P, Pdot: the plastic
    drifts of the yielding stories and their rates (none for an elastic building)."""
    sizes = {"Ydot": n_modes, "a": 1, "input": 1, "element_velocity": n_elements, "z": n_elements,
             "Yddot": n_modes, "Y": n_modes, "theta": 1, "v": 1, "element_displacement": n_elements,
             "Pdot": n_plastic, "P": n_plastic}
    names, start = {}, 0
    for name in WITH_RATES + VALUES_ONLY:
        names[name] = slice(start, start + sizes[name])
        start += sizes[name]
    return names


def curvature_columns(names: dict[str, slice]) -> dict[str, slice]:
    """The slope columns of the second derivatives of the signals the work integrals interpolate (energy.py):
    Y*'' rates for Y*', then one column for the input signal and one per element velocity after the
    slopes of WITH_RATES."""
    last = names[WITH_RATES[-1]].stop
    n_curved = names["element_velocity"].stop - names["input"].start
    return {"Ydot": names["Yddot"], "input": slice(last, last + 1),
            "element_velocity": slice(last + 1, last + n_curved)}


def _sizes(names: dict[str, slice]) -> tuple[int, int, int]:
    """(the value columns k, the slope columns of WITH_RATES, all the slope columns with the curvatures)."""
    start, n_slopes = names[VALUES_ONLY[-1]].stop, names[WITH_RATES[-1]].stop
    return start, n_slopes, curvature_columns(names)["element_velocity"].stop


#: a run with at most this many contact states has the signal rows of all built (signals); with more those used
FEW_STATES = 8


def used_states(state_ids: np.ndarray, n_states: int) -> tuple[np.ndarray, np.ndarray]:
    """(the state ids the samples use, ascending; each sample's index among them (int64)): np.unique's
    (values, inverse), by a count and a table lookup instead of a sort; every state of a few (FEW_STATES)."""
    ids = np.asarray(state_ids, dtype=np.int64)
    if n_states <= FEW_STATES:  # the rows of every state: fewer than counting the samples' states costs
        return np.arange(n_states), ids
    used = np.flatnonzero(np.bincount(ids, minlength=n_states))
    if used.size == n_states:
        return used, ids
    index = np.zeros(n_states, dtype=np.int64)
    index[used] = np.arange(used.size)
    return used, index[ids]


def _value_rows(space: StateSpace, names: dict[str, slice], velocity: np.ndarray, rows: np.ndarray) -> None:
    """Write the rows of the signals' values (rows: (S, k + ..., n_aug), each state's velocity map velocity (S or 1,
    n_p, n_aug)) but those of Y*'' and P' (the rates of Y*' and P: the caller's)."""
    model, lay = space.model, space.layout
    for name in ("a", "z", "theta", "v", "P"):  # the rows not written whole below (np.zeros: 3.5 MB set)
        rows[:, names[name]] = 0.0
    rows[:, names["Y"]] = space.modal
    rows[:, names["Ydot"]] = space.to_modal @ velocity
    if model.flexible:
        rows[:, names["theta"]] = space.position[model.n_modes]
        rows[:, names["v"]] = space.position[model.n_modes + 1]
    rows[:, names["a"].start, lay.index_acceleration] = 1.0
    rows[:, names["input"]] = (space.forcing[:, lay.index_acceleration] @ velocity)[:, None, :]
    rows[:, names["element_velocity"]] = space.directions @ velocity
    rows[:, names["element_displacement"]] = space.displacement_rows
    z_rows = np.arange(names["z"].start, names["z"].stop)
    rows[:, z_rows, lay.z_indices] = 1.0
    if lay.n_settlements:  # with a capacity, deformations of the springs: v_i - s_i, z_i - s_i (theory 14.5)
        rows[:, np.arange(names["element_displacement"].start, names["element_displacement"].stop),
             lay.settlement_indices] -= 1.0
        rows[:, z_rows, lay.settlement_indices] -= 1.0
    if lay.n_plastic:  # the plastic drifts (docs/theory.md 15)
        rows[:, np.arange(names["P"].start, names["P"].stop), lay.plastic_indices] = 1.0


def signal_rows(history: History, used: np.ndarray) -> np.ndarray:
    """The rows of the signals (signal_layout) in each contact state `used` (S, k + k_s, n_aug): the values' rows,
    the slopes' (R A), the curvatures' of the input signal and element velocities (R A^2, curvature_columns; Y*''
    gives those of Y*'). Products written in place (matmul's out), those of a shared velocity map once."""
    space = history.space
    lay = space.layout
    names = signal_layout(space.model.n_modes, lay.n_elements, lay.n_plastic)
    start, n_slopes, width = _sizes(names)
    velocity = _velocity(history.contact, used)  # (S or 1, n_p, n_aug)
    matrix = np.stack([history.contact[s].matrix for s in used])
    rows = np.empty((used.size, start + width, lay.n_aug))
    _value_rows(space, names, velocity, rows)
    np.matmul(rows[:, names["Ydot"]], matrix, out=rows[:, names["Yddot"]])
    if lay.n_plastic:  # the rates of the plastic drifts
        rows[:, names["Pdot"]] = matrix[:, lay.plastic_indices]
    np.matmul(rows[:, :n_slopes], matrix, out=rows[:, start:start + n_slopes])
    rates = start + names["input"].start  # the rates' rows of the input signal and element velocities
    np.matmul(rows[:, rates:rates + width - n_slopes], matrix, out=rows[:, start + n_slopes:])
    return rows


def _velocity(contact: list, used: np.ndarray) -> np.ndarray:
    """The velocity maps X -> p' of the states `used` (S, n_p, n_aug), or the one all share (1, n_p, n_aug: the
    fixed and bonded bases)."""
    first = contact[used[0]].velocity
    if all(contact[s].velocity is first for s in used):
        return first[None]
    return np.stack([contact[s].velocity for s in used])


def _evaluate(x: np.ndarray, ids: np.ndarray, rows: np.ndarray, start: int) -> tuple[np.ndarray, np.ndarray]:
    """(values, slopes) of rows[ids[i]] x[i] at each i (evaluate_signals; its left limits, where the ids change,
    dropped)."""
    values, slopes = np.empty((ids.size, start)), np.empty((ids.size, rows.shape[1] - start))
    n_switch = int(np.count_nonzero(ids[1:] != ids[:-1]))
    response_kernels.evaluate_signals(x, ids, rows, values, slopes, np.empty((n_switch, rows.shape[1])))
    return values, slopes


def evaluated(history: History, used: np.ndarray, ids: np.ndarray, at: np.ndarray) -> tuple:
    """(values, slopes, end values, end slopes, each state's slope rows' coefficients on the ground slope (S, k_s))
    of the signals; at: the intervals that end at a transition. From the rows of every state used (signal_rows;
    response_kernels.evaluate_signals), or, with yielding stories and more than FEW_STATES states of fewer than
    SPLIT_USES products, from them for the others only (_mixed)."""
    if history.space.layout.n_plastic and np.count_nonzero(_uses(ids, at, used.size) < SPLIT_USES) > FEW_STATES:
        return _mixed(history, used, ids, at)
    lay = history.space.layout
    rows = signal_rows(history, used)
    start = _sizes(signal_layout(history.space.model.n_modes, lay.n_elements, lay.n_plastic))[0]
    values, slopes = np.empty((ids.size, start)), np.empty((ids.size, rows.shape[1] - start))
    ends = np.empty((at.size, rows.shape[1]))
    response_kernels.evaluate_signals(history.states, ids, rows, values, slopes, ends)
    return (values, slopes, np.ascontiguousarray(ends[:, :start]), np.ascontiguousarray(ends[:, start:]),
            rows[:, start:, lay.index_slope])


#: with yielding stories, a state whose rows serve fewer products than this (its samples and left limits) has its
#: signals from the derivatives of its samples instead (_mixed; _signals.c splits the rows of the others)
SPLIT_USES = 32


def _uses(ids: np.ndarray, at: np.ndarray, n_states: int) -> np.ndarray:
    """How many products each state's rows would serve: its samples and the left limits of the intervals it ends."""
    return np.bincount(ids, minlength=n_states) + np.bincount(ids[at], minlength=n_states)


def _mixed(history: History, used: np.ndarray, ids: np.ndarray, at: np.ndarray) -> tuple:
    """evaluated's outputs of a run with yielding stories: a hundred states or more, most of them met at a few
    samples, whose rows (R A, R A^2) would cost more than their products: the states of SPLIT_USES products or
    more from their rows (the bits they always had; evaluate_signals leaves the others' samples, negative ids), the
    others from X' = A X and X'' = A X' at their samples and left limits and the values' rows (_derived: the
    same numbers to round-off)."""
    lay = history.space.layout
    start, _, width = _sizes(signal_layout(history.space.model.n_modes, lay.n_elements, lay.n_plastic))
    many = _uses(ids, at, used.size) >= SPLIT_USES
    rows = signal_rows(history, used[many]) if many.any() else np.zeros((1, start + width, lay.n_aug))
    values, slopes, ends = np.empty((ids.size, start)), np.empty((ids.size, width)), np.empty((at.size, start + width))
    local = np.where(many, np.cumsum(many) - 1, -1 - np.arange(used.size))  # the others each a negative id
    response_kernels.evaluate_signals(history.states, local[ids], rows, values, slopes, ends)
    coefficients = np.empty((used.size, width))
    coefficients[many] = rows[:many.sum(), start:, lay.index_slope]
    out = (values, slopes, np.ascontiguousarray(ends[:, :start]), np.ascontiguousarray(ends[:, start:]), coefficients)
    few, ended = ~many[ids], ~many[ids[at]]
    if few.any():
        _derived(history, used, ~many, np.vstack((history.states[few], history.states[at[ended] + 1])),
                 np.concatenate((ids[few], ids[at][ended])), (np.count_nonzero(few), few, ended), out)
    return out


def _derived(history: History, used: np.ndarray, few: np.ndarray, x: np.ndarray, state_ids: np.ndarray,
             parts: tuple, out: tuple) -> None:
    """_mixed's signals of the states `few` (of `used`) at x (the samples of those states, then the left limits of
    the intervals they end), state_ids the ids of their states: from X' = A X and X'' = A X' (derivatives) and the
    rows of each velocity map (rate_rows), into out where parts (the number of samples, the samples and the left
    limits of these states) say."""
    space = history.space
    names = signal_layout(space.model.n_modes, space.layout.n_elements, space.layout.n_plastic)
    states = used[few]
    local = (np.cumsum(few) - 1)[state_ids]
    matrices = [history.contact[s].matrix for s in states]
    velocity, group = _velocity_groups(history.contact, states)
    rows = rate_rows(space, velocity)
    # the derivatives of x, then of a unit ground slope in each state (_ground_slope), in one call: the states' A
    # transposed once
    unit = np.zeros((states.size, x.shape[1]))
    unit[:, space.layout.index_slope] = 1.0
    both = np.vstack((x, unit))
    first, second = np.empty(both.shape), np.empty(both.shape)
    response_kernels.derivatives(both, np.concatenate((local, np.arange(states.size, dtype=np.int64))), matrices,
                                 first, second)
    n = x.shape[0]
    values, slopes = _signals_of(names, rows, group[local], x, first[:n], second[:n])
    n_samples, sampled, ended = parts
    out[0][sampled], out[1][sampled] = values[:n_samples], slopes[:n_samples]
    out[2][ended], out[3][ended] = values[n_samples:], slopes[n_samples:]
    out[4][few] = _ground_slope(second[n:], group, rows[2], names)


def rate_rows(space: StateSpace, velocity: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The rows (G, ., n_aug) of each velocity map (G, n_p, n_aug) that give the signals from X, X' and X'': the
    values' on X; on X' the slopes' of WITH_RATES (their values' rows: a rate is the same row on the next
    derivative), Y*'' and P' those of Y*' and P (their values); on X'' those of Y*' and P (the slopes of Y*'' and
    P') and of the input signal and element velocities (their curvatures, curvature_columns)."""
    lay = space.layout
    names = signal_layout(space.model.n_modes, lay.n_elements, lay.n_plastic)
    start, n_slopes, _ = _sizes(names)
    values = np.zeros((velocity.shape[0], start, lay.n_aug))
    _value_rows(space, names, velocity, values)
    rates = values[:, :n_slopes].copy()
    rates[:, names["Yddot"]], rates[:, names["Pdot"]] = values[:, names["Ydot"]], values[:, names["P"]]
    second = np.concatenate((values[:, names["Ydot"]], values[:, names["P"]],
                             values[:, names["input"].start:names["element_velocity"].stop]), axis=1)
    return values, rates, second


def _velocity_groups(contact: list, states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(the distinct velocity maps of `states` (G, n_p, n_aug), each state's among them (S,))."""
    first = contact[states[0]].velocity
    if all(contact[s].velocity is first for s in states):
        return first[None], np.zeros(states.size, dtype=np.int64)
    index: dict[int, int] = {}
    maps = {index.setdefault(id(contact[s].velocity), len(index)): contact[s].velocity for s in states}
    return np.stack(list(maps.values())), np.array([index[id(contact[s].velocity)] for s in states], dtype=np.int64)


def _signals_of(names: dict[str, slice], rows: tuple, groups: np.ndarray, x: np.ndarray, first: np.ndarray,
                second: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(values, slopes) of the signals from X, X', X'' (rate_rows' rows of each one's group)."""
    _, n_slopes, width = _sizes(names)
    values, rates, curved = (_evaluate(y, groups, r, r.shape[1])[0] for y, r in zip((x, first, second), rows,
                                                                                       strict=True))
    slopes = np.empty((groups.size, width))
    slopes[:, :n_slopes] = rates
    n_m, n_p = names["Ydot"].stop - names["Ydot"].start, names["P"].stop - names["P"].start
    values[:, names["Yddot"]], values[:, names["Pdot"]] = rates[:, names["Yddot"]], rates[:, names["Pdot"]]
    slopes[:, names["Yddot"]], slopes[:, names["Pdot"]] = curved[:, :n_m], curved[:, n_m:n_m + n_p]
    slopes[:, n_slopes:] = curved[:, n_m + n_p:]
    return values, slopes


def _ground_slope(twice: np.ndarray, group: np.ndarray, second: np.ndarray, names: dict[str, slice]) -> np.ndarray:
    """Each state's slope columns' coefficients on the ground slope (S, k_s) where response._slope_rows reads them
    (the second rates; zeros elsewhere): the rows on X'' (G, ., n_aug) applied to A A e (twice, (S, n_aug)) of a
    unit ground slope e."""
    coefficients = np.empty((group.size, second.shape[1]))
    for g in range(second.shape[0]):
        coefficients[group == g] = twice[group == g] @ second[g].T
    _, n_slopes, width = _sizes(names)
    n_m, n_p = names["Ydot"].stop - names["Ydot"].start, names["P"].stop - names["P"].start
    out = np.zeros((group.size, width))
    out[:, names["Yddot"]], out[:, names["Pdot"]] = coefficients[:, :n_m], coefficients[:, n_m:n_m + n_p]
    out[:, n_slopes:] = coefficients[:, n_m + n_p:]
    return out
