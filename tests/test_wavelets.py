"""Wavelet matching: the improved tapered cosine (zero velocity and displacement), the response
matrix against an independent integration, and a matched record that keeps its onset and ends."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from upliftcli.motion.measures import arias_history, arias_times, end_offsets, final_drift
from upliftcli.motion.records import ground_displacement, ground_velocity, read_record
from upliftcli.motion.spectra import response_spectrum, sdof_history
from upliftcli.motion.wavelets import (
    control_periods,
    end_taper,
    onset_ramp,
    peak_responses,
    response_matrix,
    tapered_cosine,
    wavelet_amplitudes,
    wavelet_columns,
    wavelet_match,
)

ELCENTRO = Path(__file__).resolve().parents[1] / "records" / "elcentro_1940_ns_chopra.txt"


@pytest.mark.parametrize("period", [0.2, 1.0, 3.0])
def test_improved_wavelet_ends_at_rest(period):
    # Al Atik & Abrahamson 2010: the improved tapered cosine ends with (nearly) zero velocity and
    # displacement: its integral is sqrt(pi) gamma exp(-(w gamma)^2 / 4), w gamma = 7.4 f^0.07
    # (measured: 5e-7, 2e-5, 1e-4 of the peak velocity and 1e-4, 3e-3, 2e-2 of the peak
    # displacement at 0.2, 1, 3 s)
    dt = period / 200
    t = np.arange(0.0, 60.0 * period, dt)
    f = tapered_cosine(t, period, 0.05, 30.0 * period)
    velocity, displacement = ground_velocity(f, dt), ground_displacement(f, dt)
    assert abs(velocity[-1]) < 2e-4 * np.abs(velocity).max()
    assert abs(displacement[-1]) < 2e-2 * np.abs(displacement).max()
    frequency = 1.0 / period
    gamma = 1.178 * frequency**-0.93
    integral = math.sqrt(math.pi) * gamma * math.exp(-((2 * math.pi * frequency * math.sqrt(1 - 0.05**2) * gamma) ** 2)
                                                     / 4)
    assert abs(velocity[-1]) == pytest.approx(integral, rel=0.05, abs=1e-12)


def test_response_matrix_against_the_exact_integration():
    dt = 0.01
    t = np.arange(3000) * dt
    periods = control_periods((0.1, 2.0), 4)
    times = np.linspace(6.0, 20.0, periods.size)
    wavelets = wavelet_columns(t, periods, 0.05, times)
    matrix = response_matrix(dt, periods, 0.05, times, wavelets)
    exact = np.empty_like(matrix)
    for i, (period, time) in enumerate(zip(periods, times, strict=True)):
        for j in range(periods.size):
            u, _ = sdof_history(wavelets[:, j], dt, period, 0.05)
            exact[i, j] = (2 * math.pi / period) ** 2 * np.interp(time, t, u)
    assert np.max(np.abs(matrix - exact)) < 0.06 * np.max(np.abs(exact))  # trapezoidal rule at T/8 or finer
    # each oscillator is moved most by its own wavelet
    np.testing.assert_array_equal(np.argmax(np.abs(exact), axis=1), np.arange(periods.size))


def test_peak_responses_include_the_free_vibration():
    record = read_record(ELCENTRO)
    periods = np.array([0.3, 1.0, 4.0])
    values, times, _, _, other, _ = peak_responses(record.acceleration, record.dt, periods, 0.05)
    exact = response_spectrum(record.acceleration, record.dt, periods, [0.05]).pseudo_acceleration[0]
    np.testing.assert_allclose(np.abs(values), exact, rtol=0.02)  # sampled at T/8 at least
    assert np.all(times >= 0.0) and np.all(np.sign(other) == -np.sign(values))


def test_tapers():
    t = np.arange(0, 10.001, 0.01)
    ramp = onset_ramp(t, 2.0, 4.0)
    assert ramp[t < 2.0].max() == 0.0 and ramp[t >= 4.0].min() == 1.0 and ramp[300] == pytest.approx(0.5)
    taper = end_taper(t.size, 0.01)
    assert taper[0] == 0.0 and taper[-1] == 0.0 and taper[100:-100].min() == 1.0


def test_matched_record_keeps_its_onset_and_ends():
    record = read_record(ELCENTRO)
    periods = control_periods((0.1, 3.0))
    target = np.full(periods.size, 9.0)  # a flat 0.92 g
    seed = record.acceleration * 1.5
    result = wavelet_match(seed, record.dt, periods, target)
    values = peak_responses(result.acceleration, record.dt, periods, 0.05)[0]
    start = np.max(np.abs(np.log(np.abs(peak_responses(seed, record.dt, periods, 0.05)[0]) / target)))
    assert result.misfit < 0.1 < start
    # (the misfit is that of the iterate; the baseline correction after it moves it a little)
    assert np.max(np.abs(np.log(np.abs(values) / target))) == pytest.approx(result.misfit, abs=0.02)
    # nothing added before the 1 % Arias time but the baseline polynomial (a smooth ramp from 0,
    # 0.9 % of the PGA there), and less than 2 % of the Arias intensity before the 5 % time
    onset = arias_times(seed, record.dt, (0.01,))[0]
    k = int(onset / record.dt)
    change = result.acceleration - seed
    assert np.abs(change[:k]).max() < 0.01 * np.abs(seed).max()
    assert np.all(np.abs(np.diff(change[:k], 2)) < 1e-4)
    added = arias_history(change, record.dt)
    assert added[int(arias_times(seed, record.dt)[0] / record.dt)] < 0.02 * arias_history(result.acceleration,
                                                                                           record.dt)[-1]
    # first and last samples kept, at rest at the end
    assert result.acceleration[0] == seed[0] and result.acceleration[-1] == pytest.approx(seed[-1], abs=1e-12)
    assert max(end_offsets(result.acceleration)) < 0.01
    velocity, displacement = final_drift(result.acceleration, record.dt)
    assert abs(velocity) < 1e-12 and abs(displacement) < 1e-11


def test_a_wavelet_that_moves_no_oscillator_gets_amplitude_zero():
    """Issue 38, T9: a wavelet that is 0 wherever it would act (placed before the record's onset,
    as the peaks of a constant record are) made a zero column of C and a singular system. It now
    gets amplitude 0, and the others are those of the system without it."""
    rng = np.random.default_rng(3)
    matrix = rng.normal(size=(5, 4))
    change = rng.normal(size=5)
    full = wavelet_amplitudes(matrix, change)
    normal = matrix.T @ matrix
    normal[np.diag_indices_from(normal)] *= 1.02
    np.testing.assert_array_equal(full, np.linalg.solve(normal, matrix.T @ change))  # unchanged when none is 0
    dead = matrix.copy()
    dead[:, 1] = 0.0
    amplitudes = wavelet_amplitudes(dead, change)
    assert amplitudes[1] == 0.0
    np.testing.assert_allclose(amplitudes[[0, 2, 3]], wavelet_amplitudes(dead[:, [0, 2, 3]], change), rtol=1e-12)
    np.testing.assert_array_equal(wavelet_amplitudes(np.zeros((5, 4)), change), np.zeros(4))
