"""Contact states of a foundation whose elements yield (docs/theory.md section 14): their pattern bits,
event rows, event resets and step operators (patterns.contact_states assembles their A).

Each contact element with a bearing capacity Q_i is in one of three states: C (elastic contact),
Y (yielding) or L (lifted) (theory 14.1). The augmented state gains the plastic settlements s_i
(Layout.settlement_indices), and every state stays linear (theory 14.3):

- C: stiffness + k_i e_i^T e_i, damping + c_i e_i^T e_i, forcing + k_i e_i^T in the column of s_i
  (the spring acts on v_i - s_i);
- Y: damping + c_i e_i^T e_i, forcing + Q_i e_i^T in the column of the constant 1, and the row of
  s_i in A is the velocity row of v_i (s_i' = v_i');
- L: nothing on the mat; z_i' = -(k_i/c_i)(z_i - s_i) (c_i > 0; z_i = s_i when c_i = 0).

Two event rows per element (theory 14.2): row i the lift-off (C) or the recontact at the settled
level (L), row n_e + i the onset of yield (C) or the elastic unloading (Y); a row that cannot
cross in a state is the constant -1. A crossing of row r flips bit r of the contact pattern
(bit i: lifted, bit n_e + i: yielding) and, when the bit turns on, sets one state entry from
event_resets (the top of a lifting element, z_i := v_i; the settlement at the onset of yield,
s_i := v_i + Q_i/k_i, the spring exactly at its capacity).
"""

from __future__ import annotations

import numpy as np

from ...runtime import backend
from .kept import kept
from .soil_operators_numpy import blocks
from .statespace import ContactState, StateSpace


def pattern_bits(pattern: int, n_elements: int) -> tuple[np.ndarray, np.ndarray]:
    """(lifted, yielding) of each element in a contact pattern with a capacity (bits i and n_e + i)."""
    bits = ((np.int64(pattern) >> np.arange(2 * n_elements, dtype=np.int64)) & 1).astype(bool)
    return bits[:n_elements], bits[n_elements:]


def valid_pattern(pattern: int, n_elements: int) -> bool:
    """False where some element would be lifted and yielding at once (no such state: theory 14.2): bits i and
    n_e + i both set (pattern_bits; on Python's integers, asked once per state built)."""
    pattern = int(pattern)
    return not pattern & (pattern >> n_elements) & ((1 << n_elements) - 1)


