"""Compiled stepping loop: the matrix-vector product and the interior-excursion test."""

from __future__ import annotations

import numpy as np

from upliftcli.engines.exact import stepping_kernels as kernel


def test_matvec_takes_the_transposed_matrix():
    rng = np.random.default_rng(1)
    matrix, x = rng.normal(size=(7, 7)), rng.normal(size=7)
    out = np.empty(7)
    kernel._matvec(np.ascontiguousarray(matrix.T), x, out)
    np.testing.assert_allclose(out, matrix @ x)


def test_excursion_flags_a_positive_bump_between_negative_ends():
    """g(t) = -(t - 0.5)^2 + 0.01 on [0, 1]: negative at both ends, positive in between."""
    events = np.array([[1.0, 0.0]])   # g = x[0]
    rates = np.array([[0.0, 1.0]])    # g' = x[1]
    start = np.array([-0.24, 1.0])    # g(0) = -0.24, g'(0) = 1
    end = np.array([-0.24, -1.0])     # g(1) = -0.24, g'(1) = -1
    assert kernel._excursion(events, rates, start, end, 1.0)
    lower = np.array([-0.26, 1.0]), np.array([-0.26, -1.0])  # peak -0.01: no excursion
    assert not kernel._excursion(events, rates, *lower, 1.0)
    assert not kernel._excursion(events, rates, np.array([-0.2, -1.0]), np.array([-0.3, 0.5]), 1.0)
