"""Records that read well but hold no ground shaking to scale or match (issue 38, T9): every
sample 0, one constant acceleration, an Arias intensity that is 0 in double precision (values
near 1e-300, whose squares underflow), a single pulse (the strong motion, D5-95, shorter than
the lower period of the range: one non-zero sample, say), or a response spectrum that is 0 at
the periods of the range. Each is one line naming the record (errors.InputError), raised before
any work, instead of a factor of inf or a singular system deep in the wavelet iteration.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .measures import arias_times
from .records import Record, arias_intensity


def _name(record: Record) -> str:
    return record.source or record.name


def still_problem(acceleration: np.ndarray) -> str | None:
    """What is wrong with a record with no motion at all (every sample 0, or all the same), or None."""
    if not np.any(acceleration):
        return "every sample is 0"
    if np.all(acceleration == acceleration[0]):
        return f"every sample is {acceleration[0]:.4g} m/s^2: a constant acceleration is no ground shaking"
    return None


def pulse_problem(acceleration: np.ndarray, dt: float, lower: float) -> str | None:
    """What is wrong with a record whose motion is too small for double precision, or a single
    pulse (D5-95 shorter than the lower period [s]), or None."""
    if not arias_intensity(acceleration, dt) > 0.0:
        peak = float(np.max(np.abs(acceleration)))
        return f"its Arias intensity is 0 in double precision (peak {peak:.3g} m/s^2)"
    start, end = arias_times(acceleration, dt)
    if end - start < lower:
        return (f"its strong motion (D5-95) lasts {end - start:.3g} s from t = {start:.4g} s, less than the lower "
                f"period {lower:.4g} s: a single pulse, not a ground motion")
    return None


def check_matchable_motion(record: Record, lower: float) -> None:
    """InputError naming the record when it holds no motion that can be matched over a range
    from the lower period [s] (still_problem, pulse_problem)."""
    problem = still_problem(record.acceleration) or pulse_problem(record.acceleration, record.dt, lower)
    if problem:
        raise InputError(_name(record), "acceleration", f"a record with motion to match ({problem})")


def check_spectra(names, spectra: np.ndarray, periods: np.ndarray, what: str) -> None:
    """InputError naming the first record (names) whose S_a (a row of spectra) is not > 0 at
    every one of the periods [s] (its factor would be infinite); what: 'scaled' or 'matched'."""
    for name, row in zip(names, spectra, strict=True):
        bad = np.flatnonzero(~(row > 0.0))
        if bad.size:
            raise InputError(name, "acceleration", f"a record with a response spectrum > 0 over the period range "
                             f"to be {what}, got S_a = {row[bad[0]]:.3g} m/s^2 at {periods[bad[0]]:.4g} s")
