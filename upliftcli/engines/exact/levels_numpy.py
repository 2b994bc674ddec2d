"""The numpy twin of _levels.c: the step operators of one contact state at every bisection level,
ops[j] = expm(A h / 2^j)^T, j = 0..L, from the Taylor polynomial of the finest level and squarings
(level_operators.state_levels; docs/theory.md 15.9): the same arithmetic in the same order, so the same
bits (tests/test_level_operators.py): each entry of a matrix product is summed in the order of its terms
(product), not in the BLAS's order.

The finest level is the Taylor polynomial of degree 9 (Paterson-Stockmeyer, no solve) of
B = A h / 2^(L + s), s the fewest halvings that bring eta = max(|B^2|^(1/2), |B^3|^(1/3)) (1-norms) to
THETA_TAYLOR (Al-Mohy and Higham's bound: a matrix whose norm is that of a few large forcing columns needs
none), squared s times; each coarser level is the square of the next finer one.

The zero rows of A (the plastic drifts of elastic stories, the settlements of elements that do not
yield, the constant forcing entries) are unit rows of every exp(A t), exactly, and are left out of the
products: in M = A^T with the active indices (nonzero rows of A) first, each operator is
[[X11, 0], [X21, I]] and each power of M [[P, 0], [Q, 0]], kept as its first m columns (n x m).
"""

from __future__ import annotations

import math

import numpy as np

from .stories import story_fields

#: the degree of the Taylor polynomial, and the largest eta it is used at: the remainder, at most
#: eta^10 / 10!, is then below 2.8e-17
TAYLOR_DEGREE = 9
THETA_TAYLOR = 0.1
_INVERSE_FACTORIALS = tuple(1.0 / np.prod(np.arange(1.0, k + 1.0)) for k in range(TAYLOR_DEGREE + 1))


def state_levels(matrix: np.ndarray, h: float, ops: np.ndarray) -> None:
    """ops[j] = expm(A h / 2^j)^T, j = 0..L (ops (L + 1, n, n), written whole) of A = matrix (n, n)."""
    levels = ops.shape[0] - 1
    active = np.flatnonzero(matrix.any(axis=1))
    order = np.concatenate((active, np.flatnonzero(~matrix.any(axis=1))))
    held = order[active.size:]
    level = finest_level(matrix.T[np.ix_(order, active)] * h / 2.0**levels)
    ops[:, :, held] = 0.0  # held columns: unit columns (the rows of E of constant entries)
    ops[:, held, held] = 1.0
    columns = (order[:, None], active[None, :])
    ops[levels][columns] = level
    for j in range(levels - 1, -1, -1):
        level = compact_square(level)
        ops[j][columns] = level


def finest_level(a: np.ndarray) -> np.ndarray:
    """exp of the compact power a (n x m: [[P, 0], [Q, 0]]) as an operator in compact form, by the Taylor
    polynomial after the halvings that bring eta to THETA_TAYLOR, squared as many times."""
    m = a.shape[1]
    a2 = product(a, a[:m])
    a3 = product(a2, a[:m])
    eta = max(math.sqrt(_norm(a2)), math.cbrt(_norm(a3)))
    halvings = 0
    if eta > THETA_TAYLOR and math.isfinite(eta):  # powers of two: the powers of the scaled matrix exactly
        halvings = math.ceil(math.log2(eta / THETA_TAYLOR))
        scale = 0.5**halvings
        a, a2, a3 = a * scale, a2 * scale**2, a3 * scale**3
    level = _taylor(a, a2, a3)
    for _ in range(halvings):
        level = compact_square(level)
    return level


def compact_square(x: np.ndarray) -> np.ndarray:
    """The square of an operator [[X11, 0], [X21, I]] in compact form x (n x m)."""
    m = x.shape[1]
    out = product(x, x[:m])
    out[m:] += x[m:]
    return out


def product(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """x y (x: rows x m, y: m x w), each entry summed over k = 0..m-1 in that order, as _levels.c sums it: the
    terms x[:, k] y[k] of each k a slice of one C-ordered array, reduced over its first axis (numpy adds
    such slices one after the other; a BLAS product would sum in another order)."""
    return np.add.reduce(np.multiply(x.T[:, :, None], y[:, None, :], order="C"), axis=0)


def _norm(power: np.ndarray) -> float:
    """The 1-norm of a power of M in compact form (its held columns are zero)."""
    return float(np.add.reduce(np.abs(power), axis=0).max(initial=0.0))


def _taylor(a: np.ndarray, a2: np.ndarray, a3: np.ndarray) -> np.ndarray:
    """sum_k A^k / k!, k = 0..9, in compact form from A, A^2 and A^3: I + A + A^2/2 + A^3/6 + A^3 (A/4! + A^2/5! +
    A^3/6! + A^3 (A/7! + A^2/8! + A^3/9!))."""
    c, m = _INVERSE_FACTORIALS, a.shape[1]
    inner = product(a3, (c[7] * a + c[8] * a2 + c[9] * a3)[:m])
    identity = np.eye(a.shape[0], m)
    return identity + a + c[2] * a2 + c[3] * a3 + product(a3, (c[4] * a + c[5] * a2 + c[6] * a3 + inner)[:m])


def story_rows(bits: int, table: np.ndarray, picks: np.ndarray, rows: np.ndarray, events: np.ndarray,
               rates: np.ndarray, matrix_t: np.ndarray, fields: np.ndarray, zero_rows: int, soil_rows: int) -> None:
    """The rows of one state of yielding stories from its base's table (story_states.StoryBase.table, .picks),
    for the stories' bits `bits` (the pattern shifted past the foundation's bits): fields (n_y) their fields P +
    2 N (stories.story_fields); rows (n_aug + n_e, n_aug) its A, then its event rows, rows picks[0] + picks[1] *
    fields[picks[2]] of the table; events (n_e, n_aug) its event rows with the first zero_rows zero (a bonded
    run's foundation); matrix_t its A^T; rates (n_e, n_aug) the rates G A of its event rows: zero where the row
    is, the stories' rows (from soil_rows on) each entry summed in the order of its terms (product), the
    foundation's other rows left to the caller (np.matmul: story_requests.event_rates). The bits of _levels.c."""
    fields[:] = story_fields(bits, 0, fields.size)
    table.take(picks[0] + picks[1] * fields.take(picks[2]), axis=0, out=rows)
    n_aug = rows.shape[1]
    events[:] = rows[n_aug:]
    events[:zero_rows] = 0.0
    matrix_t[:] = rows[:n_aug].T
    rates[:zero_rows] = 0.0
    rates[soil_rows:] = product(events[soil_rows:], rows[:n_aug])
