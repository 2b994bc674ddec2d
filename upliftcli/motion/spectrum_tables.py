"""Tabulated spectra, the damping corrections of the codes and the checks shared by every
design spectrum (design_spectra.py builds on these).

* `asce_damping_coefficient`: B = 4 / (5.6 - ln(100 beta)) (ASCE 41-17 Eq. 2-3; the B_SSI of
  ASCE 7-22 chapter 19 and NIST GCR 12-917-21).
* `ec8_damping_correction`: eta = sqrt(10 / (5 + xi%)) >= 0.55 (EN 1998-1 Eq. 3.6).
* `TabulatedSpectrum`: a user table (T, S_a) at a stated damping, interpolated linearly in T.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..deck.fields import MAGNITUDE_WORDS, in_magnitude, is_number
from ..errors import InputError
from ..runtime.limits import MAX_RECORD_BYTES, read_input
from ..units import ACCELERATION_UNITS
from .readers import found, normalize_units, plain_number

#: damping corrections a table may use: name -> what it is
DAMPING_CORRECTIONS = {
    "asce": "B = 4/(5.6 - ln(100 beta)) of ASCE 41-17 Eq. 2-3 (ASCE 7-22 chapter 19)",
    "ec8": "eta = sqrt(10/(5 + xi%)) >= 0.55 of EN 1998-1 Eq. 3.6",
}


def asce_damping_coefficient(damping) -> np.ndarray:
    """B = 4 / (5.6 - ln(100 beta)), beta the damping ratio [-] (ASCE 41-17 Eq. 2-3; NIST GCR 12-917-21)."""
    return 4.0 / (5.6 - np.log(100.0 * np.asarray(damping, dtype=float)))


def ec8_damping_correction(damping) -> np.ndarray:
    """eta = sqrt(10 / (5 + xi)) >= 0.55, xi the damping in per cent (EN 1998-1 Eq. 3.6); damping ratio [-] in."""
    return np.maximum(np.sqrt(10.0 / (5.0 + 100.0 * np.asarray(damping, dtype=float))), 0.55)


def damping_factor(correction: str, damping: float, reference: float) -> float:
    """Factor from S_a at the `reference` damping to S_a at `damping` (ratios [-]) by the named rule."""
    if correction == "ec8":
        return float(ec8_damping_correction(damping) / ec8_damping_correction(reference))
    return float(asce_damping_coefficient(reference) / asce_damping_coefficient(damping))


def check_periods(periods, period_range, source: str, name: str, field: str = "period") -> np.ndarray:
    """The periods [s] as an array; InputError naming the first one outside period_range."""
    array = np.asarray(periods, dtype=float)
    low, high = period_range
    bad = ~np.isfinite(array) | (array < low) | (array > high)
    if np.any(bad):
        value = float(np.atleast_1d(array)[np.atleast_1d(bad)][0])
        raise InputError(source, field, f"periods within {low:g} to {high:g} s for {name}, got {value:g} s")
    return array


def check_damping(damping, source: str, allow_zero: bool = False) -> float:
    if isinstance(damping, np.generic):
        damping = damping.item()
    if not (is_number(damping) and (0.0 < damping < 1.0 or (allow_zero and damping == 0.0))):
        raise InputError(source, "damping", f"a damping ratio between 0 and 1 (0.05 = 5 %), got {damping!r}")
    return float(damping)


def positive(value, source: str, field: str, unit: str) -> float:
    """A number > 0 of magnitude 1e-30 to 1e30 (not a bool or a text) or InputError naming the
    field and its unit (a deck's values are checked before, by fields.check_value)."""
    if isinstance(value, np.generic):
        value = value.item()
    if not (is_number(value) and value > 0.0 and in_magnitude(value)):
        raise InputError(source, field, f"a number > 0 {MAGNITUDE_WORDS} [{unit}], got {value!r}")
    return float(value)


def _check_table(periods: np.ndarray, sa_values: np.ndarray, source: str) -> None:
    """InputError unless a table has at least two pairs, finite periods >= 0 [s] in increasing
    order and finite spectral accelerations >= 0."""
    if periods.size < 2 or periods.size != sa_values.size:
        raise InputError(source, "periods", "at least two (T, S_a) pairs, as many periods as values")
    if not (np.all(np.isfinite(periods)) and periods[0] >= 0.0 and np.all(np.diff(periods) > 0)):
        raise InputError(source, "periods", "finite periods >= 0 s in increasing order")
    if not (np.all(np.isfinite(sa_values)) and np.all(sa_values >= 0.0)):
        raise InputError(source, "sa", "finite spectral accelerations >= 0")


class TabulatedSpectrum:
    """A user table: periods [s] (increasing, >= 0), sa in `units` ('g' by default, or m/s2,
    cm/s2, in/s2), at the stated damping ratio [-]. Linear interpolation in T; no extrapolation.
    Other dampings: the EC8 factors eta(xi) / eta(damping) (damping_correction='ec8') or the
    ASCE factors B(damping) / B(xi) ('asce'), applied at every period. from_mapping chooses the
    default by the rule stated in docs/deck.md (the code of ground_motion.statistics).
    Attributes: periods [s], sa_values [m/s^2], damping [-], units, damping_correction, source."""

    def __init__(self, periods, sa, damping, units: str = "g", damping_correction: str = "ec8",
                 source: str = "spectrum table", label: str = ""):
        self.source = str(source)
        self.units = normalize_units(units, self.source, "units")
        self.periods = np.asarray(periods, dtype=float).ravel()
        self.sa_values = np.asarray(sa, dtype=float).ravel() * ACCELERATION_UNITS[self.units]
        self.damping = check_damping(damping, self.source)
        self.damping_correction = str(damping_correction).lower()
        self.label = label
        if self.damping_correction not in DAMPING_CORRECTIONS:
            raise InputError(self.source, "damping_correction", f"'ec8' or 'asce', got {damping_correction!r}")
        _check_table(self.periods, self.sa_values, self.source)

    @property
    def name(self) -> str:
        return self.label or f"table {Path(self.source).name} ({100 * self.damping:g} %)"

    @property
    def period_range(self) -> tuple[float, float]:
        return (float(self.periods[0]), float(self.periods[-1]))

    def sa(self, periods, damping: float) -> np.ndarray:
        """S_a [m/s^2] at periods [s] inside the table and damping ratio [-]."""
        t = check_periods(periods, self.period_range, self.source, self.name)
        factor = damping_factor(self.damping_correction, check_damping(damping, self.source), self.damping)
        return factor * np.interp(t, self.periods, self.sa_values)


#: what a spectrum table file is, in an error message's words (readers.found)
TABLE = "a spectrum table"


def read_spectrum_table(path: str | Path, source: str) -> tuple[np.ndarray, np.ndarray]:
    """Two columns period [s], S_a (comma or blank separated; '#' comments, one optional header
    row of names before the data: a second one is refused, _table_row)."""
    path = Path(path)
    data = read_input(path, MAX_RECORD_BYTES, source, "file", f"spectrum table ({str(path)!r})")
    lines = data.decode("utf-8-sig", errors="replace").splitlines()
    rows: list[tuple[float, float]] = []
    names = 0
    for number, line in enumerate(lines, start=1):
        text = line.split("#", 1)[0].strip()
        row = _table_row(text, str(path), number, rows, names) if text else None
        if row is None:
            names += bool(text)
        else:
            rows.append(row)
    if len(rows) < 2:
        raise InputError(str(path), None, "at least two rows of (period [s], S_a)")
    array = np.array(rows)
    return array[:, 0], array[:, 1]


def _table_row(text: str, where: str, number: int, rows: list, names: int) -> tuple[float, float] | None:
    """The (period [s], S_a) of a row of a spectrum table (text: without its comment); None for
    the header row of names before the data (rows: the data rows read before; names: the header
    rows; a row that starts with a number is data, a second header row is refused). The row is
    quoted only once rows were read (readers.found: a file that is no table is never shown)."""
    values = [plain_number(token) for token in text.replace(",", " ").split()[:2]]
    if None in values:
        if not rows and values[0] is None:
            _check_header(names, where, number)
            return None  # a header row of names (a row that starts with a number is data)
        raise InputError(where, f"line {number}", f"two numbers (period [s], S_a){found(text, bool(rows), TABLE)}")
    if len(values) < 2 or not all(math.isfinite(value) for value in values):
        raise InputError(where, f"line {number}",
                         f"two finite numbers (period [s], S_a){found(text, bool(rows), TABLE)}")
    return values[0], values[1]


def _check_header(names: int, where: str, number: int) -> None:
    """InputError at a second header row of a spectrum table (it was read silently)."""
    if names:
        raise InputError(where, f"line {number}", "one header row of names before the (period [s], S_a) rows, "
                         "found a second one (a comment starts with '#')")
