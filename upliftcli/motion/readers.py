"""Ground-motion record formats, one reader per format (records.READERS): PEER .AT2 and plain
text (one or more values per line, optional '#' header with dt and units) here, CSV with a time
column and the headered files of records/ in column_readers.py; and what every reader reads
(numbers as data files write them, comments, unit hints, the sample limit). Each reader takes
the file's lines and returns (values in the file's units, dt [s] or None, units or None, name);
records.read_record converts them to SI.

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
from ..runtime.patterns import lazy
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
_DT_RE = lazy(r"\bdt\b\s*(?:\(s\)|\[s\])?\s*[=:]?\s*(" + _NUMBER + r")", re.IGNORECASE)
_NPTS_RE = lazy(r"\bnpts\b\s*[=:]?\s*(\d+)", re.IGNORECASE)
_UNIT_HINT_RE = lazy(
    r"(?:units?\s*(?:of|[:=]|are|in)?\s*|acc(?:el(?:eration)?)?\w*?\s*(?:in\s+)?[(\[_]?\s*|\(|\[)"
    r"(g|gal|(?:m|cm|in)/s(?:ec)?(?:\^?2|/s(?:ec)?|\*\*2)|(?:m|cm|in)_s_?2)(?![\w/])",
    re.IGNORECASE,
)
#: the units of a column name in the project's CSV style (quantity_unit: acc_m_s2, accel_cm_s2)
_COLUMN_UNITS = {"m_s2": "m/s2", "m_s_2": "m/s2", "cm_s2": "cm/s2", "cm_s_2": "cm/s2", "in_s2": "in/s2",
                 "in_s_2": "in/s2"}


_PLAIN_NUMBER = lazy(_NUMBER + r"|[-+]?(?:nan|inf|infinity)", re.IGNORECASE)


def plain_number(token: str) -> float | None:
    """A number as data files write it (Fortran 'D' exponents accepted; not Python's '1_000',
    '0x10' or other literals float() takes), or None."""
    if not _PLAIN_NUMBER.fullmatch(token):
        return None
    return float(token.replace("D", "E").replace("d", "e"))


#: the most characters of a file's text that an error message quotes
EXCERPT_CHARS = 24


def excerpt(text: str) -> str:
    """A short, printable excerpt of text read from a file, quoted for an error message: at most
    EXCERPT_CHARS characters (then '...'), each one that is not printable ASCII shown as '?'."""
    kept = "".join(char if " " <= char <= "~" else "?" for char in text[:EXCERPT_CHARS])
    return repr(kept + ("..." if len(text) > EXCERPT_CHARS else ""))


def found(text: str, recognised: bool, what: str = "a record") -> str:
    """What an error message says of the text it refuses: ', got <excerpt>' in a file recognised
    as `what` (values or a record header read before it), else a note that it is not quoted:
    the lines of a file that is no record (a system file given as a record) are never shown."""
    if recognised:
        return f", got {excerpt(text)}"
    return f" (the text is not quoted: nothing before it read as {what})"


def parse_number(token: str, source: str, line_no: int, recognised: bool) -> float:
    """Parse one finite number (plain_number); InputError naming the line, quoting the token
    only in a file recognised as a record (found)."""
    value = plain_number(token)
    if value is None:
        raise InputError(source, f"line {line_no}", f"a number{found(token, recognised)}")
    if not math.isfinite(value):
        raise InputError(source, f"line {line_no}", f"a finite number, got {excerpt(token)}")
    return value


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


def is_comment(line: str) -> bool:
    """Whether a line is a comment: '#', '%', '!' or '//' first."""
    return line.lstrip().startswith(("#", "%", "!", "//"))


#: the formats that a file's extension names (.VT2 and .DT2 are read as PEER files, and refused)
_SUFFIX_FORMATS = {".at2": "at2", ".vt2": "at2", ".dt2": "at2", ".csv": "csv"}


def detect_format(path: str | Path, data: bytes | None = None) -> str:
    """Guess the format from the extension and first lines: 'at2', 'csv', 'shared' or 'text'.
    data: the file's bytes when they are read already (else the first 64 KiB of a regular file
    are read; anything else is 'text', and the reader refuses it)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in _SUFFIX_FORMATS:  # the PEER layout (a velocity or displacement file is refused on reading)
        return _SUFFIX_FORMATS[suffix]
    return _format_from_head(_head_bytes(path) if data is None else data)


