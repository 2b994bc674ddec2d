"""Record suites as data: the records, their amplitude factors, the target spectrum, the period
range and the code rule (code_rules.py), built from records or read from a folder or a list of
files; scaled (scaling.py) or spectrally matched (matching.py) as asked.

    suite = build_suite(records, target, (0.2, 2.0), RULES["asce7-22"], scaling="amplitude")
    suite.factors, suite.motions(), suite.mean_ratio(periods), suite.warnings

Checks (each an InputError naming the record or the field): a record shorter than MIN_CYCLES
times the upper period of the range, a record too coarsely sampled to be matched at the lower
period (fewer than SAMPLES_PER_PERIOD steps), a record with no ground shaking to match or scale
(usable.py: all zeros, constant, a single pulse, S_a = 0), a target that does not cover the
range. Too few
records for the code is a warning (Suite.warnings), as are factors outside 0.25-4 and, for
scaling = "none", a mean below the code's criterion.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..errors import InputError
from ..runtime import limits
from .code_rules import SCALINGS, CodeRule
from .design_spectra import spectrum_warnings
from .matching import MatchSettings, control_periods, match_record, settings_for
from .records import Record
from .scaling import amplitude_factors, factor_warnings, matched_factors, mean_ratio
from .spectra import RecordSpectrum, response_spectrum
from .suite_files import ENTRY_FIELDS as ENTRY_FIELDS
from .suite_files import RECORD_SUFFIXES as RECORD_SUFFIXES
from .suite_files import check_entry as check_entry
from .suite_files import entry_origins as entry_origins
from .suite_files import read_records as read_records
from .suite_files import suite_entries as suite_entries
from .usable import check_matchable_motion, check_spectra

MIN_CYCLES = 4  # a record lasts at least 4 x the upper period of the range
SAMPLES_PER_PERIOD = 4  # a record to be matched has a step dt <= lower period / 4
PERIODS_PER_OCTAVE = 96  # periods at which amplitude factors and the mean are checked
SCALING_MARGIN = 0.005  # amplitude factors aim 0.5 % above the criterion at the check periods ...
DENSE_FACTOR = 4  # ... and the mean is checked again on a grid this many times denser


@dataclass(frozen=True)
class Suite:
    """A suite of records for one target.

    records: the ground motions (as read, or as matched), before the factors; factors: amplitude
    factor of each [-]; target: the design spectrum (.sa); period_range: (lower, upper) [s];
    rule: the code rule; scaling: 'none', 'amplitude' or 'match'; period_note: how the period
    range was found; warnings: messages to pass on; provenance: per record, where it came from;
    damping: of the spectra compared [-]; periods: the check periods [s]; made: how each record
    was made (origins.py: recorded, matched, artificial).
    """

    records: tuple[Record, ...]
    factors: tuple[float, ...]
    target: Any
    period_range: tuple[float, float]
    rule: CodeRule
    scaling: str = "none"
    period_note: str = ""
    warnings: tuple[str, ...] = ()
    provenance: tuple[str, ...] = ()
    damping: float = 0.05
    periods: np.ndarray = field(default=None, repr=False)  # type: ignore[assignment]
    made: tuple[str, ...] = ()

    def __post_init__(self):
        if self.periods is None:
            object.__setattr__(self, "periods", control_periods(self.period_range, PERIODS_PER_OCTAVE))
        if len(self.made) != len(self.records):
            default = "matched" if self.scaling == "match" else "recorded"
            object.__setattr__(self, "made", (*self.made, *(default,) * (len(self.records) - len(self.made))))

    @property
    def matched(self) -> bool:
        """Whether the records were spectrally matched (or generated): then the code's matched mean
        applies (ASCE 7-22 16.2.3.3: 110 %), however the deck scales them."""
        return self.scaling == "match" or any(made != "recorded" for made in self.made)

    @property
    def mean_minimum(self) -> float:
        """The lowest mean S_a/target the code allows for this suite [-]."""
        return self.rule.matched_mean if self.matched else self.rule.scaled_mean

    @property
    def count(self) -> int:
        return len(self.records)

    @property
    def sources(self) -> tuple[str, ...]:
        return tuple(record.source for record in self.records)

    @property
    def statistic(self) -> str:
        """'mean' or 'max': the design value the code takes from this many records."""
        return self.rule.statistic(self.count)

    def motions(self) -> tuple[Record, ...]:
        """The records with their factors applied."""
        return tuple(replace(record, acceleration=factor * record.acceleration, scale=record.scale * factor)
                     for record, factor in zip(self.records, self.factors, strict=True))

    def spectra(self, periods=None) -> np.ndarray:
        """S_a [m/s^2] of each scaled record (rows) at periods [s] (default: the check periods,
        computed once per suite and read-only)."""
        if periods is None:
            return self._check_spectra
        return self._spectra(np.asarray(periods, dtype=float))

    @functools.cached_property
    def _check_spectra(self) -> np.ndarray:
        spectra = self._spectra(self.periods)
        spectra.flags.writeable = False
        return spectra

    def _spectra(self, periods: np.ndarray) -> np.ndarray:
        return np.array([response_spectrum(r.acceleration, r.dt, periods, [self.damping]).pseudo_acceleration[0]
                         for r in self.motions()])

    @functools.cached_property
    def record_spectra(self) -> tuple[RecordSpectrum, ...]:
        """Each scaled record's spectrum (computed on demand and cached, shared by every analysis)."""
        return tuple(RecordSpectrum(motion) for motion in self.motions())

    def mean_ratio(self, periods=None) -> np.ndarray:
        """Mean S_a / target at periods [s] (default: the check periods) [-]."""
        periods = self.periods if periods is None else np.asarray(periods, dtype=float)
        return mean_ratio(self.spectra(periods), self.target.sa(periods, self.damping), np.ones(self.count))


