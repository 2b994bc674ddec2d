"""Ground-motion records: a Record (SI), read_record (any format of READERS, unit
conversion to SI, scale, time window) and record measures (PGA, PGV, PGD, Arias intensity).

Every bad input raises `errors.InputError(file, "line N" or field, expected)`.
All accelerations inside are m/s^2; time in s.
"""

from __future__ import annotations

import hashlib
import math
import sys
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..deck.fields import Field
from ..errors import InputError
from ..runtime.limits import MAX_MAGNITUDE
from ..units import ACCELERATION_UNITS, STANDARD_GRAVITY
from .column_readers import parse_csv, parse_shared
from .readers import (
    DT,
    UNIT_CHOICES,
    check_dt,
    decode_lines,
    detect_format,
    normalize_units,
    parse_at2,
    parse_text,
    read_bytes,
)

#: record format -> reader(lines, source) -> (values, dt [s] or None, units or None, name)
READERS = {"at2": parse_at2, "text": parse_text, "csv": parse_csv, "shared": parse_shared}
FORMATS = tuple(READERS)

__all__ = ["FORMATS", "READERS", "RECORD_FIELDS", "Record", "arias_intensity", "bundled_records_dir",
           "ground_displacement", "ground_velocity", "normalize_units", "read_record"]


#: the options of read_record that a deck gives (`[ground_motion]`, a suite's entry {file, ...}):
#: one declaration, checked by the one field checker wherever they are given
RECORD_FIELDS: dict[str, Field] = {
    "format": Field("string", "-", "record format (default: detected)", "", None, FORMATS),
    "units": Field("string", "-", "record acceleration units: g, m/s2, cm/s2 or in/s2, or an alias (default: "
                   "from the file header; one that contradicts the header is an error unless "
                   "override_header_units)", "acceleration-units"),
    "override_header_units": Field("bool", "-", "read the file in `units` even where its header declares "
                                   "other units", "", False),
    "dt": replace(DT, doc="time step, for plain text files without a 'dt' header"),
    "scale": Field("number", "-", "factor applied to the record", "positive", 1.0, plausible=(0.01, 100.0)),
}


@dataclass
class Record:
    """A uniformly sampled ground acceleration history (first sample at t = 0).

    name: label; dt: time step [s]; acceleration: ground acceleration [m/s^2] (already scaled);
    source: the file it came from; units: units of the file; scale: factor applied;
    format: the reader that read it (READERS; "" for a record made in code);
    sha256: the SHA-256 of the bytes it was parsed from ("" for a record made in code).
    """

    name: str
    dt: float
    acceleration: np.ndarray
    source: str = ""
    units: str = "m/s2"
    scale: float = 1.0
    format: str = ""
    sha256: str = ""

    @property
    def npts(self) -> int:
        """Number of samples."""
        return int(self.acceleration.size)

    @property
    def time(self) -> np.ndarray:
        """Sample times [s]."""
        return np.arange(self.npts) * self.dt

    @property
    def duration(self) -> float:
        """(npts - 1) dt [s]."""
        return (self.npts - 1) * self.dt

    @property
    def pga(self) -> float:
        """Peak ground acceleration max |a| [m/s^2]."""
        return float(np.max(np.abs(self.acceleration)))



# ----------------------------------------------------------------------------- public reader

