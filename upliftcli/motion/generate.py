"""Artificial accelerograms from a stochastic seismological model, matched to a target spectrum.

Model: the site-based stochastic model of Rezaeian & Der Kiureghian (2010), a modulated filtered
white noise whose filter changes with time,

    x(t) = q(t) / sigma_f(t) sum_{tau_i <= t} h(t - tau_i, tau_i) w_i,
    h(s, tau) = w_f(tau) / sqrt(1 - z_f^2) exp(-z_f w_f(tau) s) sin(w_f(tau) sqrt(1 - z_f^2) s)   (RDK Eq. 3)

with w_i independent standard normal at the samples, the filter frequency w_f(t) = 2 pi (f_mid +
f' (t - t_mid)) falling through the record (the predominant frequency of recorded motions falls
as surface waves arrive), z_f the filter damping and sigma_f(t) the standard deviation of the
filtered noise, so that x(t) has the variance q(t)^2; then high-passed by a critically damped
oscillator (RDK Eq. 5, corner f_c) so that it ends at rest. h is an oscillator's displacement
response: above f_mid the Fourier amplitude falls as f^-2, and the strong motion crosses zero
about 2 f_mid times a second. Before the envelope, the filtered noise is multiplied in the
frequency domain by the high-frequency diminution exp(-pi kappa f) of Anderson & Hough (1984),
kappa = KAPPA (zero phase, so the envelope's onset stays where it is): recorded motions are
about flat up to 10 Hz and fall fast above 15 Hz (measures.fourier_ratio 15-40 / 1-3 Hz,
recorded median 0.015), which f^-2 alone from a raised f_mid does not give. The modulating
function q(t) is the gamma-shaped one of Rezaeian & Der Kiureghian (2008), its D5-95 drawn from
Afshari & Stewart (2016) for a scenario and its shape setting the time of 45 % of the Arias
intensity (envelopes.py, issue 36): a build-up, a strong phase and an exponential coda, the
record tapered to 0 over its first and last second (after the high-pass, so that it ends at 0).

Parameters from the target, the site and the draw: f_mid = 1/T_p (T_p the log-centre of the
periods where the target is at least 90 % of its largest ordinate), clipped to MID_FREQUENCY,
times the site factor (Vs30 / 360 m/s)^0.5 below 360 m/s (site_factor), times exp(0.25 N(0, 1)),
held within FIRM_BAND times the site factor; f' = -f_mid U(0.1, 0.4) / D5-95 (the filter's
frequency falls by 10-40 % over the strong motion); z_f = U(0.15, 0.4); f(t) is held above
1/T_upper and 0.3 Hz. The record is then matched (matching.match_acceleration: scaled, then
wavelets) to the matching target over the target's whole defined range within GENERATION_RANGE
and at least the suite's period range, not only over the suite's range: its spectrum follows the
target at short and long periods too. Every record is reproducible from (seed, index): its draws
come from numpy's PCG64 seeded with SeedSequence([seed, index]) (and [seed, index, attempt] for
the rare draw that does not meet the tolerance, or whose matched record does not look recorded,
tried again up to MAX_ATTEMPTS times).

Character of the matched record (issue 36): a draw is kept when it meets the tolerance and its
strong motion crosses zero at a rate within the site's band (CROSSINGS: 6-10 per second on a firm
site, Vs30 >= SOFT_SITE, where recorded firm-site motions sit; 3-8 on a soft one, whose recorded
motions are slower, within the 2.95-12.1 of recorded components) and its Fourier ratio 15-40 /
1-3 Hz is at most FOURIER_MAX. Matching can move a draw out (wavelets at 0.05-0.07 s placed at
the PGA add 15-30 Hz; long-period wavelets on a short record lower the crossings): then the
next draw is tried, and if none of MAX_ATTEMPTS is within, the one of least misfit
(character_misfit) among those that met the tolerance is kept.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import AnalysisError, InputError
from .code_rules import CodeRule
from .durations import Scenario
from .envelopes import Envelope, default_scenario, draw_envelope
from .matching import MatchResult, MatchSettings, control_periods, match_acceleration, matching_target, settings_for
from .measures import fourier_ratio, zero_crossing_rate
from .records import Record
from .suites import MIN_CYCLES, SAMPLES_PER_PERIOD, Suite, check_target, with_matched_factors
from .wavelets import end_taper

#: periods [s] over which artificial records follow the target (within its defined range); from
#: 0.04 s, matching a target that rises steeply below 0.1 s put 15-25 Hz content in (Fourier ratio
#: 15-40 / 1-3 Hz 0.053 for a table with S_a(0.05)/S_a(0) = 1.6; 0.040 from 0.05 s)
GENERATION_RANGE = (0.05, 6.0)
#: f_mid [Hz] is kept within these bounds
MID_FREQUENCY = (1.5, 8.0)
#: corner of the high-pass oscillator [Hz] (RDK 2010)
CORNER = 0.2
MAX_ATTEMPTS = 10  # draws tried for one record before giving up
#: changes whenever a seed gives another record (manifests and the cache of check suites name it)
GENERATOR_VERSION = "rdk2010-as16-gamma-kappa-7"
#: f_mid [Hz] of a firm site is drawn within this band; a soft site's band is lowered with f_mid
#: (site_factor). From 3.6-4.4 Hz (generator -5) the draws at 3.6 Hz crossed zero 6.2 times a
#: second before matching and 5.2-5.9 after it
FIRM_BAND = (4.6, 5.4)
#: kappa [s] of the high-frequency diminution exp(-pi kappa f) (Anderson & Hough 1984): the low end
#: of firm-site kappa_0, as the filter's f^-2 above f_mid carries the rest of the fall-off
KAPPA = 0.02
#: zero crossings per second [1/s] a matched record's strong motion is held within: (firm, soft site)
CROSSINGS = ((6.0, 10.0), (3.0, 8.0))
#: the largest Fourier ratio 15-40 / 1-3 Hz of a matched record [-] (recorded median 0.015)
FOURIER_MAX = 0.04
#: Vs30 [m/s] below which the site lowers the filter's frequency, by (Vs30 / SOFT_SITE)^SOFT_POWER
SOFT_SITE = 360.0
SOFT_POWER = 0.5


@dataclass(frozen=True)
class FilterParameters:
    """Of the time-varying filter: mid_frequency f_mid [Hz] at t_mid [s], rate f' [Hz/s],
    damping z_f [-], lowest frequency [Hz], corner of the high-pass oscillator f_c [Hz], kappa [s]
    of the high-frequency diminution."""

    mid_frequency: float
    mid_time: float
    rate: float
    damping: float
    lowest: float
    corner: float

    kappa: float = KAPPA

    def frequency(self, t: np.ndarray) -> np.ndarray:
        """f(t) [Hz]."""
        return np.maximum(self.mid_frequency + self.rate * (t - self.mid_time), self.lowest)


def predominant_period(target_spectrum, match_range: tuple[float, float], damping: float = 0.05) -> float:
    """T_p [s]: the log-centre of the periods in match_range where the target is >= 90 % of its largest."""
    periods = np.geomspace(*match_range, 200)
    sa = target_spectrum.sa(periods, damping)
    high = periods[sa >= 0.9 * sa.max()]
    return float(math.sqrt(high[0] * high[-1]))


def site_factor(vs30: float) -> float:
    """The factor [-] on f_mid of a site of this Vs30 [m/s]: (Vs30 / SOFT_SITE)^SOFT_POWER below SOFT_SITE, else 1."""
    return min(1.0, vs30 / SOFT_SITE) ** SOFT_POWER


def draw_parameters(rng: np.random.Generator, target_spectrum, match_range: tuple[float, float],
                    envelope: Envelope, vs30: float) -> FilterParameters:
    """The filter of one record (module docstring)."""
    site = site_factor(vs30)
    centre = float(np.clip(1.0 / predominant_period(target_spectrum, match_range), *MID_FREQUENCY))
    mid = float(np.clip(centre * site * math.exp(0.25 * rng.standard_normal()), *(site * f for f in FIRM_BAND)))
    rate = -mid * rng.uniform(0.1, 0.4) / envelope.d5_95
    damping = rng.uniform(0.15, 0.4)
    lowest = max(0.3, 1.0 / match_range[1])
    corner = CORNER
    return FilterParameters(mid, envelope.arias_time(0.45), rate, damping, lowest, corner)


def filtered_noise(noise: np.ndarray, dt: float, frequency: np.ndarray, damping: float) -> np.ndarray:
    """sum_{tau_i <= t} h(t - tau_i, tau_i) w_i / sigma_f(t) (RDK Eq. 3 normalised to unit variance),
    the filter frequency [Hz] of each pulse that of its own time; the sum is cut where the
    slowest pulse has decayed to exp(-8)."""
    n = noise.size
    omega = 2.0 * math.pi * frequency
    root = math.sqrt(1.0 - damping**2)
    lags = min(n, math.ceil(8.0 / (damping * float(omega.min())) / dt) + 1)
    total = np.zeros(n)
    variance = np.zeros(n)
    for lag in range(1, lags):
        s = lag * dt
        w = omega[: n - lag]
        pulse = w / root * np.exp(-damping * w * s) * np.sin(w * root * s)
        total[lag:] += pulse * noise[: n - lag]
        variance[lag:] += pulse**2
    return np.divide(total, np.sqrt(variance), out=np.zeros(n), where=variance > 0.0)


def diminished(process: np.ndarray, dt: float, kappa: float) -> np.ndarray:
    """The process times exp(-pi kappa f) in the frequency domain [-] (zero phase; padded to twice
    its length so that nothing wraps around)."""
    n = process.size
    frequencies = np.fft.rfftfreq(2 * n, dt)
    return np.fft.irfft(np.fft.rfft(process, 2 * n) * np.exp(-math.pi * kappa * frequencies), 2 * n)[:n]


def high_pass(acceleration: np.ndarray, dt: float, corner: float) -> np.ndarray:
    """u'' of u'' + 2 w_c u' + w_c^2 u = a (critically damped oscillator, RDK Eq. 5): H(s) = (s/(s + w_c))^2,
    by the bilinear transform, two first-order sections y_k = c y_(k-1) + g (x_k - x_(k-1))."""
    omega = 2.0 * math.pi * corner
    k = 2.0 / dt
    gain, pole = k / (k + omega), (k - omega) / (k + omega)
    out = np.asarray(acceleration, dtype=float)
    for _ in range(2):
        x, y = out.tolist(), [0.0] * out.size
        previous_x = previous_y = 0.0
        for i, value in enumerate(x):
            previous_y = pole * previous_y + gain * (value - previous_x)
            previous_x = value
            y[i] = previous_y
        out = np.array(y)
    return out


def stochastic_record(target_spectrum, match_range: tuple[float, float], draw, dt: float,
                      envelope: Envelope, vs30: float) -> tuple[np.ndarray, FilterParameters]:
    """The unscaled, unmatched acceleration [-] of one draw (SeedSequence(draw)) and its filter."""
    rng = np.random.default_rng(np.random.SeedSequence(draw))
    parameters = draw_parameters(rng, target_spectrum, match_range, envelope, vs30)
    n = envelope.samples(dt)
    t = np.arange(n) * dt
    noise = rng.standard_normal(n)
    process = diminished(filtered_noise(noise, dt, parameters.frequency(t), parameters.damping), dt, parameters.kappa)
    taper = end_taper(n, dt)
    return taper * high_pass(envelope(t) * taper * process, dt, parameters.corner), parameters


def generation_range(target_spectrum, period_range: tuple[float, float], dt: float) -> tuple[float, float]:
    """Periods [s] over which artificial records are matched: GENERATION_RANGE within the target's
    defined range and above SAMPLES_PER_PERIOD x dt, widened to hold the suite's period range."""
    low, high = target_spectrum.period_range
    lower = max(GENERATION_RANGE[0], low, SAMPLES_PER_PERIOD * dt)
    upper = min(GENERATION_RANGE[1], high)
    return min(lower, period_range[0]), max(upper, period_range[1])


