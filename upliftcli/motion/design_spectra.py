"""Design spectra as ground-motion input of the simplified engine and as targets of record suites:
`from_mapping` builds one from a deck table (docs/deck.md), a code spectrum of code_spectra.py
(ASCE 7-22 two-period and multi-period, EN 1998-1) or a tabulated one (spectrum_tables.py). Every
spectrum has `.sa(periods, damping) -> S_a [m/s^2]`, `.name` and `.period_range` [s].
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, deck_relative_path, not_found
from .code_spectra import (
    EC8_CODE_MAX_PERIOD,
    EC8_PARAMETERS,
    USGS_PERIODS,
    ASCE7MultiPeriodSpectrum,
    ASCE7Spectrum,
    EC8Spectrum,
    procedure_warning,
    spectrum_warnings,
)
from .spectrum_fields import SPECTRUM_FIELDS, check_spectrum
from .spectrum_tables import TabulatedSpectrum, asce_damping_coefficient, ec8_damping_correction, read_spectrum_table

__all__ = ["EC8_CODE_MAX_PERIOD", "EC8_PARAMETERS", "USGS_PERIODS", "ASCE7MultiPeriodSpectrum", "ASCE7Spectrum",
           "EC8Spectrum", "TabulatedSpectrum", "asce_damping_coefficient", "ec8_damping_correction", "from_mapping",
           "procedure_warning", "spectrum_warnings"]

#: units of the design_spectrum keys (docs/deck.md)
KEY_UNITS = {key: field.unit for key, field in SPECTRUM_FIELDS.items()}

_KEYS = {
    "asce7": ({"type", "sds", "sd1", "tl"}, {"level"}),
    "asce7-multiperiod": ({"type"}, {"sa", "file", "periods", "sds", "sd1", "units", "name", "level"}),
    "ec8": ({"type", "ag", "ground_type"}, {"spectrum_type", "importance"}),
    "table": ({"type", "damping"}, {"file", "periods", "sa", "units", "damping_correction", "name"}),
}


def check_keys(mapping, source: str, field: str, error_for=None) -> dict:
    """The keys of a design_spectrum table checked by the field checker, those of its type
    (_KEYS): spectrum_fields.check_spectrum."""
    return check_spectrum(mapping, _KEYS, source, field, error_for)


def _table_values(mapping: dict, source: str, field: str) -> tuple[np.ndarray, np.ndarray, str]:
    """(periods [s], sa, source) of a table given by 'file' or by 'periods' and 'sa'."""
    has_file = "file" in mapping
    has_values = "periods" in mapping or "sa" in mapping
    if has_file == has_values:
        raise InputError(source, f"{field}.file", "either 'file' or both 'periods' and 'sa'")
    if has_file:
        return _table_file(str(mapping["file"]), source, field)
    return _listed_values(mapping, source, field)


def _table_file(name: str, source: str, field: str) -> tuple[np.ndarray, np.ndarray, str]:
    """(periods [s], sa, path) of a spectrum table file (relative to the deck's folder)."""
    path = deck_relative_path(name, source)
    if not path.exists():
        raise InputError(source, f"{field}.file", not_found(path, name, source, "spectrum table"))
    periods, sa = read_spectrum_table(path, source)
    return periods, sa, str(path)


def _listed_values(mapping: dict, source: str, field: str) -> tuple[np.ndarray, np.ndarray, str]:
    """(periods [s], sa, source) of a table given by the lists 'periods' and 'sa' of the deck."""
    for key in ("periods", "sa"):
        if key not in mapping:
            raise InputError(source, f"{field}.{key}", "a list of numbers")
    try:
        return np.asarray(mapping["periods"], dtype=float), np.asarray(mapping["sa"], dtype=float), source
    except (TypeError, ValueError):
        raise InputError(source, f"{field}.periods", "lists of numbers for periods [s] and sa") from None


def _multiperiod(mapping: dict, source: str, field: str) -> ASCE7MultiPeriodSpectrum:
    """The ASCE 7-22 multi-period spectrum of a deck table: its 22 ordinates [g] ('sa', or a table
    at the USGS periods)."""
    sa, table_source = _multiperiod_ordinates(mapping, source, field)
    units = str(mapping.get("units", "g"))
    if units != "g":
        raise InputError(source, f"{field}.units", f"'g' (the USGS service gives g), got {units!r}")
    return ASCE7MultiPeriodSpectrum(sa, mapping.get("sds"), mapping.get("sd1"), source=table_source,
                                    label=str(mapping.get("name", "")), level=mapping.get("level", "design"))


def _multiperiod_ordinates(mapping: dict, source: str, field: str) -> tuple[np.ndarray, str]:
    """(the ordinates, their source) of a multi-period spectrum: a table at the 22 USGS periods
    ('file', or 'periods' and 'sa'), or the list 'sa' alone."""
    if "file" in mapping or "periods" in mapping:
        periods, sa, table_source = _table_values(mapping, source, field)
        _check_usgs_periods(periods, source, field)
        return sa, table_source
    if "sa" not in mapping:
        raise InputError(source, f"{field}.sa", "the 22 ordinates [g] at T = 0-10 s (or 'file')")
    try:
        return np.asarray(mapping["sa"], dtype=float), source
    except (TypeError, ValueError):
        raise InputError(source, f"{field}.sa", "a list of 22 numbers [g]") from None


def _check_usgs_periods(periods: np.ndarray, source: str, field: str) -> None:
    """InputError unless a table's periods are the 22 USGS_PERIODS [s]."""
    if periods.shape != (len(USGS_PERIODS),) or not np.allclose(periods, USGS_PERIODS, rtol=0, atol=1e-9):
        raise InputError(source, f"{field}.periods", "the 22 periods of the USGS multi-period spectrum "
                         f"({', '.join(f'{t:g}' for t in USGS_PERIODS)} s)")


def from_mapping(mapping: dict, source: str, field: str = "spectrum", default_correction: str = "ec8"):
    """Build a spectrum from a deck table, e.g. {type = "asce7", sds = 1.0, sd1 = 0.6, tl = 8.0},
    {type = "asce7-multiperiod", sa = [22 values in g]}, {type = "ec8", ag = 0.3, ground_type = "B"},
    {type = "table", file = "sa.csv", damping = 0.05} (file relative to the deck's folder) or
    {type = "table", periods = [...], sa = [...], damping = 0.05, units = "g"}.
    `field` is the deck path of the table, used in error messages; `default_correction` the
    damping correction of a table that names none ('asce' or 'ec8')."""
    mapping = check_keys(mapping, source, field)
    try:
        return _spectrum_of(mapping, source, field, default_correction)
    except InputError as error:
        blamed = _deck_location(error, source, field) or _table_location(error, mapping, source, field)
        if blamed is None:
            raise
        raise blamed from None


def _spectrum_of(mapping: dict, source: str, field: str, default_correction: str):
    """The spectrum of a checked deck table, by its type."""
    kind = mapping["type"]
    if kind == "asce7":
        return ASCE7Spectrum(mapping["sds"], mapping["sd1"], mapping["tl"], source=source,
                             level=mapping.get("level", "design"))
    if kind == "asce7-multiperiod":
        return _multiperiod(mapping, source, field)
    if kind == "ec8":
        return EC8Spectrum(mapping["ag"], mapping["ground_type"], mapping.get("spectrum_type", 1),
                           mapping.get("importance", 1.0), source=source)
    periods, sa, table_source = _table_values(mapping, source, field)
    return TabulatedSpectrum(periods, sa, mapping["damping"], units=mapping.get("units", "g"),
                             damping_correction=mapping.get("damping_correction", default_correction),
                             source=table_source, label=mapping.get("name", ""))


def _deck_location(error: InputError, source: str, field: str) -> InputError | None:
    """An error in the deck at a key of the table, named as the deck field `field`.<key> (None: another error)."""
    if error.source == source and error.location and not error.location.startswith(field + "."):
        return InputError(source, f"{field}.{error.location}", error.expected)
    return None


def _table_location(error: InputError, mapping: dict, source: str, field: str) -> InputError | None:
    """What the deck's table file holds (or a key checked with it) blamed on the deck field, naming
    the file (None: another error)."""
    table = mapping.get("file")
    if table and error.location and not error.location.startswith("line") and error.source != source:
        key = error.location if error.location in mapping else "file"
        return InputError(source, f"{field}.{key}", f"{error.expected} (spectrum read from {table!r}: "
                          f"{error.source!r})")
    return None
