"""Declared input fields: kind, unit, meaning, range check, default and choices, and the one
checker of a value against its field.

Deck tables (deck_schema.py), the options of the engines (engines/options.py) and the
fields of each foundation type (model/foundations.py) are all declared with `Field`, so a
value is checked by the same rule wherever it comes from (a deck, `--set`, `--vary` or the
Python API).
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, NoReturn

from .errors import InputError
from .limits import MAX_INTEGER, MAX_MAGNITUDE, MAX_STORIES, MIN_MAGNITUDE


@dataclass(frozen=True)
class Field:
    """One input field.

    kind: number, integer, string, bool, numbers (array), number-or-numbers, matrix,
        string-or-strings, pair (two numbers), table (passed through), files (a path, or an
        array of paths and tables).
    unit: the unit in words/symbols ("-" for dimensionless).
    doc: what it is, in a few words.
    check: a key of CHECKS ("" for none).
    default: the value used when the field is not given (None: no default).
    choices: allowed strings for string fields.
    """

    kind: str
    unit: str
    doc: str
    check: str = ""
    default: Any = None
    choices: tuple[str, ...] = ()


#: range checks: name -> (test, words)
CHECKS: dict[str, tuple[Callable[[Any], bool], str]] = {
    "positive": (lambda v: v > 0, "> 0"),
    "nonnegative": (lambda v: v >= 0, ">= 0"),
    "fraction": (lambda v: 0 <= v < 1, "in [0, 1)"),
    "unit-interval": (lambda v: 0 < v <= 1, "in (0, 1]"),
    "greater-than-one": (lambda v: v > 1, "> 1"),
    "poisson": (lambda v: 0 <= v < 0.5, "in [0, 0.5)"),
    "count": (lambda v: v >= 1, ">= 1"),
    "two-or-more": (lambda v: v >= 2, ">= 2"),
    "stories": (lambda v: 1 <= v <= MAX_STORIES, f"from 1 to {MAX_STORIES}"),
    "": (lambda v: True, ""),
}

Error = Callable[[str], NoReturn]


def suggestion(name: str, candidates) -> str:
    """' (did you mean 'x'?)' for the closest candidate, or ''."""
    close = difflib.get_close_matches(name, list(candidates), n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


def unit_suffix(field: Field) -> str:
    """' [unit]', or '' for a dimensionless field."""
    return "" if field.unit == "-" else f" [{field.unit}]"


def shown(value: Any, width: int = 80) -> str:
    """repr(value), cut to about `width` characters (a huge or deeply nested value stays readable)."""
    text = repr(value)
    return text if len(text) <= width else f"{text[:width - 5]}...{text[-2:]}"


def is_number(value: Any) -> bool:
    """A finite int or float (not a bool)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def in_magnitude(value: float) -> bool:
    """0, or MIN_MAGNITUDE <= |value| <= MAX_MAGNITUDE (limits.py)."""
    size = abs(value)
    return size == 0 or MIN_MAGNITUDE <= size <= MAX_MAGNITUDE


MAGNITUDE_WORDS = f"of magnitude {MIN_MAGNITUDE:g} to {MAX_MAGNITUDE:g}"


def _qualifier(field: Field) -> str:
    words = CHECKS[field.check][1]
    return f" {words}" if words else ""


def _number(field: Field, value: Any, error: Error, what: str = "a number") -> float:
    if not (is_number(value) and CHECKS[field.check][0](value)):
        error(f"{what}{_qualifier(field)}{unit_suffix(field)}, got {shown(value)}")
    if not in_magnitude(value):
        error(f"{what}{_qualifier(field)} {MAGNITUDE_WORDS}{unit_suffix(field)}, got {shown(value)}")
    return float(value)


def _integer(field: Field, value: Any, error: Error) -> int:
    if not isinstance(value, int) or isinstance(value, bool) or not CHECKS[field.check][0](value):
        error(f"an integer{_qualifier(field)}, got {shown(value)}")
    if value > MAX_INTEGER:
        error(f"an integer{_qualifier(field)} and at most {MAX_INTEGER:,}, got {shown(value)}")
    return int(value)


def _bool(field: Field, value: Any, error: Error) -> bool:
    if not isinstance(value, bool):
        error(f"true or false, got {shown(value)}")
    return value