@dataclass(frozen=True)
class Artificial:
    """One artificial record: result (MatchResult, acceleration [m/s^2]); seed and index it is
    reproducible from; attempt: the draw kept (0: the first; module docstring); envelope;
    parameters: its filter; match_range [s]."""

    result: MatchResult
    seed: int
    index: int
    attempt: int
    envelope: Envelope
    parameters: FilterParameters
    match_range: tuple[float, float]


def generate(target_spectrum, period_range: tuple[float, float], seed: int, index: int = 0, dt: float = 0.01,
             envelope: Envelope | None = None, settings: MatchSettings | None = None,
             scenario: Scenario | None = None) -> Artificial:
    """One artificial record for a design spectrum (.sa): matched over generation_range, the
    tolerance checked over period_range [s]; its envelope drawn for the scenario (default:
    envelopes.default_scenario) unless given. If the tolerance is not met, or the matched record
    does not look recorded (character_misfit > 0), new draws are made (SeedSequence([seed, index,
    attempt]), up to MAX_ATTEMPTS); then the draw of least misfit that met the tolerance is kept;
    AnalysisError if none met it."""
    settings = settings or MatchSettings()
    scenario = scenario or default_scenario(target_spectrum)
    envelope = envelope or record_envelope(period_range, seed, index, scenario)
    match_range = generation_range(target_spectrum, period_range, dt)
    periods = control_periods(period_range, settings.periods_per_octave)
    target = matching_target(target_spectrum, settings)
    kept = None
    for attempt in range(MAX_ATTEMPTS):
        draw = [int(seed), int(index)] + ([attempt] if attempt else [])
        seed_record, parameters = stochastic_record(target_spectrum, match_range, draw, dt, envelope, scenario.vs30)
        result = match_acceleration(seed_record, dt, target, match_range, periods, settings)
        item = Artificial(result, int(seed), int(index), attempt, envelope, parameters, match_range)
        rank = _rank(item, scenario.vs30)
        if rank == (0, 0.0):
            return item
        kept = min(kept or (rank, item), (rank, item), key=lambda pair: pair[0])
    return _kept(kept, settings, period_range)