def read_record(path: str | Path, format: str | None = None, units: str | None = None, dt: float | None = None,
                scale: float = 1.0, window: tuple[float, float] | None = None,
                override_header_units: bool = False) -> Record:
    """Read an accelerogram and convert it to m/s^2.

    format: 'at2', 'text', 'csv', 'shared' or None (detect from extension and header).
    units: 'g', 'm/s2', 'cm/s2', 'in/s2' (or an alias); None = from the file header (an error if it
        gives none). Units that contradict those the header declares are an error naming both,
        unless override_header_units (then `units` are used).
    dt: time step [s] for 'text' files without a 'dt' header line (overrides the header if given;
        for 'at2', 'csv' and 'shared' the file's own step is used and a different dt is an error).
    scale: factor applied to the acceleration [-].
    window: (start, end) [s], keep the samples in that time window (time restarts at 0).
    """
    source = str(path)
    path = Path(path)
    _check_format(format, source)
    if dt is not None:
        dt = check_dt(dt, source, "dt")
    _check_scale(scale, source)
    data = read_bytes(path, source)  # read once: the checksum is that of the bytes parsed
    fmt = (format or detect_format(path, data)).strip().lower()
    values, file_dt, file_units, name = READERS[fmt](decode_lines(data, source), source)
    step = _time_step(fmt, file_dt, dt, source)
    unit = _record_units(units, file_units, override_header_units, source)
    acceleration = _in_si(values, unit, float(scale), source)
    if window is not None:
        acceleration = _apply_window(acceleration, step, window, source)
    return Record(name=name or path.stem, dt=step, acceleration=acceleration, source=source, units=unit,
                  scale=float(scale), format=fmt, sha256=hashlib.sha256(data).hexdigest())


def _check_format(format: str | None, source: str) -> None:
    """InputError unless the format asked for is None or one of FORMATS."""
    if format is not None and format.strip().lower() not in FORMATS:
        raise InputError(source, "format", f"one of {', '.join(FORMATS)}, got {format!r}")


def _check_scale(scale: float, source: str) -> None:
    """InputError unless the scale is a finite non-zero number (not a bool)."""
    number = isinstance(scale, (int, float)) and not isinstance(scale, bool)
    if not (number and math.isfinite(scale) and scale != 0.0):
        raise InputError(source, "scale", f"a finite non-zero scale factor, got {scale!r}")


def _time_step(fmt: str, file_dt: float | None, dt: float | None, source: str) -> float:
    """The record's time step [s]: the file's, else the one given; a given dt overrides the header
    of a plain-text file only, and elsewhere must agree with the file's (within 0.1 %)."""
    if file_dt is None:  # plain text without a 'dt' header line
        if dt is None:
            raise InputError(source, "dt", "a time step dt [s] (give dt, or a 'dt = ...' header line)")
        return float(dt)
    if fmt == "text" and dt is not None:
        return float(dt)  # overrides the header of a plain-text file
    step = float(file_dt)
    if dt is not None and not math.isclose(float(dt), step, rel_tol=1e-3):
        raise InputError(source, "dt", f"dt = {step:g} s as in the file, got {float(dt):g} s")
    return step


def _record_units(units: str | None, file_units: str | None, override_header_units: bool, source: str) -> str:
    """The units the values are read in: those given (which must match the header's unless
    override_header_units), else the header's; InputError when neither gives any."""
    if units is None:
        if file_units is None:
            raise InputError(source, "units",
                             f"acceleration units {UNIT_CHOICES} (none given and none in the file header)")
        return file_units
    unit = normalize_units(units, source)
    if file_units is not None and unit != file_units and not override_header_units:
        factor = ACCELERATION_UNITS[unit] / ACCELERATION_UNITS[file_units]
        raise InputError(source, "units", f"the units that the header of {source!r} declares, {file_units}, got "
                         f"{units!r} (a factor of {factor:.4g} on every value; to read the file in {unit} anyway: "
                         "override_header_units = true in a deck, --override-header-units on the command line)")
    return unit


def _in_si(values: np.ndarray, unit: str, scale: float, source: str) -> np.ndarray:
    """The acceleration [m/s^2]: the values times the unit's factor and the scale; InputError for
    fewer than two samples or a peak above limits.MAX_MAGNITUDE."""
    if values.size < 2:
        raise InputError(source, None, f"at least two acceleration samples, found {values.size}")
    with np.errstate(over="ignore", invalid="ignore"):
        acceleration = values * (ACCELERATION_UNITS[unit] * scale)
    peak = float(np.max(np.abs(acceleration)))
    if not peak <= MAX_MAGNITUDE:
        raise InputError(source, "scale" if scale != 1.0 else None,
                         f"accelerations of magnitude at most {MAX_MAGNITUDE:g} m/s^2 after the units ({unit}) "
                         f"and the scale ({scale:g}), got {peak:.3g} m/s^2")
    return acceleration