def _head_bytes(path: Path) -> bytes:
    """The first 64 KiB of a regular file; no bytes for anything else or a file that cannot be read
    (a FIFO or a device is never opened here: the reader refuses it)."""
    try:
        if not path.is_file():
            return b""
        with path.open("rb") as handle:
            return handle.read(65536)
    except OSError:
        return b""


def _first_line(lines: list[str]) -> str:
    """The first line that is not blank, stripped ("" when there is none)."""
    return next((line for line in lines if line.strip()), "").strip()


def _format_from_head(data: bytes) -> str:
    """'at2' for a PEER title line, 'shared' for the comments of the records/ folder (time_s,
    accel_g), else 'text'; from the first 40 lines of the first 64 KiB."""
    head = data[:65536].decode("utf-8-sig", errors="replace").splitlines()[:40]
    if _first_line(head).upper().startswith(("PEER", "PACIFIC ENGINEERING")):
        return "at2"
    comments = " ".join(line.lower() for line in head if is_comment(line))
    if "time_s" in comments and "accel_g" in comments:
        return "shared"
    return "text"


# ----------------------------------------------------------------------------- readers

#: PEER NGA histories other than acceleration: word of the third header line -> (what, file extension)
_PEER_OTHER = {"VELOCITY": ("velocity", ".VT2"), "DISPLACEMENT": ("displacement", ".DT2")}
#: a sign that starts a new number right after the digit of the previous one (fixed-width
#: columns that touch: 1.71300E-02-3.43000E-03); a sign after E or D is an exponent's
_TOUCHING = lazy(r"(?<=\d)(?=[-+](?:\d*\.\d))")


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
                             f"({extension}, {excerpt(line.strip())}): give the record's .AT2 file")


def parse_at2(lines: list[str], source: str) -> tuple[np.ndarray, float, str | None, str]:
    """PEER NGA .AT2: 4 header lines (title, event, units, NPTS/DT), then values row by row
    (columns that touch are separated: separated); a velocity (.VT2) or displacement (.DT2)
    history is refused, naming what it is."""
    if len(lines) < 4:
        raise InputError(source, f"line {len(lines)}", "a PEER .AT2 header of 4 lines")
    _peer_quantity(lines[2], source)
    npts_text, dt_text = _at2_counts(lines[3], source)
    npts = int(float(npts_text))
    dt = check_dt(parse_number(dt_text, source, 4, True), source, "line 4")
    units = _unit_hint(lines[2])
    values = _values_row_by_row([separated(line) for line in lines], 4, source, True)
    _check_npts(values, npts, "line 4", source, "NPTS")
    return values, dt, units, lines[1].strip()


def _at2_counts(header: str, source: str) -> tuple[str, str]:
    """The NPTS and DT of the fourth line of a PEER file, as written: 'NPTS= n, DT= dt SEC', or
    the old 'n   dt   NPTS, DT'."""
    npts_match = _NPTS_RE.search(header)
    dt_match = _DT_RE.search(header)
    if npts_match is not None and dt_match is not None:
        return npts_match.group(1), dt_match.group(1)
    numbers = re.findall(_NUMBER, header)  # old format: "5590   0.0050   NPTS, DT"
    if len(numbers) >= 2 and "NPTS" in header.upper():
        return numbers[0], numbers[1]
    raise InputError(source, "line 4", "an AT2 header 'NPTS= n, DT= dt SEC'")


def _check_npts(values: np.ndarray, npts: int | None, location: str, source: str, word: str = "npts") -> None:
    """InputError when a header gives the number of values (npts) and the file holds another."""
    if npts is not None and values.size != npts:
        raise InputError(source, location, f"{word} = {npts} values as the header says, found {values.size}")


def check_sample_count(count: int, source: str, line_no: int) -> None:
    """InputError once a record holds more than limits.MAX_RECORD_SAMPLES values."""
    if count > MAX_RECORD_SAMPLES:
        raise InputError(source, f"line {line_no}", f"at most {MAX_RECORD_SAMPLES:,} samples (limit of the tool)")