def _rank(item: Artificial, vs30: float) -> tuple[int, float]:
    """How a draw ranks (the least first): (0, character_misfit) if it met the tolerance, else
    (1, the spread of its S_a/target in log); (0, 0.0): it is kept at once."""
    if item.result.converged:
        return 0, character_misfit(item.result.acceleration, item.result.dt, vs30)
    return 1, float(np.ptp(np.log(item.result.ratios)))


def _kept(kept: tuple[tuple[int, float], Artificial], settings: MatchSettings,
          period_range: tuple[float, float]) -> Artificial:
    """The best-ranked draw if it met the tolerance; else AnalysisError naming the ratios it reached."""
    (missed, _), item = kept
    if not missed:
        return item
    low, high = item.result.ratio_range
    raise AnalysisError(f"artificial record {item.index + 1} (seed {item.seed}): no draw of {MAX_ATTEMPTS} met the "
                        f"tolerance {settings.low:g}-{settings.high:g} over {period_range[0]:.3g}-{period_range[1]:.3g}"
                        f" s (S_a/target {low:.3f} to {high:.3f}); try another seed")


def crossing_band(vs30: float) -> tuple[float, float]:
    """Zero crossings per second [1/s] of a recorded motion's strong motion at a site of this Vs30 [m/s]."""
    return CROSSINGS[0] if vs30 >= SOFT_SITE else CROSSINGS[1]


