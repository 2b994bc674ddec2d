"""Record measures against closed forms: a sine's zero crossings and Arias intensity, a
constructed Fourier spectrum, a boxcar's durations, a record's end offsets and drift."""

from __future__ import annotations

import math

import numpy as np
import pytest

from upliftcli.motion.measures import (
    arias_history,
    arias_times,
    end_offsets,
    final_drift,
    fourier_ratio,
    measures,
    significant_duration,
    zero_crossing_rate,
)
from upliftcli.motion.records import arias_intensity
from upliftcli.units import STANDARD_GRAVITY

DT = 0.005


def sine(frequency: float, amplitude: float, duration: float, phase: float = 0.3) -> np.ndarray:
    t = np.arange(round(duration / DT) + 1) * DT
    return amplitude * np.sin(2.0 * math.pi * frequency * t + phase)


@pytest.mark.parametrize("frequency", [0.5, 2.0, 3.7, 11.0])
def test_zero_crossings_of_a_sine_are_twice_its_frequency(frequency):
    a = sine(frequency, 2.0, 20.0)
    assert zero_crossing_rate(a, DT, (0.0, 20.0)) == pytest.approx(2.0 * frequency, abs=1.0 / 20.0)
    # the default window (t_5 to t_95 of a stationary sine: 0.9 of it) gives the same rate
    assert zero_crossing_rate(a, DT) == pytest.approx(2.0 * frequency, abs=1.0 / 18.0 + 0.02 * frequency)


def test_arias_intensity_of_a_sine():
    # pi/(2g) A^2/2 T over a whole number of cycles; the piecewise-linear record between samples
    # has (w dt)^2/12 less: 1.6e-6 at 2 Hz and dt = 0.0005 s
    amplitude, duration, dt = 3.0, 10.0, 0.0005
    t = np.arange(round(duration / dt) + 1) * dt
    a = amplitude * np.sin(4.0 * math.pi * t)
    exact = math.pi / (2.0 * STANDARD_GRAVITY) * amplitude**2 / 2.0 * duration
    assert arias_history(a, dt)[-1] == pytest.approx(exact, rel=1e-5)
    assert arias_history(a, dt)[-1] == pytest.approx(arias_intensity(a, dt), rel=1e-12)


def test_arias_times_and_duration_of_a_boxcar():
    # constant acceleration over 4-14 s, zero elsewhere: I(t) grows linearly over the box
    t = np.arange(0, 20.0 + DT / 2, DT)
    a = np.where((t >= 4.0) & (t <= 14.0), 1.5, 0.0)
    t5, t95 = arias_times(a, DT)
    assert t5 == pytest.approx(4.0 + 0.05 * 10.0, abs=DT)
    assert t95 == pytest.approx(4.0 + 0.95 * 10.0, abs=DT)
    assert significant_duration(a, DT) == pytest.approx(9.0, abs=2 * DT)


def test_fourier_ratio_of_a_constructed_spectrum():
    n = 8192
    frequencies = np.fft.rfftfreq(n, DT)
    rng = np.random.default_rng(3)
    amplitude = np.where((frequencies >= 1.0) & (frequencies <= 3.0), 1.0, 0.0)
    amplitude += np.where((frequencies >= 15.0) & (frequencies <= 40.0), 0.07, 0.0)
    lines = amplitude * np.exp(2j * math.pi * rng.random(frequencies.size))
    lines[0] = lines[-1] = 0.0
    a = np.fft.irfft(lines, n) / DT
    assert fourier_ratio(a, DT) == pytest.approx(0.07, rel=1e-9)
    with pytest.raises(ValueError, match="no Fourier line"):
        fourier_ratio(a[:8], DT, high=(99.0, 99.5))


def test_end_offsets_and_drift():
    a = np.array([0.2, 1.0, -2.0, 0.5, 0.1])
    assert end_offsets(a) == pytest.approx((0.1, 0.05))
    # a constant 1 m/s^2 for 2 s from rest: v = 2 m/s, d = 2 m
    velocity, displacement = final_drift(np.ones(401), DT)
    assert (velocity, displacement) == pytest.approx((2.0, 2.0), rel=1e-12)


def test_measures_collects_them():
    a = sine(2.0, 1.0, 10.0, phase=0.0)
    m = measures(a, DT)
    assert m.zero_crossings == pytest.approx(4.0, abs=0.15)
    assert m.arias == pytest.approx(arias_intensity(a, DT))
    assert m.d5_95 == pytest.approx(9.0, abs=0.1) and m.t5 == pytest.approx(0.5, abs=0.1)
    assert m.end_offset == pytest.approx(0.0, abs=1e-9) and m.pga == pytest.approx(1.0, abs=1e-6)
