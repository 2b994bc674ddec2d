"""Amplitude factors of a suite of records against a target spectrum (arrays in, arrays out).

* `amplitude_factors`: one factor per record, or one for the suite, meeting the code's mean
  criterion (ASCE 7-22 16.2.3.2 and EN 1998-1 3.2.3.1.2(4): the mean S_a not below 90 % of the
  target over the period range). Per record, each record is first fitted to the target in the
  least-squares sense in log S_a over the range (f_i = exp(mean ln(target / S_a,i))); then one
  common multiplier F = max_T (criterion x target / mean_i f_i S_a,i) brings the mean onto the
  criterion at its governing period (the least scaling that meets it). For the suite: f_i = 1.
* `matched_factors`: the amplitude factors of spectrally matched records: each record centred on
  the aim level, kept within its tolerance band, and raised together if the mean must reach the
  code's matched mean (ASCE 7-22 16.2.3.3: 110 %).
* `factor_warnings`: factors outside 0.25-4 (a usual limit on amplitude scaling).
"""

from __future__ import annotations

import numpy as np

from ..errors import AnalysisError

#: amplitude factors outside this range are reported with a warning
FACTOR_LIMITS = (0.25, 4.0)


def amplitude_factors(spectra, target, criterion: float, per_record: bool = True) -> np.ndarray:
    """Factors [-] of the records whose S_a [m/s^2] are the rows of `spectra` (n_records, n_periods)
    so that the mean of the scaled spectra is >= criterion x target [m/s^2] at every period,
    with equality at the governing period (module docstring)."""
    spectra = np.atleast_2d(np.asarray(spectra, dtype=float))
    target = np.asarray(target, dtype=float)
    fits = np.exp(np.mean(np.log(target / spectra), axis=1)) if per_record else np.ones(spectra.shape[0])
    mean = np.mean(fits[:, None] * spectra, axis=0)
    return fits * float(np.max(criterion * target / mean))


def mean_ratio(spectra, target, factors) -> np.ndarray:
    """Mean over the records of factor x S_a / target at each period [-]."""
    spectra = np.atleast_2d(np.asarray(spectra, dtype=float))
    return np.mean(np.asarray(factors, dtype=float)[:, None] * spectra, axis=0) / np.asarray(target, dtype=float)


def matched_factors(ratios, level: float, low: float, high: float, mean_minimum: float, margin: float = 0.0,
                    names=None) -> np.ndarray:
    """Factors [-] of matched records with S_a/target `ratios` (n_records, n_periods): each record's
    log-centre of its ratios put on `level`, within the interval that keeps its ratios in
    [low (1 + margin), high / (1 + margin)]; if the mean then falls below mean_minimum (1 + margin)
    somewhere, all are raised by one common multiplier (bisection), each still within its interval
    (as far as the intervals allow: the caller checks the mean). AnalysisError when a record's
    ratios cannot fit the band with any factor."""
    ratios = np.atleast_2d(np.asarray(ratios, dtype=float))
    names = list(names) if names is not None else [f"record {k + 1}" for k in range(ratios.shape[0])]
    smallest, largest = ratios.min(axis=1), ratios.max(axis=1)
    lower = low * (1.0 + margin) / smallest
    upper = high / ((1.0 + margin) * largest)
    for name, a, b, s, t in zip(names, lower, upper, smallest, largest, strict=True):
        if a > b:
            raise AnalysisError(f"{name}: S_a/target spans {s:.3f} to {t:.3f} over the period range, wider than "
                                f"the tolerance {low:g} to {high:g} allows")
    bounds = (level / np.sqrt(smallest * largest), lower, upper)
    return _clipped(_common_multiplier(bounds, ratios, mean_minimum * (1.0 + margin)), bounds)


def _clipped(multiplier: float, bounds: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
    """The factors multiplier x centre, each within its interval; bounds: (centre, lower, upper)."""
    centre, lower, upper = bounds
    return np.clip(multiplier * centre, lower, upper)


def _mean_reaches(multiplier: float, bounds, ratios: np.ndarray, need: float) -> bool:
    """Whether the mean of the factored ratios (_clipped) is at least `need` at every period."""
    return bool(np.min(np.mean(_clipped(multiplier, bounds)[:, None] * ratios, axis=0)) >= need)


def _common_multiplier(bounds, ratios: np.ndarray, need: float) -> float:
    """The multiplier of every centre: 1 when the mean reaches `need` already; the largest the
    intervals allow when even that does not (the caller reports the shortfall); else the smallest
    that does, by 60 bisections."""
    if _mean_reaches(1.0, bounds, ratios, need):
        return 1.0
    centre, _, upper = bounds
    top = float(np.max(upper / centre))
    if not _mean_reaches(top, bounds, ratios, need):
        return top  # the highest mean the tolerance allows; the caller reports the shortfall
    bottom = 1.0
    for _ in range(60):
        middle = 0.5 * (bottom + top)
        bottom, top = (bottom, middle) if _mean_reaches(middle, bounds, ratios, need) else (middle, top)
    return top


def factor_warnings(names, factors) -> list[str]:
    """One message per factor outside FACTOR_LIMITS."""
    low, high = FACTOR_LIMITS
    return [f"{name}: amplitude factor {factor:.3g} is outside {low:g}-{high:g}"
            for name, factor in zip(names, factors, strict=True) if not low <= factor <= high]
