"""The values of a sweep: `--vary PATH=VALUES` and `--periods` parsed into the values of one deck
field (a range START:STOP:N[:log|lin], a comma list or a TOML array; docs/sweep.md), each
checked once against the deck's schema. Nothing here prints or exits (sweep/plan.py plans the
cases from them).
"""

from __future__ import annotations

import json
import math
from collections import Counter
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..deck import schema
from ..deck.fields import shown
from ..deck.overrides import toml_value
from ..errors import InputError
from ..runtime.limits import MAX_VARY_VALUES
from ..units import conversion, system_unit

#: deck fields that are case dimensions of their own, not --vary paths
NOT_VARIED = {"analysis.engine": "--engine", "analysis.supports": "--support"}


def _shortened(text: str) -> str:
    """The values as an error message shows them: at most 80 characters."""
    return text if len(text) <= 80 else text[:75] + "..."


def _too_many(option: str, text: str, count: int) -> InputError:
    return InputError(option, _shortened(text),
                      f"at most {MAX_VARY_VALUES:,} values in one range (limit of the tool), got {count:,}")


def parse_values(text: str, option: str, default_spacing: str = "linear") -> tuple[list[Any], str]:
    """'START:STOP:N[:log|lin]' -> N values (linear or geometric), '[a, b]' (TOML array) or
    'a,b,c' -> explicit list. Returns (values, spacing: "linear" | "log" | "list"); a value given
    twice (after the rounding of a range) is refused: two cases with one key (sweep/store.py)."""
    values, spacing = _parse_values(text, option, default_spacing)
    _check_each_once(values, text, option)
    return values, spacing


def _check_each_once(values: list[Any], text: str, option: str) -> None:
    """InputError naming the first value given twice (compared as JSON)."""
    seen = Counter(json.dumps(value, sort_keys=True, default=str) for value in values)
    repeated = [key for key, count in seen.items() if count > 1]
    if repeated:
        raise InputError(option, _shortened(text),
                         f"each value once ({repeated[0]} is given {seen[repeated[0]]} times)")


def _parse_values(text: str, option: str, default_spacing: str) -> tuple[list[Any], str]:
    text = text.strip()
    _check_text(text, option)
    if text.startswith("["):
        return _parse_array(text, option), "list"
    parts = text.split(":")
    if len(parts) in (3, 4):
        return _parse_range(text, parts, option, default_spacing)
    if len(parts) != 1:
        raise InputError(option, text, "START:STOP:N[:log|lin], a comma list or a TOML array")
    return _parse_list(text, option), "list"


def _check_text(text: str, option: str) -> None:
    """The values on one line, and not more commas than values allowed (counted before parsing)."""
    if any(not (ch.isprintable() or ch == "\t") for ch in text):
        raise InputError(option, None, "values on one line (without line breaks or control characters)")
    if text.count(",") >= MAX_VARY_VALUES:
        raise _too_many(option, text, text.count(",") + 1)


def _parse_array(text: str, option: str) -> list[Any]:
    """'[a, b]': a non-empty TOML array."""
    value = toml_value(text)
    if not isinstance(value, list) or not value:
        raise InputError(option, text, "a non-empty TOML array of values, e.g. [0.5, 1.0]")
    return value


def _parse_list(text: str, option: str) -> list[Any]:
    """'a,b,c': each a TOML value (empty items skipped), at least one."""
    values = [toml_value(part.strip()) for part in text.split(",") if part.strip()]
    if not values:
        raise InputError(option, text, "at least one value")
    return values


#: the spacing suffix of a range -> its spacing
_SPACINGS = {"log": "log", "lin": "linear", "linear": "linear"}


def _range_spacing(parts: list[str], default_spacing: str) -> str | None:
    """The spacing a range asks for (its fourth part, else the default); None if unknown."""
    suffix = parts[3].strip().lower() if len(parts) == 4 else default_spacing
    return _SPACINGS.get(suffix)


def _range_numbers(parts: list[str]) -> tuple[float, float, int]:
    """(START, STOP, N) of a range; (nan, nan, 0) if any is not a number."""
    try:
        return float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        return math.nan, math.nan, 0


def _finite_range(start: float, stop: float, count: int) -> bool:
    """Finite ends and at least one value."""
    return math.isfinite(start) and math.isfinite(stop) and count >= 1


def _positive_ends(start: float, stop: float) -> bool:
    """Both ends > 0 (a log range)."""
    return start > 0.0 and stop > 0.0


def _check_range(text: str, option: str, spacing: str | None, start: float, stop: float, count: int) -> None:
    """A known spacing, finite ends, 1 <= N <= MAX_VARY_VALUES, and ends > 0 for a log range."""
    if spacing is None or not _finite_range(start, stop, count):
        raise InputError(option, text, "START:STOP:N[:log|lin] with finite numbers and N >= 1, "
                         "e.g. 1e7:1e10:25:log")
    if spacing == "log" and not _positive_ends(start, stop):
        raise InputError(option, text, "START > 0 and STOP > 0 for a log range")
    if count > MAX_VARY_VALUES:
        raise _too_many(option, text, count)


