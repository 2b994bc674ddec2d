"""The post-processing loops (compiled or numpy, as upliftcli.runtime.backend chooses) against direct
evaluation; the two implementations against each other: tests/test_response_numpy.py."""

from __future__ import annotations

import numpy as np
import pytest

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
        value, where = postkernel.quintic_extremum(p0, p1, d0, d1, c0, c1)
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

        def f(t, k=0):
            return np.real((1j * omega) ** k * np.exp(1j * omega * t))

        value, _ = postkernel.quintic_extremum(f(t0), f(t1), f(t0, 1) * h, f(t1, 1) * h,
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
    postkernel.evaluate_signals(states, ids, rows, values, slopes, ends)
    for i in range(6):
        np.testing.assert_allclose(values[i], rows[ids[i], :3] @ states[i])
        np.testing.assert_allclose(slopes[i], rows[ids[i], 3:] @ states[i])
    for n, i in enumerate([1, 3, 4]):  # intervals ending at a state change: old rows, next sample
        np.testing.assert_allclose(ends[n], rows[ids[i]] @ states[i + 1])


def test_evaluate_signals_gives_the_same_bits_with_rows_split_or_whole():
    """A state used at least 32 times has its rows split (copies, sparse sums, a dense product);
    one used fewer times is multiplied whole (_signals.c, SPLIT_USES): the same rows give the same
    bits either way, and those of the dense product R x. Rows with a copy, sparse ones and dense
    ones; state 0 (40 samples) and state 1 (3 samples) have the same rows; the samples and the left
    limits at both transitions. The compiled loop's (the twin's BLAS products sum in another order)."""
    from backends import compiled_or_skip

    compiled_or_skip()
    from upliftcli.engines.exact import _signals

    rng = np.random.default_rng(28)
    n_aug = 12
    rows = rng.normal(size=(7, n_aug))
    rows[1] = rows[0]  # a copy
    rows[2, 2:] = rows[3, :9] = 0.0  # sparse
    rows = np.stack([rows, rows])
    states = rng.normal(size=(43, n_aug))
    states[:, 5] = 0.0  # an input that is zero
    ids = np.array([0] * 20 + [1] * 3 + [0] * 20)
    states[20:23] = states[:3]  # the samples of state 1 repeat samples of state 0
    values, slopes, ends = np.empty((43, 4)), np.empty((43, 3)), np.empty((2, 7))
    _signals.evaluate_signals(states, ids, rows, values, slopes, ends)
    np.testing.assert_array_equal(values[20:23], values[:3])
    np.testing.assert_array_equal(slopes[20:23], slopes[:3])
    dense = np.array([[sum(row[q] * x[q] for q in range(n_aug) if x[q] != 0.0) for row in rows[0]] for x in states])
    np.testing.assert_array_equal(np.hstack((values, slopes)), dense)
    # the left limits: state 0's rows (split) at sample 20, state 1's (whole) at sample 23
    np.testing.assert_array_equal(ends, dense[[20, 23]])


# ----------------------------------------------------------------------------- an independent reference

def _hermite_peaks_dense(values, slopes, end_values, end_slopes, switch, value_cols, rate_cols, curvature_cols,
                         rows, lengths, points=20001):
    """hermite_peaks without any pruning (a reference, not a twin): every interval's quintic
    evaluated on a dense grid."""
    r = values[:, value_cols] @ rows.T
    d = values[:, rate_cols] @ rows.T
    c = slopes[:, curvature_cols] @ rows.T
    r1, d1, c1 = r[1:].copy(), d[1:].copy(), c[1:].copy()
    ends = switch >= 0
    r1[ends] = end_values[switch[ends]][:, value_cols] @ rows.T
    d1[ends] = end_values[switch[ends]][:, rate_cols] @ rows.T
    c1[ends] = end_slopes[switch[ends]][:, curvature_cols] @ rows.T
    s = np.linspace(0.0, 1.0, points)[:, None, None]
    length = lengths[None, :, None]
    dense = _quintic(r[None, :-1], r1[None], d[None, :-1] * length, d1[None] * length,
                     c[None, :-1] * length**2, c1[None] * length**2, s)
    return np.maximum(np.abs(dense).max(axis=(0, 1)), np.abs(r).max(axis=0))


def test_hermite_peaks_match_a_dense_evaluation_with_rates_and_transitions():
    """Random signals (the interpolant does not need them consistent), responses combining Y*
    and Y*' columns, two intervals ending at transitions (their left limits differ)."""
    rng = np.random.default_rng(11)
    n, k = 40, 6
    values = rng.normal(size=(n, k))
    slopes = rng.normal(size=(n, k))
    switch = np.full(n - 1, -1, dtype=np.int64)
    switch[[7, 21]] = [0, 1]
    end_values, end_slopes = rng.normal(size=(2, k)), rng.normal(size=(2, k))
    lengths = rng.uniform(0.5, 1.0, n - 1)
    value_cols, rate_cols = np.array([0, 1, 2, 3]), np.array([2, 3, 4, 5])  # (Y, Y') then (Y', Y'')
    rows = rng.normal(size=(3, 4))
    best, _where = postkernel.hermite_peaks(values, slopes, end_values, end_slopes, switch, value_cols, rate_cols,
                                           rate_cols, np.ascontiguousarray(rows.T), lengths, np.zeros(3))
    twin = _hermite_peaks_dense(values, slopes, end_values, end_slopes, switch, value_cols, rate_cols, rate_cols,
                               rows, lengths)
    np.testing.assert_allclose(best, twin, rtol=1e-6)
    assert np.all(best >= twin * (1 - 1e-12))  # the dense grid can only undershoot


def _assert_together_as_alone(compiled, arguments, rows, lengths, fractions):
    """The compiled hermite_peaks of the responses `rows` (m, n_basis) searched together gives each response the
    bits (peak and instant) it gets searched alone, and each peak is that of a dense evaluation of its quintics
    (_hermite_peaks_dense, an independent reference; arguments: its first eight)."""

    def peaks(rows_t, fractions):
        best, where = np.zeros(rows_t.shape[1]), np.zeros(rows_t.shape[1])
        compiled.hermite_peaks(*arguments, rows_t, lengths, fractions, best, where)
        return best, where

    best, where = peaks(np.ascontiguousarray(rows.T), fractions)
    for j in range(rows.shape[0]):
        alone = peaks(np.ascontiguousarray(rows[j:j + 1].T), fractions[j:j + 1])
        assert (best[j], where[j]) == (alone[0][0], alone[1][0])
        dense = _hermite_peaks_dense(*arguments, rows[j:j + 1], lengths, points=5001)[0]
        assert dense * (1 - 1e-12) <= best[j] <= dense * (1 + 1e-6)  # the dense grid can only undershoot


def test_hermite_peaks_of_responses_searched_together_have_the_bits_of_each_alone():
    """The compiled loop takes the rates of every response at once in an interval where many are searched, one
    response at a time elsewhere: the same sums in the same order. Three responses searched everywhere (fraction
    0) and thirteen near their peaks give intervals of both kinds; each response alone (every interval at once)
    gives the same bits, and the peak of a dense evaluation."""
    compiled = pytest.importorskip("upliftcli.engines.exact._peaks")
    rng = np.random.default_rng(5)
    n, k, m = 400, 8, 16
    values, slopes = rng.normal(size=(n, k)), rng.normal(size=(n, k))
    switch = np.full(n - 1, -1, dtype=np.int64)
    switch[[30, 31, 200]] = [0, 1, 2]
    end_values, end_slopes = rng.normal(size=(3, k)), rng.normal(size=(3, k))
    lengths = rng.uniform(0.5, 1.0, n - 1)
    value_cols, rate_cols = np.arange(4, dtype=np.int64), np.arange(2, 6, dtype=np.int64)
    rows = rng.normal(size=(m, 4))
    fractions = np.full(m, 0.9)
    fractions[[0, 5, 9]] = 0.0
    arguments = (values, slopes, end_values, end_slopes, switch, value_cols, rate_cols, rate_cols)

    _assert_together_as_alone(compiled, arguments, rows, lengths, fractions)


@pytest.mark.parametrize("n_basis", [4, 7])
def test_rates_taken_at_once_leave_out_zero_inputs_to_the_bit(n_basis):
    """The rates and curvatures of many responses at once (lanes_product_pair) over basis signals whose rates and
    curvatures are zero in runs of samples (a yielding run's plastic drifts before their story yields): four zero
    inputs of both leave out a pass, a zero term among nonzero ones is summed; each response alone (every interval
    at once) gives the same bits, with the rows in groups of four and a remainder, and the peak of a dense
    evaluation."""
    compiled = pytest.importorskip("upliftcli.engines.exact._peaks")
    rng = np.random.default_rng(6)
    n, m = 300, 16
    values, slopes = rng.normal(size=(n, 2 * n_basis)), rng.normal(size=(n, 2 * n_basis))
    values[100:200, n_basis:], slopes[100:200, :n_basis] = 0.0, 0.0  # all rates and curvatures zero
    values[220:260, n_basis + 1], slopes[240:280, 2] = 0.0, 0.0  # one of them zero
    switch = np.full(n - 1, -1, dtype=np.int64)
    switch[[150, 230]] = [0, 1]
    end_values, end_slopes = values[[151, 231]], slopes[[151, 231]]
    lengths = rng.uniform(0.5, 1.0, n - 1)
    value_cols, rate_cols = np.arange(n_basis), np.arange(n_basis, 2 * n_basis)
    rows = rng.normal(size=(m, n_basis))
    fractions = np.full(m, 0.9)
    fractions[[0, 5, 9, 12]] = 0.0
    arguments = (values, slopes, end_values, end_slopes, switch, value_cols, rate_cols, value_cols)

    _assert_together_as_alone(compiled, arguments, rows, lengths, fractions)


def test_evaluate_signals_takes_each_whole_states_own_rows_as_the_states_alternate():
    """The rows of a state used fewer than 32 times are transposed as its samples begin (_signals.c, one state's
    at a time): three such states met in turn, and again, give each sample and left limit its own state's R x."""
    rng = np.random.default_rng(9)
    rows = rng.normal(size=(3, 5, 6))
    ids = np.array([0, 0, 1, 2, 2, 0, 1, 1, 2])
    states = rng.normal(size=(ids.size, 6))
    values, slopes, ends = np.empty((ids.size, 3)), np.empty((ids.size, 2)), np.empty((5, 5))
    postkernel.evaluate_signals(states, ids, rows, values, slopes, ends)
    expected = np.einsum("irq,iq->ir", rows[ids], states)
    np.testing.assert_allclose(np.hstack((values, slopes)), expected, rtol=1e-13, atol=1e-13)
    switches = np.flatnonzero(ids[1:] != ids[:-1])
    np.testing.assert_allclose(ends, np.einsum("irq,iq->ir", rows[ids[switches]], states[switches + 1]),
                               rtol=1e-13, atol=1e-13)
