"""Tests of upliftcli.spectra against closed forms, an independent fine-step integration
(scipy's exact first-order-hold discretisation run through lfilter) and textbook values."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fine_spectra import peak_displacement, pseudo_acceleration
from scipy import signal

from upliftcli.errors import InputError
from upliftcli.motion.spectra import RecordSpectrum, response_spectrum, sdof_history, substeps
from upliftcli.units import STANDARD_GRAVITY

G = STANDARD_GRAVITY
INCH = 0.0254



def brute_force(acceleration, dt, period, damping, refine=200, tail_periods=2.0):
    """Independent reference: the record linearly interpolated on a step dt/refine, a 2T zero tail,
    scipy's exact FOH discretisation of the SDOF state space, lfilter; peaks sampled on the fine grid.
    (The FOH state starts at rest only if the first sample is zero, as in the El Centro file.)"""
    assert acceleration[0] == 0.0
    fine_dt = dt / refine
    n = acceleration.size
    fine_t = np.arange((n - 1) * refine + 1) * fine_dt
    fine_a = np.interp(fine_t, np.arange(n) * dt, acceleration)
    fine_a = np.concatenate([fine_a, np.zeros(math.ceil(tail_periods * period / fine_dt) + 1)])
    omega = 2 * math.pi / period
    a_matrix = np.array([[0.0, 1.0], [-omega**2, -2 * damping * omega]])
    b_matrix = np.array([[0.0], [-1.0]])
    peaks = []
    for c_row in ([[1.0, 0.0]], [[-omega**2, -2 * damping * omega]]):  # u and absolute acceleration
        ad, bd, cd, dd, _ = signal.cont2discrete((a_matrix, b_matrix, np.array(c_row), np.zeros((1, 1))),
                                                 fine_dt, method="foh")
        num, den = signal.ss2tf(ad, bd, cd, dd)
        peaks.append(np.max(np.abs(signal.lfilter(num[0], den, fine_a))))
    return peaks


def test_step_acceleration_history_and_peak_match_closed_form():
    period, damping, a0 = 0.7, 0.05, 1.3
    omega = 2 * math.pi / period
    omega_d = omega * math.sqrt(1 - damping**2)
    dt = period / 3.0  # coarse on purpose: the peak at t = pi / omega_d is between samples
    acc = np.full(40, a0)
    u, v = sdof_history(acc, dt, period, damping)
    t = np.arange(acc.size) * dt
    decay = np.exp(-damping * omega * t)
    ratio = damping / math.sqrt(1 - damping**2)
    u_exact = -a0 / omega**2 * (1 - decay * (np.cos(omega_d * t) + ratio * np.sin(omega_d * t)))
    v_exact = -a0 / omega**2 * decay * (omega**2 / omega_d) * np.sin(omega_d * t)
    np.testing.assert_allclose(u, u_exact, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(v, v_exact, rtol=1e-10, atol=1e-14)
    spectrum = response_spectrum(acc, dt, [period], [damping], free_vibration=False)
    peak_exact = a0 / omega**2 * (1 + math.exp(-math.pi * ratio))
    assert spectrum.displacement[0, 0] == pytest.approx(peak_exact, rel=1e-10)
    # the samples alone miss it by several per cent
    assert np.max(np.abs(u)) < 0.97 * peak_exact


def test_undamped_step_peak_is_twice_static():
    period = 1.0
    spectrum = response_spectrum(np.full(200, 2.0), 0.013, [period], [0.0], free_vibration=False)
    assert spectrum.displacement[0, 0] == pytest.approx(2 * 2.0 / (2 * math.pi / period) ** 2, rel=1e-10)
    assert spectrum.absolute_acceleration[0, 0] == pytest.approx(4.0, rel=1e-10)


def test_harmonic_input_matches_closed_form():
    period, damping = 0.8, 0.03
    amplitude, forcing_period = 2.0, 1.1
    omega, big_omega = 2 * math.pi / period, 2 * math.pi / forcing_period
    dt = forcing_period / 4000  # piecewise-linear sine: error ~ (Omega dt)^2 / 12
    t = np.arange(int(6 / dt)) * dt
    acc = amplitude * np.sin(big_omega * t)
    u, v = sdof_history(acc, dt, period, damping)
    # u'' + 2 xi w u' + w^2 u = -A sin(Omega t), zero initial conditions
    denominator = (omega**2 - big_omega**2) ** 2 + (2 * damping * omega * big_omega) ** 2
    c_sin = -amplitude * (omega**2 - big_omega**2) / denominator
    c_cos = -amplitude * (-2 * damping * omega * big_omega) / denominator
    u_particular = c_sin * np.sin(big_omega * t) + c_cos * np.cos(big_omega * t)
    v_particular = big_omega * (c_sin * np.cos(big_omega * t) - c_cos * np.sin(big_omega * t))
    sigma, omega_d = damping * omega, omega * math.sqrt(1 - damping**2)
    h_a = -c_cos
    h_b = (-big_omega * c_sin + sigma * h_a) / omega_d
    decay = np.exp(-sigma * t)
    u_homogeneous = decay * (h_a * np.cos(omega_d * t) + h_b * np.sin(omega_d * t))
    v_homogeneous = decay * ((h_b * omega_d - sigma * h_a) * np.cos(omega_d * t)
                             - (h_a * omega_d + sigma * h_b) * np.sin(omega_d * t))
    scale = np.max(np.abs(u_particular + u_homogeneous))
    np.testing.assert_allclose(u, u_particular + u_homogeneous, atol=2e-6 * scale)
    np.testing.assert_allclose(v, v_particular + v_homogeneous, atol=2e-6 * scale * omega)


@pytest.mark.parametrize("period", [100.0, 0.01])
def test_step_coefficients_agree_with_matrix_exponential(period):
    """Extreme w*dt: the closed-form recurrence against scipy's expm discretisation."""
    rng = np.random.default_rng(1)
    acc = rng.normal(size=300)
    acc[0] = 0.0  # scipy's FOH state starts at rest only if the first input is zero
    dt, damping = 0.02, 0.05
    u, _ = sdof_history(acc, dt, period, damping)
    omega = 2 * math.pi / period
    system = (np.array([[0.0, 1.0], [-omega**2, -2 * damping * omega]]), np.array([[0.0], [-1.0]]),
              np.array([[1.0, 0.0]]), np.zeros((1, 1)))
    ad, bd, cd, dd, _ = signal.cont2discrete(system, dt, method="foh")
    num, den = signal.ss2tf(ad, bd, cd, dd)
    reference = signal.lfilter(num[0], den, acc)
    np.testing.assert_allclose(u, reference, atol=1e-7 * np.max(np.abs(reference)))


