"""Declared input fields: kind, unit, meaning, range check, default and choices, and the one
checker of a value against its field.

Deck tables (deck/schema.py), the options of the engines (engines/options.py), the fields of
each foundation type (model/foundations.py), the keys of a design spectrum
(motion/design_spectra.py) and of a suite's record entry (motion/records.py) are all declared
with `Field`, so a value is checked by the same rule wherever it comes from (a deck, `--set`,
`--vary`, a table read from a file or the Python API): its type, its unit (a number may carry
one, "11.5 ft"; a bare number is in the deck's unit system, units.py), converted to the
field's unit, the 1e-30..1e30 limits and the field's range. `check_mapping` checks a table of
fields and gathers every error; `implausible` compares a value with the range of building
practice a field declares (a warning, not an error).
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, NoReturn

from ..errors import InputError, InputErrors
from ..runtime.limits import MAX_CONTACT_ELEMENTS, MAX_INTEGER, MAX_MAGNITUDE, MAX_RECORD_DT, MAX_STORIES, MIN_MAGNITUDE
from ..units import KIND_OF_UNIT, acceleration_unit, conversion, split_quantity, system_unit


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
    """0, or MIN_MAGNITUDE <= |value| <= MAX_MAGNITUDE (runtime/limits.py)."""
    size = abs(value)
    return size == 0 or MIN_MAGNITUDE <= size <= MAX_MAGNITUDE


MAGNITUDE_WORDS = f"of magnitude {MIN_MAGNITUDE:g} to {MAX_MAGNITUDE:g}"


def _qualifier(field: Field) -> str:
    words = CHECKS[field.check][1]
    return f" {words}" if words else ""


def in_field_unit(field: Field, value: Any, system: str = "si") -> float | None:
    """A number of `field` in its own unit: a bare number (in the deck's unit system `system`:
    units.system_unit of the field's quantity) or a text 'number unit' ('11.5 ft') of the
    field's dimension, converted; None if `value` is neither (a bool, a date, an array, a text
    that is not a number with a unit of that dimension, a number as a text without a unit, a
    unit on a dimensionless field)."""
    if system == "si" and is_number(value):
        return value  # a bare SI number: every field's unit is the SI unit of its quantity
    kind = field.quantity_kind
    if isinstance(value, str):
        parsed = split_quantity(value)
        if parsed is None or kind is None:
            return None
        number, unit = parsed
        try:  # a text is a number with its unit ('1.0' alone is a text, not a number)
            return number * conversion(unit, field.unit) if unit else None
        except ValueError:
            return None
    if not is_number(value):
        return None
    return _bare(value, field, kind, system) if kind is not None else value


def _bare(number: float, field: Field, kind: str, system: str) -> float:
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


def _number(field: Field, value: Any, error: Error, what: str = "a number", system: str = "si") -> float:
    number = in_field_unit(field, value, system)
    if number is None or not math.isfinite(number) or not CHECKS[field.check][0](number):
        error(f"{what}{_qualifier(field)}{unit_words(field, system, value)}, got {shown(value)}")
    if not in_magnitude(number):
        error(f"{what}{_qualifier(field)} {MAGNITUDE_WORDS}{unit_suffix(field)}, got {shown(value)}")
    return float(number)


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
    if field.check and not CHECKS[field.check][0](value):
        error(f"{CHECKS[field.check][1]}, got {shown(value)}")
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


def _numbers(field: Field, value: Any, error: Error, system: str = "si") -> list[float]:
    if not isinstance(value, list) or not value:
        error(f"a non-empty array of numbers{_qualifier(field)}{unit_words(field, system)}, got {shown(value)}")
    return [_number(field, v, error, "every entry a number", system) for v in value]


def _number_or_numbers(field: Field, value: Any, error: Error, system: str = "si") -> float | list[float]:
    return _numbers(field, value, error, system) if isinstance(value, list) else \
        _number(field, value, error, system=system)


def _pair(field: Field, value: Any, error: Error, system: str = "si") -> tuple[float, float]:
    """[start, end] with 0 <= start < end, and the field's check of the pair (band-around-one:
    [low, high] with low < 1 < high), named in its words."""
    pair = [in_field_unit(field, v, system) for v in value] if isinstance(value, list) and len(value) == 2 else None
    shape, rule = ("[low, high]", CHECKS[field.check][1]) if field.check else ("[start, end]", "0 <= start < end")
    if not (pair and all(v is not None and math.isfinite(v) for v in pair) and 0 <= pair[0] < pair[1]
            and CHECKS[field.check][0](pair)):
        error(f"{shape} with {rule}{unit_words(field, system)}, got {shown(value)}")
    if not all(in_magnitude(v) for v in pair):
        error(f"{shape} {MAGNITUDE_WORDS}{unit_suffix(field)}, got {shown(value)}")
    return (float(pair[0]), float(pair[1]))


def _matrix(field: Field, value: Any, error: Error, system: str = "si") -> list[list[float]]:
    square = isinstance(value, list) and value and all(isinstance(row, list) for row in value) \
        and all(len(row) == len(value) for row in value)
    rows = [[in_field_unit(field, v, system) for v in row] for row in value] if square else None
    if not (rows and all(v is not None and math.isfinite(v) for row in rows for v in row)):
        error(f"a square array of arrays of numbers{unit_words(field, system)}, got {shown(value)}")
    if not all(in_magnitude(v) for row in rows for v in row):
        error(f"a square array of arrays of numbers {MAGNITUDE_WORDS}{unit_suffix(field)}, got {shown(value)}")
    return [[float(v) for v in row] for row in rows]


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
        where = f"{path}.{key}" if path else str(key)
        if key not in fields:
            gather(gathered, error_for(where), f"{what or 'a known key'}: {', '.join(fields)}"
                   f"{suggestion(str(key), fields)}; unknown key {key!r}")
            continue
        result = gather(gathered, check_value, fields[key], value, error_for(where), system)
        if result is not None:
            checked[key] = result
    raise_all(gathered)
    return checked


def raiser(source: str) -> Callable[[str], Error]:
    """error_for(path) of check_mapping that names `source` (a file, or "--set")."""
    def error_for(path: str) -> Error:
        def error(expected: str) -> NoReturn:
            raise InputError(source, path, expected)
        return error
    return error_for


def gather(errors: list[InputError], check: Callable[..., Any], *args: Any) -> Any:
    """check(*args), or None with its InputError(s) appended to `errors` (to report them all)."""
    try:
        return check(*args)
    except InputError as bad:
        errors.extend(getattr(bad, "errors", [bad]))
        return None


def raise_all(errors: list[InputError]) -> None:
    """Raise the gathered errors: one InputError as it is, several as one InputErrors."""
    if len(errors) == 1:
        raise errors[0]
    if errors:
        raise InputErrors(errors)


def implausible(field: Field, value: Any, system: str = "si") -> str | None:
    """Words for a checked value (a number or an array of numbers, in the field's unit) outside
    the range of building practice the field declares (Field.plausible), or None; in a deck of
    units `system` "us", the value and the range in its US unit too."""
    if field.plausible is None or field.kind not in NUMERIC:
        return None
    low, high = field.plausible
    values = value if isinstance(value, (list, tuple)) else [value]
    flat = [v for item in values for v in (item if isinstance(item, (list, tuple)) else [item])]
    outside = [v for v in flat if not low <= v <= high]
    if not outside:
        return None
    unit = "" if field.unit == "-" else f" {field.unit}"
    shown_value, shown_range = f"{outside[0]:.4g}{unit}", f"{low:g} to {high:g}{unit}"
    kind = field.quantity_kind
    if system == "us" and kind is not None and system_unit(kind, "us") != field.unit:
        us = system_unit(kind, "us")
        factor = conversion(field.unit, us)
        shown_value += f" = {outside[0] * factor:.4g} {us}"
        shown_range += f" = {low * factor:.4g} to {high * factor:.4g} {us}"
    return f"{shown_value} is far outside building practice ({shown_range}): a unit mistake? (the analysis goes on)"
