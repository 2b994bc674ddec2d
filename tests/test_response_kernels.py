"""Compiled post-processing loops against direct evaluation."""

from __future__ import annotations

from dataclasses import replace

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
    postkernel.evaluate_signals(states, ids, np.ascontiguousarray(rows.transpose(0, 2, 1)), values, slopes, ends)
    for i in range(6):
        np.testing.assert_allclose(values[i], rows[ids[i], :3] @ states[i])
        np.testing.assert_allclose(slopes[i], rows[ids[i], 3:] @ states[i])
    for n, i in enumerate([1, 3, 4]):  # intervals ending at a state change: old rows, next sample
        np.testing.assert_allclose(ends[n], rows[ids[i]] @ states[i + 1])


# ----------------------------------------------------------------------------- numpy twins

def _hermite_peaks_twin(values, slopes, end_values, end_slopes, switch, value_cols, rate_cols, curvature_cols,
                        rows, lengths, points=20001):
    """hermite_peaks without any pruning: every interval's quintic evaluated on a dense grid."""
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


def test_hermite_peaks_equals_its_numpy_twin_with_rates_and_transitions():
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
    twin = _hermite_peaks_twin(values, slopes, end_values, end_slopes, switch, value_cols, rate_cols, rate_cols,
                               rows, lengths)
    np.testing.assert_allclose(best, twin, rtol=1e-6)
    assert np.all(best >= twin * (1 - 1e-12))  # the dense grid can only undershoot


def _work_integrals_twin(values, slopes, switch, end_values, end_slopes, lengths, lifted, row_a, row_input, row_ydot,
                         n_modes, row_vel, row_z, n_el, modal_damping, k_el, c_el):
    """The same 3-point Gauss quadrature of the cubic Hermite interpolants, written with numpy."""
    nodes = 0.5 + 0.5 * np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
    weights = np.array([5.0, 8.0, 5.0]) / 18.0
    v0, d0 = values[:-1], slopes[:-1] * lengths[:, None]
    v1, d1 = values[1:].copy(), slopes[1:].copy()
    ends = switch >= 0
    v1[ends], d1[ends] = end_values[switch[ends]], end_slopes[switch[ends]]
    d1 = d1 * lengths[:, None]
    d1[~ends, row_a] = d0[~ends, row_a]  # a_g is linear inside each interval
    k = slopes.shape[1]
    total_in = total_struct = total_found = 0.0
    for s, w in zip(nodes, weights, strict=True):
        h00, h10, h01, h11 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
        g = h00 * v0[:, :k] + h10 * d0 + h01 * v1[:, :k] + h11 * d1
        total_in += np.sum(w * lengths * g[:, row_a] * g[:, row_input])
        total_struct += np.sum(w * lengths * (g[:, row_ydot:row_ydot + n_modes] ** 2 @ modal_damping))
        vel = g[:, row_vel:row_vel + n_el]
        total_found += np.sum(w * lengths * np.where(~lifted & (c_el > 0), c_el * vel**2, 0.0).sum(axis=1))
    z0, z1 = v0[:, row_z:row_z + n_el], v1[:, row_z:row_z + n_el]  # lifted: k z + c z' = 0, exactly
    total_found += np.sum(np.where(lifted & (c_el > 0), 0.5 * k_el * (z0**2 - z1**2), 0.0))
    return total_in, total_struct, total_found


def test_work_integrals_equal_their_numpy_twin():
    rng = np.random.default_rng(4)
    n, k, n_modes, n_el = 30, 9, 3, 2
    values, slopes = rng.normal(size=(n, k + 2)), rng.normal(size=(n, k))
    switch = np.full(n - 1, -1, dtype=np.int64)
    switch[[4, 17]] = [0, 1]
    end_values, end_slopes = rng.normal(size=(2, k + 2)), rng.normal(size=(2, k))
    lengths = rng.uniform(0.5, 1.0, n - 1)
    lifted = rng.random((n - 1, n_el)) < 0.3
    args = (values, slopes, switch, end_values, end_slopes, lengths, lifted)
    layout = (3, 4, 0, n_modes, 5, 7, n_el, np.array([1.0, 2.0, 3.0]), np.array([5.0, 6.0]), np.array([0.5, 0.0]))
    got = postkernel.work_integrals(*args, k, *layout)
    np.testing.assert_allclose(got, _work_integrals_twin(*args, *layout), rtol=1e-12)


