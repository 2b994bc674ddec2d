"""Declared input fields: kind, unit, meaning, range check, default and choices, and the one
checker of a value against its field.

Deck tables (deck/schema.py), the options of the engines (engines/options.py), the fields of
each foundation type (model/foundations.py), the keys of a design spectrum
(motion/design_spectra.py) and of a suite's record entry (motion/records.py) are all declared
with `Field`, so a value is checked by the same rule wherever it comes from (a deck, `--set`,
`--vary`, a table read from a file or the Python API): its type, its unit (a number may carry
one, "11.5 ft"; a bare number is in the deck's unit system, units.py), converted to the
field's unit, the 1e-30..1e30 limits and the field's range. `check_mapping` checks a table of
fields and gathers every error; deck/practice.implausible compares a value with the range of
building practice a field declares (a warning, not an error); deck/choices.py suggests the
closest name and reads the names of a command-line option (parse_choices).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from itertools import chain
from typing import Any, NoReturn

from ..errors import InputError, gather, raise_all
from ..runtime.limits import MAX_CONTACT_ELEMENTS, MAX_INTEGER, MAX_MAGNITUDE, MAX_RECORD_DT, MAX_STORIES, MIN_MAGNITUDE
from ..units import KIND_OF_UNIT, acceleration_unit, conversion, split_quantity, system_unit
from .choices import parse_choices, suggestion  # noqa: F401 - part of this module's interface


@dataclass(frozen=True)
class Field:
    """One input field.

    kind: number, integer, string, bool, numbers (array), number-or-numbers, matrix,
        string-or-strings, pair (two numbers), table (passed through), files (a path, or an
        array of paths and tables).
    unit: the unit of the checked value ("-" for dimensionless; the SI unit of its quantity for
        a deck field, or "g" for spectral ordinates).
    doc: what it is, in a few words.
    check: a key of CHECKS ("" for none).
    default: the value used when the field is not given (None: no default).
    choices: allowed strings for string fields.
    quantity: its kind in units.QUANTITY_KINDS (default: the kind of `unit`, units.KIND_OF_UNIT;
        "displacement" for a length taken in inches under `units = "us"`); a field whose unit
        has no kind takes no unit text.
    plausible: (low, high) in `unit`: the range of building practice; a value outside gives a
        warning (implausible), not an error.
    """

    kind: str
    unit: str
    doc: str
    check: str = ""
    default: Any = None
    choices: tuple[str, ...] = ()
    quantity: str = ""
    plausible: tuple[float, float] | None = None

    @property
    def quantity_kind(self) -> str | None:
        """The quantity kind of its values (units.QUANTITY_KINDS), None for a dimensionless field."""
        return self.quantity or KIND_OF_UNIT.get(self.unit)


#: range checks: name -> (test, words)
CHECKS: dict[str, tuple[Callable[[Any], bool], str]] = {
    "positive": (lambda v: v > 0, "> 0"),
    "nonnegative": (lambda v: v >= 0, ">= 0"),
    "fraction": (lambda v: 0 <= v < 1, "in [0, 1)"),
    "unit-interval": (lambda v: 0 < v <= 1, "in (0, 1]"),
    "greater-than-one": (lambda v: v > 1, "> 1"),
    "at-least-one": (lambda v: v >= 1, ">= 1"),
    "importance-factor": (lambda v: v in (1.0, 1.25, 1.5), "1.0, 1.25 or 1.5 (ASCE 7-22 Table 1.5-2)"),
    "poisson": (lambda v: 0 <= v < 0.5, "in [0, 0.5)"),
    "count": (lambda v: v >= 1, ">= 1"),
    "two-or-more": (lambda v: v >= 2, ">= 2"),
    "stories": (lambda v: 1 <= v <= MAX_STORIES, f"from 1 to {MAX_STORIES}"),
    "time-step": (lambda v: 0 < v <= MAX_RECORD_DT, f"> 0 and at most {MAX_RECORD_DT:g}"),
    "damping-ratio": (lambda v: 0 < v < 1, "in (0, 1) (0.05 = 5 %)"),
    "one-or-two": (lambda v: v in (1, 2), "1 or 2"),
    "acceleration-units": (lambda v: acceleration_unit(v) is not None,
                           "acceleration units g, m/s2, cm/s2 or in/s2 (or an alias of docs/deck.md)"),
    "contact-elements": (lambda v: 2 <= v <= MAX_CONTACT_ELEMENTS, f"from 2 to {MAX_CONTACT_ELEMENTS}"),
    "one-line": (lambda v: bool(v.strip()) and all(ch.isprintable() for ch in v),
                 "a non-empty text on one line (without line breaks or control characters)"),
    "band-around-one": (lambda v: v[0] < 1 < v[1], "0 <= low < 1 < high (ratios simplified / exact)"),
    "": (lambda v: True, ""),
}

Error = Callable[[str], NoReturn]


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
    """0, or MIN_MAGNITUDE <= |value| <= MAX_MAGNITUDE (runtime/limits.py)."""
    size = abs(value)
    return size == 0 or MIN_MAGNITUDE <= size <= MAX_MAGNITUDE


MAGNITUDE_WORDS = f"of magnitude {MIN_MAGNITUDE:g} to {MAX_MAGNITUDE:g}"


def _qualifier(field: Field) -> str:
    words = CHECKS[field.check][1]
    return f" {words}" if words else ""


def _meets_check(field: Field, value: Any) -> bool:
    """Whether `value` passes the field's range check (CHECKS[field.check])."""
    return CHECKS[field.check][0](value)