def _string(field: Field, value: Any, error: Error) -> str:
    if not isinstance(value, str):
        error(f"a string, got {shown(value)}")
    if field.choices and value not in field.choices:
        error(f"one of {', '.join(field.choices)}, got {shown(value)}{suggestion(value, field.choices)}")
    return value


def _strings(field: Field, value: Any, error: Error) -> list[str]:
    items = [value] if isinstance(value, str) else value
    if not isinstance(items, list) or not items or not all(isinstance(i, str) for i in items):
        error(f"a string or a non-empty array of strings, got {shown(value)}")
    for item in items:
        if field.choices and item not in field.choices:
            error(f"one or more of {', '.join(field.choices)}, got {item!r}{suggestion(item, field.choices)}")
    return list(dict.fromkeys(items))


def _numbers(field: Field, value: Any, error: Error) -> list[float]:
    if not isinstance(value, list) or not value:
        error(f"a non-empty array of numbers{_qualifier(field)}{unit_suffix(field)}, got {shown(value)}")
    return [_number(field, v, error, "every entry a number") for v in value]


def _number_or_numbers(field: Field, value: Any, error: Error) -> float | list[float]:
    return _numbers(field, value, error) if isinstance(value, list) else _number(field, value, error)


def _pair(field: Field, value: Any, error: Error) -> tuple[float, float]:
    if not (isinstance(value, list) and len(value) == 2 and all(is_number(v) for v in value)
            and 0 <= value[0] < value[1]):
        error(f"[start, end] with 0 <= start < end{unit_suffix(field)}, got {shown(value)}")
    if not all(in_magnitude(v) for v in value):
        error(f"[start, end] {MAGNITUDE_WORDS}{unit_suffix(field)}, got {shown(value)}")
    return (float(value[0]), float(value[1]))


def _matrix(field: Field, value: Any, error: Error) -> list[list[float]]:
    if not (isinstance(value, list) and value and all(isinstance(row, list) for row in value)
            and all(len(row) == len(value) for row in value) and all(is_number(v) for row in value for v in row)):
        error(f"a square array of arrays of numbers{unit_suffix(field)}, got {shown(value)}")
    if not all(in_magnitude(v) for row in value for v in row):
        error(f"a square array of arrays of numbers {MAGNITUDE_WORDS}{unit_suffix(field)}, got {shown(value)}")
    return [[float(v) for v in row] for row in value]


def _files(field: Field, value: Any, error: Error) -> str | list:
    if isinstance(value, str) and value:
        return value
    if not (isinstance(value, list) and value and all(isinstance(v, (str, dict)) for v in value)):
        error(f"a folder (string) or a non-empty array of file paths or tables {{file = ...}}, got {shown(value)}")
    return list(value)


def _table(field: Field, value: Any, error: Error) -> dict:
    if not isinstance(value, dict):
        error(f"a table, got {shown(value)}")
    return value


#: field kind -> checker(field, value, error) returning the value in its canonical type
CHECKERS: dict[str, Callable[[Field, Any, Error], Any]] = {
    "number": _number,
    "integer": _integer,
    "bool": _bool,
    "string": _string,
    "string-or-strings": _strings,
    "numbers": _numbers,
    "number-or-numbers": _number_or_numbers,
    "pair": _pair,
    "matrix": _matrix,
    "table": _table,
    "files": _files,
}


def parse_choices(texts, choices, option: str) -> list[str]:
    """Repeated and/or comma-separated names of a command-line option ('all' = every
    choice), in the order given; names are matched exactly, as in a deck (InputError naming
    `option` otherwise)."""
    names: list[str] = []
    for text in texts:
        for name in (part.strip() for part in text.split(",")):
            if not name:
                continue
            if name == "all":
                names.extend(choices)
            elif name in choices:
                names.append(name)
            else:
                hint = f" (names are lower case: {name.lower()!r})" if name.lower() in choices \
                    else suggestion(name, choices)
                raise InputError(option, name, f"one of {', '.join(choices)} or all{hint}")
    return list(dict.fromkeys(names))


def check_value(field: Field, value: Any, error: Error) -> Any:
    """Validate one value against its field; `error(expected)` raises (it names the source)."""
    return CHECKERS[field.kind](field, value, error)