_INTEGER_RE = lazy(r"[-+]?\d+")


def _integers(pieces: list[str]) -> bool:
    """Whether a word split at its commas is two or more integers ('0,05': a decimal comma?)."""
    return len(pieces) > 1 and all(_INTEGER_RE.fullmatch(piece) for piece in pieces)


def _tokens(line: str, source: str, line_no: int, recognised: bool) -> list[str]:
    """The numbers of a row, separated by blanks and/or commas; a comma between digits
    alone ('0,05') is refused: it may be a decimal comma, which would split one value in two."""
    tokens = []
    for word in line.split():
        pieces = [piece for piece in word.split(",") if piece]
        if _integers(pieces):
            raise InputError(source, f"line {line_no}", f"numbers with a decimal point{found(word, recognised)} (a "
                             "decimal comma? write 0.05, and separate values by blanks)")
        tokens.extend(pieces)
    return tokens


def _values_row_by_row(lines: list[str], start: int, source: str, recognised: bool) -> np.ndarray:
    """The values of the rows from index `start`; recognised: the header says the file is a
    record (else it is recognised once a row of values is read; found)."""
    values: list[float] = []
    for index in range(start, len(lines)):
        line = lines[index]
        if not line.strip() or is_comment(line):
            continue
        known = recognised or bool(values)
        for token in _tokens(line, source, index + 1, known):
            values.append(parse_number(token, source, index + 1, known))
        check_sample_count(len(values), source, index + 1)
    if not values:
        raise InputError(source, None, "acceleration values after the header (none found)")
    return np.asarray(values, dtype=float)


def parse_text(lines: list[str], source: str) -> tuple[np.ndarray, float | None, str | None, str]:
    """Plain text: optional '#' header lines (may give 'dt = ...', 'units: g', 'npts = n'),
    then values row by row (one or more columns; columns that touch are separated: separated)."""
    header = _text_header(lines)
    start = header[-1][0] if header else 0
    dt = _header_dt(header, source)
    npts, npts_line = _header_npts(header)
    values = _values_row_by_row([separated(line) for line in lines], start, source, dt is not None or npts is not None)
    _check_npts(values, npts, f"line {npts_line}", source)
    header_text = [text for _, text in header]
    name = header_text[0].lstrip("#%!/ ").strip() if header_text else ""
    return values, dt, header_units(header_text), name


def _text_header(lines: list[str]) -> list[tuple[int, str]]:
    """The header of a plain-text record, (line number, stripped line): the comment lines and
    lines of words before the first row of numbers (blank lines are passed over)."""
    header = []
    for index, line in enumerate(lines):
        stripped = line.strip()
        if not stripped:
            continue
        if not (is_comment(line) or starts_as_word(stripped, _LETTER)):
            break
        header.append((index + 1, stripped))
    return header


def _header_dt(header: list[tuple[int, str]], source: str) -> float | None:
    """The time step [s] of the first header line that gives one ('dt = 0.01'), checked; or None."""
    for line_no, text in header:
        match = _DT_RE.search(text)
        if match:
            return check_dt(parse_number(match.group(1), source, line_no, True), source, f"line {line_no}")
    return None


def _header_npts(header: list[tuple[int, str]]) -> tuple[int | None, int]:
    """The number of values of the first header line that gives one ('npts = 2000') and its line; or (None, 0)."""
    for line_no, text in header:
        match = _NPTS_RE.search(text)
        if match:
            return int(match.group(1)), line_no
    return None, 0


def header_units(header_text: list[str]) -> str | None:
    """The units of the first header line that names some (_unit_hint), or None."""
    return next((units for units in map(_unit_hint, header_text) if units), None)


#: how a header line of words starts (a letter), unlike nan or inf
_LETTER = lazy(r"[A-Za-z]")
_NAN_OR_INF = lazy(r"[-+]?(nan|inf)", re.I)


def starts_as_word(text: str, start: re.Pattern[str]) -> bool:
    """True when text starts as a word does (start), not as the number nan or inf."""
    return bool(start.match(text)) and not _NAN_OR_INF.match(text)