def character_misfit(acceleration: np.ndarray, dt: float, vs30: float) -> float:
    """How far a matched record is from looking recorded [-]: 0 when its zero crossings are within
    crossing_band(vs30) and its Fourier ratio at most FOURIER_MAX, else the sum of the relative
    excesses."""
    low, high = crossing_band(vs30)
    rate = zero_crossing_rate(acceleration, dt)
    ratio = fourier_ratio(acceleration, dt)
    return max(low - rate, 0.0) / low + max(rate - high, 0.0) / high + max(ratio / FOURIER_MAX - 1.0, 0.0)


def check_generation(target_spectrum, period_range: tuple[float, float], dt: float, source: str) -> None:
    """InputError, before any work, for what generation cannot do: a target that does not cover
    the period range, a step too coarse for its lower period, a target with a zero ordinate
    where the records are matched."""
    check_target(target_spectrum, period_range, source, "period_range")
    if not 0.0 < dt <= period_range[0] / SAMPLES_PER_PERIOD:
        raise InputError(source, "dt", f"a time step > 0 and <= {period_range[0] / SAMPLES_PER_PERIOD:.4g} s "
                         f"(the lower period {period_range[0]:.4g} s / {SAMPLES_PER_PERIOD}), got {dt:g} s")
    match_range = generation_range(target_spectrum, period_range, dt)
    periods = np.geomspace(*match_range, 200)
    zero = periods[target_spectrum.sa(periods, 0.05) <= 0.0]
    if zero.size:
        raise InputError(source, "target", f"a target spectrum > 0 over {match_range[0]:.3g}-{match_range[1]:.3g} s, "
                         f"where the records are matched ({target_spectrum.name} is 0 at {zero[0]:.3g} s)")


