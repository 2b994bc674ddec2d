"""Ground-motion record formats, one reader per format (the READERS table): PEER .AT2, plain
text (one or more values per line, optional '#' header with dt and units), CSV with a time
column, and the headered files of records/ ('#' lines, then time and acceleration). Each reader
takes the file's lines and returns (values in the file's units, dt [s] or None, units or None,
name); records.read_record converts them to SI.

Every bad input raises `errors.InputError(file, "line N" or field, expected)`.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from ..deck.fields import Field, check_value
from ..errors import InputError
from ..runtime.limits import MAX_RECORD_BYTES, MAX_RECORD_SAMPLES, read_input
from ..units import ACCELERATION_ALIASES, acceleration_unit

UNIT_CHOICES = "one of g, m/s2, cm/s2, in/s2"
#: the time step of a record, wherever it is given (a file header, the deck, a suite entry)
DT = Field("number", "s", "time step of the record", "time-step", plausible=(1e-4, 0.1))


def normalize_units(units: str, source: str, location: str = "units") -> str:
    """Canonical unit name ('g', 'm/s2', 'cm/s2', 'in/s2'; aliases: units.ACCELERATION_ALIASES) or InputError."""
    unit = acceleration_unit(units)
    if unit is None:
        raise InputError(source, location, f"acceleration units {UNIT_CHOICES}, got {units!r}")
    return unit


# ----------------------------------------------------------------------------- helpers

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"
_DT_RE = re.compile(r"\bdt\b\s*(?:\(s\)|\[s\])?\s*[=:]?\s*(" + _NUMBER + r")", re.IGNORECASE)
_NPTS_RE = re.compile(r"\bnpts\b\s*[=:]?\s*(\d+)", re.IGNORECASE)
_UNIT_HINT_RE = re.compile(
    r"(?:units?\s*(?:of|[:=]|are|in)?\s*|acc(?:el(?:eration)?)?\w*?\s*(?:in\s+)?[(\[_]?\s*|\(|\[)"
    r"(g|gal|(?:m|cm|in)/s(?:ec)?(?:\^?2|/s(?:ec)?|\*\*2)|(?:m|cm|in)_s_?2)(?![\w/])",
    re.IGNORECASE,
)
#: the units of a column name in the project's CSV style (quantity_unit: acc_m_s2, accel_cm_s2)
_COLUMN_UNITS = {"m_s2": "m/s2", "m_s_2": "m/s2", "cm_s2": "cm/s2", "cm_s_2": "cm/s2", "in_s2": "in/s2",
                 "in_s_2": "in/s2"}


_PLAIN_NUMBER = re.compile(_NUMBER + r"|[-+]?(?:nan|inf|infinity)", re.IGNORECASE)


def plain_number(token: str) -> float | None:
    """A number as data files write it (Fortran 'D' exponents accepted; not Python's '1_000',
    '0x10' or other literals float() takes), or None."""
    if not _PLAIN_NUMBER.fullmatch(token):
        return None
    return float(token.replace("D", "E").replace("d", "e"))


def _float(token: str, source: str, line_no: int) -> float:
    """Parse one finite number (plain_number)."""
    value = plain_number(token)
    if value is None:
        raise InputError(source, f"line {line_no}", f"a number, got {token!r}")
    if not math.isfinite(value):
        raise InputError(source, f"line {line_no}", f"a finite number, got {token!r}")
    return value


def _resolution(token: str) -> float:
    """Rounding step of a printed number: 0.005 for '1.235' (0 when it has an exponent)."""
    if "e" in token.lower() or "." not in token:
        return 0.0
    return 10.0 ** -len(token.split(".", 1)[1])


def _unit_hint(text: str) -> str | None:
    match = _UNIT_HINT_RE.search(text)
    if not match:
        return None
    found = match.group(1).lower()
    return _COLUMN_UNITS.get(found) or ACCELERATION_ALIASES.get(found.replace("sec", "s"))


def read_bytes(path: Path, source: str) -> bytes:
    """The bytes of a record file, read once (limits.read_input: a regular file of at most
    MAX_RECORD_BYTES); its SHA-256, its format and its values all come from these bytes."""
    return read_input(path, MAX_RECORD_BYTES, source, None, "record file")


def decode_lines(data: bytes, source: str) -> list[str]:
    """The lines of a text record's bytes (a UTF-8 byte-order mark is dropped); a file holding
    NUL bytes is refused as binary."""
    if b"\0" in data:
        raise InputError(source, None, "a text record file (NUL bytes found: binary data)")
    lines = data.decode("utf-8-sig", errors="replace").splitlines()
    if not any(line.strip() for line in lines):
        raise InputError(source, None, "acceleration values (the file is empty)")
    return lines


def read_lines(path: Path, source: str) -> list[str]:
    """The lines of a text record (read_bytes, then decode_lines)."""
    return decode_lines(read_bytes(path, source), source)


def check_dt(dt: float, source: str, location: str) -> float:
    """The time step [s] checked by the field checker (DT: > 0, at most limits.MAX_RECORD_DT, of
    magnitude 1e-30 to 1e30); InputError(source, location, ...) otherwise."""
    def error(expected: str):
        raise InputError(source, location, f"a time step dt: {expected}")

    return check_value(DT, dt, error)


def _is_comment(line: str) -> bool:
    return line.lstrip().startswith(("#", "%", "!", "//"))


def detect_format(path: str | Path, data: bytes | None = None) -> str:
    """Guess the format from the extension and first lines: 'at2', 'csv', 'shared' or 'text'.
    data: the file's bytes when they are read already (else the first 64 KiB of a regular file
    are read; anything else is 'text', and the reader refuses it)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in (".at2", ".vt2", ".dt2"):  # the PEER layout (a velocity or displacement file is refused on reading)
        return "at2"
    if suffix == ".csv":
        return "csv"
    if data is None:
        try:
            if not path.is_file():  # a FIFO or a device is never opened here (the reader refuses it)
                return "text"
            with path.open("rb") as handle:
                data = handle.read(65536)
        except OSError:
            return "text"
    head = data[:65536].decode("utf-8-sig", errors="replace").splitlines()[:40]
    first = next((line for line in head if line.strip()), "")
    if first.strip().upper().startswith(("PEER", "PACIFIC ENGINEERING")):
        return "at2"
    comments = " ".join(line.lower() for line in head if _is_comment(line))
    if "time_s" in comments and "accel_g" in comments:
        return "shared"
    return "text"