def _range_grid(start: float, stop: float, count: int, spacing: str) -> list[Any]:
    """The N values of a range, at 12 significant digits (0.4, not 0.39999999999999997)."""
    grid = np.geomspace(start, stop, count) if spacing == "log" else np.linspace(start, stop, count)
    return [float(f"{v:.12g}") for v in grid]


def _integer_range(parts: list[str], values: list[Any], spacing: str) -> bool:
    """Whether a linear range of integer ends gives integers only (analysis.modes=1:5:5)."""
    if spacing != "linear" or not all(p.strip().lstrip("+-").isdigit() for p in parts[:2]):
        return False
    return all(v == int(v) for v in values)


def _parse_range(text: str, parts: list[str], option: str, default_spacing: str) -> tuple[list[Any], str]:
    """'START:STOP:N[:log|lin]' -> (N values, spacing); integers for an integer field's range."""
    spacing = _range_spacing(parts, default_spacing)
    start, stop, count = _range_numbers(parts)
    _check_range(text, option, spacing, start, stop, count)
    values = _range_grid(start, stop, count, spacing)
    if _integer_range(parts, values, spacing):
        values = [int(v) for v in values]
    return values, spacing


@dataclass(frozen=True)
class Vary:
    """One varied deck field: dotted path, its values and how they were spaced; system: the deck's
    unit system (`units`), in which its bare values are given (and shown in the rows and files)."""

    path: str
    values: tuple
    spacing: str  # "linear", "log" or "list"
    system: str = "si"

    @property
    def si_unit(self) -> str:
        """The field's declared SI unit ('' for an unknown path)."""
        found = deck_field(self.path)
        return found.unit if found else ""

    @property
    def unit(self) -> str:
        """The unit of its values as given: a bare number's unit in the deck's system."""
        found = deck_field(self.path)
        kind = found.quantity_kind if found else None
        return system_unit(kind, self.system) if kind else self.si_unit

    @property
    def to_si(self) -> float:
        """The factor from its values as given to SI (1 in an SI deck)."""
        unit, si_unit = self.unit, self.si_unit
        return 1.0 if unit == si_unit else conversion(unit, si_unit)


#: field kinds whose value is itself an array: varied as a TOML array of arrays, one per case
ARRAY_KINDS = ("numbers", "pair", "matrix")


def deck_field(path: str):
    """The declared field of a dotted deck path (fields.Field), or None."""
    table, _, name = path.rpartition(".")
    return schema.TABLES.get(table, {}).get(name)


def parse_vary(text: str, option: str = "--vary") -> Vary:
    """'path=RANGE' (see parse_values); the path is any deck field, as for --set."""
    path, values_text = _split_vary(text, option)
    _check_vary_path(path, option)
    values, spacing = parse_values(values_text, f"{option} {path}")
    _check_array_cases(path, values, values_text, option)
    return Vary(path, tuple(values), spacing)


def _split_vary(text: str, option: str) -> tuple[str, str]:
    """'PATH=VALUES' -> (path, values text), both given, the path on one line."""
    path, sep, values_text = text.partition("=")
    path = path.strip()
    if any(not ch.isprintable() for ch in path):
        raise InputError(option, None, "PATH=VALUES on one line (without line breaks or control characters)")
    if not sep or not path or not values_text.strip():
        raise InputError(option, text, "PATH=START:STOP:N[:log] or PATH=a,b,c, e.g. foundation.k_f=1e7:1e10:25:log")
    return path, values_text


def _check_vary_path(path: str, option: str) -> None:
    """A known deck field, not one of the case dimensions of their own (NOT_VARIED)."""
    if path in NOT_VARIED:
        raise InputError(option, path, f"a deck field other than {path} (use {NOT_VARIED[path]})")
    if not schema.known_path(path):
        raise InputError(option, path, f"a known deck field{schema.suggestion(path, schema.all_paths())}")


def _first_single(path: str, values: list[Any]) -> Any:
    """For a field whose value is an array (ARRAY_KINDS): the first case that is not an array."""
    field = deck_field(path)
    if not field or field.kind not in ARRAY_KINDS:
        return None
    return next((v for v in values if not isinstance(v, list)), None)


def _check_array_cases(path: str, values: list[Any], values_text: str, option: str) -> None:
    """Each case of an array field an array: `check_band=[0.9,1.1]` is two cases of one number
    each, not one band."""
    single = _first_single(path, values)
    if single is not None:
        raise InputError(option, path, "a TOML array of arrays, one array per case (the field's value is itself an "
                         f"array), e.g. {path}=[[0.9, 1.1], [0.8, 1.25]]; got {shown(values_text.strip(), 40)}, "
                         f"whose case {shown(single)} is not an array")


# ----------------------------------------------------------------------------- cases
