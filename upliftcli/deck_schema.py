"""The deck schema: every table and field of an `uplift` deck, with its unit, default and check.

docs/deck.md documents the same fields (a test keeps the two in step). Validation here is
purely about types and ranges of single fields; how fields combine (which alternatives
are given) is decided in deck.py.
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass
from typing import Any

from .errors import InputError
from .units import STANDARD_GRAVITY

REQUIRED = object()


@dataclass(frozen=True)
class Field:
    """One deck field.

    kind: number, integer, string, bool, numbers (array), number-or-numbers, matrix,
        string-or-strings, pair (two numbers), table (passed through).
    unit: the unit in words/symbols ("-" for dimensionless).
    check: positive, nonnegative, fraction ([0, 1)), unit-interval ((0, 1]), poisson ([0, 0.5)),
        count (integer >= 1), elements (integer >= 2), or "" for none.
    choices: allowed strings for string fields.
    """

    kind: str
    unit: str
    doc: str
    check: str = ""
    default: Any = None
    choices: tuple[str, ...] = ()


TABLES: dict[str, dict[str, Field]] = {
    "": {
        "title": Field("string", "-", "a label for the deck, printed with the results"),
    },
    "building": {
        "stories": Field("integer", "-", "number of stories N (uniform shorthand)", "count"),
        "floor_mass": Field("number", "kg", "mass of every floor m_j (uniform shorthand)", "positive"),
        "masses": Field("numbers", "kg", "floor masses m_1..m_N, lowest floor first", "positive"),
        "story_height": Field("number", "m", "height of every story (uniform shorthand)", "positive"),
        "story_heights": Field("numbers", "m", "story heights h_j - h_(j-1), lowest story first", "positive"),
        "story_stiffness": Field("number", "N/m", "lateral stiffness k_j of every story", "positive"),
        "story_stiffnesses": Field("numbers", "N/m", "story stiffnesses k_1..k_N, lowest story first",
                                   "positive"),
        "stiffness_matrix": Field("matrix", "N/m", "lateral stiffness matrix K of a frame (N x N, "
                                  "symmetric positive definite), instead of story stiffnesses"),
        "period": Field("number", "s", "fixed-base fundamental period T_1; alone it sets a uniform story "
                        "stiffness, with a stiffness it scales that stiffness to give T_1", "positive"),
        "damping": Field("number-or-numbers", "-", "modal damping ratio xi_n: one value for all modes or "
                         "one per mode", "fraction", 0.05),
    },
    "foundation": {
        "type": Field("string", "-", "foundation idealisation", "", "two-element",
                      ("two-element", "winkler", "halfspace")),
        "b": Field("number", "m", "half-width b of the rigid mat in the plane of motion", "positive"),
        "slenderness": Field("number", "-", "h_1*/b: sets b from the first-mode effective height "
                             "(instead of b)", "positive"),
        "mat_mass": Field("number", "kg", "mass m_0 of the mat", "nonnegative", 0.0),
        "mat_rotary_inertia": Field("number", "kg m^2", "rotary inertia I_0 of the mat about its centre",
                                    "nonnegative", 0.0),
        "k_f": Field("number", "N/m", "two-element: stiffness of each edge element", "positive"),
        "c_f": Field("number", "N s/m", "two-element: damping of each edge element", "nonnegative", 0.0),
        "frequency_ratio": Field("number", "-", "two-element: w_v/w_1 with w_v = sqrt(2 k_f / m_t) "
                                 "(instead of k_f)", "positive"),
        "damping_ratio": Field("number", "-", "two-element: xi_v = c_f / (m_t w_v) (instead of c_f)",
                               "nonnegative"),
        "k_w": Field("number", "N/m^2", "winkler: stiffness per unit length along the width", "positive"),
        "c_w": Field("number", "N s/m^2", "winkler: damping per unit length along the width",
                     "nonnegative", 0.0),
        "elements": Field("integer", "-", "winkler: number of discrete elements for the exact engine",
                          "elements", 20),
        "shear_modulus": Field("number", "Pa", "halfspace: shear modulus G", "positive"),
        "shear_wave_velocity": Field("number", "m/s", "halfspace: V_s (instead of G; G = rho V_s^2)",
                                     "positive"),
        "poisson_ratio": Field("number", "-", "halfspace: Poisson's ratio nu", "poisson", 1.0 / 3.0),
        "density": Field("number", "kg/m^3", "halfspace: mass density rho", "positive"),
        "half_length": Field("number", "m", "halfspace: half-dimension of the mat normal to the plane of "
                             "motion (default: b, a square mat)", "positive"),
    },
    "ground_motion": {
        "record": Field("string", "-", "path of the accelerogram file (relative to the deck)"),
        "format": Field("string", "-", "record format (default: detected)", "", None,
                        ("at2", "text", "csv", "shared")),
        "units": Field("string", "-", "record acceleration units: g, m/s2, cm/s2 or in/s2 (default: from "
                       "the file header)"),
        "dt": Field("number", "s", "time step, for plain text files without a 'dt' header", "positive"),
        "scale": Field("number", "-", "factor applied to the record", "positive", 1.0),
        "window": Field("pair", "s", "[start, end] time window of the record to keep"),
        "design_spectrum": Field("table", "-", "a design spectrum instead of a record (see the records "
                                 "documentation for its fields)"),
    },
    "analysis": {
        "engine": Field("string-or-strings", "-", "engine(s): simplified (response spectrum, paper Eqs. "
                        "21-35), approximate, exact", "", ["simplified"], ("simplified", "approximate", "exact")),
        "supports": Field("string-or-strings", "-", "support condition(s)", "", ["rigid", "bonded", "uplift"],
                          ("rigid", "bonded", "uplift")),
        "modes": Field("integer", "-", "number of modes (default: all N)", "count"),
        "mass_participation": Field("number", "-", "keep the fewest modes whose effective masses reach this "
                                    "fraction of the building mass (instead of modes)", "unit-interval"),
        "combination": Field("string", "-", "modal combination rule (simplified engine)", "", "srss",
                             ("srss", "cqc")),
        "effective_properties": Field("string", "-", "T1bar and xi1bar from Eqs. 21-25 (formula) or from the "
                                      "complex eigenvalue of the bonded one-mode system (eigenvalue)", "",
                                      "formula", ("formula", "eigenvalue")),
        "uplift_damping": Field("string", "-", "damping while uplifted: zeta = xi1bar r/b [27] (xi1bar) or "
                                "xi_1 r/b (xi1, rigid-pivot derivation)", "", "xi1bar", ("xi1bar", "xi1")),
        "uplift_x": Field("string", "-", "amplitude ratio in X: (S_a/g)^2 (h_1*/b)^2 = (m_t S_a/V_c)^2 "
                          "(spectral) or (V_1/V_c)^2 = (m_1* S_a/V_c)^2 (mass-consistent)", "", "spectral",
                          ("spectral", "mass-consistent")),
        "uplift_x_factor": Field("string", "-", "factor on X for the decay from the uplift crossing to the "
                                 "bonded peak: e^(xi1bar pi) (exponential), 1 (none), or "
                                 "e^(2 xi1bar (pi/2 - asin(1/sqrt(X0)))) (phase)", "", "exponential",
                                 ("exponential", "none", "phase")),
        "uplift_formula": Field("string", "-", "uplift base shear: full Eq. 28a or slender-structure Eq. 29",
                                "", "full", ("full", "slender")),
        "gravity": Field("number", "m/s^2", "acceleration of gravity g", "positive", STANDARD_GRAVITY),
    },
    "analysis.exact": {
        "n_modes": Field("integer", "-", "fixed-base modes kept by the exact/approximate engines (default: "
                         "analysis.modes, else all)", "count"),
        "criterion": Field("string", "-", "uplift criterion [4a, 4b]", "", "reaction",
                           ("reaction", "displacement")),
        "steps_per_period": Field("integer", "-", "internal steps per shortest governing period (T_1, the "
                                  "bonded vertical period, modes with >= 1 % mass)", "count", 6),
        "time_step": Field("number", "s", "internal time step (default: from steps_per_period and the "
                           "record step)", "positive"),
        "free_vibration": Field("number", "s", "free vibration appended after the record", "nonnegative", 0.0),
        "flight": Field("string", "-", "both edges lifted: free flight (allow) or an error", "", "allow",
                        ("allow", "error")),
        "residual_inertia": Field("string", "-", "with fewer modes than stories: neglect (default) or include "
                                  "the rotary inertia of the truncated modes", "", "neglect",
                                  ("neglect", "include")),
    },
    "criteria": {
        "drift_ratio": Field("number", "-", "largest allowed story drift ratio", "positive"),
        "drift": Field("number", "m", "largest allowed story drift", "positive"),
        "displacement": Field("number", "m", "largest allowed floor displacement (relative to the mat)",
                              "positive"),
        "base_shear": Field("number", "N", "largest allowed base shear", "positive"),
        "base_shear_coefficient": Field("number", "-", "largest allowed V_b/(m_t g)", "positive"),
        "base_moment": Field("number", "N m", "largest allowed base overturning moment", "positive"),
        "base_moment_coefficient": Field("number", "-", "largest allowed M_b/(m_t g h_1*)", "positive"),
        "uplift": Field("bool", "-", "whether uplift of the mat is acceptable (false: uplift fails)"),
    },
}

#: tables that may appear inside others (dotted name -> parent)
SUBTABLES = {"analysis.exact": "analysis"}


def dotted(table: str, name: str) -> str:
    return f"{table}.{name}" if table else name


def suggestion(name: str, candidates) -> str:
    """' (did you mean 'x'?)' for the closest candidate, or ''."""
    close = difflib.get_close_matches(name, list(candidates), n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


def known_path(path: str) -> bool:
    """Whether a dotted path names a deck field (or lies inside a pass-through table)."""
    parts = path.split(".")
    for depth in range(len(parts) - 1, -1, -1):
        table, rest = ".".join(parts[:depth]), parts[depth:]
        if table in TABLES and rest and rest[0] in TABLES[table]:
            field = TABLES[table][rest[0]]
            return len(rest) == 1 or field.kind == "table"
    return False


def all_paths() -> list[str]:
    return [dotted(table, name) for table, fields in TABLES.items() for name in fields]


_CHECKS = {
    "positive": (lambda v: v > 0, "> 0"),
    "nonnegative": (lambda v: v >= 0, ">= 0"),
    "fraction": (lambda v: 0 <= v < 1, "in [0, 1)"),
    "unit-interval": (lambda v: 0 < v <= 1, "in (0, 1]"),
    "poisson": (lambda v: 0 <= v < 0.5, "in [0, 0.5)"),
    "count": (lambda v: v >= 1, ">= 1"),
    "elements": (lambda v: v >= 2, ">= 2"),
    "": (lambda v: True, ""),
}


def _unit(field: Field) -> str:
    return "" if field.unit == "-" else f" [{field.unit}]"


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def check_value(field: Field, value: Any, error) -> Any:
    """Validate one value against its field; `error(expected)` raises the InputError."""
    test, words = _CHECKS[field.check]
    qualifier = f" {words}" if words else ""

    def number(v, what="a number"):
        if not _is_number(v):
            error(f"{what}{qualifier}{_unit(field)}, got {v!r}")
        if not test(v):
            error(f"{what}{qualifier}{_unit(field)}, got {v!r}")
        return float(v)

    kind = field.kind
    if kind == "number":
        return number(value)
    if kind == "integer":
        if not isinstance(value, int) or isinstance(value, bool) or not test(value):
            error(f"an integer{qualifier}, got {value!r}")
        return int(value)
    if kind == "bool":
        if not isinstance(value, bool):
            error(f"true or false, got {value!r}")
        return value
    if kind == "string":
        if not isinstance(value, str):
            error(f"a string, got {value!r}")
        if field.choices and value not in field.choices:
            error(f"one of {', '.join(field.choices)}, got {value!r}{suggestion(value, field.choices)}")
        return value
    if kind == "string-or-strings":
        items = [value] if isinstance(value, str) else value
        if not isinstance(items, list) or not items or not all(isinstance(i, str) for i in items):
            error(f"a string or a non-empty array of strings, got {value!r}")
        for item in items:
            if field.choices and item not in field.choices:
                error(f"one or more of {', '.join(field.choices)}, got {item!r}{suggestion(item, field.choices)}")
        return list(dict.fromkeys(items))
    if kind in ("numbers", "number-or-numbers"):
        if kind == "number-or-numbers" and not isinstance(value, list):
            return number(value)
        if not isinstance(value, list) or not value:
            error(f"a non-empty array of numbers{qualifier}{_unit(field)}, got {value!r}")
        return [number(v, "every entry a number") for v in value]
    if kind == "pair":
        if not (isinstance(value, list) and len(value) == 2 and all(_is_number(v) for v in value)
                and 0 <= value[0] < value[1]):
            error(f"[start, end] with 0 <= start < end{_unit(field)}, got {value!r}")
        return (float(value[0]), float(value[1]))
    if kind == "matrix":
        if not (isinstance(value, list) and value and all(isinstance(row, list) for row in value)
                and all(len(row) == len(value) for row in value) and all(_is_number(v) for row in value for v in row)):
            error(f"a square array of arrays of numbers{_unit(field)}, got {value!r}")
        return [[float(v) for v in row] for row in value]
    if kind == "table":
        if not isinstance(value, dict):
            error(f"a table, got {value!r}")
        return value
    raise AssertionError(kind)


def validate(raw: dict, source: str, overridden: frozenset[str] = frozenset()) -> dict[str, dict[str, Any]]:
    """Check every key, type and range; return {table: {field: value}} with only the given fields.

    Values that came from `--set` are reported with source "--set".
    """
    values: dict[str, dict[str, Any]] = {table: {} for table in TABLES}

    def raiser(path: str):
        def error(expected: str):
            raise InputError("--set" if path in overridden else source, path, expected)
        return error

    def walk(table: str, mapping: dict) -> None:
        fields = TABLES[table]
        for key, value in mapping.items():
            path = dotted(table, key)
            if path in TABLES and SUBTABLES.get(path, "") == table:
                if not isinstance(value, dict):
                    raiser(path)(f"a table [{path}], got {value!r}")
                walk(path, value)
                continue
            if key not in fields:
                names = list(fields) + [name.rsplit(".", 1)[-1] for name, parent in SUBTABLES.items()
                                        if parent == table]
                if table == "":
                    names += [name for name in TABLES if name and "." not in name]
                where = f"[{table}]" if table else "the top level"
                raiser(path)(f"a known field of {where}{suggestion(key, names)}; unknown key {key!r}")
            values[table][key] = check_value(fields[key], value, raiser(path))

    walk("", raw)
    return values