# ----------------------------------------------------------------------------- readers

#: PEER NGA histories other than acceleration: word of the third header line -> (what, file extension)
_PEER_OTHER = {"VELOCITY": ("velocity", ".VT2"), "DISPLACEMENT": ("displacement", ".DT2")}
#: a sign that starts a new number right after the digit of the previous one (fixed-width
#: columns that touch: 1.71300E-02-3.43000E-03); a sign after E or D is an exponent's
_TOUCHING = re.compile(r"(?<=\d)(?=[-+](?:\d*\.\d))")


def separated(line: str) -> str:
    """A row of fixed-width numbers with a blank where two touch (a negative value filling its
    column): '1.71300E-02-3.43000E-03' -> '1.71300E-02 -3.43000E-03'."""
    return _TOUCHING.sub(" ", line)


def _peer_quantity(line: str, source: str) -> None:
    """InputError when the PEER header's third line, or the file's extension, says the file is
    not an acceleration history (a .VT2 velocity or .DT2 displacement history)."""
    words = line.upper().split()
    suffix = Path(source).suffix.upper()
    for word, (what, extension) in _PEER_OTHER.items():
        if (word in words and "ACCELERATION" not in words) or suffix == extension:
            raise InputError(source, "line 3", f"an acceleration history (PEER .AT2); this is a {what} history "
                             f"({extension}, {line.strip()!r}): give the record's .AT2 file")


