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

from .expm import expm
from .modal import vertical_period
from .statespace import ContactState, Layout, StateSpace, stacked


def pattern_bits(pattern: int, n_elements: int) -> tuple[np.ndarray, np.ndarray]:
    """(lifted, yielding) of each element in a contact pattern with a capacity (bits i and n_e + i)."""
    bits = np.array([(pattern >> i) & 1 for i in range(2 * n_elements)], dtype=bool)
    return bits[:n_elements], bits[n_elements:]


def valid_pattern(pattern: int, n_elements: int) -> bool:
    """False where some element would be lifted and yielding at once (no such state: theory 14.2)."""
    lifted, yielding = pattern_bits(pattern, n_elements)
    return not np.any(lifted & yielding)


def event_rows(terms: list[StateSpace], lay: Layout, lifted: np.ndarray, yielding: np.ndarray,
               edge_velocity: np.ndarray, criterion: str) -> np.ndarray:
    """The 2 n_e event rows of each item of a batch of patterns (lifted, yielding) (R, n_e) with a
    bearing capacity (theory 14.2; > 0: the element switches), edge_velocity (R, n_e, n_aug): X -> v_i';
    dimensionless: forces by W, displacements by the static settlement delta_st, velocities by g / w_v."""
    contact = ~lifted & ~yielding
    n_aug = lay.n_aug
    unit = np.eye(n_aug)
    s_rows, z_rows, one = unit[lay.settlement_indices], unit[lay.z_indices], unit[lay.index_one]
    weight = np.array([t.weight for t in terms])[:, None, None]
    settlement = np.array([t.settlement for t in terms])[:, None, None]
    # delta_st w_v = g / w_v, w_v = 2 pi / T_v the bonded vertical frequency
    vertical = np.array([2.0 * np.pi / vertical_period(t.model) for t in terms])[:, None, None]
    k_el, c_el = stacked(terms, "element_stiffness")[:, :, None], stacked(terms, "element_damping")[:, :, None]
    q_el = stacked(terms, "element_capacity")[:, :, None]
    spring = stacked(terms, "displacement_rows") - s_rows  # v_i - s_i
    # lift-off: F_i > 0 [4a] or v_i - s_i > 0 [4b]
    separation = (k_el * spring + c_el * edge_velocity) / weight if criterion == "reaction" else spring / settlement
    top = np.where(c_el > 0.0, z_rows, s_rows)  # where a lifted element's top is
    recontact = (top - stacked(terms, "displacement_rows")) / settlement
    onset = -(k_el * spring + q_el * one) / weight
    unloading = edge_velocity / (settlement * vertical)
    never = np.broadcast_to(-one, spring.shape)
    first = np.where(lifted[:, :, None], recontact, np.where(yielding[:, :, None], never, separation))
    second = np.where(contact[:, :, None], onset, np.where(yielding[:, :, None], unloading, never))
    return np.concatenate((first, second), axis=1)


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
                   out: list[np.ndarray] | None = None) -> list[np.ndarray]:
    """E_j^T = expm(A h / 2^j)^T, j = 0..levels, of contact states with a bearing capacity, from the
    exponential of a small block of each (docs/theory.md 14.3), written into out[r] (levels + 1,
    n_aug, n_aug) each, which hold zeros (new arrays if None), and returned. Of the augmented state, the rows of A
    that are not coupled back into the motion are
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
    The finest level by expm, the coarser ones by squaring it, level 0 by its own expm (as
    operators.add_states), all the states' blocks in one stacked call. tests/test_operators.py
    compares every level with expm(A h/2^j)."""
    blocks, core, loads = coupled_blocks(space, states)
    lengths = h / 2.0 ** np.arange(levels + 1)
    count, size = blocks.shape[:2]
    ends_of = expm(np.concatenate((blocks * lengths[levels], blocks * h)))
    block = np.empty((count, levels + 1, size, size))
    block[:, levels], block[:, 0] = ends_of[:count], ends_of[count:]
    for j in range(levels - 1, 0, -1):
        block[:, j] = block[:, j + 1] @ block[:, j + 1]
    n = space.layout.n_aug
    out = [np.zeros((levels + 1, n, n)) for _ in states] if out is None else out
    for r, state in enumerate(states):
        _assemble(space, state, block[r], core, loads, lengths, out[r])
    return out


