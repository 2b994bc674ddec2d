"""Artificial accelerograms from a target spectrum alone (Gasparini & Vanmarcke 1976, SIMQKE).

A stationary random process x(t) = sum_k A_k sin(w_k t + phi_k) (random phases phi_k, uniform in
[0, 2 pi), at the frequencies of the discrete Fourier transform over the record's duration) is
multiplied by the envelope of Jennings, Housner & Tsai (1968): (t/t_rise)^2 while rising, 1 over
the stationary part, then exp(-c (t - t_2)) down to `final` at the end. The amplitudes start from
the power spectral density that Vanmarcke's relation gives for the target,
G(w) = xi S_a(w)^2 / (pi w r^2) with a peak factor r = 2.5, and are then corrected iteratively
by the ratio target/S_a, as matching.iterate_to_target does for a recorded seed, each iterate
baseline-corrected (baseline.py). Every record is reproducible from (seed, index): its phases are
drawn from numpy's PCG64 seeded with SeedSequence([seed, index]) (and [seed, index, attempt] for
the rare draw that does not meet the tolerance, tried again up to MAX_ATTEMPTS times).

EN 1998-1 3.2.3.1.2 asks artificial records to have a stationary part of at least 10 s (the
default); the stationary part is lengthened so that the record lasts at least MIN_CYCLES of the
longest period of the range (suites.MIN_CYCLES).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy import fft

from ..errors import AnalysisError
from .baseline import baseline_correct
from .code_rules import CodeRule
from .matching import DEFAULT_SETTINGS, MatchResult, MatchSettings, control_periods, iterate_to_target, settings_for
from .records import Record
from .suites import MIN_CYCLES, Suite, check_target, with_matched_factors

PEAK_FACTOR = 2.5  # r of Vanmarcke's relation, for the starting amplitudes only


@dataclass(frozen=True)
class Envelope:
    """Jennings, Housner & Tsai (1968) envelope: rise [s] with (t/rise)^2, stationary part
    `strong` [s] at 1, then exponential decay over `decay` [s] down to `final` [-]."""

    rise: float = 2.0
    strong: float = 10.0
    decay: float = 8.0
    final: float = 0.05

    @property
    def duration(self) -> float:
        """Total duration [s]."""
        return self.rise + self.strong + self.decay

    def __call__(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        t2 = self.rise + self.strong
        rate = -math.log(self.final) / self.decay
        decay = np.exp(-rate * np.maximum(t - t2, 0.0))  # 1 before t2 (no overflow where it is not used)
        return np.where(t < self.rise, (t / self.rise) ** 2, np.where(t <= t2, 1.0, decay))

    def samples(self, dt: float) -> int:
        """Samples of a record of this envelope at step dt [s] (generate_acceleration); 2^62 for
        a count beyond it (an infinite duration / dt)."""
        count = self.duration / dt
        return round(count) + 1 if count < 2.0**62 else 2**62


def starting_amplitudes(frequencies: np.ndarray, periods: np.ndarray, target: np.ndarray, damping: float,
                        duration: float) -> np.ndarray:
    """Amplitudes A_k [m/s^2] of the sinusoids at `frequencies` [Hz] from Vanmarcke's
    G(w) = xi S_a^2 / (pi w r^2), S_a interpolated in log f from the target [m/s^2] at the control
    periods [s] and held constant beyond; A_k = sqrt(2 G(w_k) dw), dw = 2 pi / duration."""
    omega = 2.0 * math.pi * frequencies
    log_f = np.log(1.0 / periods[::-1])
    sa = np.zeros_like(frequencies)
    positive = frequencies > 0.0
    sa[positive] = np.exp(np.interp(np.log(frequencies[positive]), log_f, np.log(target[::-1])))
    density = np.zeros_like(frequencies)
    density[positive] = damping * sa[positive] ** 2 / (math.pi * omega[positive] * PEAK_FACTOR**2)
    return np.sqrt(2.0 * density * 2.0 * math.pi / duration)


def generate_acceleration(periods: np.ndarray, target: np.ndarray, draw, dt: float = 0.01,
                          envelope: Envelope = Envelope(), settings: MatchSettings = DEFAULT_SETTINGS) -> MatchResult:
    """One artificial accelerogram [m/s^2] at step dt [s] iterated to target S_a [m/s^2] at the
    control periods [s] (module docstring); its phases from SeedSequence(draw), e.g. [seed, index]."""
    n = envelope.samples(dt)
    t = np.arange(n) * dt
    shape = envelope(t)
    frequencies = fft.rfftfreq(n, dt)
    rng = np.random.default_rng(np.random.SeedSequence(draw))
    phases = rng.uniform(0.0, 2.0 * math.pi, frequencies.size)
    amplitudes = starting_amplitudes(frequencies, periods, target, settings.damping, n * dt)
    amplitudes[0] = 0.0
    if n % 2 == 0:
        amplitudes[-1] = 0.0  # the Nyquist line has no phase
    spectrum = 0.5 * n * amplitudes * np.exp(1j * (phases - 0.5 * math.pi))  # sin(w t + phi) lines

    def synthesize(lines: np.ndarray) -> np.ndarray:
        return baseline_correct(shape * fft.irfft(lines, n), dt)

    return iterate_to_target(spectrum, frequencies, synthesize, dt, periods, target, settings)


def envelope_for(period_range: tuple[float, float], min_cycles: float, envelope: Envelope = Envelope()) -> Envelope:
    """`envelope` with its stationary part lengthened (never shortened) so that the record lasts
    at least min_cycles x the upper period [s] of the range."""
    shortfall = min_cycles * period_range[1] - envelope.duration
    if shortfall <= 0.0:
        return envelope
    return Envelope(envelope.rise, envelope.strong + shortfall, envelope.decay, envelope.final)


MAX_ATTEMPTS = 5  # phase draws tried for one record before giving up


@dataclass(frozen=True)
class Artificial:
    """One artificial record: result (MatchResult, acceleration [m/s^2]); seed and index it is
    reproducible from; attempt: the phase draw that met the tolerance (0: the first); envelope."""

    result: MatchResult
    seed: int
    index: int
    attempt: int
    envelope: Envelope


def generate(target_spectrum, period_range: tuple[float, float], seed: int, index: int = 0, dt: float = 0.01,
             envelope: Envelope = Envelope(), settings: MatchSettings = DEFAULT_SETTINGS) -> Artificial:
    """One artificial record for a design spectrum (.sa) over period_range [s]. If the iteration
    does not meet the tolerance, new phases are drawn (SeedSequence([seed, index, attempt]), up to
    MAX_ATTEMPTS); AnalysisError if none does."""
    periods = control_periods(period_range, settings.periods_per_octave)
    target = settings.reference * target_spectrum.sa(periods, settings.damping)
    settings = replace(settings, taper_above=True)
    best = None
    for attempt in range(MAX_ATTEMPTS):
        draw = [int(seed), int(index)] + ([attempt] if attempt else [])
        result = generate_acceleration(periods, target, draw, dt, envelope, settings)
        if result.converged:
            return Artificial(result, int(seed), int(index), attempt, envelope)
        best = result if best is None or np.ptp(np.log(result.ratios)) < np.ptp(np.log(best.ratios)) else best
    low, high = best.ratio_range
    raise AnalysisError(f"artificial record {index + 1} (seed {seed}): no draw of {MAX_ATTEMPTS} met the tolerance "
                        f"{settings.low:g}-{settings.high:g} over {period_range[0]:.3g}-{period_range[1]:.3g} s "
                        f"(S_a/target {low:.3f} to {high:.3f}); try another seed or a narrower range")


def suite_envelope(period_range: tuple[float, float], rule: CodeRule, envelope: Envelope = Envelope()) -> Envelope:
    """The envelope of the records of generate_suite: a stationary part of at least
    rule.stationary_duration, lengthened for MIN_CYCLES of the upper period [s]."""
    strong = max(envelope.strong, rule.stationary_duration)
    return envelope_for(period_range, MIN_CYCLES, replace(envelope, strong=strong))


def generate_suite(target_spectrum, period_range: tuple[float, float], rule: CodeRule, count: int, seed: int,
                   dt: float = 0.01, envelope: Envelope = Envelope(), settings: MatchSettings | None = None,
                   period_note: str = "") -> tuple[Suite, list[Artificial]]:
    """`count` artificial records (indices 0..count-1 of `seed`) for the target over period_range [s],
    as a matched Suite (amplitude factors by scaling.matched_factors) and the records' details.
    The stationary part is at least rule.stationary_duration and long enough for MIN_CYCLES."""
    check_target(target_spectrum, period_range, "record generate", "period_range")
    settings = settings or settings_for(rule)
    envelope = suite_envelope(period_range, rule, envelope)
    items = [generate(target_spectrum, period_range, seed, k, dt, envelope, settings) for k in range(count)]
    records = tuple(Record(name=f"artificial {seed}-{k + 1:02d}", dt=dt, acceleration=item.result.acceleration,
                           source=f"artificial {seed}-{k + 1:02d}", units="g") for k, item in enumerate(items))
    provenance = tuple(f"artificial record, seed {seed}, index {item.index}, draw {item.attempt}" for item in items)
    suite = Suite(records, (1.0,) * count, target_spectrum, tuple(period_range), rule, "match", period_note, (),
                  provenance, settings.damping, items[0].result.periods)
    return with_matched_factors(suite, [item.result.ratios for item in items], settings), items