def _parse_at2(lines: list[str], source: str) -> tuple[np.ndarray, float, str | None, str]:
    """PEER NGA .AT2: 4 header lines (title, event, units, NPTS/DT), then values row by row
    (columns that touch are separated: separated); a velocity (.VT2) or displacement (.DT2)
    history is refused, naming what it is."""
    if len(lines) < 4:
        raise InputError(source, f"line {len(lines)}", "a PEER .AT2 header of 4 lines")
    _peer_quantity(lines[2], source)
    header = lines[3]
    npts_match = _NPTS_RE.search(header)
    dt_match = _DT_RE.search(header)
    if npts_match is None or dt_match is None:
        numbers = re.findall(_NUMBER, header)  # old format: "5590   0.0050   NPTS, DT"
        if len(numbers) >= 2 and "NPTS" in header.upper():
            npts_text, dt_text = numbers[0], numbers[1]
        else:
            raise InputError(source, "line 4", "an AT2 header 'NPTS= n, DT= dt SEC'")
    else:
        npts_text, dt_text = npts_match.group(1), dt_match.group(1)
    npts = int(float(npts_text))
    dt = check_dt(_float(dt_text, source, 4), source, "line 4")
    units = _unit_hint(lines[2])
    values = _values_row_by_row([separated(line) for line in lines], 4, source)
    if values.size != npts:
        raise InputError(source, "line 4", f"NPTS = {npts} values as the header says, found {values.size}")
    return values, dt, units, lines[1].strip()


_INTEGER_RE = re.compile(r"[-+]?\d+")


def _tokens(line: str, source: str, line_no: int) -> list[str]:
    """The numbers of a row, separated by blanks and/or commas; a comma between digits
    alone ('0,05') is refused: it may be a decimal comma, which would split one value in two."""
    tokens = []
    for word in line.split():
        pieces = [piece for piece in word.split(",") if piece]
        if len(pieces) > 1 and all(_INTEGER_RE.fullmatch(piece) for piece in pieces):
            raise InputError(source, f"line {line_no}", f"numbers with a decimal point, got {word!r} (a decimal "
                             "comma? write 0.05, and separate values by blanks)")
        tokens.extend(pieces)
    return tokens


def _values_row_by_row(lines: list[str], start: int, source: str) -> np.ndarray:
    values: list[float] = []
    for index in range(start, len(lines)):
        line = lines[index]
        if not line.strip() or _is_comment(line):
            continue
        for token in _tokens(line, source, index + 1):
            values.append(_float(token, source, index + 1))
        if len(values) > MAX_RECORD_SAMPLES:
            raise InputError(source, f"line {index + 1}", f"at most {MAX_RECORD_SAMPLES:,} samples (limit of the tool)")
    if not values:
        raise InputError(source, None, "acceleration values after the header (none found)")
    return np.asarray(values, dtype=float)


def _parse_text(lines: list[str], source: str) -> tuple[np.ndarray, float | None, str | None, str]:
    """Plain text: optional '#' header lines (may give 'dt = ...', 'units: g', 'npts = n'),
    then values row by row (one or more columns; columns that touch are separated: separated)."""
    start = 0
    header_text = []
    dt = None
    npts = None
    npts_line = 0
    for index, line in enumerate(lines):
        stripped = line.strip()
        if not stripped:
            continue
        if _is_comment(line) or (re.match(r"[A-Za-z]", stripped) and not re.match(r"[-+]?(nan|inf)", stripped, re.I)):
            header_text.append(stripped)
            match = _DT_RE.search(stripped)
            if match and dt is None:
                dt = check_dt(_float(match.group(1), source, index + 1), source, f"line {index + 1}")
            match = _NPTS_RE.search(stripped)
            if match and npts is None:
                npts, npts_line = int(match.group(1)), index + 1
            start = index + 1
            continue
        break
    values = _values_row_by_row([separated(line) for line in lines], start, source)
    if npts is not None and values.size != npts:
        raise InputError(source, f"line {npts_line}", f"npts = {npts} values as the header says, found {values.size}")
    units = None
    for text in header_text:
        units = units or _unit_hint(text)
    name = header_text[0].lstrip("#%!/ ").strip() if header_text else ""
    return values, dt, units, name