def check_target(target, period_range: tuple[float, float], source: str, field: str) -> None:
    """InputError when the target spectrum does not cover the period range [s]."""
    low, high = target.period_range
    if period_range[0] < low or period_range[1] > high:
        raise InputError(source, field, f"a period range within the target's {low:g}-{high:g} s "
                         f"({target.name}), got {period_range[0]:.4g}-{period_range[1]:.4g} s")


def check_record(record: Record, period_range: tuple[float, float], matching: bool) -> None:
    """InputError naming the record when it is too short (or too coarse to be matched) for the range."""
    need = MIN_CYCLES * period_range[1]
    if record.duration < need:
        raise InputError(record.source or record.name, "duration",
                         f"a record of at least {MIN_CYCLES} x the upper period {period_range[1]:.4g} s = "
                         f"{need:.4g} s for the period range, got {record.duration:.4g} s")
    if matching:
        _check_matchable(record, period_range[0])


def _check_matchable(record: Record, lower: float) -> None:
    """InputError naming the record when it has no motion to match (usable.check_matchable_motion:
    all zeros, constant, a single pulse) or a time step above the lower period [s] / SAMPLES_PER_PERIOD."""
    check_matchable_motion(record, lower)
    if record.dt > lower / SAMPLES_PER_PERIOD:
        raise InputError(record.source or record.name, "dt",
                         f"a time step of at most {lower / SAMPLES_PER_PERIOD:.4g} s (the lower period "
                         f"{lower:.4g} s / {SAMPLES_PER_PERIOD}) to be matched, got {record.dt:g} s")


def check_work(records, period_range: tuple[float, float], matching: bool, source: str) -> None:
    """The documented limits of a suite, before any spectrum is computed (InputError naming the
    period range): its lower period within every record's spectrum range (limits.period_problem),
    the oscillator sub-steps of the records' spectra at the check periods (limits.spectrum_work:
    [1e-6, 2e-6] s ran past 300 s), and for matching the samples (limits.suite_samples_problem)."""
    _check_lower_period(records, period_range[0], source)
    _check_spectrum_work(records, period_range, source)
    if matching:
        _check_match_samples(records, source)


def _check_lower_period(records, lower: float, source: str) -> None:
    """InputError naming the period range when its lower period [s] is outside a record's spectrum
    range (limits.period_problem)."""
    for record in records:
        problem = limits.period_problem([lower], record.dt, record.npts)
        if problem:
            raise InputError(source, "period_range", f"{problem} (record {record.source or record.name})")