def in_field_unit(field: Field, value: Any, system: str = "si") -> float | None:
    """A number of `field` in its own unit: a bare number (in the deck's unit system `system`:
    units.system_unit of the field's quantity) or a text 'number unit' ('11.5 ft') of the
    field's dimension, converted; None if `value` is neither (a bool, a date, an array, a text
    that is not a number with a unit of that dimension, a number as a text without a unit, a
    unit on a dimensionless field)."""
    if system == "si" and is_number(value):
        return value  # a bare SI number: every field's unit is the SI unit of its quantity
    if isinstance(value, str):
        return _text_in_unit(field, value)
    if not is_number(value):
        return None
    return _bare(value, field, system)


def _text_in_unit(field: Field, text: str) -> float | None:
    """A text 'number unit' of the field's dimension converted to its unit ('1.0' alone is a text,
    not a number: None), None for a unit on a dimensionless field or of another dimension."""
    parsed = split_quantity(text)
    if parsed is None or field.quantity_kind is None:
        return None
    number, unit = parsed
    if not unit:
        return None
    try:
        return number * conversion(unit, field.unit)
    except ValueError:
        return None


def _bare(number: float, field: Field, system: str) -> float:
    """A bare number in the deck's unit system, in the field's unit (a dimensionless one as it is)."""
    kind = field.quantity_kind
    if kind is None:
        return number
    unit = system_unit(kind, system)
    return number if unit == field.unit else number * conversion(unit, field.unit)


def unit_words(field: Field, system: str = "si", value: Any = None) -> str:
    """' [unit]' of a bare number of the field in the deck's unit system ('' if dimensionless);
    for a text value, also what a text with a unit must be."""
    kind = field.quantity_kind
    if kind is None:
        return unit_suffix(field) + (" (a bare number: this field takes no unit)" if isinstance(value, str) else "")
    unit = system_unit(kind, system)
    if isinstance(value, str):
        return f" [{unit}] or a text 'number unit' with a unit of {kind} (docs/deck.md, Units)"
    return f" [{unit}]"


def _finite(number: float | None) -> bool:
    """A finite number (None: a value that was not a number of the field)."""
    return number is not None and math.isfinite(number)


def _all_finite(numbers) -> bool:
    """Every entry a finite number."""
    return all(_finite(v) for v in numbers)


def _all_in_magnitude(numbers) -> bool:
    """Every entry 0 or of a magnitude the tool takes (in_magnitude)."""
    return all(in_magnitude(v) for v in numbers)


