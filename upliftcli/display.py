"""Display units: the one table of how a value is shown to a person, in SI or US units.

Every human output (terminal tables, the report, the figures, the sweep and spectra
summaries) converts its SI values here. The machine outputs (JSON, CSV) are SI with their units
stated, unless `--units us` is given on the command line: then they are written in US customary
units (file_unit, in_file_units), their units stated the same way. The display system is the
deck's `units` unless --units is given; the files follow --units only (a deck's units never
change the files a script reads). A value is shown by its *kind*: an SI unit ("N", "N m", "N/m", "kg" ...) or
one of the display choices "mm" (a small length: displacements, drifts, uplift, spectral
displacements), "mm/s" (a ground or spectral velocity), "%" (a ratio
in percent: drift ratios), "g" (an acceleration in g), "mrad" (a small angle: the mat's
rotation), "coefficient" (a ratio to 4 decimals).
`--units si` (the default) shows kN, kN m, mm, m and g; `--units us` kip, kip ft, in, ft and g.

SUMMARY is the display record of the scalar results (V_b, M_b, their coefficients, V_c, M_c,
b/h_1*, uplift, yielded): every summary table takes its columns from it; `yielded` only where a
result tells (verdicts).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .units import STANDARD_GRAVITY, SYSTEMS

INCH, FOOT = 0.0254, 0.3048  # m
KIP = 4448.2216152605  # N (1000 lbf)
POUND_MASS = 0.45359237  # kg


def unsigned_zero(text: str) -> str:
    """A formatted number that rounds to zero shown without a sign: '-0.00' -> '0.00' (a value
    of round-off size below zero, such as a residual settlement at rest, is displayed as 0; the
    value itself is not changed)."""
    if text.startswith("-") and any(c.isdigit() for c in text) and not any(c in "123456789" for c in
                                                                          text.split("e")[0]):
        return text[1:]
    return text


def _plain_digits(value: float, digits: int) -> str:
    """A finite, nonzero value to `digits` significant digits without exponent: at least its
    integer digits, no trailing zeros."""
    decimals = max(0, digits - 1 - math.floor(math.log10(abs(value))))
    text = f"{value:.{decimals}f}"
    return text.rstrip("0").rstrip(".") if "." in text else text


def _float_text(value: float, digits: int) -> str:
    """A float to `digits` significant digits: plain between 1e-4 and 1e12 (_plain_digits), else
    with an exponent; '-' when not finite."""
    if not math.isfinite(value):
        return "-"
    if value == 0.0 or not 1e-4 <= abs(value) < 1e12:
        return unsigned_zero(f"{value:.{digits}g}")
    return _plain_digits(value, digits)


def _other_text(value) -> str:
    """A value that is not a float as text: a boolean yes/no, an integer, None as '-', else str(value)."""
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    return "-" if value is None else str(value)


def number(value, digits: int = 5) -> str:
    """A value as text: numbers to `digits` significant digits (plain between 1e-4 and 1e12,
    at least their integer digits, no trailing zeros), lists joined, booleans yes/no, non-finite as '-'."""
    if isinstance(value, (list, tuple, np.ndarray)):
        return ", ".join(number(v, digits) for v in value)
    if isinstance(value, (float, np.floating)):
        return _float_text(float(value), digits)
    return _other_text(value)


@dataclass(frozen=True)
class Unit:
    """A display unit: label, factor from SI, format spec ("": `number`, 5 significant digits)."""

    label: str
    factor: float = 1.0
    format: str = ""

    def show(self, value) -> str:
        """An SI value (a number, a list of numbers) in this unit; '-' when it is not finite or missing."""
        if isinstance(value, (list, tuple, np.ndarray)):
            return ", ".join(self.show(v) for v in value)
        if value is None or isinstance(value, (bool, np.bool_, str)):
            return number(value)
        return self._converted(float(value) * self.factor)

    def _converted(self, value: float) -> str:
        """A value already converted to this unit, in its format (without one: `number`); '-' when
        it is not finite."""
        if self.format and math.isfinite(value):
            return unsigned_zero(format(value, self.format))
        return number(value)


#: kind -> (SI display unit, US display unit)
DISPLAY: dict[str, tuple[Unit, Unit]] = {
    "N": (Unit("kN", 1e-3, ".1f"), Unit("kip", 1 / KIP, ".1f")),
    "N m": (Unit("kN m", 1e-3, ".1f"), Unit("kip ft", 1 / (KIP * FOOT), ".1f")),
    "mm": (Unit("mm", 1e3, ".2f"), Unit("in", 1 / INCH, ".3f")),
    "mm/s": (Unit("mm/s", 1e3, ".1f"), Unit("in/s", 1 / INCH, ".2f")),
    "m": (Unit("m"), Unit("ft", 1 / FOOT)),
    "g": (Unit("g", 1 / STANDARD_GRAVITY, ".4f"),) * 2,
    "%": (Unit("%", 100.0, ".3f"),) * 2,
    "mrad": (Unit("mrad", 1e3, ".3f"),) * 2,
    "coefficient": (Unit("-", 1.0, ".4f"),) * 2,
    "m/s^2": (Unit("m/s^2"), Unit("in/s^2", 1 / INCH)),
    "m/s": (Unit("m/s"), Unit("ft/s", 1 / FOOT)),
    "kg": (Unit("kg"), Unit("kip s^2/in", INCH / KIP)),
    "kg m": (Unit("kg m"), Unit("kip s^2", 1 / KIP)),
    "kg m^2": (Unit("kg m^2"), Unit("kip ft s^2", 1 / (KIP * FOOT))),
    "kg/m^3": (Unit("kg/m^3"), Unit("lb/ft^3", FOOT**3 / POUND_MASS)),
    "N/m": (Unit("kN/m", 1e-3), Unit("kip/in", INCH / KIP)),
    "N/m^2": (Unit("kN/m^2", 1e-3), Unit("kip/in^2", INCH**2 / KIP)),
    "N s/m": (Unit("kN s/m", 1e-3), Unit("kip s/in", INCH / KIP)),
    "N s/m^2": (Unit("kN s/m^2", 1e-3), Unit("kip s/in^2", INCH**2 / KIP)),
    "N m/rad": (Unit("kN m/rad", 1e-3), Unit("kip ft/rad", 1 / (KIP * FOOT))),
    "N m s/rad": (Unit("kN m s/rad", 1e-3), Unit("kip ft s/rad", 1 / (KIP * FOOT))),
    "Pa": (Unit("MPa", 1e-6), Unit("ksi", INCH**2 / KIP)),
    "J": (Unit("kJ", 1e-3), Unit("kip ft", 1 / (KIP * FOOT))),
}


def unit(kind: str, system: str = "si") -> Unit:
    """The display unit of a kind (module docstring) in a system; an unknown kind (s, rad, -)
    is shown as it is."""
    pair = DISPLAY.get(kind)
    if pair is None:
        return Unit(kind)
    return pair[SYSTEMS.index(system)]


def show(value, kind: str, system: str = "si") -> str:
    """An SI value shown in its kind's display unit (unit(kind, system).show)."""
    return unit(kind, system).show(value)


