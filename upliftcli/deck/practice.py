"""The range of building practice of a field (Field.plausible): words for a checked value far
outside it, a warning of a likely unit mistake and not an error (deck/schema.plausibility)."""

from __future__ import annotations

from typing import Any

from ..units import conversion, system_unit
from .fields import NUMERIC, Field


def implausible(field: Field, value: Any, system: str = "si") -> str | None:
    """Words for a checked value (a number or an array of numbers, in the field's unit) outside
    the range of building practice the field declares (Field.plausible), or None; in a deck of
    units `system` "us", the value and the range in its US unit too."""
    if field.plausible is None or field.kind not in NUMERIC:
        return None
    low, high = field.plausible
    outside = [v for v in _flat(value) if not low <= v <= high]
    if not outside:
        return None
    shown_value, shown_range = _practice_words(field, outside[0], system)
    return f"{shown_value} is far outside building practice ({shown_range}): a unit mistake? (the analysis goes on)"


def _listed(value: Any) -> list | tuple:
    """A list or tuple as it is, anything else as a list of one."""
    return value if isinstance(value, (list, tuple)) else [value]


def _flat(value: Any) -> list:
    """The numbers of a number, an array or an array of arrays, in order."""
    return [v for item in _listed(value) for v in _listed(item)]


def _practice_words(field: Field, value: float, system: str) -> tuple[str, str]:
    """(the value, the field's range of building practice) in its unit, and in the US unit under
    `units = "us"` when that differs."""
    low, high = field.plausible
    unit = "" if field.unit == "-" else f" {field.unit}"
    shown_value, shown_range = f"{value:.4g}{unit}", f"{low:g} to {high:g}{unit}"
    us = _us_unit(field, system)
    if us is not None:
        factor = conversion(field.unit, us)
        shown_value += f" = {value * factor:.4g} {us}"
        shown_range += f" = {low * factor:.4g} to {high * factor:.4g} {us}"
    return shown_value, shown_range


def _us_unit(field: Field, system: str) -> str | None:
    """The US unit of the field's quantity in a deck of units "us", when it is not the field's own."""
    kind = field.quantity_kind
    if system != "us" or kind is None:
        return None
    unit = system_unit(kind, "us")
    return None if unit == field.unit else unit
