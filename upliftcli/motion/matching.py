"""Spectral matching of a record to a target spectrum that keeps the record (issue 24).

The record is first scaled to fit the target in the least-squares sense in log S_a over the
matching range, then adjusted in the time domain by wavelets (wavelets.py, Al Atik & Abrahamson
2010): each correction is placed at the time of the oscillator peak it moves, peaks below the
target are raised where the record is strong (between its 5 % and 95 % Arias times) and nothing
is added before its first arrival (1 % of its Arias intensity), so the record keeps its phasing,
its build-up and its duration (docs/suites.md measures it on the FEMA P695 far-field records).
The frequency-domain iteration used before (SIMQKE's gain applied to a recorded seed) spread
energy before the first arrival and lengthened D5-95 up to 2.2x; it is gone.

The matching range is the period range of the suite, or wider (artificial records are matched
over the target's whole defined range, generate.py); the tolerance is checked on the suite's
check periods (96 per octave over its period range) with the exact spectrum
(spectra.response_spectrum).

Tolerance: each record within low = 0.9 and high = 1.3 times the matching target (-10 %/+30 %)
at every check period. The matching target is the design spectrum times max(1, the code's
matched mean): 110 % for ASCE 7-22 (16.2.3.3 asks the mean of matched records to reach 110 %),
100 % for EN 1998-1 (whose 90 % is the lower bound of the tolerance). A record converges when
one amplitude factor can bring its ratios within [low (1 + margin), high / (1 + margin)]
(margin 2 %, for the ordinates between the check periods); the factors themselves
(scaling.matched_factors) centre each record on the matching target and raise the suite
together where the mean must be higher.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from ..errors import AnalysisError
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
    (default: accepted_spread); damping [-]; periods_per_octave: check periods; wavelets_per_octave:
    control periods of the wavelet iteration, which stops after max_iterations or when every
    control ordinate is within exp(+-wavelet_tolerance) of the aim."""

    reference: float = 1.0
    level: float = 1.0
    low: float = TOLERANCE[0]
    high: float = TOLERANCE[1]
    margin: float = 0.02
    goal: float | None = None
    damping: float = 0.05
    max_iterations: int = 30
    periods_per_octave: int = 96
    wavelets_per_octave: int = 16
    wavelet_tolerance: float = 0.04

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


def matching_target(target_spectrum, settings: MatchSettings) -> Callable[[np.ndarray], np.ndarray]:
    """periods [s] -> the matching target reference x S_a [m/s^2] of the design spectrum."""
    return lambda periods: settings.reference * target_spectrum.sa(periods, settings.damping)


def control_periods(period_range: tuple[float, float], per_octave: int = 96) -> np.ndarray:
    """Periods [s] spaced evenly in log T from the lower to the upper bound, both included."""
    lower, upper = period_range
    count = max(math.ceil(math.log2(upper / lower) * per_octave) + 1, 8)
    return np.geomspace(lower, upper, count)


@dataclass(frozen=True)
class MatchResult:
    """acceleration [m/s^2] at step dt [s]; iterations done; converged: one factor brings every
    ratio within the tolerance; periods: check periods [s]; ratios: S_a/target there [-]; scale:
    the factor applied to the seed before the wavelets [-]."""

    acceleration: np.ndarray
    dt: float
    iterations: int
    converged: bool
    periods: np.ndarray
    ratios: np.ndarray
    scale: float = 1.0

    @property
    def ratio_range(self) -> tuple[float, float]:
        return float(self.ratios.min()), float(self.ratios.max())


def check_ratios(acceleration: np.ndarray, dt: float, periods: np.ndarray, target: np.ndarray,
                 damping: float) -> np.ndarray:
    """S_a / target at the check periods [s] (exact spectrum)."""
    return response_spectrum(acceleration, dt, periods, [damping]).pseudo_acceleration[0] / target