def test_work_integrals_are_exact_for_polynomial_signals():
    """Closed forms, independent of the quadrature: on t in [0, 2] (two intervals of 1 s),
    a_g = 1 + 2t and the input signal t^3 give W_in = int (1 + 2t) t^3 dt = 16.8; a modal
    velocity t^2 with c_1 = 1 gives int t^4 dt = 6.4; an element in contact on [0, 1] with
    v' = t and c = 0.5 dissipates 0.5/3, then lifted on [1, 2] its dashpot relaxes with the
    spring, k (z0^2 - z1^2)/2 = 5 (0.3^2 - 0.1^2)/2 = 0.2 (3-point Gauss is exact to degree 5)."""
    t = np.array([0.0, 1.0, 2.0])
    k = 9
    values, slopes = np.zeros((3, k + 2)), np.zeros((3, k))
    values[:, 0], slopes[:, 0] = t**2, 2 * t  # modal velocity Y*'_1
    values[:, 3], slopes[:, 3] = 1 + 2 * t, 2.0  # a_g
    values[:, 4], slopes[:, 4] = t**3, 3 * t**2  # the signal a_g works on
    values[:, 5], slopes[:, 5] = t, 1.0  # velocity of element 1
    values[:, 7] = [0.0, 0.3, 0.1]  # z of element 1 (read where it is lifted)
    switch = np.full(2, -1, dtype=np.int64)
    lifted = np.array([[False, False], [True, False]])
    layout = (3, 4, 0, 3, 5, 7, 2, np.array([1.0, 0.0, 0.0]), np.array([5.0, 6.0]), np.array([0.5, 0.0]))
    work_in, structure, foundation = postkernel.work_integrals(values, slopes, switch, np.zeros((0, k + 2)),
                                                               np.zeros((0, k)), np.ones(2), lifted, k, *layout)
    assert work_in == pytest.approx(16.8, rel=1e-13)
    assert structure == pytest.approx(6.4, rel=1e-13)
    assert foundation == pytest.approx(0.5 / 3 + 0.2, rel=1e-13)