def record_envelope(period_range: tuple[float, float], seed: int, index: int, scenario: Scenario,
                    minimum: float = 0.0) -> Envelope:
    """The envelope of record `index` of `seed` (envelopes.draw_envelope): D5-95 at least
    `minimum` [s], the record at least MIN_CYCLES x the upper period [s]."""
    return draw_envelope(seed, index, scenario, minimum, MIN_CYCLES * period_range[1])


def suite_envelopes(target_spectrum, period_range: tuple[float, float], rule: CodeRule, count: int, seed: int,
                    scenario: Scenario | None = None, minimum: float = 0.0) -> list[Envelope]:
    """The envelopes of generate_suite's records: D5-95 at least rule.stationary_duration (EN 1998-1
    3.2.3.1.2(3)) and `minimum` [s]."""
    scenario = suite_scenario(target_spectrum, scenario)
    shortest = max(rule.stationary_duration, minimum)
    return [record_envelope(period_range, seed, k, scenario, shortest) for k in range(count)]


def suite_scenario(target_spectrum, scenario: Scenario | None = None) -> Scenario:
    """The scenario given, else the target's default (envelopes.default_scenario)."""
    return scenario or default_scenario(target_spectrum)


def generate_suite(target_spectrum, period_range: tuple[float, float], rule: CodeRule, count: int, seed: int,
                   dt: float = 0.01, envelopes: list[Envelope] | None = None, settings: MatchSettings | None = None,
                   period_note: str = "", scenario: Scenario | None = None) -> tuple[Suite, list[Artificial]]:
    """`count` artificial records (indices 0..count-1 of `seed`) for the target over period_range [s],
    as a matched Suite (amplitude factors by scaling.matched_factors) and the records' details.
    Each record's envelope is drawn for the scenario (record_envelope) unless `envelopes` are given."""
    check_generation(target_spectrum, period_range, dt, "record generate")
    settings = settings or settings_for(rule)
    scenario = suite_scenario(target_spectrum, scenario)
    envelopes = envelopes or suite_envelopes(target_spectrum, period_range, rule, count, seed, scenario)
    items = [generate(target_spectrum, period_range, seed, k, dt, envelopes[k], settings, scenario)
             for k in range(count)]
    records = tuple(Record(name=f"artificial {seed}-{k + 1:02d}", dt=dt, acceleration=item.result.acceleration,
                           source=f"artificial {seed}-{k + 1:02d}", units="g") for k, item in enumerate(items))
    provenance = tuple(f"artificial record, seed {seed}, index {item.index}, draw {item.attempt}" for item in items)
    suite = Suite(records, (1.0,) * count, target_spectrum, tuple(period_range), rule, "match", period_note, (),
                  provenance, settings.damping, items[0].result.periods, ("artificial",) * count)
    return with_matched_factors(suite, [item.result.ratios for item in items], settings), items
