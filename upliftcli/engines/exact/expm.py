"""Matrix exponential of a stack of matrices in numpy: scaling and squaring with the [13/13]
Padé approximant (N. J. Higham, SIAM J. Matrix Anal. Appl. 26(4), 2005, Algorithm 2.3;
docs/exact-engine.md). The exact engine's step operators need nothing else of scipy.linalg,
whose import alone costs a command 0.15-0.2 s. Backward error below the unit round-off;
tests/test_expm.py checks it against closed forms and scipy.linalg.expm.
"""

from __future__ import annotations

import numpy as np

#: the coefficients b_0..b_13 of the [13/13] Padé approximant of exp
_B = (64764752532480000.0, 32382376266240000.0, 7771770303897600.0, 1187353796428800.0, 129060195264000.0,
      10559470521600.0, 670442572800.0, 33522128640.0, 1323241920.0, 40840800.0, 960960.0, 16380.0, 182.0, 1.0)
#: the largest 1-norm for which the [13/13] approximant is accurate to the unit round-off
THETA_13 = 5.371920351148152


def expm(matrices: np.ndarray) -> np.ndarray:
    """exp(A) of each matrix A of a stack (..., n, n) (or of one matrix)."""
    a = np.asarray(matrices, dtype=float)
    stack = a.reshape(-1, *a.shape[-2:])
    norms = np.abs(stack).sum(axis=-2).max(axis=-1) if stack.size else np.zeros(stack.shape[0])
    squarings = np.maximum(0, np.ceil(np.log2(np.maximum(norms, 1e-300) / THETA_13))).astype(int)
    scaled = stack / (2.0 ** squarings)[:, None, None]
    identity = np.eye(stack.shape[-1])
    a2 = scaled @ scaled
    a4 = a2 @ a2
    a6 = a2 @ a4
    b = _B
    u = scaled @ (a6 @ (b[13] * a6 + b[11] * a4 + b[9] * a2) + b[7] * a6 + b[5] * a4 + b[3] * a2 + b[1] * identity)
    v = a6 @ (b[12] * a6 + b[10] * a4 + b[8] * a2) + b[6] * a6 + b[4] * a4 + b[2] * a2 + b[0] * identity
    result = np.linalg.solve(v - u, v + u)
    for level in range(int(squarings.max(initial=0))):
        more = squarings > level
        result[more] = result[more] @ result[more]
    return result.reshape(a.shape)


#: the degree of the Taylor polynomial of squared_levels, and the largest eta (below) it is used at: the
#: remainder, at most eta^10 / 10!, is then below 2.8e-17
TAYLOR_DEGREE = 9
THETA_TAYLOR = 0.1
_INVERSE_FACTORIALS = tuple(1.0 / np.prod(np.arange(1.0, k + 1.0)) for k in range(TAYLOR_DEGREE + 1))


def squared_levels(matrices: np.ndarray, levels: int) -> np.ndarray:
    """exp(A / 2^j), j = 0..levels, of each A of a stack (R, n, n) -> (R, levels + 1, n, n): the finest
    level by the Taylor polynomial of degree TAYLOR_DEGREE (Paterson-Stockmeyer, no solve) of
    A / 2^(levels + s), s the fewest halvings that bring eta = max(|B^2|^(1/2), |B^3|^(1/3)) (B = A / 2^levels,
    1-norms) to THETA_TAYLOR (Al-Mohy and Higham's bound: a matrix whose norm is that of a few large forcing
    columns needs none), squared s times; each coarser level the square of the next finer one. Fewer
    products than the exponentials of the finest and of the coarsest level (operators._stacked_operators);
    tests/test_expm.py compares every level with scipy.linalg.expm."""
    a = np.asarray(matrices, dtype=float) / 2.0**levels
    a2 = a @ a
    a3 = a2 @ a
    eta = np.maximum(np.sqrt(_norm(a2)), np.cbrt(_norm(a3)))
    halvings = np.zeros(eta.size, dtype=int)
    out = np.empty((a.shape[0], levels + 1, *a.shape[1:]))
    if eta.max(initial=0.0) > THETA_TAYLOR:  # powers of two: the powers of the scaled matrix exactly
        halvings = np.maximum(0, np.ceil(np.log2(eta / THETA_TAYLOR))).astype(int)
        scale = (0.5**halvings)[:, None, None]
        a, a2, a3 = a * scale, a2 * scale**2, a3 * scale**3
    out[:, levels] = _taylor(a, a2, a3)
    _squared(out[:, levels], halvings)
    for j in range(levels - 1, -1, -1):
        np.matmul(out[:, j + 1], out[:, j + 1], out=out[:, j])
    return out


def _squared(stack: np.ndarray, times: np.ndarray) -> None:
    """Square each matrix of a stack (in place) its number of times."""
    for level in range(int(times.max(initial=0))):
        more = times > level
        stack[more] = stack[more] @ stack[more]


def _norm(stack: np.ndarray) -> np.ndarray:
    """The 1-norm of each matrix of a stack."""
    return np.abs(stack).sum(axis=-2).max(axis=-1)


def _taylor(a: np.ndarray, a2: np.ndarray, a3: np.ndarray) -> np.ndarray:
    """sum_k A^k / k!, k = 0..9, of a stack of A from A, A^2 and A^3: I + A + A^2/2 + A^3/6 + A^3 (A/4! + A^2/5! +
    A^3/6! + A^3 (A/7! + A^2/8! + A^3/9!))."""
    c = _INVERSE_FACTORIALS
    inner = a3 @ (c[7] * a + c[8] * a2 + c[9] * a3)
    return np.eye(a.shape[-1]) + a + c[2] * a2 + c[3] * a3 + a3 @ (c[4] * a + c[5] * a2 + c[6] * a3 + inner)