def _cubic_maximum(p0, p1, d0, d1):
    """Largest value of the cubic Hermite p(s), s in [0, 1], with p(0) = p0, p(1) = p1,
    p'(0) = d0, p'(1) = d1 (slopes times the interval length), elementwise; (value, s)."""
    a = 2.0 * (p0 - p1) + d0 + d1
    b = 3.0 * (p1 - p0) - 2.0 * d0 - d1
    best = np.maximum(p0, p1)
    where = np.where(p1 > p0, 1.0, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        disc = b * b - 3.0 * a * d0
        root = np.sqrt(np.maximum(disc, 0.0))
        quadratic = np.abs(a) > 1e-14 * (np.abs(b) + np.abs(d0))
        candidates = [np.where(quadratic, (-b + root) / (3.0 * a), np.where(b != 0.0, -d0 / (2.0 * b), -1.0)),
                      np.where(quadratic, (-b - root) / (3.0 * a), -1.0)]
    for s in candidates:
        inside = (s > 0.0) & (s < 1.0) & (disc >= 0.0)
        value = ((a * s + b) * s + d0) * s + p0
        better = inside & (value > best)
        best = np.where(better, value, best)
        where = np.where(better, s, where)
    return best, where


def test_the_cubic_maximum_of_the_twin_matches_dense_evaluation():
    rng = np.random.default_rng(5)
    p0, p1, d0, d1 = rng.normal(size=(4, 300)) * np.array([[1.0], [1.0], [3.0], [3.0]])
    value, where = _cubic_maximum(p0, p1, d0, d1)
    s = np.linspace(0.0, 1.0, 20001)[:, None]
    dense = ((2 * s**3 - 3 * s**2 + 1) * p0 + (s**3 - 2 * s**2 + s) * d0 + (-2 * s**3 + 3 * s**2) * p1
             + (s**3 - s**2) * d1)
    np.testing.assert_allclose(value, dense.max(axis=0), atol=1e-8)
    at = ((2 * where**3 - 3 * where**2 + 1) * p0 + (where**3 - 2 * where**2 + where) * d0
          + (-2 * where**3 + 3 * where**2) * p1 + (where**3 - where**2) * d1)
    np.testing.assert_allclose(at, value, atol=1e-12)


def _contact_twin(values, slopes, end_values, end_slopes, switch, lifted, lengths, times, k, c, rows):
    """contact_response written with numpy: (peak, peak_time, impact, impact_time, summary)."""
    disp, vel, z, theta = rows
    n_e = lifted.shape[1]
    columns = np.arange(n_e)

    def reaction(v, s):
        return -(v[:, disp:disp + n_e] * k + v[:, vel:vel + n_e] * c), -(v[:, vel:vel + n_e] * k
                                                                         + s[:, vel:vel + n_e] * c)

    r, d = reaction(values, slopes)
    r, d = np.where(lifted, 0.0, r), np.where(lifted, 0.0, d)
    r1, d1 = r[1:].copy(), d[1:].copy()
    ends = switch >= 0
    if ends.any():
        r1[ends], d1[ends] = reaction(end_values[switch[ends]], end_slopes[switch[ends]])
    contact = ~lifted[:-1]
    r1, d1 = np.where(contact, r1, 0.0), np.where(contact, d1, 0.0)
    value, fraction = _cubic_maximum(r[:-1], r1, d[:-1] * lengths[:, None], d1 * lengths[:, None])
    value = np.where(contact, value, 0.0)
    interval = np.argmax(value, axis=0)
    peak = np.maximum(value[interval, columns], 0.0)
    when = times[interval] + fraction[interval, columns] * lengths[interval]
    recontact = lifted[:-1] & ~lifted[1:]
    at_impact = np.where(recontact, r[1:], -np.inf)
    sample = np.argmax(at_impact, axis=0)
    hit = recontact.any(axis=0)
    impact = np.where(hit, np.maximum(at_impact[sample, columns], 0.0), 0.0)
    displacement = values[:, disp:disp + n_e]
    gap = np.where(lifted, displacement - np.where(c > 0.0, values[:, z:z + n_e], 0.0), 0.0)
    any_lifted = lifted.any(axis=1)
    in_contact = np.where(lifted, np.inf, reaction(values, slopes)[0])
    summary = [np.abs(values[:, theta]).max() if theta >= 0 else 0.0, lengths[any_lifted[:-1]].sum(),
               np.count_nonzero(any_lifted[1:] & ~any_lifted[:-1]),
               lengths[lifted.all(axis=1)[:-1]].sum() if n_e > 1 else 0.0]
    summary += [np.count_nonzero(lifted[1:, i] & ~lifted[:-1, i]) for i in (0, -1)]
    summary += [max(gap[:, i].max(), 0.0) for i in (0, -1)] + [displacement[:, i].max() for i in (0, -1)]
    summary += [in_contact[:, 0].min(), in_contact[:, -1].min(), in_contact.min()]
    return peak, when, impact, np.where(hit, times[sample + 1], np.nan), np.array(summary, dtype=float)


@pytest.mark.parametrize("n_elements", [1, 2, 5])
def test_contact_response_equals_its_numpy_twin_bit_for_bit(n_elements):
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
    got = postkernel.contact_response(*args)
    twin = _contact_twin(*args)
    for mine, theirs in zip(got, twin, strict=True):
        np.testing.assert_array_equal(mine, theirs)
    assert got[4][1] > 0.0 and got[2].max() > 0.0  # uplift and recontacts did happen


def test_contact_response_equals_its_numpy_twin_on_histories(elcentro):
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
        got = postkernel.contact_response(*args)
        for mine, theirs in zip(got, _contact_twin(*args), strict=True):
            np.testing.assert_array_equal(mine, theirs)
        assert got[4][1] > 0.0  # the mat did lift off