def stated(value, kind: str, system: str = "si", spec: str = "") -> str:
    """'360.8 mm/s': an SI value in its kind's display unit, followed by the unit; spec: a format
    of the converted value (default: the unit's own)."""
    shown = unit(kind, system)
    text = unsigned_zero(format(float(value) * shown.factor, spec)) if spec else shown.show(value)
    return f"{text} {shown.label}"


def label(kind: str, system: str = "si") -> str:
    """The unit label of a kind in a system ('kN', 'kip', '-', 's' ...)."""
    return unit(kind, system).label


def heading(text: str, kind: str, system: str = "si") -> str:
    """'V_b [kN]': a column heading with its display unit ('[-]' left out for a coefficient)."""
    shown = label(kind, system)
    return text if kind == "coefficient" else f"{text} [{shown}]"


#: intermediate values (engines/quantities.INTERMEDIATES) shown in another kind than their SI unit's:
#: accelerations in g, the mat's motion as the accuracy check shows it (edge uplift in mm, rotation in mrad)
INTERMEDIATE_KINDS = {"Sa_n": "g", "Sa1bar": "g", "impact_acceleration": "g", "max_uplift": "mm",
                      "max_uplift_left": "mm", "max_uplift_right": "mm", "max_rotation": "mrad",
                      "xi1bar/xi1": "coefficient"}