@pytest.mark.parametrize("damping", [0.02, 0.05])
def test_spectrum_of_record_matches_brute_force(elcentro, damping):
    periods = [0.04, 0.07, 0.1, 0.3, 1.0, 3.0]  # 0.04 s = 2 dt: sub-steps and analytic peaks
    spectrum = response_spectrum(elcentro.acceleration, elcentro.dt, periods, [damping])
    for index, period in enumerate(periods):
        peak_u, peak_at = brute_force(elcentro.acceleration, elcentro.dt, period, damping)
        assert spectrum.displacement[0, index] == pytest.approx(peak_u, rel=1e-3)
        assert spectrum.absolute_acceleration[0, index] == pytest.approx(peak_at, rel=1e-3)


@pytest.mark.parametrize("damping", [0.0, 0.05])
def test_white_noise_spectrum_matches_brute_force(damping):
    """A rough input (white noise) stresses the between-sample peaks at every period, T = 2.5 dt up."""
    rng = np.random.default_rng(7)
    acc = rng.normal(size=400)
    acc[0] = 0.0
    dt = 0.01
    periods = [0.025, 0.04, 0.13, 0.7]
    spectrum = response_spectrum(acc, dt, periods, [damping])
    for index, period in enumerate(periods):
        peak_u, peak_at = brute_force(acc, dt, period, damping, refine=400)
        assert spectrum.displacement[0, index] == pytest.approx(peak_u, rel=1e-4)
        assert spectrum.absolute_acceleration[0, index] == pytest.approx(peak_at, rel=1e-4)


