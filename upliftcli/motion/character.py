"""Keep a matched record's Husid curve at the original's t_5 and t_95 (issue 36).

The wavelets add nothing before the original's t_5 nor after its t_95 (wavelets.WINDOW), but
where they lower the strong motion the record's total Arias intensity falls, and the unchanged
weak motion before t_5 and coda after t_95 then hold more than 5 % of it each: t_5 comes earlier,
t_95 later, D5-95 grows (measured up to 1.48x and a net early gain up to 5.3 % on the FEMA P695
records). So the part before t_5 is multiplied by a gain g <= 1 that rises to 1 by a half-cosine
from t_4 to t_5 (and the coda by one that falls from 1 from t_95 to t_96), g chosen so that the
matched record's normalised Husid curve at the original's t_5 is 5 % (at t_95: 95 %) again;
a part that holds less is left as it is. The baseline correction then brings the record to rest.
"""

from __future__ import annotations

import numpy as np

from .baseline import baseline_correct
from .measures import arias_history, arias_times

#: (ramp start, t_5) and (t_95, ramp end) as fractions of the original's Arias intensity
EARLY = (0.04, 0.05)
LATE = (0.95, 0.96)
#: fixed-point passes of the gains (each gain changes the total the other is measured against)
PASSES = 4


def _ramp(t: np.ndarray, begin: float, end: float) -> np.ndarray:
    """0 before `begin` [s], a half-cosine up to 1 at `end` [s], 1 after."""
    if end <= begin:
        return (t >= begin).astype(float)
    x = np.clip((t - begin) / (end - begin), 0.0, 1.0)
    return 0.5 - 0.5 * np.cos(np.pi * x)


def _gain(weight: np.ndarray, energy: np.ndarray, share: float, rest: float) -> float:
    """The gain c <= 1 of the part weighted by `weight` (1 where the gain applies fully, 0 where
    not at all) such that its energy is `share` of the total, `rest` the energy of the other parts."""
    full = float(np.sum(weight**2 * energy))
    mixed = float(np.sum(2.0 * weight * (1.0 - weight) * energy))
    fixed = float(np.sum((1.0 - weight) ** 2 * energy))
    # (c^2 full + c mixed + fixed) = share / (1 - share) x rest
    goal = share / (1.0 - share) * rest
    if full <= 0.0 or fixed + mixed + full <= goal:
        return 1.0
    c = (-mixed + np.sqrt(max(mixed**2 - 4.0 * full * (fixed - goal), 0.0))) / (2.0 * full)
    return float(np.clip(c, 0.0, 1.0))


def keep_shares(matched, original, dt: float) -> np.ndarray:
    """The matched acceleration [m/s^2] with its weak start and coda scaled (module docstring)."""
    a = np.asarray(matched, dtype=float)
    t = np.arange(a.size) * dt
    t2, t5, t95, t98 = arias_times(original, dt, (EARLY[0], EARLY[1], LATE[0], LATE[1]))
    early_weight = 1.0 - _ramp(t, t2, t5)
    late_weight = _ramp(t, t95, t98)
    energy = np.concatenate((np.diff(arias_history(a, dt)), [0.0]))
    early_part, late_part = t < t5, t > t95
    middle = float(np.sum(energy[~early_part & ~late_part]))
    c_early = c_late = 1.0
    for _ in range(PASSES):
        late_energy = float(np.sum(((1.0 - (1.0 - c_late) * late_weight) ** 2 * energy)[late_part]))
        c_early = _gain(early_weight[early_part], energy[early_part], EARLY[1], middle + late_energy)
        early_energy = float(np.sum(((1.0 - (1.0 - c_early) * early_weight) ** 2 * energy)[early_part]))
        c_late = _gain(late_weight[late_part], energy[late_part], 1.0 - LATE[0], middle + early_energy)
    gain = (1.0 - (1.0 - c_early) * early_weight) * (1.0 - (1.0 - c_late) * late_weight)
    return a if c_early == c_late == 1.0 else baseline_correct(a * gain, dt)