def intermediate_kind(name: str, si_unit: str) -> str:
    """The display kind of an intermediate value (INTERMEDIATE_KINDS, else its SI unit)."""
    return INTERMEDIATE_KINDS.get(name, si_unit)


@dataclass(frozen=True)
class Column:
    """A scalar result as the summary tables show it: the AnalysisResult attribute, its symbol
    (the heading without unit), its display kind ("yes/no" for a verdict) and its meaning."""

    name: str
    symbol: str
    kind: str
    meaning: str

    def value(self, result):
        """The result's value (None where it has none; a one-value peak, base_shear_strength, as a float)."""
        value = getattr(result, self.name, None)
        return float(value[0]) if isinstance(value, np.ndarray) else value

    def heading(self, system: str = "si") -> str:
        return self.symbol if self.kind == "yes/no" else heading(self.symbol, self.kind, system)

    def cell(self, result, system: str = "si") -> str:
        value = self.value(result)
        if self.kind == "yes/no":
            return "-" if value is None else "yes" if value else "no"
        return show(value, self.kind, system)

    def stated(self, result, system: str = "si") -> str:
        """'V_c = 3432.3 kN': the symbol, the value and its unit (none for a coefficient)."""
        shown = "" if self.kind in ("coefficient", "yes/no") else f" {label(self.kind, system)}"
        return f"{self.symbol} = {self.cell(result, system)}{shown}"


#: the display record of the scalar results, in table order
SUMMARY: dict[str, Column] = {c.name: c for c in (
    Column("base_shear", "V_b", "N", "peak base shear [14a]"),
    Column("base_shear_coefficient", "V_b/W", "coefficient", "base shear coefficient V_b/(m_t g)"),
    Column("base_moment", "M_b", "N m", "peak base overturning moment [14b]"),
    Column("base_moment_coefficient", "M_b/(W h_1*)", "coefficient", "base moment coefficient M_b/(m_t g h_1*)"),
    Column("critical_base_shear", "V_c", "N", "critical base shear m_t g b / h_1* [16a]"),
    Column("critical_base_moment", "M_c", "N m", "critical base moment m_t g b [16b]"),
    Column("critical_coefficient", "b/h_1*", "coefficient", "critical value of both coefficients [16a, 16b]"),
    Column("uplift", "uplift", "yes/no", "whether the mat lifts off"),
    Column("yielded", "yielded", "yes/no", "whether the soil under a contact element yields (a bearing capacity; "
           "'-': the engine does not tell, docs/theory.md 14.6)"),
)}
#: the summary columns of a building with story strengths (building_verdicts), after SUMMARY's
BUILDING_SUMMARY: dict[str, Column] = {c.name: c for c in (
    Column("building_yielded", "building yielded", "yes/no", "whether a story yielded (story strengths, docs/theory.md "
           "15.5)"),
    Column("base_shear_strength", "V_y", "N", "base-shear strength: the strength of the first story"),
)}
BUILDING_COLUMNS = tuple(BUILDING_SUMMARY)
#: what the summary tables' building columns mean, when they show them
BUILDING_LEGEND = ("building yielded: a story yielded ('-': an elastic building or an engine that does not tell); "
                   "V_y: base-shear strength")
#: what the summary tables' verdict columns mean, when they show `yielded`
VERDICT_LEGEND = ("uplift: the mat lifts off; yielded: the soil under an element yields (bearing capacity); '-': "
                  "not modelled (rigid, bonded: linear references) or not told (the simplified engine, whose uplift "
                  "then means V_c passed, by lifting or yielding)")
#: what the summary tables' W means
WEIGHT_LEGEND = "W = m_t g"


def summary_columns(names: Sequence[str]) -> list[Column]:
    """The display record's columns of these names, in the order given."""
    return [SUMMARY.get(name) or BUILDING_SUMMARY[name] for name in names]


def verdicts(results: Sequence) -> tuple[str, ...]:
    """The verdict columns of a summary of these results: uplift, and yielded when a result is
    on a foundation with a bearing capacity (AnalysisResult.yielded tells, or the simplified
    engine's intermediate Q_y says there is one: its yielded is '-', VERDICT_LEGEND)."""
    capacity = any(getattr(r, "yielded", None) is not None or "Q_y" in getattr(r, "intermediates", {})
                   for r in results)
    return ("uplift", *(("yielded",) if capacity else ()))