def test_short_period_peaks_between_samples(elcentro):
    """At T = 0.1 s = 5 dt the peak read at the record samples is 6 % low; the exact peak agrees
    with the fine integration. The figure tabulated with this record elsewhere, 0.608 g at 0.1 s
    (records/README.md), is the peak read at the samples: scipy's exact first-order-hold
    discretisation on the record's own step (tests/fine_spectra.py) reproduces it, and the
    project's sampled history gives the same peak."""
    period, damping = 0.1, 0.05
    exact = response_spectrum(elcentro.acceleration, elcentro.dt, [period], [damping]).displacement[0, 0]
    fine = brute_force(elcentro.acceleration, elcentro.dt, period, damping, refine=400)[0]
    u, _ = sdof_history(elcentro.acceleration, elcentro.dt, period, damping)
    sampled = np.max(np.abs(u))
    assert exact == pytest.approx(fine, rel=2e-4)
    assert sampled < 0.95 * exact
    at_samples = peak_displacement(elcentro.acceleration, elcentro.dt, period, damping, per_period=1)
    assert sampled == pytest.approx(at_samples, rel=1e-9)
    assert at_samples * (2 * math.pi / period) ** 2 / G == pytest.approx(0.608, abs=0.0005)


def test_elcentro_reference_values(elcentro):
    """Chopra, Dynamics of Structures, Fig. 6.4.1 prints the 2 % deformations of El Centro N-S at
    T = 0.5, 1 and 2 s: 2.67, 5.97 and 7.47 in. They are the peaks at the record's samples (dt =
    0.02 s): scipy's exact first-order-hold discretisation on the record's own step
    (tests/fine_spectra.py, none of upliftcli's spectrum code) reproduces them to 0.1 %, and the
    5 % pseudo-accelerations tabulated with the record, 0.916, 0.454 and
    0.137 g (records/README.md), to the printed digits. The tool's spectrum is the true peak, between samples: the same
    integration on 2,000 steps a period agrees with it to 2e-6."""
    periods = [0.5, 1.0, 2.0]
    at_samples = [peak_displacement(elcentro.acceleration, elcentro.dt, t, 0.02, per_period=1) for t in periods]
    # to 0.006 in, 0.1 % (at 2 s 7.465 in here: Chopra's last digit is his own integration's)
    np.testing.assert_allclose(np.array(at_samples) / INCH, [2.67, 5.97, 7.47], atol=0.006)
    sampled_sa = [peak_displacement(elcentro.acceleration, elcentro.dt, t, 0.05, per_period=1) * (2 * math.pi / t) ** 2
                  for t in periods]
    np.testing.assert_allclose(np.array(sampled_sa) / G, [0.916, 0.454, 0.137], atol=0.0005)
    spectrum = response_spectrum(elcentro.acceleration, elcentro.dt, periods, [0.02, 0.05])
    for row, damping in enumerate((0.02, 0.05)):
        fine = pseudo_acceleration(elcentro.acceleration, elcentro.dt, periods, damping, per_period=2000)
        assert np.all(fine <= spectrum.pseudo_acceleration[row] * (1 + 1e-9))  # a sampled peak is never above
        np.testing.assert_allclose(fine, spectrum.pseudo_acceleration[row], rtol=2e-6)
    assert np.all(spectrum.displacement[0] >= np.array(at_samples))
    np.testing.assert_allclose(spectrum.pseudo_velocity, spectrum.displacement * 2 * math.pi / spectrum.periods)
    assert elcentro.pga / G == pytest.approx(0.319, abs=0.0005)


def test_zero_period_is_rigid_and_long_period_tends_to_ground_displacement(elcentro):
    spectrum = response_spectrum(elcentro.acceleration, elcentro.dt, [0.0, 1e-3], [0.05])
    assert spectrum.pseudo_acceleration[0, 0] == pytest.approx(elcentro.pga)
    assert spectrum.displacement[0, 0] == 0.0
    assert spectrum.pseudo_acceleration[0, 1] == pytest.approx(elcentro.pga, rel=1e-3)


