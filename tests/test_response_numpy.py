"""The numpy twins of the post-processing loops (engines/exact/response_numpy.py) against the
compiled loops, on both backends in one process (tests/backends.py; skipped where the C
extensions were not built) and against direct evaluation."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from backends import on_both

from upliftcli.engines.exact import response_kernels as postkernel
from upliftcli.engines.exact import response_numpy


def test_quintic_extremum_twin_gives_the_loops_bits():
    rng = np.random.default_rng(8)
    cases = rng.normal(size=(300, 6)) * [1, 1, 3, 3, 10, 10]
    compiled, twin = on_both(lambda: [postkernel.quintic_extremum(*case) for case in cases])
    assert compiled == twin


def test_evaluate_signals_twin_matches_the_loop():
    """Random states in three contact states, some rows sparse or repeated (the loop's shortcuts):
    the same values to the rounding of the products (BLAS sums in another order)."""
    rng = np.random.default_rng(9)
    n, n_aug, k, k_s = 200, 12, 7, 4
    states = rng.normal(size=(n, n_aug))
    ids = np.repeat(rng.integers(0, 3, n // 10), 10).astype(np.int64)
    rows = rng.normal(size=(3, k + k_s, n_aug))
    rows[:, 2, 3:] = 0.0  # sparse
    rows[:, 5] = rows[:, 1]  # repeated
    n_switch = np.count_nonzero(ids[1:] != ids[:-1])

    def run():
        values, slopes, ends = np.empty((n, k)), np.empty((n, k_s)), np.empty((n_switch, k + k_s))
        postkernel.evaluate_signals(states, ids, rows, values, slopes, ends)
        return values, slopes, ends

    for compiled, twin in zip(*on_both(run), strict=True):
        np.testing.assert_allclose(twin, compiled, rtol=1e-13, atol=1e-13 * np.abs(compiled).max())


def test_hermite_peaks_twin_finds_the_loops_peaks_and_places():
    """Random signals with transitions, pruning by fractions in use: the same peaks (to the rounding
    of the sampled products) at the same interval and fraction."""
    rng = np.random.default_rng(12)
    n, k = 500, 8
    values, slopes = rng.normal(size=(n, k)), rng.normal(size=(n, k))
    switch = np.full(n - 1, -1, dtype=np.int64)
    at = np.sort(rng.choice(n - 1, 20, replace=False))
    switch[at] = np.arange(at.size)
    end_values, end_slopes = rng.normal(size=(at.size, k)), rng.normal(size=(at.size, k))
    lengths = rng.uniform(0.5, 1.0, n - 1)
    value_cols, rate_cols = np.array([0, 1, 2, 3]), np.array([2, 3, 4, 5])
    rows_t = np.ascontiguousarray(rng.normal(size=(5, 4)).T)
    fractions = np.array([0.0, 0.5, 0.9, 0.95, 1.0])
    compiled, twin = on_both(lambda: postkernel.hermite_peaks(values, slopes, end_values, end_slopes, switch,
                                                              value_cols, rate_cols, rate_cols, rows_t, lengths,
                                                              fractions))
    np.testing.assert_allclose(twin[0], compiled[0], rtol=1e-14)
    np.testing.assert_allclose(twin[1], compiled[1], rtol=1e-12)
    assert np.any(twin[1] % 1.0 > 0.0)  # some peaks lie between samples


def test_the_cubic_maximum_of_the_twin_matches_dense_evaluation():
    rng = np.random.default_rng(5)
    p0, p1, d0, d1 = rng.normal(size=(4, 300)) * np.array([[1.0], [1.0], [3.0], [3.0]])
    value, where = response_numpy.cubic_maximum(p0, p1, d0, d1)
    s = np.linspace(0.0, 1.0, 20001)[:, None]
    dense = ((2 * s**3 - 3 * s**2 + 1) * p0 + (s**3 - 2 * s**2 + s) * d0 + (-2 * s**3 + 3 * s**2) * p1
             + (s**3 - s**2) * d1)
    np.testing.assert_allclose(value, dense.max(axis=0), atol=1e-8)
    at = ((2 * where**3 - 3 * where**2 + 1) * p0 + (where**3 - 2 * where**2 + where) * d0
          + (-2 * where**3 + 3 * where**2) * p1 + (where**3 - where**2) * d1)
    np.testing.assert_allclose(at, value, atol=1e-12)


@pytest.mark.parametrize("n_elements", [1, 2, 5])
def test_contact_response_twin_gives_the_loops_bits(n_elements):
    """Random signals, contact episodes on each element (flight included), intervals ending at
    transitions (their left limits differ), damped and undamped elements."""
    rng = np.random.default_rng(n_elements)
    n, k = 400, 12
    values, slopes = rng.normal(size=(n, k + 3)), rng.normal(size=(n, k))
    switch = np.full(n - 1, -1, dtype=np.int64)
    at = np.sort(rng.choice(n - 1, 30, replace=False))
    switch[at] = np.arange(at.size)
    end_values, end_slopes = rng.normal(size=(at.size, k + 3)), rng.normal(size=(at.size, k))
    lifted = np.repeat(rng.random((n // 20, n_elements)) < 0.4, 20, axis=0)
    lengths = rng.uniform(0.5, 1.0, n - 1)
    times = np.concatenate(([0.0], np.cumsum(lengths)))
    stiffness = rng.uniform(1.0, 2.0, n_elements)
    damping = np.where(np.arange(n_elements) % 2 == 0, 0.3, 0.0)
    rows = (0, k - n_elements, k + 3 - n_elements, 6)
    args = (values, slopes, end_values, end_slopes, switch, lifted, lengths, times, stiffness, damping, rows)
    got, twin = on_both(lambda: postkernel.contact_response(*args))
    for mine, theirs in zip(got, twin, strict=True):
        np.testing.assert_array_equal(mine, theirs)
    assert got[4][1] > 0.0 and got[2].max() > 0.0  # uplift and recontacts did happen


def test_contact_response_twin_gives_the_loops_bits_on_histories(elcentro):
    """The ten-story example (uplift, flight at T_1 = 0.05 s) and a Winkler mat: bit for bit."""
    from paper_example import paper_system

    from upliftcli.engines.exact import response
    from upliftcli.engines.exact.engine import model_for
    from upliftcli.engines.exact.stepping import simulate
    from upliftcli.engines.options import ExactOptions
    from upliftcli.model.foundations import Winkler

    base = paper_system(0.5)
    two, b = base.foundation, base.half_width  # the same rocking stiffness and damping, spread over the mat
    winkler = replace(base, foundation=Winkler(3.0 * two.stiffness / b, 3.0 * two.damping / b, 6))
    for system in (paper_system(0.05), paper_system(0.5), winkler):
        space = model_for(system, "uplift", ExactOptions())
        ((_, history),) = simulate([space], [4], elcentro.acceleration[:600], elcentro.dt, "reaction", uplift=True,
                                   allow_flight=True)
        sig = response.signals(history)
        rows = sig.rows
        args = (sig.values, sig.slopes, sig.end_values, sig.end_slopes, sig.switch, history.lifted,
                history.lengths, history.times, space.element_stiffness, space.element_damping,
                (rows["element_displacement"].start, rows["element_velocity"].start, rows["z"].start,
                 rows["theta"].start))
        got, twin = on_both(lambda args=args: postkernel.contact_response(*args))
        for mine, theirs in zip(got, twin, strict=True):
            np.testing.assert_array_equal(mine, theirs)
        assert got[4][1] > 0.0  # the mat did lift off