def _check_window(start: float, end: float, duration: float, source: str) -> None:
    """InputError unless 0 <= start < end [s] (finite) and the start is within the record's duration [s]."""
    if not (math.isfinite(start) and math.isfinite(end) and 0.0 <= start < end):
        raise InputError(source, "window", f"0 <= start < end [s], got ({start:g}, {end:g})")
    if start > duration:
        raise InputError(source, "window", f"a start time within the record (0 to {duration:g} s), got {start:g}")


def _apply_window(acceleration: np.ndarray, dt: float, window: tuple[float, float], source: str) -> np.ndarray:
    """The samples within the time window (start, end) [s] (an end past the record keeps the rest
    of it); InputError for a window that holds fewer than two samples."""
    start, end = (float(value) for value in window)
    duration = (acceleration.size - 1) * dt
    _check_window(start, end, duration, source)
    end = min(end, duration)  # an end past the record keeps the rest of it
    first = math.ceil(start / dt - 1e-9)
    last = min(math.floor(end / dt + 1e-9), acceleration.size - 1)
    if last - first < 1:
        raise InputError(source, "window", f"a window holding at least two samples (dt = {dt:g} s)")
    return acceleration[first:last + 1].copy()


# ----------------------------------------------------------------------------- measures

def ground_velocity(acceleration: np.ndarray, dt: float) -> np.ndarray:
    """Ground velocity [m/s] by exact integration of the piecewise-linear acceleration
    (trapezoidal rule), v(0) = 0, no baseline correction; along axis 0 (columns: records)."""
    a = np.asarray(acceleration, dtype=float)
    zero = np.zeros((1, *a.shape[1:]))
    return np.concatenate((zero, np.cumsum(0.5 * dt * (a[1:] + a[:-1]), axis=0)))


def ground_displacement(acceleration: np.ndarray, dt: float) -> np.ndarray:
    """Ground displacement [m], exact double integral of the piecewise-linear acceleration,
    d(0) = v(0) = 0, no baseline correction: d_{i+1} = d_i + v_i dt + (2 a_i + a_{i+1}) dt^2 / 6;
    along axis 0."""
    a = np.asarray(acceleration, dtype=float)
    v = ground_velocity(a, dt)
    increments = v[:-1] * dt + (2.0 * a[:-1] + a[1:]) * dt * dt / 6.0
    return np.concatenate((np.zeros((1, *a.shape[1:])), np.cumsum(increments, axis=0)))


def arias_intensity(acceleration: np.ndarray, dt: float) -> float:
    """Arias intensity I_a = pi / (2 g) * integral a^2 dt [m/s], exact for piecewise-linear a."""
    a = np.asarray(acceleration, dtype=float)
    integral = float(np.sum(dt / 3.0 * (a[:-1] ** 2 + a[:-1] * a[1:] + a[1:] ** 2)))
    return math.pi / (2.0 * STANDARD_GRAVITY) * integral


def bundled_records_dir() -> Path:
    """The records/ folder shipped beside the package (source checkout)."""
    return Path(__file__).resolve().parents[2] / "records"


def is_suite(motion) -> bool:
    """Whether a deck's ground motion is a record suite (motion/suites.Suite), without importing the
    suites' modules (matching, scaling, measures: a deck with a record needs none of them): a Suite
    exists only once motion/suites.py is loaded."""
    suites = sys.modules.get(f"{__package__}.suites")
    return suites is not None and isinstance(motion, suites.Suite)