def _parse_columns(lines: list[str], source: str, delimiter: str | None, time_column: int, accel_column: int
                   ) -> tuple[np.ndarray, float, str | None, str]:
    """Time column + acceleration column; the time step must be uniform."""
    header_text = []
    times: list[float] = []
    values: list[float] = []
    line_numbers: list[int] = []
    time_resolution = 0.0
    for index, line in enumerate(lines):
        stripped = line.strip()
        if not stripped:
            continue
        if _is_comment(line):
            header_text.append(stripped)
            continue
        tokens = [token.strip() for token in (stripped.split(delimiter) if delimiter else stripped.split())]
        if not times and not values and tokens and re.match(r"[A-Za-z\"']", tokens[0]) \
                and not re.match(r"[-+]?(nan|inf)", tokens[0], re.I):
            header_text.append(stripped)  # column names
            continue
        if len(tokens) <= max(time_column, accel_column):
            raise InputError(source, f"line {index + 1}",
                             f"at least {max(time_column, accel_column) + 1} columns (time, acceleration)")
        times.append(_float(tokens[time_column], source, index + 1))
        time_resolution = max(time_resolution, _resolution(tokens[time_column]))
        values.append(_float(tokens[accel_column], source, index + 1))
        line_numbers.append(index + 1)
        if len(values) > MAX_RECORD_SAMPLES:
            raise InputError(source, f"line {index + 1}", f"at most {MAX_RECORD_SAMPLES:,} samples (limit of the tool)")
    if len(values) < 2:
        raise InputError(source, None, "at least two (time, acceleration) rows")
    time = np.asarray(times)
    steps = np.diff(time)
    if not steps[0] > 0.0:
        raise InputError(source, f"line {line_numbers[1]}",
                         f"increasing times (time step dt > 0 s), got {steps[0]:g} s")
    # each step must equal the first one, within 0.1 % or the rounding of the printed times (< dt / 2)
    tolerance = min(max(1e-3 * steps[0], 1.01 * time_resolution), 0.5 * steps[0])
    bad = np.flatnonzero(np.abs(steps - steps[0]) > tolerance)
    if bad.size:
        i = int(bad[0])
        raise InputError(source, f"line {line_numbers[i + 1]}",
                         f"a uniform time step of {steps[0]:g} s (as in the first rows), got {steps[i]:g} s")
    dt = (time[-1] - time[0]) / (time.size - 1)
    units = None
    for text in header_text:
        units = units or _unit_hint(text)
    name = next((text.lstrip("#%!/ ") for text in header_text if not text.startswith(("time", "t,", "t "))), "")
    return np.asarray(values, dtype=float), float(dt), units, name


def _parse_csv(lines: list[str], source: str) -> tuple[np.ndarray, float, str | None, str]:
    """CSV: a time column and an acceleration column (an optional header row of names)."""
    return _parse_columns(lines, source, ",", 0, 1)


def _parse_shared(lines: list[str], source: str) -> tuple[np.ndarray, float, str | None, str]:
    """The headered files of the project's records/ folder: '#' lines, then time_s accel_g."""
    values, dt, units, name = _parse_columns(lines, source, None, 0, 1)
    return values, dt, units or "g", name


#: record format -> reader(lines, source) -> (values, dt [s] or None, units or None, name)
READERS = {"at2": _parse_at2, "text": _parse_text, "csv": _parse_csv, "shared": _parse_shared}
FORMATS = tuple(READERS)

