"""Record files of columns: a time column and an acceleration column (CSV, or the headered files
of the project's records/ folder: '#' lines, then time_s accel_g); the time step must be uniform.
The readers of records.READERS for 'csv' and 'shared' (readers.py: the other formats and what
every reader reads).

Every bad input raises `errors.InputError(file, "line N" or field, expected)`.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..runtime.patterns import lazy
from .readers import check_sample_count, header_units, is_comment, parse_number, starts_as_word

#: a row of column names starts with a letter or a quote
_LETTER_OR_QUOTE = lazy(r"[A-Za-z\"']")


def _resolution(token: str) -> float:
    """Rounding step of a printed number: 0.005 for '1.235' (0 when it has an exponent)."""
    if "e" in token.lower() or "." not in token:
        return 0.0
    return 10.0 ** -len(token.split(".", 1)[1])


def _parse_columns(lines: list[str], source: str, delimiter: str | None, recognised: bool
                   ) -> tuple[np.ndarray, float, str | None, str]:
    """Time column + acceleration column; the time step must be uniform. recognised: the file's
    header says it is a record (else it is once a row is read: readers.found)."""
    header_text, rows = _column_rows(lines, delimiter, source)
    times, values, time_resolution = _column_values(rows, source, recognised)
    dt = _uniform_step(np.asarray(times), [line_no for line_no, _ in rows], time_resolution, source)
    name = next((text.lstrip("#%!/ ") for text in header_text if not text.startswith(("time", "t,", "t "))), "")
    return np.asarray(values, dtype=float), dt, header_units(header_text), name


def _column_rows(lines: list[str], delimiter: str | None, source: str
                 ) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """The header lines of a column file (comments anywhere, and one row of column names before
    the data) and its data rows: (line number, stripped tokens). A second row of names is
    refused (_check_names): it was read silently, as a header row of another table would be."""
    header_text: list[str] = []
    rows: list[tuple[int, list[str]]] = []
    names = 0
    for index, line in enumerate(lines):
        stripped = line.strip()
        if not stripped or is_comment(line):
            header_text += [stripped] if stripped else []
            continue
        tokens = _row_tokens(stripped, delimiter)
        if not rows and starts_as_word(tokens[0], _LETTER_OR_QUOTE):
            names = _check_names(names, index + 1, source)
            header_text.append(stripped)  # column names
            continue
        rows.append((index + 1, tokens))
    return header_text, rows


def _check_names(names: int, line_no: int, source: str) -> int:
    """The count of rows of column names once this one is counted; InputError at the second."""
    if names:
        raise InputError(source, f"line {line_no}", "one row of column names before the data, found a second one "
                         "(a comment starts with '#')")
    return names + 1


def _row_tokens(row: str, delimiter: str | None) -> list[str]:
    """The fields of a row of a column file, stripped (delimiter None: runs of blanks)."""
    return [token.strip() for token in row.split(delimiter)]


def _column_values(rows: list[tuple[int, list[str]]], source: str, recognised: bool
                   ) -> tuple[list[float], list[float], float]:
    """The times (first column) and accelerations (second) of the data rows, and the rounding
    step of the printed times (_resolution); InputError for a short row, a bad number, too many
    or fewer than two rows (a bad number quoted once the file is recognised as a record)."""
    times: list[float] = []
    values: list[float] = []
    time_resolution = 0.0
    for line_no, tokens in rows:
        if len(tokens) < 2:
            raise InputError(source, f"line {line_no}", "at least 2 columns (time, acceleration)")
        times.append(parse_number(tokens[0], source, line_no, recognised or bool(values)))
        time_resolution = max(time_resolution, _resolution(tokens[0]))
        values.append(parse_number(tokens[1], source, line_no, recognised or bool(values)))
        check_sample_count(len(values), source, line_no)
    if len(values) < 2:
        raise InputError(source, None, "at least two (time, acceleration) rows")
    return times, values, time_resolution


def _uniform_step(time: np.ndarray, line_numbers: list[int], time_resolution: float, source: str) -> float:
    """The time step [s] of a time column, (last - first) / (n - 1); InputError unless the times
    increase and every step equals the first one, within 0.1 % or the rounding of the printed
    times (< dt / 2)."""
    steps = np.diff(time)
    if not steps[0] > 0.0:
        raise InputError(source, f"line {line_numbers[1]}",
                         f"increasing times (time step dt > 0 s), got {steps[0]:g} s")
    tolerance = min(max(1e-3 * steps[0], 1.01 * time_resolution), 0.5 * steps[0])
    bad = np.flatnonzero(np.abs(steps - steps[0]) > tolerance)
    if bad.size:
        i = int(bad[0])
        raise InputError(source, f"line {line_numbers[i + 1]}",
                         f"a uniform time step of {steps[0]:g} s (as in the first rows), got {steps[i]:g} s")
    return float((time[-1] - time[0]) / (time.size - 1))


def parse_csv(lines: list[str], source: str) -> tuple[np.ndarray, float, str | None, str]:
    """CSV: a time column and an acceleration column (an optional header row of names)."""
    return _parse_columns(lines, source, ",", False)


def parse_shared(lines: list[str], source: str) -> tuple[np.ndarray, float, str | None, str]:
    """The headered files of the project's records/ folder: '#' lines, then time_s accel_g."""
    values, dt, units, name = _parse_columns(lines, source, None, True)
    return values, dt, units or "g", name
