"""Selection of recorded motions for a target spectrum (ASCE 7-22 16.2.2; the method of the PEER
ground-motion tool): every candidate is fitted to the target in the least-squares sense in
log S_a over the period range, and ranked by the misfit of its fitted spectrum, the RMS of
ln(f S_a / target) over the range; the best are taken in turn, at most `per_event` from one
earthquake. A candidate whose factor leaves the limits is passed over, not clipped (as the PEER
tool excludes records whose scale factor is outside its limits). The factor that counts is the
one the record is written with: its own fit times the common multiplier of amplitude scaling
(scaling.amplitude_factors: the least that brings the suite's mean to the code's criterion), so
the choice is made again without any record that this multiplier pushes out of the limits,
until every chosen record's factor is within them. check_factors then refuses a written suite
whose factors leave the limits (the multiplier raised on the denser grid of suites.py).
Arrays in, arrays out; the CLI is `uplift record select`.

    choice = select(spectra, target, events, count=11, limits=(0.25, 4.0), per_event=3)
    choice.indices, choice.fits, choice.misfits, choice.factors
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..runtime import limits as size_limits
from .scaling import amplitude_factors
from .spectra import response_spectrum

#: default scale-factor limits [-] and records per earthquake
FACTOR_LIMITS = (0.25, 4.0)
PER_EVENT = 3
#: the mean S_a / target the common multiplier aims at by default: ASCE 7-22 16.2.3.2's 90 %,
#: 0.5 % above it (suites.SCALING_MARGIN)
CRITERION = 0.9 * 1.005


@dataclass(frozen=True)
class Selection:
    """indices: the chosen candidates, best first; fits [-]: the factor of each that fits the
    target in log S_a; misfits [-]: RMS of ln(fit S_a / target) of each; factors [-]: the fits
    times the common multiplier that brings the mean to the criterion (each within the limits)."""

    indices: tuple[int, ...]
    fits: tuple[float, ...]
    misfits: tuple[float, ...]
    factors: tuple[float, ...] = ()


def candidate_spectra(records, periods, damping: float, source: str) -> np.ndarray:
    """S_a [m/s^2] of each candidate record (rows) at periods [s]; InputError naming `source` (--from)
    when a record's time step cannot give the shortest period, or when the candidates' spectra take
    more than limits.MAX_SELECTION_WORK oscillator sub-steps (the pool, not a suite: a suite's own
    limit, MAX_SPECTRUM_WORK, is checked on the records chosen)."""
    periods = np.asarray(periods, dtype=float)
    _check_candidates(records, periods, source)
    return np.array([response_spectrum(r.acceleration, r.dt, periods, [damping]).pseudo_acceleration[0]
                     for r in records])


def _check_candidates(records, periods: np.ndarray, source: str) -> None:
    """InputError naming --from when a record cannot give the shortest period or the pool's
    spectra exceed limits.MAX_SELECTION_WORK (candidate_spectra)."""
    for record in records:
        _check_shortest_period(record, periods, source)
    work = sum(size_limits.spectrum_work(periods, 1, record.dt, record.npts) for record in records)
    if work > size_limits.MAX_SELECTION_WORK:
        raise InputError("--from", source, f"at most {size_limits.MAX_SELECTION_WORK:,} oscillator sub-steps for the "
                         f"candidates' spectra, got {work:,} ({len(records)} records, {periods.size} periods from "
                         f"{periods[0]:.4g} s): fewer candidates, or a longer lower period (period_range)")


def _check_shortest_period(record, periods: np.ndarray, source: str) -> None:
    """InputError naming --from and the record when its time step cannot give the shortest period."""
    problem = size_limits.period_problem(periods[:1], record.dt, record.npts)
    if problem:
        raise InputError("--from", source, f"{problem} (record {record.source or record.name})")


def fits(spectra, target) -> tuple[np.ndarray, np.ndarray]:
    """(factor, misfit) of each candidate (rows of spectra [m/s^2], target [m/s^2] at the same
    periods): the least-squares factor in log S_a, exp(mean ln(target / S_a)), and the RMS of
    ln(factor S_a / target) [-], the standard deviation of ln(S_a / target) over the periods."""
    spectra = np.atleast_2d(np.asarray(spectra, dtype=float))
    log_ratio = np.log(np.asarray(target, dtype=float)[None, :] / spectra)
    factors = np.exp(log_ratio.mean(axis=1))
    misfits = np.sqrt(np.mean((np.log(factors)[:, None] - log_ratio) ** 2, axis=1))
    return factors, misfits


def within(factors, limits: tuple[float, float]) -> np.ndarray:
    """Whether each factor [-] is within the limits (low, high), to round-off."""
    factors = np.asarray(factors, dtype=float)
    return (factors >= limits[0] * (1.0 - 1e-9)) & (factors <= limits[1] * (1.0 + 1e-9))


def select(spectra, target, events, count: int, limits: tuple[float, float] = FACTOR_LIMITS,
           per_event: int = PER_EVENT, source: str = "record select", criterion: float = CRITERION) -> Selection:
    """The `count` candidates of least misfit, at most per_event from one earthquake (events: a
    label per candidate), each written with a factor within the limits (module docstring);
    InputError naming the factor limit or --count when fewer can be taken."""
    spectra = np.atleast_2d(np.asarray(spectra, dtype=float))
    own, misfits = fits(spectra, target)
    allowed = within(own, limits)
    order = np.argsort(misfits, kind="stable")
    while True:
        taken = _taken(order[allowed[order]], events, count, per_event)
        if len(taken) < count:
            raise _too_few(own, events, (count, per_event), limits, source)
        factors = amplitude_factors(spectra[taken], target, criterion)
        inside = within(factors, limits)
        if inside.all():
            return _selection(taken, own, misfits, factors)
        allowed[np.asarray(taken)[~inside]] = False


def _selection(taken: list[int], own: np.ndarray, misfits: np.ndarray, factors: np.ndarray) -> Selection:
    """The Selection of the candidates `taken` (own fits and misfits of every candidate; their factors)."""
    return Selection(tuple(taken), tuple(own[taken].tolist()), tuple(misfits[taken].tolist()), tuple(factors.tolist()))


def _too_few(own: np.ndarray, events, wanted: tuple[int, int], limits: tuple[float, float],
             source: str) -> InputError:
    """The error when fewer than `count` candidates can be taken: the factor limit that passed
    candidates over when the earthquakes alone would allow `count`, else --count."""
    count, per_event = wanted
    possible = len(_taken(np.arange(own.size), events, count, per_event))
    if possible < count:
        return InputError(source, "--count", f"at most {possible} records from {len(set(events))} earthquakes with "
                          f"--per-event {per_event} ({len(events)} usable candidates), got --count {count}")
    option, advice = ("--factor-max", "stronger") if np.any(own > limits[1]) else ("--factor-min", "weaker")
    return InputError(source, option, f"scale factors within {limits[0]:g}-{limits[1]:g} that bring the mean to the "
                      f"target's criterion: only {int(within(own, limits).sum())} of {own.size} candidates fit the "
                      f"target within them, too few for --count {count} with --per-event {per_event} (their own "
                      f"fits span {own.min():.3g} to {own.max():.3g}; widen {option} or give {advice} records)")


def _taken(order: np.ndarray, events, count: int, per_event: int) -> list[int]:
    """The first `count` candidates in `order`, passing over those whose earthquake (events) has
    given per_event already (fewer when the candidates run out)."""
    taken: list[int] = []
    per: Counter = Counter()
    for k in order:
        if per[events[k]] < per_event:
            taken.append(int(k))
            per[events[k]] += 1
        if len(taken) == count:
            break
    return taken


def check_factors(factors, limits: tuple[float, float], criterion: float, source: str = "record select") -> None:
    """InputError naming --factor-max or --factor-min when the suite's factors (the common multiplier
    that brings the mean to the criterion included) leave the limits."""
    factors = np.asarray(factors, dtype=float)
    low, high = limits
    if factors.max() > high * (1.0 + 1e-9):
        raise InputError(source, "--factor-max", f"scale factors up to {high:g} that bring the mean to {criterion:g} "
                         f"x the target: the chosen records need up to {factors.max():.3g} (the candidates are too "
                         "weak for this target; raise --factor-max or give stronger records)")
    if factors.min() < low * (1.0 - 1e-9):
        raise InputError(source, "--factor-min", f"scale factors down to {low:g} that bring the mean to {criterion:g} "
                         f"x the target: the chosen records need {factors.min():.3g} (the candidates are too strong "
                         "for this target; lower --factor-min)")
