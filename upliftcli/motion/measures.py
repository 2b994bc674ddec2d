"""Measures that tell whether an accelerogram looks like an earthquake, not only what spectrum it has
(docs/suites.md, "What a record must look like"): arrays in, numbers out.

* `arias_history`: the Husid plot, cumulative Arias intensity I(t) = pi/(2 g) int_0^t a^2 [m/s],
  exact for the piecewise-linear record (records.arias_intensity is its last value);
* `arias_times`, `significant_duration`: the times [s] at which I(t) reaches fractions of its
  total, and D5-95 = t_95 - t_5 (Trifunac & Brady 1975);
* `zero_crossing_rate`: sign changes of the acceleration per second in the strong motion
  (t_5 to t_95): about 2 f for a narrow-band motion at f [Hz]; recorded motions 4.9-12 per s
  (issue 24), stationary white-ish noise shaped to a design spectrum about 20;
* `fourier_ratio`: the mean Fourier amplitude over a high band (15-40 Hz) over that of a low
  band (1-3 Hz): the high-frequency fall-off (kappa; recorded: median 0.015);
* `end_offsets`, `final_drift`: the first and last samples as fractions of the PGA, and the
  velocity [m/s] and displacement [m] at the end (the baseline).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..units import STANDARD_GRAVITY
from .records import ground_displacement, ground_velocity

#: bands of fourier_ratio [Hz]: (high, low)
HIGH_BAND = (15.0, 40.0)
LOW_BAND = (1.0, 3.0)


def arias_history(acceleration, dt: float) -> np.ndarray:
    """Cumulative Arias intensity I(t_k) [m/s] at the samples, I(0) = 0 (exact for piecewise-linear a)."""
    a = np.asarray(acceleration, dtype=float)
    steps = dt / 3.0 * (a[:-1] ** 2 + a[:-1] * a[1:] + a[1:] ** 2)
    return math.pi / (2.0 * STANDARD_GRAVITY) * np.concatenate(([0.0], np.cumsum(steps)))


def arias_times(acceleration, dt: float, fractions=(0.05, 0.95)) -> np.ndarray:
    """Times [s] at which the Arias intensity reaches each fraction of its total (linear between samples)."""
    history = arias_history(acceleration, dt)
    total = history[-1]
    if total <= 0.0:
        return np.zeros(len(fractions))
    time = np.arange(history.size) * dt
    return np.interp(np.asarray(fractions, dtype=float) * total, history, time)


def significant_duration(acceleration, dt: float, low: float = 0.05, high: float = 0.95) -> float:
    """D_low-high [s]: time between low and high fractions of the Arias intensity (D5-95 by default)."""
    start, end = arias_times(acceleration, dt, (low, high))
    return float(end - start)


def zero_crossing_rate(acceleration, dt: float, window: tuple[float, float] | None = None) -> float:
    """Sign changes of the acceleration per second [1/s] within window [s] (default t_5 to t_95)."""
    a = np.asarray(acceleration, dtype=float)
    start, end = arias_times(a, dt) if window is None else window
    first, last = round(start / dt), round(end / dt)
    part = a[first:last + 1]
    part = part[part != 0.0]
    if part.size < 2 or end <= start:
        return 0.0
    return float(np.count_nonzero(np.signbit(part[1:]) != np.signbit(part[:-1])) / (end - start))


def band_amplitude(acceleration, dt: float, band: tuple[float, float]) -> float:
    """Mean Fourier amplitude |A(f)| dt [m/s] over the frequencies of the band [Hz]."""
    a = np.asarray(acceleration, dtype=float)
    spectrum = np.abs(np.fft.rfft(a)) * dt
    frequencies = np.fft.rfftfreq(a.size, dt)
    inside = (frequencies >= band[0]) & (frequencies <= band[1])
    if not np.any(inside):
        raise ValueError(f"no Fourier line in {band[0]:g}-{band[1]:g} Hz (dt = {dt:g} s, {a.size} samples)")
    return float(np.mean(spectrum[inside]))


def fourier_ratio(acceleration, dt: float, high: tuple[float, float] = HIGH_BAND,
                  low: tuple[float, float] = LOW_BAND) -> float:
    """Mean Fourier amplitude over the high band / over the low band [-] (bands in Hz)."""
    return band_amplitude(acceleration, dt, high) / band_amplitude(acceleration, dt, low)


def end_offsets(acceleration) -> tuple[float, float]:
    """|a(0)| / PGA and |a(end)| / PGA [-]."""
    a = np.asarray(acceleration, dtype=float)
    pga = float(np.max(np.abs(a)))
    return (abs(float(a[0])) / pga, abs(float(a[-1])) / pga) if pga > 0.0 else (0.0, 0.0)


def final_drift(acceleration, dt: float) -> tuple[float, float]:
    """Velocity [m/s] and displacement [m] at the end of the record (exact integrals, from rest)."""
    return float(ground_velocity(acceleration, dt)[-1]), float(ground_displacement(acceleration, dt)[-1])


@dataclass(frozen=True)
class Measures:
    """The measures of one record: zero_crossings [1/s], fourier_ratio [-], arias [m/s], d5_95 [s],
    t5 [s], end_offset: the larger of the first and last samples / PGA [-], final velocity [m/s]
    and displacement [m], pga [m/s^2]."""

    zero_crossings: float
    fourier_ratio: float
    arias: float
    d5_95: float
    t5: float
    end_offset: float
    final_velocity: float
    final_displacement: float
    pga: float


def measures(acceleration, dt: float) -> Measures:
    """All the measures of a record [m/s^2] at step dt [s]."""
    a = np.asarray(acceleration, dtype=float)
    t5, t95 = arias_times(a, dt)
    velocity, displacement = final_drift(a, dt)
    return Measures(zero_crossing_rate(a, dt, (t5, t95)), fourier_ratio(a, dt), float(arias_history(a, dt)[-1]),
                    float(t95 - t5), float(t5), max(end_offsets(a)), velocity, displacement,
                    float(np.max(np.abs(a))))


@dataclass(frozen=True)
class CharacterChange:
    """What matching changed in a record (issue 36): d5_95_ratio, matched / original [-];
    early_gain: the matched record's normalised Husid curve at the original's t_5 less 0.05 (the
    net share of the Arias intensity added before the first arrival) [-]; pgv_ratio, pgd_ratio:
    peak ground velocity and displacement of the matched record over those of the original times
    a scale factor (character_change) [-]."""

    d5_95_ratio: float
    early_gain: float
    pgv_ratio: float
    pgd_ratio: float


def husid_at(acceleration, dt: float, time: float) -> float:
    """The normalised Husid curve I(time) / I(end) [-] (linear between samples)."""
    history = arias_history(acceleration, dt)
    if history[-1] <= 0.0:
        return 0.0
    return float(np.interp(time, np.arange(history.size) * dt, history) / history[-1])


def peak_motion(acceleration, dt: float) -> tuple[float, float]:
    """PGV [m/s] and PGD [m] (exact integrals from rest)."""
    return (float(np.max(np.abs(ground_velocity(acceleration, dt)))),
            float(np.max(np.abs(ground_displacement(acceleration, dt)))))


def character_change(original, matched, dt: float, scale: float | None = None) -> CharacterChange:
    """The CharacterChange of `matched` against `original` [m/s^2], both at step dt [s]; scale: the
    factor the original was scaled by before the wavelets [-] (default: the one that gives it the
    matched record's Arias intensity)."""
    t5 = float(arias_times(original, dt)[0])
    if scale is None:
        scale = math.sqrt(arias_history(matched, dt)[-1] / arias_history(original, dt)[-1])
    pgv, pgd = peak_motion(matched, dt)
    pgv0, pgd0 = peak_motion(original, dt)
    return CharacterChange(significant_duration(matched, dt) / significant_duration(original, dt),
                           husid_at(matched, dt, t5) - 0.05, pgv / (abs(scale) * pgv0), pgd / (abs(scale) * pgd0))