def _check_match_samples(records, source: str) -> None:
    """InputError when the records hold too many samples to be matched (limits.suite_samples_problem)."""
    problem = limits.suite_samples_problem([r.npts for r in records], f"{len(records)} records")
    if problem:
        raise InputError(source, "suite", f"{problem} to be matched")


def _check_spectrum_work(records, period_range: tuple[float, float], source: str) -> None:
    """InputError when the records' spectra at the check periods take more than
    limits.MAX_SPECTRUM_WORK oscillator sub-steps."""
    periods = control_periods(period_range, PERIODS_PER_OCTAVE)
    work = sum(limits.spectrum_work(periods, 1, record.dt, record.npts) for record in records)
    if work > limits.MAX_SPECTRUM_WORK:
        raise InputError(source, "period_range", f"at most {limits.MAX_SPECTRUM_WORK:,} oscillator sub-steps for the "
                         f"spectra of the suite (about 15 s), got {work:,} ({periods.size} check periods from "
                         f"{period_range[0]:.4g} s, {len(records)} records): a longer lower period")


def build_suite(records, target, period_range: tuple[float, float], rule: CodeRule, scaling: str = "none",
                suite_factor: bool = False, period_note: str = "", provenance=(), damping: float = 0.05,
                settings: MatchSettings | None = None, source: str = "suite", made=()) -> Suite:
    """A Suite of records.Record for the target over period_range [s] under `rule`, scaled by
    `scaling` ('none', 'amplitude': one factor per record, or one for the suite if suite_factor;
    'match': every record matched, then amplitude factors within the tolerance); made: how each
    record was made (origins.py; default "recorded")."""
    records = tuple(records)
    period_range = _checked_request(records, scaling, period_range, source)
    check_target(target, period_range, source, "period_range")
    _check_records(records, period_range, scaling)
    check_work(records, period_range, scaling == "match", source)
    if scaling == "match":
        settings = settings or settings_for(rule, damping=damping)
        return _matched_suite(records, target, period_range, rule, period_note, provenance, damping, settings)
    suite = Suite(records, (1.0,) * len(records), target, period_range, rule, scaling, period_note, (),
                  tuple(provenance) or tuple(r.source for r in records), damping, made=tuple(made))
    if scaling == "amplitude":
        suite = with_amplitude_factors(suite, suite_factor)
    return with_warnings(suite)


def _checked_request(records: tuple[Record, ...], scaling: str, period_range: tuple[float, float], source: str
                     ) -> tuple[float, float]:
    """The period range (lower, upper) [s] as floats; InputError for no records, an unknown
    scaling or a range that is not 0 < lower < upper."""
    if not records:
        raise InputError(source, "suite", "at least one record")
    if scaling not in SCALINGS:
        raise InputError(source, "scaling", f"one of {', '.join(SCALINGS)}, got {scaling!r}")
    lower, upper = (float(value) for value in period_range)
    if not 0.0 < lower < upper:
        raise InputError(source, "period_range", f"0 < lower < upper [s], got {lower:g}-{upper:g}")
    return lower, upper


def _check_records(records: tuple[Record, ...], period_range: tuple[float, float], scaling: str) -> None:
    """check_record for each record; a record to be scaled must also have a non-zero sample."""
    for record in records:
        check_record(record, period_range, scaling == "match")
        if scaling != "none" and not np.any(record.acceleration):  # its factor would be nan (0/0)
            raise InputError(record.source or record.name, None, f"a record with non-zero accelerations to be "
                             f"scaled (scaling = \"{scaling}\"): every sample is 0")


def _matched_suite(records: tuple[Record, ...], target, period_range: tuple[float, float], rule: CodeRule,
                   period_note: str, provenance, damping: float, settings: MatchSettings) -> Suite:
    """The suite of the records each matched to the target (matching.match_record), with the
    factors of with_matched_factors."""
    results = [match_record(record, target, period_range, settings) for record in records]
    matched = tuple(replace(record, acceleration=result.acceleration, name=f"{record.name} (matched)")
                    for record, result in zip(records, results, strict=True))
    suite = Suite(matched, (1.0,) * len(records), target, period_range, rule, "match", period_note, (),
                  tuple(provenance) or tuple(f"matched from {r.source}" for r in records), damping,
                  results[0].periods)
    return with_matched_factors(suite, [result.ratios for result in results], settings)