def building_verdicts(results: Sequence) -> tuple[str, ...]:
    """BUILDING_COLUMNS when a result tells whether its building yielded (story strengths), else none."""
    told = any(getattr(r, "building_yielded", None) is not None for r in results)
    return BUILDING_COLUMNS if told else ()


#: the columns of the rocking tables (the terminal's and the report's: rocking_rows)
ROCKING_HEADINGS = ("quantity", "where", "value", "unit", "time [s]")


def rocking_rows(entries: Sequence, system: str = "si") -> list[list[str]]:
    """The rows of the rocking tables (ROCKING_HEADINGS) from quantities.rocking_entries of a
    result: each value in its kind's display unit, its unit, and the instant of a peak [s]
    ('end' for a residual, '-' where none is known)."""
    return [[q.name.replace("_", " "), place, show(value, q.display, system), label(q.display, system),
             _instant_text(q.name, instant)] for q, _, place, value, instant in entries]


def _instant_text(name: str, instant: float | None) -> str:
    """The instant of a peak [s] as the rocking tables show it: 'end' for a residual, '-' where
    none is known."""
    if name.startswith("residual"):
        return "end"
    return "-" if instant is None else f"{instant:.3f}"


# ----------------------------------------------------------------------------- files in US units

#: the SI units a file writes in US customary units under --units us (each in its US display
#: unit; a displacement or a velocity shown in mm or mm/s in in or in/s); every other value (s,
#: rad, g, ratios) as it is
FILE_CONVERTED = frozenset({"m", "N", "N m", "m/s^2", "m/s", "kg", "kg m", "kg m^2", "kg/m^3", "N/m", "N/m^2",
                            "N s/m", "N s/m^2", "N m/rad", "N m s/rad", "Pa", "J"})
#: the keys of a results document never converted: ratios, bands, what the run was
FILE_KEPT = frozenset({"provenance", "details", "ratio", "spectrum_ratio", "procedure_ratio", "compared", "band",
                       "motion_band", "left_out", "warnings", "statistic_meanings", "suite_rule"})


def file_unit(si_unit: str, kind: str = "", system: str = "si") -> Unit:
    """The unit a file writes a value of this SI unit (and display kind) in: the SI unit itself
    (factor 1), or in the system 'us' its US display unit (FILE_CONVERTED)."""
    if system != "us" or si_unit not in FILE_CONVERTED:
        return Unit(si_unit)
    return unit(kind if kind in ("mm", "mm/s") else si_unit, "us")


def unit_suffix(text: str) -> str:
    """A unit as the suffix of a column name: 'kip ft' -> '_kipft', 'in/s^2' -> '_in_s2' ('-', '': none)."""
    if text in ("-", ""):
        return ""
    return "_" + text.replace(" ", "").replace("/", "_").replace("^", "")


def in_file_units(document, units: dict):
    """A JSON-ready document with every value whose key `units` names ({key: Unit, or a nested
    {key: Unit} for the values under that key}) multiplied by its unit's factor; lists and
    dicts walked (a key of FILE_KEPT not); everything else as it is."""
    if isinstance(document, dict):
        return {key: _converted_entry(key, value, units) for key, value in document.items()}
    if isinstance(document, list):
        return [in_file_units(item, units) for item in document]
    return document


def _converted_entry(key: str, value, units: dict):
    """One entry of in_file_units: a number (or list of numbers) of a named unit converted, a
    nested unit table followed, a kept key as it is, anything else walked."""
    found = units.get(key)
    if key in FILE_KEPT:
        return value
    if isinstance(found, dict):
        return in_file_units(value, found)
    if isinstance(found, Unit) and found.factor != 1.0:
        return _scaled(value, found.factor, units)
    return in_file_units(value, units)


def _scaled(value, factor: float, units: dict):
    """A number times factor; a list: each item; a dict (left, centre, right edge): each value."""
    if isinstance(value, list):
        return [_scaled(item, factor, units) for item in value]
    if isinstance(value, dict):
        return {key: _scaled(item, factor, units) for key, item in value.items()}
    return _scaled_number(value, factor)


def _scaled_number(value, factor: float):
    """A number (not a bool) times factor; anything else as it is."""
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_)):
        return float(value) * factor
    return value