def test_free_vibration_tail_is_the_first_turning_point():
    """A pulse then silence: with the tail the peak is the first free-vibration extreme."""
    period, damping, dt = 2.0, 0.05, 0.01
    acc = np.zeros(51)
    acc[1:50] = 1.0  # ends at 0.5 s, before the response peaks
    with_tail = response_spectrum(acc, dt, [period], [damping]).displacement[0, 0]
    without = response_spectrum(acc, dt, [period], [damping], free_vibration=False).displacement[0, 0]
    longer = np.concatenate([acc, np.zeros(400)])  # explicit 4 s of zeros, exact peaks
    explicit = response_spectrum(longer, dt, [period], [damping], free_vibration=False).displacement[0, 0]
    assert with_tail == pytest.approx(explicit, rel=1e-12)
    assert without < 0.9 * with_tail


def test_spectrum_shape_and_vectorisation(elcentro):
    periods = np.geomspace(0.05, 5, 7)
    dampings = [0.0, 0.02, 0.1]
    together = response_spectrum(elcentro.acceleration, elcentro.dt, periods, dampings)
    assert together.pseudo_acceleration.shape == (3, 7)
    single = response_spectrum(elcentro.acceleration, elcentro.dt, [periods[4]], [0.1])
    assert together.displacement[2, 4] == single.displacement[0, 0]
    assert np.all(together.displacement[0] >= together.displacement[1])  # more damping, less response


def test_record_spectrum_sa_and_errors(elcentro):
    spectrum = RecordSpectrum(elcentro)
    direct = response_spectrum(elcentro.acceleration, elcentro.dt, [0.3, 1.2], [0.07]).pseudo_acceleration[0]
    np.testing.assert_allclose(spectrum.sa([0.3, 1.2], 0.07), direct)
    assert float(spectrum.sa(1.2, 0.07)) == pytest.approx(direct[1])
    assert spectrum.period_range == (0.0, math.inf)
    with pytest.raises(InputError, match="period"):
        spectrum.sa([-1.0], 0.05)
    with pytest.raises(InputError, match="damping"):
        spectrum.sa([1.0], 1.5)


def test_the_record_spectrum_cache_is_bounded_and_gives_the_same_values(elcentro, monkeypatch):
    # issue 38 item 5: a sweep asks ~40 new periods a case; 10^5 cases kept 0.5 GiB of cached S_a
    from upliftcli.motion import spectra

    unbounded = RecordSpectrum(elcentro)
    expected = [unbounded.sa([0.1 * k, 0.1 * k + 0.05, 1.0], 0.05) for k in range(1, 8)]
    monkeypatch.setattr(spectra, "MAX_CACHED", 4)
    bounded = RecordSpectrum(elcentro)
    for k, values in enumerate(expected, start=1):
        assert np.array_equal(bounded.sa([0.1 * k, 0.1 * k + 0.05, 1.0], 0.05), values)  # to the bit
        assert len(bounded._cache) <= 4
    assert len(unbounded._cache) == 15


def test_the_numpy_loops_take_a_long_record_in_segments_of_time(elcentro, monkeypatch):
    """The numpy loops hold at most NUMPY_BLOCK oscillator sub-steps at once: a record longer
    than that for one oscillator is integrated in segments, each from the state where the last
    ended, with the peaks of the compiled loop (which streams) to rounding."""
    from upliftcli.motion import spectra_numpy

    periods = [0.05, 1.0]
    reference = response_spectrum(elcentro.acceleration, elcentro.dt, periods, [0.05], method="compiled")
    monkeypatch.setattr(spectra_numpy, "NUMPY_BLOCK", 400)
    assert list(substeps(elcentro.dt, periods)) == [2, 1]
    original, sizes = spectra_numpy._segment_peaks, []

    def bounded(acc, dt, omegas, xis, nsub, *rest):
        sizes.append(nsub * (acc.size - 1) * omegas.size)
        return original(acc, dt, omegas, xis, nsub, *rest)

    monkeypatch.setattr(spectra_numpy, "_segment_peaks", bounded)
    numpy_path = response_spectrum(elcentro.acceleration, elcentro.dt, periods, [0.05], method="numpy")
    assert len(sizes) > 8 and max(sizes) <= 400
    np.testing.assert_allclose(numpy_path.displacement, reference.displacement, rtol=1e-12)
    np.testing.assert_allclose(numpy_path.absolute_acceleration, reference.absolute_acceleration, rtol=1e-12)
