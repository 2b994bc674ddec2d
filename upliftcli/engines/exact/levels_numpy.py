"""The numpy twin of _levels.c: the step operators of one contact state at every bisection level,
ops[j] = expm(A h / 2^j)^T, j = 0..L, from the Taylor polynomial of the finest level and squarings
(level_operators.state_levels; docs/theory.md 15.9): the same arithmetic in the same order, so the same
bits (tests/test_level_operators.py): each entry of a matrix product is summed in the order of its terms
(product), not in the BLAS's order.

The finest level is the Taylor polynomial (Paterson-Stockmeyer, no solve) of B = A h / 2^L: of degree 6
(three products) where eta = max(|B^2|^(1/2), |B^3|^(1/3)) (1-norms) is at most THETA_SIX, else of degree 9
(four) of B / 2^s, s the fewest halvings that bring eta to THETA_TAYLOR, squared s times (Al-Mohy and
Higham's bound: a matrix whose norm is that of a few large forcing columns needs none); each coarser level
is the square of the next finer one.

The zero rows of A (the plastic drifts of elastic stories, the settlements of elements that do not
yield, the constant forcing entries) are unit rows of every exp(A t), exactly, and are left out of the
products: in M = A^T with the active indices (nonzero rows of A) first, each operator is
[[X11, 0], [X21, I]] and each power of M [[P, 0], [Q, 0]], kept as its first m columns (n x m).
"""

from __future__ import annotations

import math

import numpy as np

from .stories import story_fields

#: the degree of the Taylor polynomial, and the largest eta it is used at (after halvings): its remainder
#: exp(B) - T_9(B), at most sum_{k > 9} eta^k / k! (Al-Mohy and Higham 2009, theorem 4.2: the norms of the
#: powers bounded by eta^k), is then below 2.8e-17 of the unit operator, a quarter of the unit round-off
TAYLOR_DEGREE = 9
THETA_TAYLOR = 0.1
#: the largest eta the polynomial of degree 6 is used at, one product fewer: its remainder, at most
#: sum_{k > 6} eta^k / k!, is then 1.1e-16, below the unit round-off 2^-53 (it is 4.4e-18 at the README deck's
#: eta of the rigid base, 0.0112; the bonded base's reach 0.0114-0.035: tests/test_level_operators.py)
THETA_SIX = 0.0177
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
    polynomial of degree 6 where eta <= THETA_SIX, else of degree 9 after the halvings that bring eta to
    THETA_TAYLOR, squared as many times."""
    m = a.shape[1]
    a2 = product(a, a[:m])
    a3 = product(a, a2[:m])  # A A^2: _levels.c takes the sparse factor first
    eta = max(math.sqrt(_norm(a2)), math.cbrt(_norm(a3)))
    if eta <= THETA_SIX:
        return _taylor(a, a2, a3, None)
    halvings = 0
    if eta > THETA_TAYLOR and math.isfinite(eta):  # powers of two: the powers of the scaled matrix exactly
        halvings = math.ceil(math.log2(eta / THETA_TAYLOR))
        scale = 0.5**halvings
        a, a2, a3 = a * scale, a2 * scale**2, a3 * scale**3
    c = _INVERSE_FACTORIALS
    level = _taylor(a, a2, a3, product(a3, (c[7] * a + c[8] * a2 + c[9] * a3)[:m]))
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


def _taylor(a: np.ndarray, a2: np.ndarray, a3: np.ndarray, inner: np.ndarray | None) -> np.ndarray:
    """sum_k A^k / k! in compact form from A, A^2 and A^3: I + A + A^2/2 + A^3/6 + A^3 (A/4! + A^2/5! + A^3/6! +
    inner), inner = A^3 (A/7! + A^2/8! + A^3/9!) (degree 9) or None (degree 6)."""
    c, m = _INVERSE_FACTORIALS, a.shape[1]
    middle = c[4] * a + c[5] * a2 + c[6] * a3
    if inner is not None:
        middle += inner
    identity = np.eye(a.shape[0], m)
    return identity + a + c[2] * a2 + c[3] * a3 + product(a3, middle[:m])


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