def with_amplitude_factors(suite: Suite, suite_factor: bool = False) -> Suite:
    """The suite with the amplitude factors of scaling.amplitude_factors for its criterion plus
    SCALING_MARGIN at the check periods, raised if the mean still dips below the criterion on
    the DENSE_FACTOR times denser grid (between the check periods)."""
    criterion = suite.mean_minimum
    check_spectra([r.source or r.name for r in suite.records], suite.spectra(), suite.periods, "scaled")
    factors = amplitude_factors(suite.spectra(), suite.target.sa(suite.periods, suite.damping),
                                criterion * (1.0 + SCALING_MARGIN), per_record=not suite_factor)
    suite = replace(suite, factors=tuple(float(f) for f in factors))
    dense = control_periods(suite.period_range, DENSE_FACTOR * PERIODS_PER_OCTAVE)
    lowest = float(np.min(suite.mean_ratio(dense)))
    if lowest < criterion:
        suite = replace(suite, factors=tuple(f * criterion / lowest for f in suite.factors))
    return suite


def with_matched_factors(suite: Suite, ratios, settings: MatchSettings) -> Suite:
    """The suite of matched records with the factors of scaling.matched_factors (ratios: S_a/matching
    target of each record at the suite's check periods) and its warnings."""
    factors = matched_factors(ratios, settings.level, settings.low, settings.high,
                              suite.mean_minimum / settings.reference, settings.margin,
                              [r.source or r.name for r in suite.records])
    return with_warnings(replace(suite, factors=tuple(float(f) for f in factors)))


def with_warnings(suite: Suite) -> Suite:
    """The suite with the messages it calls for: too few records for the code, the target's own
    warnings for response-history analysis, factors outside 0.25-4, EN 1998-1's zero-period
    condition, artificial records under ASCE 7-22 (16.2.2), a mean below the code's criterion
    (110 % for matched or artificial records under ASCE 7-22, wherever they are loaded)."""
    rule, upper = suite.rule, suite.period_range[1]
    warnings = [*rule.count_warnings(suite.count), *spectrum_warnings(suite.target, [upper], "response-history")]
    warnings += factor_warnings([r.source or r.name for r in suite.records], suite.factors)
    warnings += _zero_period_warnings(suite)
    warnings += _artificial_warnings(suite)
    warnings += _mean_warnings(suite)
    return replace(suite, warnings=tuple(warnings))


def _zero_period_warnings(suite: Suite) -> list[str]:
    """EN 1998-1 3.2.3.1.2(4)b: the mean PGA of the scaled records at least a_g S."""
    zero_period = getattr(suite.target, "design_ground_acceleration", None)
    if suite.rule.name != "ec8" or zero_period is None:
        return []
    pga = float(np.mean([motion.pga for motion in suite.motions()]))
    if pga < zero_period:
        return [f"EN 1998-1 3.2.3.1.2(4)b: the mean PGA {pga / zero_period:.3f} a_g S is below a_g S"]
    return []


def _artificial_warnings(suite: Suite) -> list[str]:
    """ASCE 7-22 16.2.2: artificial records only to supplement recorded ones."""
    artificial = sum(made == "artificial" for made in suite.made)
    if suite.rule.name != "asce7-22" or not artificial:
        return []
    return [f"ASCE 7-22 16.2.2 asks for recorded ground motions, simulated ones only to supplement them "
            f"where not enough appropriate recorded motions are available: {artificial} of {suite.count} "
            "records are artificial (uplift record select chooses recorded motions)"]


def _mean_warnings(suite: Suite) -> list[str]:
    """A mean S_a/target below the code's criterion at a check period."""
    lower, upper = suite.period_range
    minimum = float(np.min(suite.mean_ratio()))
    if not minimum < suite.mean_minimum * (1.0 - 1e-9):
        return []
    how = "spectrally matched or artificial records" if suite.matched else f"scaling = \"{suite.scaling}\""
    return [f"{suite.rule.label}: the mean S_a/target is {minimum:.3f} somewhere in {lower:.4g}-{upper:.4g} s, "
            f"below {suite.mean_minimum:g} ({how})"]