def event_resets(space: StateSpace) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(index, rows, with_row) per event row: when a crossing of row r turns its pattern bit on,
    X[index[r]] := rows[r] . X where with_row[r], else 0 (stepping_kernels.Elements). Elastic
    elements: the top of a lifting element, z_i := v_i (c_i > 0; 0 without a dashpot); with a
    capacity also z_i := s_i without a dashpot, and s_i := v_i + Q_i/k_i at the onset of yield."""
    lay = space.layout
    damped = space.element_damping > 0.0
    if not lay.n_settlements:
        return lay.z_indices, space.displacement_rows, damped
    unit = np.eye(lay.n_aug)
    lift = np.where(damped[:, None], space.displacement_rows, unit[lay.settlement_indices])
    onset = space.displacement_rows + (space.element_capacity / space.element_stiffness)[:, None] \
        * unit[lay.index_one]
    return (np.concatenate((lay.z_indices, lay.settlement_indices)), np.vstack((lift, onset)),
            np.ones(2 * lay.n_elements, dtype=bool))


def step_operators(space: StateSpace, states: list[ContactState], h: float, levels: int,
                   out: np.ndarray | list[np.ndarray] | None = None) -> list[np.ndarray]:
    """E_j^T = expm(A h / 2^j)^T, j = 0..levels, of contact states with a bearing capacity, from the
    exponential of a small block of each (docs/theory.md 14.3), written into out (R, levels + 1, n_aug,
    n_aug), or into out[r] (levels + 1, n_aug, n_aug) each, of any contents (new arrays if None), and
    returned per state. Of the augmented state, the rows of A that are not coupled back into the motion are
    - z_i: k_i (z_i - s_i) + c_i z_i' = 0 while lifted (c_i > 0), else z_i' = 0: in closed form,
      z_i(t) = e^(-r t) z_i + (1 - e^(-r t)) s_i with r = k_i / c_i;
    - s_i, constant unless the element yields (s_i' = v_i': s_i - v_i stays constant, so the row
      of E is that of v_i, d_i E, plus the unit row of s_i, minus d_i);
    no other row reads them but the motion, which the s_i of the elements in contact load only
    through the mat's two forces (vertical force and moment: the column of s_i in A is k_i e_i
    applied to the columns G of those two forces, e_i the mat's row of v_i). So the block
    exponentiated is the motion and the forcing entries (a_g, a_g', 1) with the two columns G:
    23 + 3 + 2 = 28 of the 66 entries of the 20-element mat of benchmarks/bench_yielding.py,
    whatever the contact pattern; the columns of s_i in E are those of the two forces times k_i e_i.
    Level s, the squarings the exponential of B h scales by (10 on that mat at h = 0.01 s: its norm is that
    of the large columns G), by the exponential and the coarser ones by squaring it down to level 0 (the
    products expm(B h) makes, so level 0 is what it gives); the finest by the exponential and the levels
    between by squaring it: 11 squarings instead of 21 for the finest squared down to level 1 and level 0
    on its own, and levels 1..s - 1 more accurate (6.6e-14 of the largest entry at level 1 instead of
    5.8e-13). By the compiled loop _soil_operators.c or its twin soil_operators_numpy.py
    (upliftcli.runtime.backend). tests/test_operators.py compares every level with expm(A h/2^j)."""
    n = space.layout.n_aug
    if out is None:
        out = np.empty((len(states), levels + 1, n, n))
    if isinstance(out, np.ndarray):
        _soil_operators(space, states, h, out)
        return list(out)
    for state, slot in zip(states, out, strict=True):
        _soil_operators(space, [state], h, slot[None])
    return list(out)


def _loops():
    """The module that builds the block operators: _soil_operators (C) or soil_operators_numpy
    (upliftcli.runtime.backend)."""
    return backend.loops(f"{__package__}._soil_operators", f"{__package__}.soil_operators_numpy")


def _soil_operators(space: StateSpace, states: list[ContactState], h: float, out: np.ndarray) -> None:
    """step_operators of `states` into the stack out (R, levels + 1, n_aug, n_aug), of any contents."""
    core, loads, damped, rates, displacement, n_motion = kept(space, _block_terms)
    if len(states) == 1:
        lifted, yielding, matrices = states[0].lifted[None], states[0].yielding[None], states[0].matrix[None]
    else:
        lifted = np.array([state.lifted for state in states], dtype=bool)
        yielding = np.array([state.yielding for state in states], dtype=bool)
        matrices = np.stack([state.matrix for state in states])
    lay = space.layout
    _loops().soil_operators(np.ascontiguousarray(matrices), ~lifted & ~yielding, np.ascontiguousarray(yielding),
                            lifted & damped, core, lay.settlement_indices, lay.z_indices, loads, displacement, rates,
                            float(h), n_motion, out)


def _block_terms(space: StateSpace) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]:
    """What the block operators of every state of a model share (kept.kept): core and loads (_core), where
    the elements have a dashpot, k_i / c_i there (0 elsewhere), the rows d_i of v_i = d_i X and the size of
    the motion X[:n_m]."""
    lay = space.layout
    core, loads = _core(space)
    damped = space.element_damping > 0.0
    rates = np.divide(space.element_stiffness, space.element_damping, out=np.zeros(lay.n_elements), where=damped)
    return (core, np.ascontiguousarray(loads), damped, rates, np.ascontiguousarray(space.displacement_rows),
            core.size - (lay.n_aug - lay.n_x))


def _core(space: StateSpace) -> tuple[np.ndarray, np.ndarray]:
    """The indices in X of the motion and the forcing entries (the block's rows and columns but the
    two of the mat's forces), and loads (2, n_e): the mat's vertical force and moment per unit s_i
    (k_i e_i on (theta, v))."""
    lay = space.layout
    passive = np.zeros(lay.n_aug, dtype=bool)
    passive[lay.z_indices] = passive[lay.settlement_indices] = True
    mat = np.flatnonzero(np.any(space.directions != 0.0, axis=0))  # the mat's coordinates (theta, v)
    return np.flatnonzero(~passive), (space.element_stiffness[:, None] * space.directions[:, mat]).T


def coupled_blocks(space: StateSpace, states: list[ContactState]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The blocks B (R, n_c + 2, n_c + 2) whose exponentials give the states' step operators
    (step_operators): the rows and columns of A of the motion and the forcing entries (core: their
    n_c indices in X), and the two columns G of the mat's forces (soil_operators_numpy.load_columns);
    with core and loads (2, n_e), the mat's vertical force and moment per unit s_i (k_i e_i on (theta, v))."""
    core, loads = _core(space)
    contact = np.array([~state.lifted & ~state.yielding for state in states], dtype=bool)
    matrices = np.stack([state.matrix for state in states])
    return blocks(matrices, contact, core, space.layout.settlement_indices, loads), core, loads