def _list_of(value: Any, types) -> bool:
    """A non-empty list whose items are all of `types`."""
    return isinstance(value, list) and bool(value) and all(isinstance(item, types) for item in value)


def _number(field: Field, value: Any, error: Error, what: str = "a number", system: str = "si") -> float:
    number = in_field_unit(field, value, system)
    if not (_finite(number) and _meets_check(field, number)):
        error(f"{what}{_qualifier(field)}{unit_words(field, system, value)}, got {shown(value)}")
    if not in_magnitude(number):
        error(f"{what}{_qualifier(field)} {MAGNITUDE_WORDS}{unit_suffix(field)}, got {shown(value)}")
    return float(number)


def _integer(field: Field, value: Any, error: Error) -> int:
    if not (_is_integer(value) and _meets_check(field, value)):
        error(f"an integer{_qualifier(field)}, got {shown(value)}")
    if value > MAX_INTEGER:
        error(f"an integer{_qualifier(field)} and at most {MAX_INTEGER:,}, got {shown(value)}")
    return int(value)


def _is_integer(value: Any) -> bool:
    """An int (not a bool)."""
    return isinstance(value, int) and not isinstance(value, bool)


def _bool(field: Field, value: Any, error: Error) -> bool:
    if not isinstance(value, bool):
        error(f"true or false, got {shown(value)}")
    return value


def _string(field: Field, value: Any, error: Error) -> str:
    if not isinstance(value, str):
        error(f"a string, got {shown(value)}")
    if not _meets_check(field, value):
        error(f"{CHECKS[field.check][1]}, got {shown(value)}")
    _check_choice(field, value, error, "one of", shown(value))
    return value


def _check_choice(field: Field, name: str, error: Error, words: str, got: str) -> None:
    """`name` one of the field's choices, if it has any (the closest named otherwise)."""
    if field.choices and name not in field.choices:
        error(f"{words} {', '.join(field.choices)}, got {got}{suggestion(name, field.choices)}")


def _strings(field: Field, value: Any, error: Error) -> list[str]:
    items = [value] if isinstance(value, str) else value
    if not _list_of(items, str):
        error(f"a string or a non-empty array of strings, got {shown(value)}")
    for item in items:
        _check_choice(field, item, error, "one or more of", repr(item))
    return list(dict.fromkeys(items))


def _numbers(field: Field, value: Any, error: Error, system: str = "si") -> list[float]:
    if not (isinstance(value, list) and value):
        error(f"a non-empty array of numbers{_qualifier(field)}{unit_words(field, system)}, got {shown(value)}")
    return [_number(field, v, error, "every entry a number", system) for v in value]


def _number_or_numbers(field: Field, value: Any, error: Error, system: str = "si") -> float | list[float]:
    return _numbers(field, value, error, system) if isinstance(value, list) else \
        _number(field, value, error, system=system)


def _in_unit(field: Field, values: list, system: str) -> list[float | None]:
    """Each value in the field's unit (in_field_unit: None for one that is not a number of the field)."""
    return [in_field_unit(field, v, system) for v in values]


def _pair(field: Field, value: Any, error: Error, system: str = "si") -> tuple[float, float]:
    """[start, end] with 0 <= start < end, and the field's check of the pair (band-around-one:
    [low, high] with low < 1 < high), named in its words."""
    pair = _in_unit(field, value, system) if isinstance(value, list) and len(value) == 2 else None
    shape, rule = _pair_words(field)
    if not (pair and _ordered_pair(field, pair)):
        error(f"{shape} with {rule}{unit_words(field, system)}, got {shown(value)}")
    if not _all_in_magnitude(pair):
        error(f"{shape} {MAGNITUDE_WORDS}{unit_suffix(field)}, got {shown(value)}")
    return (float(pair[0]), float(pair[1]))


def _pair_words(field: Field) -> tuple[str, str]:
    """(the pair's shape, its rule) in words: those of the field's check, else [start, end]."""
    if field.check:
        return "[low, high]", CHECKS[field.check][1]
    return "[start, end]", "0 <= start < end"


