"""Selection of recorded motions for a target spectrum (ASCE 7-22 16.2.2; the method of the PEER
ground-motion tool): every candidate is scaled to fit the target in the least-squares sense in
log S_a over the period range, its factor kept within the limits, and ranked by the misfit of its
scaled spectrum, the RMS of ln(f S_a / target) over the range; the best are taken in turn, at
most `per_event` from one earthquake. The suite's factors are then those of amplitude scaling
(suites.with_amplitude_factors: the same fits, times one common multiplier that brings the mean
to the code's criterion), and check_factors refuses a suite whose factors leave the limits.
Arrays in, arrays out; the CLI is `uplift record select`.

    choice = select(spectra, target, events, count=11, limits=(0.25, 4.0), per_event=3)
    choice.indices, choice.fits, choice.misfits
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

#: default scale-factor limits [-] and records per earthquake
FACTOR_LIMITS = (0.25, 4.0)
PER_EVENT = 3


@dataclass(frozen=True)
class Selection:
    """indices: the chosen candidates, best first; fits [-]: the factor of each that fits the
    target in log S_a (within the limits); misfits [-]: RMS of ln(fit S_a / target) of each."""

    indices: tuple[int, ...]
    fits: tuple[float, ...]
    misfits: tuple[float, ...]


def fits(spectra, target, limits: tuple[float, float] = FACTOR_LIMITS) -> tuple[np.ndarray, np.ndarray]:
    """(factor, misfit) of each candidate (rows of spectra [m/s^2], target [m/s^2] at the same
    periods): the least-squares factor in log S_a clipped to the limits, and the RMS of
    ln(factor S_a / target) [-]."""
    spectra = np.atleast_2d(np.asarray(spectra, dtype=float))
    log_ratio = np.log(np.asarray(target, dtype=float)[None, :] / spectra)
    factors = np.clip(np.exp(log_ratio.mean(axis=1)), *limits)
    misfits = np.sqrt(np.mean((np.log(factors)[:, None] - log_ratio) ** 2, axis=1))
    return factors, misfits


def select(spectra, target, events, count: int, limits: tuple[float, float] = FACTOR_LIMITS,
           per_event: int = PER_EVENT, source: str = "record select") -> Selection:
    """The `count` candidates of least misfit, at most per_event from one earthquake (events: a
    label per candidate); InputError naming --count when fewer can be taken."""
    factors, misfits = fits(spectra, target, limits)
    taken = _taken(np.argsort(misfits, kind="stable"), events, count, per_event)
    if len(taken) < count:
        raise InputError(source, "--count", f"at most {len(taken)} records from {len(set(events))} earthquakes with "
                         f"--per-event {per_event} ({len(events)} usable candidates), got --count {count}")
    return Selection(tuple(taken), tuple(float(f) for f in factors[taken]), tuple(float(m) for m in misfits[taken]))


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