def match_acceleration(acceleration, dt: float, target_sa: Callable[[np.ndarray], np.ndarray],
                       match_range: tuple[float, float], check_periods: np.ndarray,
                       settings: MatchSettings = MatchSettings(), name: str = "record") -> MatchResult:
    """Match a ground acceleration [m/s^2] (step dt [s]) to the matching target target_sa(periods)
    [m/s^2] over match_range [s]: scaled to fit in log S_a, then adjusted by wavelets (module
    docstring); the ratios are those at the check periods [s]. Baseline-corrected, ends kept. When
    the check periods (between the control ones) miss the tolerance, the iteration goes on with
    control periods twice as dense. InputError naming the record (name) when its S_a is 0 at a
    control period (no factor scales it to the target)."""
    from .usable import check_spectra
    from .wavelets import control_periods as wavelet_periods  # here: loading a suite deck imports this module
    from .wavelets import wavelet_match

    periods = wavelet_periods(match_range, settings.wavelets_per_octave)
    aim = settings.level * target_sa(periods)
    seed = np.asarray(acceleration, dtype=float)
    start = response_spectrum(seed, dt, periods, [settings.damping]).pseudo_acceleration[0]
    check_spectra([name], start[None, :], periods, "matched")
    scale = float(np.exp(np.mean(np.log(aim / start))))
    scaled = seed * scale
    adjusted = wavelet_match(scaled, dt, periods, aim, settings.damping, settings.wavelet_tolerance,
                             settings.max_iterations)
    ratios = check_ratios(adjusted.acceleration, dt, check_periods, target_sa(check_periods), settings.damping)
    iterations = adjusted.iterations
    if not _within(ratios, settings):  # ordinates between the control periods: once more, twice as dense
        periods = wavelet_periods(match_range, 2 * settings.wavelets_per_octave)
        again = wavelet_match(adjusted.acceleration, dt, periods, settings.level * target_sa(periods),
                              settings.damping, settings.wavelet_tolerance, settings.max_iterations // 2)
        more = check_ratios(again.acceleration, dt, check_periods, target_sa(check_periods), settings.damping)
        if _spread(more) < _spread(ratios):
            adjusted, ratios, iterations = again, more, iterations + again.iterations
    kept, ratios = _kept(adjusted.acceleration, ratios, seed, dt, (periods, target_sa, check_periods), settings)
    return MatchResult(kept, dt, iterations, _within(ratios, settings), check_periods, ratios, scale)


def _kept(acceleration: np.ndarray, ratios: np.ndarray, seed: np.ndarray, dt: float, grid, settings: MatchSettings
          ) -> tuple[np.ndarray, np.ndarray]:
    """The matched record with its weak start and coda returned their shares (character.keep_shares)
    and its ratios at the check periods; when that breaks the tolerance, the wavelets once more
    from there (grid: the control periods, the target, the check periods) and the shares again."""
    from .character import keep_shares
    from .wavelets import wavelet_match

    periods, target_sa, check_periods = grid
    kept = keep_shares(acceleration, seed, dt)
    if kept is acceleration:
        return acceleration, ratios
    ratios = check_ratios(kept, dt, check_periods, target_sa(check_periods), settings.damping)
    if _within(ratios, settings):
        return kept, ratios
    again = wavelet_match(kept, dt, periods, settings.level * target_sa(periods), settings.damping,
                          settings.wavelet_tolerance, settings.max_iterations // 2)
    retried = keep_shares(again.acceleration, seed, dt)
    more = check_ratios(retried, dt, check_periods, target_sa(check_periods), settings.damping)
    return (retried, more) if _spread(more) < _spread(ratios) else (kept, ratios)


def _spread(ratios: np.ndarray) -> float:
    return float(ratios.max() / ratios.min()) if np.all(ratios > 0.0) else math.inf


def _within(ratios: np.ndarray, settings: MatchSettings) -> bool:
    """Whether one factor brings every ratio within the tolerance less its margin."""
    return _spread(ratios) <= settings.accepted_spread


def match_record(record, target_spectrum, period_range: tuple[float, float],
                 settings: MatchSettings = MatchSettings()) -> MatchResult:
    """Match a records.Record to a design spectrum (.sa) over period_range [s]; AnalysisError,
    naming the record and the ratios reached, when it does not meet the tolerance."""
    periods = control_periods(period_range, settings.periods_per_octave)
    result = match_acceleration(record.acceleration, record.dt, matching_target(target_spectrum, settings),
                                period_range, periods, settings, record.source or record.name)
    if not result.converged:
        low, high = result.ratio_range
        raise AnalysisError(
            f"{record.source or record.name}: spectral matching did not reach the tolerance in "
            f"{settings.max_iterations} iterations: S_a/matching target {low:.3f} to {high:.3f} over "
            f"{period_range[0]:.3g}-{period_range[1]:.3g} s, "
            f"tolerance {settings.low:g} to {settings.high:g} (a seed closer to the target in shape, or a "
            "narrower ground_motion.period_range, may help)")
    return result
