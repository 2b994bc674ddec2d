"""The numpy twin of the compiled spectrum loop (upliftcli.motion.spectra_numpy): the same peaks
as the compiled (C) kernel to rounding, and against an independent fine-step integration."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_spectra import brute_force

from upliftcli.motion.spectra import RecordSpectrum, response_spectrum
from upliftcli.motion.spectra_numpy import _states

#: the two differ by the rounding of the step coefficients, largest at long periods (cancellation
#: in B ~ h^2: 1.6e-12 at T = 7 s on El Centro), and of the recurrence (3e-13 against extended
#: precision for either, test_states_match_extended_precision)
AGREEMENT = 5e-12



def both(acc, dt, periods, dampings, **options):
    return (response_spectrum(acc, dt, periods, dampings, method="compiled", **options),
            response_spectrum(acc, dt, periods, dampings, method="numpy", **options))


@pytest.mark.parametrize("free_vibration", [True, False])
def test_numpy_matches_kernel_on_a_record(elcentro, free_vibration):
    """El Centro, T = 0 and 0.01-10 s (T < 4 dt: sub-steps), four dampings."""
    periods = np.concatenate(([0.0], np.geomspace(0.01, 10.0, 41)))
    compiled, numpy = both(elcentro.acceleration, elcentro.dt, periods, [0.0, 0.02, 0.05, 0.3],
                           free_vibration=free_vibration)
    for name in ("displacement", "absolute_acceleration", "pseudo_acceleration"):
        np.testing.assert_allclose(getattr(numpy, name), getattr(compiled, name), rtol=AGREEMENT, atol=0)


@pytest.mark.parametrize("damping", [0.0, 0.05])
def test_numpy_matches_kernel_on_white_noise_ending_off_zero(damping):
    """A rough input ending at a non-zero value (the ramp to zero, then free vibration), periods
    down to dt / 2 (eight sub-steps) where peaks lie between samples at every step."""
    rng = np.random.default_rng(3)
    acc = rng.normal(size=500)
    acc[-1] = 2.5
    periods = [0.005, 0.013, 0.025, 0.04, 0.13, 0.7, 3.0]
    compiled, numpy = both(acc, 0.01, periods, [damping])
    np.testing.assert_allclose(numpy.displacement, compiled.displacement, rtol=AGREEMENT, atol=0)
    np.testing.assert_allclose(numpy.absolute_acceleration, compiled.absolute_acceleration, rtol=AGREEMENT, atol=0)


@pytest.mark.parametrize("damping", [0.02, 0.05])
def test_numpy_matches_brute_force(elcentro, damping):
    """Independent: scipy's exact first-order-hold discretisation on a step dt/200, peaks sampled."""
    periods = [0.04, 0.1, 1.0, 3.0]
    spectrum = response_spectrum(elcentro.acceleration, elcentro.dt, periods, [damping], method="numpy")
    for index, period in enumerate(periods):
        peak_u, peak_at = brute_force(elcentro.acceleration, elcentro.dt, period, damping)
        assert spectrum.displacement[0, index] == pytest.approx(peak_u, rel=1e-3)
        assert spectrum.absolute_acceleration[0, index] == pytest.approx(peak_at, rel=1e-3)


def test_step_peak_between_samples_matches_closed_form():
    """A step of ground acceleration, dt = T/3: the first peak (1 + exp(-pi xi/sqrt(1-xi^2))) a0/w^2
    lies between samples."""
    period, damping, a0 = 0.7, 0.05, 1.3
    omega = 2 * math.pi / period
    spectrum = response_spectrum(np.full(40, a0), period / 3.0, [period], [damping], free_vibration=False,
                                 method="numpy")
    ratio = damping / math.sqrt(1 - damping**2)
    assert spectrum.displacement[0, 0] == pytest.approx(a0 / omega**2 * (1 + math.exp(-math.pi * ratio)), rel=1e-12)


def test_states_match_extended_precision(elcentro):
    """The doubling scan of the step recurrence against the recurrence run step by step in
    extended precision (np.longdouble), at a long and a short period."""
    acc, dt = elcentro.acceleration, elcentro.dt
    for period, damping in ((7.0, 0.05), (0.05, 0.05), (2.0, 0.0)):
        omega = 2 * math.pi / period
        u, _ = _states(np.array([omega]), np.array([damping]), dt, acc[:-1], acc[1:])
        big = np.longdouble
        w, h = big(2) * np.arccos(big(-1)) / big(period), big(dt)
        sigma = big(damping) * w
        wd = w * np.sqrt(1 - big(damping) ** 2)
        e, c, s = np.exp(-sigma * h), np.cos(wd * h), np.sin(wd * h)
        x, v, reference = big(0), big(0), [big(0)]
        for a_start, a_end in zip(acc[:-1].astype(big), acc[1:].astype(big), strict=True):
            c1 = -(a_end - a_start) / h / w**2
            c0 = -a_start / w**2 - 2 * sigma * c1 / w**2
            amp_a = x - c0
            amp_b = (v - c1 + sigma * amp_a) / wd
            x, v = (c0 + c1 * h + e * (amp_a * c + amp_b * s),
                    c1 + e * ((amp_b * wd - sigma * amp_a) * c - (amp_a * wd + sigma * amp_b) * s))
            reference.append(x)
        reference = np.array(reference)
        assert float(np.max(np.abs(u[0] - reference)) / np.max(np.abs(reference))) < 1e-12


def test_record_spectrum_does_not_depend_on_grouping_and_agrees_with_numpy(elcentro):
    """RecordSpectrum: the compiled loop, a value the same (to the bit) whether asked alone or
    with others, and the numpy twin's to rounding."""
    periods = [0.03, 0.3, 1.2, 4.0]
    together = RecordSpectrum(elcentro).sa(periods, 0.05)
    alone = [float(RecordSpectrum(elcentro).sa([t], 0.05)[0]) for t in periods]
    assert together.tolist() == alone
    direct = response_spectrum(elcentro.acceleration, elcentro.dt, periods, [0.05])
    assert together.tolist() == direct.pseudo_acceleration[0].tolist()
    numpy_path = response_spectrum(elcentro.acceleration, elcentro.dt, periods, [0.05], method="numpy")
    np.testing.assert_allclose(together, numpy_path.pseudo_acceleration[0], rtol=1e-13)


def test_unknown_method_is_refused(elcentro):
    with pytest.raises(ValueError, match="method"):
        response_spectrum(elcentro.acceleration, elcentro.dt, [1.0], [0.05], method="fortran")