def _ordered_pair(field: Field, pair: list[float | None]) -> bool:
    """Finite numbers with 0 <= start < end that pass the field's check."""
    return _all_finite(pair) and 0 <= pair[0] < pair[1] and _meets_check(field, pair)


def _matrix(field: Field, value: Any, error: Error, system: str = "si") -> list[list[float]]:
    rows = _matrix_rows(field, value, system)
    if not (rows and _all_finite(chain.from_iterable(rows))):
        error(f"a square array of arrays of numbers{unit_words(field, system)}, got {shown(value)}")
    if not _all_in_magnitude(chain.from_iterable(rows)):
        error(f"a square array of arrays of numbers {MAGNITUDE_WORDS}{unit_suffix(field)}, got {shown(value)}")
    return [[float(v) for v in row] for row in rows]


def _matrix_rows(field: Field, value: Any, system: str) -> list[list[float | None]] | None:
    """The rows of a square array of arrays in the field's unit (_in_unit), None if not square."""
    if not _is_square(value):
        return None
    return [_in_unit(field, row, system) for row in value]


def _is_square(value: Any) -> bool:
    """A non-empty array of arrays, each as long as the array."""
    return _list_of(value, list) and all(len(row) == len(value) for row in value)


def _files(field: Field, value: Any, error: Error) -> str | list:
    if isinstance(value, str) and value:
        return value
    if not _list_of(value, (str, dict)):
        error(f"a folder (string) or a non-empty array of file paths or tables {{file = ...}}, got {shown(value)}")
    return list(value)


def _table(field: Field, value: Any, error: Error) -> dict:
    if not isinstance(value, dict):
        error(f"a table, got {shown(value)}")
    return value


#: field kind -> checker(field, value, error) returning the value in its canonical type
#: (the numeric kinds also take the deck's unit system: NUMERIC)
CHECKERS: dict[str, Callable[..., Any]] = {
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


#: field kinds whose values are numbers (with a unit, converted)
NUMERIC = ("number", "numbers", "number-or-numbers", "pair", "matrix")


def check_value(field: Field, value: Any, error: Error, system: str = "si") -> Any:
    """Validate one value against its field; `error(expected)` raises (it names the source).
    Numbers are returned in the field's unit: a text with a unit converted, a bare number
    read in the unit system `system` ("si" or "us", units.QUANTITY_KINDS)."""
    if field.kind in NUMERIC:
        return CHECKERS[field.kind](field, value, error, system=system)
    return CHECKERS[field.kind](field, value, error)


def check_mapping(fields: dict[str, Field], mapping: dict, path: str, error_for: Callable[[str], Error],
                  system: str = "si", what: str = "") -> dict[str, Any]:
    """Every key of `mapping` checked against `fields` (an unknown key: an error with the closest
    known one); the checked values. `error_for(dotted path)` gives the error function of a key;
    every error is gathered and raised together (errors.InputErrors) after all keys are seen.
    what: the words for a known key in the message ('a key of a table spectrum')."""
    gathered: list[InputError] = []
    checked: dict[str, Any] = {}
    for key, value in mapping.items():
        result = gather(gathered, _check_key, fields, key, value, path, error_for, system, what)
        if result is not None:
            checked[key] = result
    raise_all(gathered)
    return checked


def _check_key(fields: dict[str, Field], key: str, value: Any, path: str, error_for: Callable[[str], Error],
               system: str, what: str) -> Any:
    """One key of check_mapping: known (else the error names the known keys) and its value checked."""
    error = error_for(f"{path}.{key}" if path else str(key))
    if key not in fields:
        error(f"{what or 'a known key'}: {', '.join(fields)}{suggestion(str(key), fields)}; unknown key {key!r}")
    return check_value(fields[key], value, error, system)


def raiser(source: str) -> Callable[[str], Error]:
    """error_for(path) of check_mapping that names `source` (a file, or "--set")."""
    def error_for(path: str) -> Error:
        def error(expected: str) -> NoReturn:
            raise InputError(source, path, expected)
        return error
    return error_for
