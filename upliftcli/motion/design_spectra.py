"""Design spectra as ground-motion input of the simplified engine.

* `ASCE7Spectrum`: ASCE 7-22 section 11.4.5.2 two-period design spectrum (S_DS, S_D1, T_L),
  with the damping coefficient B = 4 / (5.6 - ln(100 beta)) of ASCE 41-17 Eq. (2-3), the
  factor used for soil-structure-interaction damping in NIST GCR 12-917-21 and ASCE 7-22
  chapter 19 (B_SSI); the branch below T0 follows ASCE 41-17 Eq. (2-9).
* `EC8Spectrum`: EN 1998-1:2004 section 3.2.2.2 horizontal elastic spectrum, Type 1 or 2,
  ground types A to E (Tables 3.2, 3.3), damping correction eta = sqrt(10 / (5 + xi%)) >= 0.55
  (Eq. 3.6).
* `TabulatedSpectrum`: a user table (T, S_a) at a stated damping.

Every spectrum has `.sa(periods, damping) -> S_a [m/s^2]`, `.name` and `.period_range` [s];
code parameters are in g as the codes give them. `from_mapping` builds one from a deck table.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..units import ACCELERATION_UNITS, STANDARD_GRAVITY
from .records import normalize_units

#: EN 1998-1 Tables 3.2 (Type 1) and 3.3 (Type 2): ground type -> (S, T_B, T_C, T_D) [-, s, s, s]
EC8_PARAMETERS = {
    1: {"A": (1.0, 0.15, 0.4, 2.0), "B": (1.2, 0.15, 0.5, 2.0), "C": (1.15, 0.20, 0.6, 2.0),
        "D": (1.35, 0.20, 0.8, 2.0), "E": (1.4, 0.15, 0.5, 2.0)},
    2: {"A": (1.0, 0.05, 0.25, 1.2), "B": (1.35, 0.05, 0.25, 1.2), "C": (1.5, 0.10, 0.25, 1.2),
        "D": (1.8, 0.10, 0.30, 1.2), "E": (1.6, 0.05, 0.25, 1.2)},
}
EC8_MAX_PERIOD = 4.0  # s, EN 1998-1 3.2.2.2 defines the elastic spectrum up to 4 s


def asce_damping_coefficient(damping) -> np.ndarray:
    """B = 4 / (5.6 - ln(100 beta)), beta the damping ratio [-] (ASCE 41-17 Eq. 2-3; NIST GCR 12-917-21)."""
    return 4.0 / (5.6 - np.log(100.0 * np.asarray(damping, dtype=float)))


def ec8_damping_correction(damping) -> np.ndarray:
    """eta = sqrt(10 / (5 + xi)) >= 0.55, xi the damping in per cent (EN 1998-1 Eq. 3.6); damping ratio [-] in."""
    return np.maximum(np.sqrt(10.0 / (5.0 + 100.0 * np.asarray(damping, dtype=float))), 0.55)


def _check_periods(periods, period_range, source: str, name: str) -> np.ndarray:
    array = np.asarray(periods, dtype=float)
    low, high = period_range
    bad = ~np.isfinite(array) | (array < low) | (array > high)
    if np.any(bad):
        value = float(np.atleast_1d(array)[np.atleast_1d(bad)][0])
        raise InputError(source, "period", f"periods within {low:g} to {high:g} s for {name}, got {value:g} s")
    return array


def _check_damping(damping, source: str, allow_zero: bool = False) -> float:
    damping = float(damping)
    if not (0.0 < damping < 1.0 or (allow_zero and damping == 0.0)):
        raise InputError(source, "damping", f"a damping ratio between 0 and 1 (0.05 = 5 %), got {damping:g}")
    return damping


def _positive(value, source: str, field: str, unit: str) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(source, field, f"a number > 0 [{unit}], got {value!r}") from None
    if not (math.isfinite(number) and number > 0.0):
        raise InputError(source, field, f"a number > 0 [{unit}], got {value!r}")
    return number


@dataclass
class ASCE7Spectrum:
    """ASCE 7-22 11.4.5.2 design spectrum. sds, sd1: design spectral accelerations at short
    periods and at 1 s [g]; tl: long-period transition period T_L [s]. Reference damping 5 %;
    other dampings divide by B(beta) / B(5 %) (so 5 % reproduces the code spectrum exactly)."""

    sds: float
    sd1: float
    tl: float
    source: str = "asce7 spectrum"

    def __post_init__(self):
        self.sds = _positive(self.sds, self.source, "sds", "g")
        self.sd1 = _positive(self.sd1, self.source, "sd1", "g")
        self.tl = _positive(self.tl, self.source, "tl", "s")
        if self.tl <= self.ts:
            raise InputError(self.source, "tl", f"T_L above T_S = S_D1/S_DS = {self.ts:g} s, got {self.tl:g} s")

    @property
    def ts(self) -> float:
        """T_S = S_D1 / S_DS [s]."""
        return self.sd1 / self.sds

    @property
    def t0(self) -> float:
        """T_0 = 0.2 S_D1 / S_DS [s]."""
        return 0.2 * self.ts

    @property
    def name(self) -> str:
        return f"ASCE 7-22 (S_DS = {self.sds:g} g, S_D1 = {self.sd1:g} g, T_L = {self.tl:g} s)"

    @property
    def period_range(self) -> tuple[float, float]:
        return (0.0, math.inf)

    def sa(self, periods, damping: float) -> np.ndarray:
        """S_a [m/s^2] at periods [s] and damping ratio [-]."""
        t = _check_periods(periods, self.period_range, self.source, self.name)
        b = float(asce_damping_coefficient(_check_damping(damping, self.source))
                  / asce_damping_coefficient(0.05))
        with np.errstate(divide="ignore", invalid="ignore"):
            sa = np.where(t < self.t0, self.sds * ((5.0 / b - 2.0) * t / self.ts + 0.4),
                 np.where(t <= self.ts, self.sds / b,
                 np.where(t <= self.tl, self.sd1 / (b * t), self.sd1 * self.tl / (b * t * t))))
        return sa * STANDARD_GRAVITY


@dataclass
class EC8Spectrum:
    """EN 1998-1 3.2.2.2 horizontal elastic spectrum. ag: reference peak ground acceleration on
    type A ground a_gR [g]; ground_type 'A'..'E'; spectrum_type 1 or 2; importance: gamma_I [-]
    (a_g = gamma_I a_gR). Reference damping 5 %; other dampings through eta (Eq. 3.6)."""

    ag: float
    ground_type: str
    spectrum_type: int = 1
    importance: float = 1.0
    source: str = "ec8 spectrum"

    def __post_init__(self):
        self.ag = _positive(self.ag, self.source, "ag", "g")
        self.importance = _positive(self.importance, self.source, "importance", "-")
        ground = str(self.ground_type).strip().upper()
        if ground not in ("A", "B", "C", "D", "E"):
            raise InputError(self.source, "ground_type",
                             f"ground type A, B, C, D or E (S1, S2 need special studies), got {self.ground_type!r}")
        self.ground_type = ground
        if self.spectrum_type not in (1, 2, "1", "2"):
            raise InputError(self.source, "spectrum_type", f"1 or 2, got {self.spectrum_type!r}")
        self.spectrum_type = int(self.spectrum_type)

    @property
    def parameters(self) -> tuple[float, float, float, float]:
        """(S [-], T_B [s], T_C [s], T_D [s]) of EN 1998-1 Table 3.2 / 3.3."""
        return EC8_PARAMETERS[self.spectrum_type][self.ground_type]

    @property
    def name(self) -> str:
        return f"EC8 Type {self.spectrum_type} ground {self.ground_type} (a_g = {self.ag * self.importance:g} g)"

    @property
    def period_range(self) -> tuple[float, float]:
        return (0.0, EC8_MAX_PERIOD)

    def sa(self, periods, damping: float) -> np.ndarray:
        """S_e [m/s^2] at periods [s] and damping ratio [-] (EN 1998-1 Eqs. 3.2-3.5)."""
        t = _check_periods(periods, self.period_range, self.source, self.name)
        eta = float(ec8_damping_correction(_check_damping(damping, self.source, allow_zero=True)))
        soil, tb, tc, td = self.parameters
        ag = self.ag * self.importance * STANDARD_GRAVITY
        with np.errstate(divide="ignore", invalid="ignore"):
            sa = np.where(t <= tb, 1.0 + t / tb * (2.5 * eta - 1.0),
                 np.where(t <= tc, 2.5 * eta,
                 np.where(t <= td, 2.5 * eta * tc / t, 2.5 * eta * tc * td / (t * t))))
        return ag * soil * sa


class TabulatedSpectrum:
    """A user table: periods [s] (increasing, >= 0), sa in `units` ('g' by default, or m/s2,
    cm/s2, in/s2), at the stated damping ratio [-]. Linear interpolation in T; no extrapolation.
    Other dampings: ratio of the EC8 factors eta(xi) / eta(damping) (damping_correction='ec8',
    default) or of the ASCE factors B(damping) / B(xi) ('asce'), applied at every period.
    Attributes: periods [s], sa_values [m/s^2], damping [-], units, damping_correction, source."""

    def __init__(self, periods, sa, damping, units: str = "g", damping_correction: str = "ec8",
                 source: str = "spectrum table", label: str = ""):
        self.source = str(source)
        self.units = normalize_units(units, self.source, "units")
        self.periods = np.asarray(periods, dtype=float).ravel()
        self.sa_values = np.asarray(sa, dtype=float).ravel() * ACCELERATION_UNITS[self.units]
        self.damping = _check_damping(damping, self.source)
        self.damping_correction = str(damping_correction).lower()
        self.label = label
        if self.damping_correction not in ("ec8", "asce"):
            raise InputError(self.source, "damping_correction", f"'ec8' or 'asce', got {damping_correction!r}")
        if self.periods.size < 2 or self.periods.size != self.sa_values.size:
            raise InputError(self.source, "periods", "at least two (T, S_a) pairs, as many periods as values")
        if not (np.all(np.isfinite(self.periods)) and self.periods[0] >= 0.0 and np.all(np.diff(self.periods) > 0)):
            raise InputError(self.source, "periods", "finite periods >= 0 s in increasing order")
        if not (np.all(np.isfinite(self.sa_values)) and np.all(self.sa_values >= 0.0)):
            raise InputError(self.source, "sa", "finite spectral accelerations >= 0")

    @property
    def name(self) -> str:
        return self.label or f"table {Path(self.source).name} ({100 * self.damping:g} %)"

    @property
    def period_range(self) -> tuple[float, float]:
        return (float(self.periods[0]), float(self.periods[-1]))

    def sa(self, periods, damping: float) -> np.ndarray:
        """S_a [m/s^2] at periods [s] inside the table and damping ratio [-]."""
        t = _check_periods(periods, self.period_range, self.source, self.name)
        damping = _check_damping(damping, self.source)
        if self.damping_correction == "ec8":
            factor = float(ec8_damping_correction(damping) / ec8_damping_correction(self.damping))
        else:
            factor = float(asce_damping_coefficient(self.damping) / asce_damping_coefficient(damping))
        return factor * np.interp(t, self.periods, self.sa_values)


def read_spectrum_table(path: str | Path, source: str) -> tuple[np.ndarray, np.ndarray]:
    """Two columns period [s], S_a (comma or blank separated; '#' comments, an optional header row)."""
    path = Path(path)
    try:
        lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError:
        raise InputError(source, "file", f"a readable spectrum table, cannot read {str(path)!r}") from None
    rows: list[tuple[float, float]] = []
    for number, line in enumerate(lines, start=1):
        text = line.split("#", 1)[0].strip()
        if not text:
            continue
        tokens = text.replace(",", " ").split()
        try:
            values = [float(token) for token in tokens[:2]]
        except ValueError:
            if not rows:
                continue  # header row
            raise InputError(str(path), f"line {number}", f"two numbers (period [s], S_a), got {text!r}") from None
        if len(values) < 2 or not all(math.isfinite(value) for value in values):
            raise InputError(str(path), f"line {number}", f"two finite numbers (period [s], S_a), got {text!r}")
        rows.append((values[0], values[1]))
    if len(rows) < 2:
        raise InputError(str(path), None, "at least two rows of (period [s], S_a)")
    array = np.array(rows)
    return array[:, 0], array[:, 1]


_KEYS = {
    "asce7": ({"type", "sds", "sd1", "tl"}, set()),
    "ec8": ({"type", "ag", "ground_type"}, {"spectrum_type", "importance"}),
    "table": ({"type", "damping"}, {"file", "periods", "sa", "units", "damping_correction", "name"}),
}


def from_mapping(mapping: dict, source: str, field: str = "spectrum"):
    """Build a spectrum from a deck table, e.g. {type = "asce7", sds = 1.0, sd1 = 0.6, tl = 8.0},
    {type = "ec8", ag = 0.3, ground_type = "B", spectrum_type = 1},
    {type = "table", file = "sa.csv", damping = 0.05} (file relative to the deck's folder) or
    {type = "table", periods = [...], sa = [...], damping = 0.05, units = "g"}.
    `field` is the deck path of the table, used in error messages."""
    if not isinstance(mapping, dict):
        raise InputError(source, field, "a table with a 'type' key (asce7, ec8 or table)")
    kind = str(mapping.get("type", "")).strip().lower()
    if kind not in _KEYS:
        raise InputError(source, f"{field}.type", f"one of asce7, ec8, table, got {mapping.get('type')!r}")
    required, optional = _KEYS[kind]
    for key in mapping:
        if key not in required | optional:
            raise InputError(source, f"{field}.{key}",
                             f"a key of a {kind} spectrum: {', '.join(sorted(required | optional))}")
    for key in sorted(required):
        if key not in mapping:
            raise InputError(source, f"{field}.{key}", f"a value (required for a {kind} spectrum)")
    try:
        if kind == "asce7":
            return ASCE7Spectrum(mapping["sds"], mapping["sd1"], mapping["tl"], source=source)
        if kind == "ec8":
            return EC8Spectrum(mapping["ag"], mapping["ground_type"], mapping.get("spectrum_type", 1),
                               mapping.get("importance", 1.0), source=source)
        has_file = "file" in mapping
        has_values = "periods" in mapping or "sa" in mapping
        if has_file == has_values:
            raise InputError(source, f"{field}.file", "either 'file' or both 'periods' and 'sa'")
        if has_file:
            path = Path(mapping["file"])
            if not path.is_absolute():
                path = Path(source).parent / path
            periods, sa = read_spectrum_table(path, source)
            table_source = str(path)
        else:
            for key in ("periods", "sa"):
                if key not in mapping:
                    raise InputError(source, f"{field}.{key}", "a list of numbers")
            try:
                periods = np.asarray(mapping["periods"], dtype=float)
                sa = np.asarray(mapping["sa"], dtype=float)
            except (TypeError, ValueError):
                raise InputError(source, f"{field}.periods", "lists of numbers for periods [s] and sa") from None
            table_source = source
        return TabulatedSpectrum(periods, sa, mapping["damping"], units=mapping.get("units", "g"),
                                 damping_correction=mapping.get("damping_correction", "ec8"),
                                 source=table_source, label=str(mapping.get("name", "")))
    except InputError as error:
        if error.source == source and error.location and not error.location.startswith(field + "."):
            raise InputError(source, f"{field}.{error.location}", error.expected) from None
        raise
