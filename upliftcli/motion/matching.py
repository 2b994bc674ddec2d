"""Spectral matching of a record to a target spectrum by frequency-domain iteration.

Each iteration computes the exact 5 % pseudo-acceleration spectrum S_a (spectra.response_spectrum)
at control periods spaced evenly in log T over the period range (96 per octave), forms the gain
G = level x target / S_a there, interpolates it linearly in log f, multiplies the Fourier
transform of the record (zero-padded to twice its length) by G(f) and transforms back; the
result is baseline-corrected (baseline.py) and the loop repeats (Gasparini & Vanmarcke 1976,
SIMQKE's iteration, applied to a recorded seed). Beyond the range the gain goes to 1 over one
octave on the long-period side (and on the short-period side for artificial records; a recorded
seed keeps the gain of the lower period there, so its PGA follows its short-period ordinates).

The gain is real and smooth in log f, so the correction is a zero-phase filter with a short
impulse response: each frequency band keeps its phase and timing, and the record keeps its
non-stationarity (its Arias-intensity build-up). A wavelet method (the CWT of reqpy) is the same
in this respect: scaling each wavelet scale by a factor and summing is also a linear
time-invariant filter whose gain is a smooth function of frequency.

Tolerance: each record within low = 0.9 and high = 1.3 times the matching target (-10 %/+30 %)
at every control period. The matching target is the design spectrum times max(1, the code's
matched mean): 110 % for ASCE 7-22 (16.2.3.3 asks the mean of matched records to reach 110 %),
100 % for EN 1998-1 (whose 90 % is the lower bound of the tolerance). The iteration stops when
one amplitude factor can bring the ratios within [low (1 + margin), high / (1 + margin)]
(margin 2 %, for the ordinates between the control periods); the factors themselves
(scaling.matched_factors) centre each record on the matching target and raise the suite
together where the mean must be higher. What a frequency-domain iteration cannot remove is the
fine roughness of S_a(T) (valleys where the peak response passes from one instant to another):
it typically leaves a spread max/min of 1.2-1.35 over the range.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from ..errors import AnalysisError
from .baseline import baseline_correct
from .code_rules import CodeRule
from .spectra import response_spectrum

#: per-record tolerance of a matched or artificial record, S_a / target [-]
TOLERANCE = (0.9, 1.3)


@dataclass(frozen=True)
class MatchSettings:
    """reference: the matching target is reference x the design spectrum [-] (1.1 for ASCE 7-22);
    ratios, level, low and high are relative to the matching target.
    level: the aim, S_a = level x matching target [-]; low, high: accepted S_a/target [-]; margin [-]:
    the ratios at the control periods must fit [low (1 + margin), high / (1 + margin)] (for the
    ordinates between them); goal: the spread max/min of the ratios at which the iteration stops
    (default: accepted_spread); it also stops after max_iterations, or after `patience` iterations
    without a better spread; damping [-]; periods_per_octave: control periods; taper_above: the
    gain goes to 1 beyond the short-period end (artificial records) instead of being held."""

    reference: float = 1.0
    level: float = 1.0
    low: float = TOLERANCE[0]
    high: float = TOLERANCE[1]
    margin: float = 0.02
    goal: float | None = None
    damping: float = 0.05
    max_iterations: int = 40
    patience: int = 4
    periods_per_octave: int = 96
    taper_above: bool = False

    @property
    def accepted_spread(self) -> float:
        """The largest max/min of the ratios that one factor can bring within the tolerance [-]."""
        return self.high / self.low / (1.0 + self.margin) ** 2


DEFAULT_SETTINGS = MatchSettings()


def settings_for(rule: CodeRule, **changes) -> MatchSettings:
    """The settings for records matched under `rule`: the matching target is max(1, the code's
    matched mean) x the design spectrum (110 % for ASCE 7-22, the level 16.2.3.3 asks of the mean
    of matched records; 100 % for EN 1998-1, whose 90 % is the tolerance's lower bound). The
    iteration aims at the spread with which a record alone meets the code's mean (goal)."""
    settings = MatchSettings(reference=max(1.0, rule.matched_mean), **changes)
    mean = rule.matched_mean / settings.reference
    goal = settings.high / max(settings.low, mean) / (1.0 + settings.margin) ** 2
    return replace(settings, goal=changes.get("goal", goal))


def control_periods(period_range: tuple[float, float], per_octave: int = 96) -> np.ndarray:
    """Periods [s] spaced evenly in log T from the lower to the upper bound, both included."""
    lower, upper = period_range
    count = max(math.ceil(math.log2(upper / lower) * per_octave) + 1, 8)
    return np.geomspace(lower, upper, count)


@dataclass(frozen=True)
class MatchResult:
    """acceleration [m/s^2] at step dt [s]; iterations done; converged: every ratio within
    [low, high]; periods: control periods [s]; ratios: S_a/target there [-]."""

    acceleration: np.ndarray
    dt: float
    iterations: int
    converged: bool
    periods: np.ndarray
    ratios: np.ndarray

    @property
    def ratio_range(self) -> tuple[float, float]:
        return float(self.ratios.min()), float(self.ratios.max())


def iterate_to_target(spectrum: np.ndarray, frequencies: np.ndarray, synthesize: Callable[[np.ndarray], np.ndarray],
                      dt: float, periods: np.ndarray, target: np.ndarray, settings: MatchSettings) -> MatchResult:
    """The loop shared by matching and generation: `spectrum` (complex, on `frequencies` [Hz]) is
    multiplied by the gain each iteration and `synthesize(spectrum)` gives the accelerogram
    [m/s^2]; target [m/s^2] at the control periods [s]. Returns the best iterate."""
    log_f = np.log(1.0 / periods[::-1])
    positive = frequencies > 0.0
    log_frequencies = np.log(frequencies[positive])
    goal = settings.goal or settings.accepted_spread
    best: tuple[float, np.ndarray, np.ndarray, int] | None = None
    for iteration in range(settings.max_iterations + 1):
        acceleration = synthesize(spectrum)
        sa = response_spectrum(acceleration, dt, periods, [settings.damping]).pseudo_acceleration[0]
        ratios = sa / target
        spread = float(np.max(ratios) / np.min(ratios)) if np.all(sa > 0.0) else math.inf
        if best is None or spread < best[0]:
            best = (spread, acceleration, ratios, iteration)
        if spread <= goal or iteration >= min(settings.max_iterations, best[3] + settings.patience) \
                or not math.isfinite(spread):
            break
        gain = np.log(settings.level * target / sa)[::-1]
        log_gain = np.interp(log_frequencies, log_f, gain)
        below = log_frequencies < log_f[0]  # periods above the range: taper to no change an octave down
        log_gain[below] *= np.clip(1.0 - (log_f[0] - log_frequencies[below]) / math.log(2.0), 0.0, 1.0)
        if settings.taper_above:  # periods below the range likewise (else the gain is held)
            above = log_frequencies > log_f[-1]
            log_gain[above] *= np.clip(1.0 - (log_frequencies[above] - log_f[-1]) / math.log(2.0), 0.0, 1.0)
        spectrum = spectrum.copy()
        spectrum[positive] *= np.exp(log_gain)
    spread, acceleration, ratios, iteration = best
    return MatchResult(acceleration, dt, iteration, spread <= settings.accepted_spread, periods, ratios)


def match_acceleration(acceleration, dt: float, periods: np.ndarray, target: np.ndarray,
                       settings: MatchSettings = MatchSettings()) -> MatchResult:
    """Match a ground acceleration [m/s^2] (step dt [s]) to target S_a [m/s^2] at the control
    periods [s] (module docstring). The result is baseline-corrected."""
    from scipy import fft  # here: loading a suite deck (motion/suites.py) imports this module, not scipy

    seed = np.asarray(acceleration, dtype=float)
    n = seed.size
    size = fft.next_fast_len(2 * n, real=True)
    frequencies = fft.rfftfreq(size, dt)

    def synthesize(spectrum: np.ndarray) -> np.ndarray:
        return baseline_correct(fft.irfft(spectrum, size)[:n], dt)

    return iterate_to_target(fft.rfft(seed, size), frequencies, synthesize, dt, periods, target, settings)


def match_record(record, target_spectrum, period_range: tuple[float, float],
                 settings: MatchSettings = MatchSettings()) -> MatchResult:
    """Match a records.Record to a design spectrum (.sa) over period_range [s]; AnalysisError,
    naming the record and the ratios reached, when it does not meet the tolerance."""
    periods = control_periods(period_range, settings.periods_per_octave)
    target = settings.reference * target_spectrum.sa(periods, settings.damping)
    result = match_acceleration(record.acceleration, record.dt, periods, target, settings)
    if not result.converged:
        low, high = result.ratio_range
        raise AnalysisError(
            f"{record.source or record.name}: spectral matching did not converge in {settings.max_iterations} "
            f"iterations: S_a/matching target {low:.3f} to {high:.3f} over "
            f"{period_range[0]:.3g}-{period_range[1]:.3g} s, "
            f"tolerance {settings.low:g} to {settings.high:g} (a seed closer to the target in shape, or a "
            "narrower ground_motion.period_range, may help)")
    return result
