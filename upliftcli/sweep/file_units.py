"""A sweep's tables in the units of the files: SI (as the rows are computed), or US customary
units under `--units us` (display.file_unit: kip, kip ft, ft, in, in/s^2 ...): each output
column with a physical unit renamed by its unit (base_shear_N -> base_shear_kip) and its
values converted. A varied field's values stay as given, in the deck's units, which its unit
entry states (`--resume` matches cases by them)."""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Sequence

from ..display import file_unit, unit_suffix
from ..engines.quantities import column_name, file_kind


def _kind(column: str, unit: str) -> str:
    """The display kind of an output column (of the quantity it takes: max_displacement_m -> 'mm')."""
    base = column.removesuffix(column_name("", unit)).removeprefix("max_")
    return file_kind(base)


def converted_columns(units: dict[str, str], varied: Sequence[str], system: str) -> dict[str, tuple[str, float, str]]:
    """column -> (its name in the files, factor from SI, unit) of each output column the system
    converts (none in SI; the varied fields never)."""
    found = {}
    for column, unit in units.items():
        shown = file_unit(unit, _kind(column, unit), system)
        if column not in varied and shown.label != unit:
            name = column.removesuffix(column_name("", unit)) + unit_suffix(shown.label)
            found[column] = (name, shown.factor, shown.label)
    return found


def renamed(names: Sequence[str], converted: dict) -> list[str]:
    """The column names in the files."""
    return [converted[name][0] if name in converted else name for name in names]


def file_units(units: dict[str, str], converted: dict) -> dict[str, str]:
    """The units entry of the files: each column by its name there, with its unit there."""
    return {converted.get(name, (name,))[0]: converted[name][2] if name in converted else unit
            for name, unit in units.items()}


def file_rows(rows: Iterable[dict], converted: dict) -> list[dict]:
    """The rows with the converted columns renamed and their numbers scaled (other values as they are)."""
    return list(iter_file_rows(rows, converted))


def iter_file_rows(rows: Iterable[dict], converted: dict) -> Iterator[dict]:
    """file_rows one row at a time (a sweep's rows are read back from its rows file, never all in memory)."""
    if not converted:
        yield from rows
        return
    for row in rows:
        yield file_row(row, converted)


def file_row(row: dict, converted: dict) -> dict:
    """A row with the converted columns renamed and their numbers scaled (other values as they are)."""
    return {converted.get(key, (key,))[0]: _scaled(value, converted.get(key)) for key, value in row.items()}


def _scaled(value, conversion) -> object:
    """A number times the conversion's factor; anything else (None, a bool, text) as it is."""
    if conversion is None or isinstance(value, bool) or not isinstance(value, (int, float)):
        return value
    return float(value) * conversion[1]