def coupled_blocks(space: StateSpace, states: list[ContactState]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The blocks B (R, n_c + 2, n_c + 2) whose exponentials give the states' step operators
    (step_operators): the rows and columns of A of the motion and the forcing entries (core: their
    n_c indices in X), and the two columns G of the mat's forces (_load_columns); with core and
    loads (2, n_e), the mat's vertical force and moment per unit s_i (k_i e_i on (theta, v))."""
    lay = space.layout
    passive = np.zeros(lay.n_aug, dtype=bool)
    passive[lay.z_indices] = passive[lay.settlement_indices] = True
    core = np.flatnonzero(~passive)
    mat = np.flatnonzero(np.any(space.directions != 0.0, axis=0))  # the mat's coordinates (theta, v)
    n_c, n_f = core.size, mat.size
    loads = (space.element_stiffness[:, None] * space.directions[:, mat]).T  # (n_f, n_e)
    blocks = np.zeros((len(states), n_c + n_f, n_c + n_f))
    for r, state in enumerate(states):
        blocks[r, :n_c, :n_c] = state.matrix[np.ix_(core, core)]
        contact = np.flatnonzero(~state.lifted & ~state.yielding)
        if contact.size:
            blocks[r, :n_c, n_c:] = _load_columns(state.matrix[core], lay.settlement_indices, loads, contact)
    return blocks, core, loads


def _load_columns(rows: np.ndarray, s_idx: np.ndarray, loads: np.ndarray, contact: np.ndarray) -> np.ndarray:
    """G (n_core, 2), the columns of the mat's two forces in A, from the columns of s_i in the core
    rows of A (rows[:, s_i] = G loads[:, i]): from the two elements in contact furthest apart
    (G = [a_i a_j] [l_i l_j]^-1, the 2 x 2 inverse written out), or from the one (the least-norm
    G = a_i l_i^T / |l_i|^2, exact for it and no other column needed). The first and last in
    contact are the furthest apart, and [l_i l_j] = [[-k_i x_i, -k_j x_j], [k_i, k_j]] is singular
    only if x_i = x_j: the positions of foundations.Winkler, the only foundation with more than two
    elements, increase strictly (tests/test_operators.py: the closest pair too)."""
    i, j = contact[0], contact[-1]
    if i == j:
        return np.outer(rows[:, s_idx[i]], loads[:, i]) / (loads[:, i] @ loads[:, i])
    (a, b), (c, d) = loads[:, i], loads[:, j]  # the 2 x 2 [l_i l_j] = [[a, c], [b, d]]
    det = a * d - b * c
    return np.outer(rows[:, s_idx[i]], [d / det, -c / det]) + np.outer(rows[:, s_idx[j]], [-b / det, a / det])


def _assemble(space: StateSpace, state: ContactState, block: np.ndarray, core: np.ndarray, loads: np.ndarray,
              lengths: np.ndarray, out: np.ndarray) -> None:
    """out (levels + 1, n_aug, n_aug), zeros, := E_j^T of one state from the exponentials of its
    block (step_operators), the rows left out in closed form. Only the nonzero entries are written
    (a fill of the 450 kB of each state of the 20-element mat cost a tenth of its run, measured),
    by slices: the coupled entries are the motion X[:n_m] and the forcing X[n_x:] (core)."""
    lay = space.layout
    s_idx, z_idx, n_c, n_x = lay.settlement_indices, lay.z_indices, core.size, lay.n_x
    n_m = n_c - (lay.n_aug - n_x)
    block_t = block.transpose(0, 2, 1)  # exp(B l)^T: out[j, b, a] = E_j[a, b]
    out[:, :n_m, :n_m] = block_t[:, :n_m, :n_m]
    out[:, :n_m, n_x:] = block_t[:, :n_m, n_m:n_c]
    out[:, n_x:, :n_m] = block_t[:, n_m:n_c, :n_m]
    out[:, n_x:, n_x:] = block_t[:, n_m:n_c, n_m:n_c]
    contact = ~state.lifted & ~state.yielding
    settled = loads[:, contact].T @ block_t[:, n_c:, :n_c]  # the rows s_i (in contact) of E^T
    out[:, s_idx[contact], :n_m] = settled[:, :, :n_m]
    out[:, s_idx[contact], n_x:] = settled[:, :, n_m:]
    out[:, s_idx, s_idx] = 1.0
    relaxing = state.lifted & (space.element_damping > 0.0)
    out[:, z_idx[~relaxing], z_idx[~relaxing]] = 1.0
    rate = space.element_stiffness[relaxing] / space.element_damping[relaxing]
    out[:, z_idx[relaxing], z_idx[relaxing]] = np.exp(-np.outer(lengths, rate))
    out[:, s_idx[relaxing], z_idx[relaxing]] = -np.expm1(-np.outer(lengths, rate))
    # a yielding s_i: its row of E is d_i E - d_i + the unit row, with v_i = d_i X reading the mat's
    # coordinates only (within X[:n_m])
    rows = space.displacement_rows[state.yielding]
    out[:, :, s_idx[state.yielding]] += out[:, :, :n_m] @ rows[:, :n_m].T - rows.T
