"""The deck schema: every table and field of an `uplift` deck, with its unit, default and check.

The fields of each foundation type come from its class (model/foundations.py), the engine
options from engines/options.py, the engine and support names from engines/registry.py and
the record formats from motion/records.py. docs/deck.md documents the same fields (a test
keeps the two in step). Validation here is purely about types and ranges of single fields;
how fields combine (which alternatives are given) is decided in deck.py.
"""

from __future__ import annotations

from typing import Any

from .engines.options import ExactOptions, SimplifiedOptions, deck_fields
from .engines.quantities import QUANTITIES, SCALARS
from .engines.registry import ENGINES, SUPPORTS
from .errors import InputError
from .fields import Field, check_value, suggestion
from .model.foundations import FOUNDATIONS
from .motion.code_rules import RULES, SCALINGS
from .motion.readers import FORMATS
from .units import STANDARD_GRAVITY

TABLES: dict[str, dict[str, Field]] = {
    "": {
        "title": Field("string", "-", "a label for the deck, printed with the results"),
    },
    "building": {
        "stories": Field("integer", "-", "number of stories N (uniform shorthand)", "stories"),
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
        "type": Field("string", "-", "foundation idealisation", "", "two-element", tuple(FOUNDATIONS)),
        "b": Field("number", "m", "half-width b of the rigid mat in the plane of motion", "positive"),
        "slenderness": Field("number", "-", "h_1*/b: sets b from the first-mode effective height "
                             "(instead of b)", "positive"),
        "mat_mass": Field("number", "kg", "mass m_0 of the mat", "nonnegative", 0.0),
        "mat_rotary_inertia": Field("number", "kg m^2", "rotary inertia I_0 of the mat about its centre",
                                    "nonnegative", 0.0),
        **{name: field for kind in FOUNDATIONS.values() for name, field in kind.deck_fields.items()},
    },
    "ground_motion": {
        "record": Field("string", "-", "path of the accelerogram file (relative to the deck)"),
        "format": Field("string", "-", "record format (default: detected)", "", None, FORMATS),
        "units": Field("string", "-", "record acceleration units: g, m/s2, cm/s2 or in/s2 (default: from "
                       "the file header)"),
        "dt": Field("number", "s", "time step, for plain text files without a 'dt' header", "positive"),
        "scale": Field("number", "-", "factor applied to the record", "positive", 1.0),
        "window": Field("pair", "s", "[start, end] time window of the record to keep"),
        "design_spectrum": Field("table", "-", "a design spectrum instead of a record (see the records "
                                 "documentation for its fields); the target of a suite"),
        "suite": Field("files", "-", "a suite of records: a folder, or an array of files or tables {file, format, "
                       "units, dt, scale} (relative to the deck)"),
        "scaling": Field("string", "-", "how the suite meets the target", "", "none", SCALINGS),
        "suite_factor": Field("bool", "-", "amplitude scaling: one factor for the whole suite (true) or one per "
                              "record (false)", "", False),
        "period_range": Field("pair", "s", "[lower, upper] periods of scaling and matching (default: the code's "
                              "rule on the structure's periods)"),
        "statistics": Field("string", "-", "the code whose suite rules apply (default: that of the design "
                            "spectrum)", "", None, tuple(RULES)),
    },
    "analysis": {
        "engine": Field("string-or-strings", "-", "engine(s): " + ", ".join(e.label for e in ENGINES.values()),
                        "", ["simplified"], tuple(ENGINES)),
        "supports": Field("string-or-strings", "-", "support condition(s)", "", list(SUPPORTS), SUPPORTS),
        "modes": Field("integer", "-", "number of modes (default: all N)", "count"),
        "mass_participation": Field("number", "-", "keep the fewest modes whose effective masses reach this "
                                    "fraction of the building mass (instead of modes)", "unit-interval"),
        **deck_fields(SimplifiedOptions),
        "gravity": Field("number", "m/s^2", "acceleration of gravity g", "positive", STANDARD_GRAVITY),
        "check_band": Field("pair", "-", "[low, high]: a ratio simplified / exact of the accuracy check outside "
                            "it is a warning (uplift analyze with a record)", "", [0.8, 1.25]),
        "check_band_motion": Field("pair", "-", "[low, high]: the same for the edge uplift and the mat rotation",
                                   "", [0.5, 2.0]),
    },
    "analysis.exact": deck_fields(ExactOptions),
    "criteria": {
        **{q.name: Field("number", q.unit, f"largest allowed {q.meaning}", "positive")
           for q in QUANTITIES.values() if q.criterion},
        **{q.name: Field("number", q.unit, f"largest allowed {q.meaning}", "positive") for q in SCALARS.values()},
        "uplift": Field("bool", "-", "whether uplift of the mat is acceptable (false: uplift fails)"),
        "simplified_error": Field("number", "-", "largest relative error e of the simplified engine in the "
                                  "accuracy check: a ratio simplified / exact outside [1/(1+e), 1+e] fails",
                                  "positive"),
    },
}

#: tables that may appear inside others (dotted name -> parent)
SUBTABLES = {"analysis.exact": "analysis"}


def dotted(table: str, name: str) -> str:
    return f"{table}.{name}" if table else name


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
