"""The numpy twin of the compiled step operators of a yielding mat of many elements (_soil_operators.c;
upliftcli.runtime.backend chooses between the two): the exponential of a small block of each state's A,
its squarings for the bisection levels, and the operators E_j^T written into each state's slot
(docs/theory.md 14.3; the arguments: soil_operators.py)."""

from __future__ import annotations

import numpy as np

from .expm import THETA_13, expm


def soil_operators(matrices: np.ndarray, contact: np.ndarray, yielding: np.ndarray, relaxing: np.ndarray,
                   core: np.ndarray, settlements: np.ndarray, tops: np.ndarray, loads: np.ndarray,
                   displacement: np.ndarray, rates: np.ndarray, h: float, n_motion: int, out: np.ndarray) -> None:
    """out[r] (levels + 1, n_aug, n_aug), of any contents, := E_j^T = expm(A_r h / 2^j)^T, j = 0..levels, of each
    state r from the exponentials of its block (exponentials), assembled (assemble)."""
    levels = out.shape[1] - 1
    stack = blocks(matrices, contact, core, settlements, loads)
    lengths = h / 2.0 ** np.arange(levels + 1)
    for r, ladder in enumerate(exponentials(stack, h, levels)):
        assemble(ladder, contact[r], yielding[r], relaxing[r], core, settlements, tops, loads,
                 displacement[:, :n_motion], rates, lengths, out[r])


def exponentials(stack: np.ndarray, h: float, levels: int) -> np.ndarray:
    """exp(B h / 2^j), j = 0..levels (R, levels + 1, n, n), of each block B of a stack: level s, the squarings
    expm.expm scales exp(B h) by (at most levels), by expm and the coarser ones by squaring it down to level
    0 (the products expm(B h) makes: level 0 as it gives it, the levels between more accurate than squared
    from the finest); the finest by expm and the levels between by squaring it."""
    norms = np.abs(stack * h).sum(axis=-2).max(axis=-1)
    scalings = np.ceil(np.log2(np.maximum(norms, 1e-300) / THETA_13))
    scalings = np.clip(scalings, 0, levels).astype(int)
    out = np.empty((stack.shape[0], levels + 1, *stack.shape[1:]))
    out[np.arange(stack.shape[0]), scalings] = expm(stack * (h / 2.0**scalings)[:, None, None])
    finest = scalings < levels
    out[finest, levels] = expm(stack[finest] * (h / 2.0**levels))
    for j in range(levels - 1, -1, -1):
        squared = j != scalings  # level s is its own exponential
        out[squared, j] = out[squared, j + 1] @ out[squared, j + 1]
    return out


def blocks(matrices: np.ndarray, contact: np.ndarray, core: np.ndarray, settlements: np.ndarray,
           loads: np.ndarray) -> np.ndarray:
    """The blocks B (R, n_c + 2, n_c + 2) of the states' A (R, n_aug, n_aug): the rows and columns `core`
    (the motion and the forcing entries) and the two columns G of the mat's forces (load_columns; zero
    where no element is in contact)."""
    n_c = core.size
    out = np.zeros((matrices.shape[0], n_c + 2, n_c + 2))
    out[:, :n_c, :n_c] = matrices[:, core[:, None], core[None, :]]
    for r in range(matrices.shape[0]):
        touching = np.flatnonzero(contact[r])
        if touching.size:
            out[r, :n_c, n_c:] = load_columns(matrices[r][core], settlements, loads, touching)
    return out


def load_columns(rows: np.ndarray, settlements: np.ndarray, loads: np.ndarray, contact: np.ndarray) -> np.ndarray:
    """G (n_core, 2), the columns of the mat's two forces in A, from the columns of s_i in the core
    rows of A (rows[:, s_i] = G loads[:, i]): from the two elements in contact furthest apart
    (G = [a_i a_j] [l_i l_j]^-1, the 2 x 2 inverse written out), or from the one (the least-norm
    G = a_i l_i^T / |l_i|^2, exact for it and no other column needed). The first and last in
    contact are the furthest apart, and [l_i l_j] = [[-k_i x_i, -k_j x_j], [k_i, k_j]] is singular
    only if x_i = x_j: the positions of foundations.Winkler, the only foundation with more than two
    elements, increase strictly (tests/test_operators.py: the closest pair too)."""
    i, j = contact[0], contact[-1]
    if i == j:
        return np.outer(rows[:, settlements[i]], loads[:, i]) / (loads[:, i] @ loads[:, i])
    (a, b), (c, d) = loads[:, i], loads[:, j]  # the 2 x 2 [l_i l_j] = [[a, c], [b, d]]
    det = a * d - b * c
    return np.outer(rows[:, settlements[i]], [d / det, -c / det]) + np.outer(rows[:, settlements[j]],
                                                                             [-b / det, a / det])


def assemble(block: np.ndarray, contact: np.ndarray, yielding: np.ndarray, relaxing: np.ndarray, core: np.ndarray,
             settlements: np.ndarray, tops: np.ndarray, loads: np.ndarray, motion_rows: np.ndarray,
             rates: np.ndarray, lengths: np.ndarray, out: np.ndarray) -> None:
    """out (levels + 1, n_aug, n_aug), of any contents (an earlier run's: kept.reused), := E_j^T of one state
    from the exponentials of its block, the rows left out in closed form. motion_rows: the rows d_i of
    v_i = d_i X on the motion X[:n_m]; rates: k_i / c_i of the relaxing tops."""
    n_c, n_m = core.size, motion_rows.shape[1]
    block_t = block.transpose(0, 2, 1)  # exp(B l)^T: out[j, b, a] = E_j[a, b]
    out[...] = 0.0
    out[:, core[:, None], core[None, :]] = block_t[:, :n_c, :n_c]
    settled = loads[:, contact].T @ block_t[:, n_c:, :n_c]  # the rows s_i (in contact) of E^T
    out[:, settlements[contact, None], core[None, :]] = settled
    out[:, settlements, settlements] = 1.0
    out[:, tops[~relaxing], tops[~relaxing]] = 1.0
    decay = np.outer(lengths, rates[relaxing])
    out[:, tops[relaxing], tops[relaxing]] = np.exp(-decay)
    out[:, settlements[relaxing], tops[relaxing]] = -np.expm1(-decay)
    # a yielding s_i: its row of E is d_i E - d_i + the unit row, with v_i = d_i X reading the mat's
    # coordinates only (within X[:n_m])
    rows = motion_rows[yielding]
    out[:, :, settlements[yielding]] += out[:, :, :n_m] @ rows.T
    out[:, :n_m, settlements[yielding]] -= rows.T
