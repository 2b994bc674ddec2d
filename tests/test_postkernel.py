"""Compiled post-processing loops against direct evaluation."""

from __future__ import annotations

import numpy as np

from upliftcli.engines.exact import response_kernels as postkernel


def _quintic(p0, p1, d0, d1, c0, c1, s):
    """Quintic Hermite basis (independent of the kernel's monomial coefficients)."""
    h = [1 - 10 * s**3 + 15 * s**4 - 6 * s**5, s - 6 * s**3 + 8 * s**4 - 3 * s**5,
         0.5 * s**2 - 1.5 * s**3 + 1.5 * s**4 - 0.5 * s**5, 0.5 * s**3 - s**4 + 0.5 * s**5,
         -4 * s**3 + 7 * s**4 - 3 * s**5, 10 * s**3 - 15 * s**4 + 6 * s**5]
    return h[0] * p0 + h[1] * d0 + h[2] * c0 + h[3] * c1 + h[4] * d1 + h[5] * p1


def test_quintic_extremum_matches_dense_evaluation():
    rng = np.random.default_rng(7)
    s = np.linspace(0.0, 1.0, 200_001)
    for _ in range(200):
        p0, p1, d0, d1, c0, c1 = rng.normal(size=6) * [1, 1, 3, 3, 10, 10]
        value, where = postkernel._quintic_extremum(p0, p1, d0, d1, c0, c1)
        dense = np.abs(_quintic(p0, p1, d0, d1, c0, c1, s))
        assert abs(value - dense.max()) < 1e-9 * max(1.0, dense.max())
        assert abs(value - abs(_quintic(p0, p1, d0, d1, c0, c1, where))) < 1e-12 * max(1.0, value)


def test_quintic_interpolant_reproduces_a_sinusoid_peak_at_coarse_sampling():
    """exact values, slopes and curvatures at 5 samples per period: peak within (w h)^6 / 46080."""
    omega, h = 2 * np.pi, 0.2
    phase = 0.37
    best = 0.0
    for i in range(5):
        t0, t1 = i * h + phase, (i + 1) * h + phase
        f = lambda t, k=0: np.real((1j * omega) ** k * np.exp(1j * omega * t))
        value, _ = postkernel._quintic_extremum(f(t0), f(t1), f(t0, 1) * h, f(t1, 1) * h,
                                                 f(t0, 2) * h * h, f(t1, 2) * h * h)
        best = max(best, value)
    assert abs(best - 1.0) < (omega * h) ** 6 / 46080 * 2


def test_evaluate_signals_uses_each_samples_state_and_left_limits():
    rng = np.random.default_rng(3)
    states = rng.normal(size=(6, 4))
    ids = np.array([0, 0, 1, 1, 0, 1])
    rows = rng.normal(size=(2, 5, 4))  # 3 value rows, 2 slope rows per state
    values, slopes = np.empty((6, 3)), np.empty((6, 2))
    ends = np.empty((3, 5))
    postkernel.evaluate_signals(states, ids, np.ascontiguousarray(rows.transpose(0, 2, 1)), values, slopes, ends)
    for i in range(6):
        np.testing.assert_allclose(values[i], rows[ids[i], :3] @ states[i])
        np.testing.assert_allclose(slopes[i], rows[ids[i], 3:] @ states[i])
    for n, i in enumerate([1, 3, 4]):  # intervals ending at a state change: old rows, next sample
        np.testing.assert_allclose(ends[n], rows[ids[i]] @ states[i + 1])
