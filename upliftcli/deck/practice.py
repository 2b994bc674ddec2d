"""The range of building practice of a field (Field.plausible): words for a checked value far
outside it (implausible), and one warning per such field of a deck (plausibility): a likely unit
mistake, not an error."""

from __future__ import annotations

from typing import Any

from ..units import conversion, system_unit
from .fields import NUMERIC, Field
from .schema import TABLES, dotted, set_by_override


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
    shown_value, shown_range = f"{given(value)}{unit}", f"{low:g} to {high:g}{unit}"
    us = _us_unit(field, system)
    if us is not None:
        factor = conversion(field.unit, us)
        shown_value += f" = {value * factor:.4g} {us}"
        shown_range += f" = {low * factor:.4g} to {high * factor:.4g} {us}"
    return shown_value, shown_range


def given(value: float) -> str:
    """A value as given: to 4 significant digits when that is the value itself, else its shortest
    text that reads back as it (repr): a safety factor of 1.0000001 is not warned about as '1'."""
    short = f"{value:.4g}"
    return short if float(short) == value else repr(float(value))


def _us_unit(field: Field, system: str) -> str | None:
    """The US unit of the field's quantity in a deck of units "us", when it is not the field's own."""
    kind = field.quantity_kind
    if system != "us" or kind is None:
        return None
    unit = system_unit(kind, "us")
    return None if unit == field.unit else unit


def plausibility(values: dict[str, dict[str, Any]], source: str, overridden=frozenset()) -> list[str]:
    """One warning per validated field whose value lies outside the range of building practice
    its declaration gives (Field.plausible; the design spectrum's keys too), naming the deck
    ('(--set)' after it for a value of --set) and the field: 'inputs/a.toml: building.floor_mass:
    300 kg is far outside ...'."""
    system = values[""].get("units", "si")
    warnings = []
    for path, field, value in _declared(values) + _spectrum_declared(values):
        words = implausible(field, value, system)
        if words:
            warnings.append(f"{source}{' (--set)' if set_by_override(path, overridden) else ''}: {path}: {words}")
    return warnings


def _declared(values: dict[str, dict[str, Any]]) -> list[tuple[str, Field, Any]]:
    """(dotted path, field, value) of every validated deck field."""
    return [(dotted(table, name), TABLES[table][name], value) for table, fields in values.items()
            for name, value in fields.items()]


def _spectrum_declared(values: dict[str, dict[str, Any]]) -> list[tuple[str, Field, Any]]:
    """(dotted path, field, value) of every declared key of the design spectrum."""
    from ..motion.spectrum_fields import SPECTRUM_FIELDS

    spectrum = values.get("ground_motion", {}).get("design_spectrum") or {}
    return [(f"ground_motion.design_spectrum.{key}", SPECTRUM_FIELDS[key], value) for key, value in spectrum.items()
            if key in SPECTRUM_FIELDS]
