"""The deck schema: every table and field of an `uplift` deck, with its unit, default and check.

The fields of each foundation type come from its class (model/foundations.py), the engine
options from engines/options.py, the engine and support names from engines/registry.py and
the record formats from motion/records.py. docs/deck.md documents the same fields (a test
keeps the two in step). Validation here is purely about types and ranges of single fields
(and exactly_one: at most one of a table's alternative fields); how fields combine is decided
in deck/load.py, deck/building.py and deck/motion.py.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..engines.options import ExactOptions, SimplifiedOptions, deck_fields
from ..engines.quantities import QUANTITIES, ROCKING, SCALARS
from ..engines.registry import ENGINES, SUPPORTS
from ..errors import InputError
from ..model.foundations import FOUNDATIONS
from ..motion.code_rules import RULES, SCALINGS
from ..motion.design_spectra import check_keys
from ..motion.records import RECORD_FIELDS
from ..motion.suites import check_entry
from ..units import STANDARD_GRAVITY, SYSTEMS
from .fields import NUMERIC, Field, check_value, gather, implausible, raise_all, raiser, suggestion

#: the range of building practice of acceptance limits (a value outside: a warning)
CRITERIA_PLAUSIBLE = {"drift_ratio": (1e-4, 0.1), "base_shear_coefficient": (1e-3, 3.0),
                      "base_moment_coefficient": (1e-3, 3.0)}

TABLES: dict[str, dict[str, Field]] = {
    "": {
        "title": Field("string", "-", "a label for the deck, printed with the results"),
        "units": Field("string", "-", "unit system of the deck's bare numbers: si, or us (US customary units "
                       "of ASCE 7 practice, docs/deck.md)", "", "si", SYSTEMS),
    },
    "project": {
        "project": Field("string", "-", "project name, in the report's title block and running header"),
        "job_number": Field("string", "-", "job (project) number, in the title block and running header"),
        "engineer": Field("string", "-", "the engineer who prepared the calculation (title and sign-off blocks)"),
        "checker": Field("string", "-", "the engineer who checks it (title and sign-off blocks)"),
        "revision": Field("string", "-", "revision of the calculation, e.g. \"A\" or \"P01\""),
    },
    "building": {
        "stories": Field("integer", "-", "number of stories N (uniform shorthand)", "stories"),
        "floor_mass": Field("number", "kg", "mass of every floor m_j (uniform shorthand)", "positive",
                            plausible=(1e3, 1e8)),
        "masses": Field("numbers", "kg", "floor masses m_1..m_N, lowest floor first", "positive",
                        plausible=(1e3, 1e8)),
        "story_height": Field("number", "m", "height of every story (uniform shorthand)", "positive",
                              plausible=(1.5, 30.0)),
        "story_heights": Field("numbers", "m", "story heights h_j - h_(j-1), lowest story first", "positive",
                               plausible=(1.5, 30.0)),
        "story_stiffness": Field("number", "N/m", "lateral stiffness k_j of every story", "positive",
                                 plausible=(1e5, 1e12)),
        "story_stiffnesses": Field("numbers", "N/m", "story stiffnesses k_1..k_N, lowest story first",
                                   "positive", plausible=(1e5, 1e12)),
        "stiffness_matrix": Field("matrix", "N/m", "lateral stiffness matrix K of a frame (N x N, "
                                  "symmetric positive definite), instead of story stiffnesses"),
        "period": Field("number", "s", "fixed-base fundamental period T_1; alone it sets a uniform story "
                        "stiffness, with a stiffness it scales that stiffness to give T_1", "positive",
                        plausible=(0.02, 20.0)),
        "damping": Field("number-or-numbers", "-", "modal damping ratio xi_n: one value for all modes or "
                         "one per mode", "fraction", 0.05, plausible=(0.0, 0.3)),
    },
    "foundation": {
        "type": Field("string", "-", "foundation idealisation", "", "two-element", tuple(FOUNDATIONS)),
        "b": Field("number", "m", "half-width b of the rigid mat in the plane of motion", "positive",
                   plausible=(0.5, 300.0)),
        "slenderness": Field("number", "-", "h_1*/b: sets b from the first-mode effective height "
                             "(instead of b)", "positive", plausible=(0.1, 30.0)),
        "mat_mass": Field("number", "kg", "mass m_0 of the mat", "nonnegative", 0.0),
        "mat_rotary_inertia": Field("number", "kg m^2", "rotary inertia I_0 of the mat about its centre",
                                    "nonnegative", 0.0),
        **{name: field for kind in FOUNDATIONS.values() for name, field in kind.deck_fields.items()},
    },
    "ground_motion": {
        "record": Field("string", "-", "path of the accelerogram file (relative to the deck)"),
        **RECORD_FIELDS,
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
        "gravity": Field("number", "m/s^2", "acceleration of gravity g", "positive", STANDARD_GRAVITY,
                         plausible=(9.7, 9.9)),
        "check_band": Field("pair", "-", "[low, high]: a ratio simplified / exact of the accuracy check outside "
                            "it is a warning (uplift analyze with a record)", "band-around-one", [0.8, 1.25]),
        "check_band_motion": Field("pair", "-", "[low, high]: the same for the edge uplift and the mat rotation",
                                   "band-around-one", [0.5, 2.0]),
    },
    "analysis.exact": deck_fields(ExactOptions),
    "criteria": {
        **{q.name: Field("number", q.unit, f"largest allowed {q.meaning}", "positive",
                         quantity="displacement" if q.unit == "m" else "", plausible=CRITERIA_PLAUSIBLE.get(q.name))
           for q in QUANTITIES.values() if q.criterion},
        **{q.name: Field("number", q.unit, f"largest allowed {q.meaning}", "positive",
                         plausible=CRITERIA_PLAUSIBLE.get(q.name)) for q in SCALARS.values()},
        **{q.name: Field("number", q.unit, f"largest allowed {q.meaning}: the exact engine's uplift analysis of a "
                         "foundation with a bearing capacity; the limit of ASCE 41-17 section 8.4 for the chosen "
                         "performance level, as the user reads it there", "positive",
                         quantity="displacement" if q.unit == "m" else "")
           for q in ROCKING.values() if q.criterion},
        "uplift": Field("bool", "-", "whether uplift of the mat is acceptable (false: uplift fails)"),
        "simplified_error": Field("number", "-", "largest relative error e of the simplified engine in the "
                                  "accuracy check: a ratio simplified / exact outside [1/(1+e), 1+e] fails",
                                  "positive"),
    },
}
#: where each limit of [criteria] comes from, as the user states it (a standard's table and row, a
#: performance objective): reported with the limit's verdict (deck/criteria.py)
#: (one line: it is repeated in the one-line violation message)
TABLES["criteria.sources"] = {name: Field("string", "-", f"the source of the limit criteria.{name}, as the user "
                                          "states it (e.g. \"ASCE 41-17 Table 8-4, life safety, A_c/A = 0.2\")",
                                          "one-line")
                              for name in TABLES["criteria"]}

#: tables that may appear inside others (dotted name -> parent)
SUBTABLES = {"analysis.exact": "analysis", "criteria.sources": "criteria"}


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


def set_by_override(path: str, overridden) -> bool:
    """Whether the field at `path` came from a --set: the path itself or a table or array it is
    in (ground_motion.design_spectrum.sds, ground_motion.suite[1].file) was overridden."""
    return bool(overridden) and (path in overridden or any(path[:i] in overridden for i, ch in enumerate(path)
                                                           if ch in ".["))


def default(table: str, name: str) -> Any:
    """The default of the deck field table.name."""
    return TABLES[table][name].default


def exactly_one(fields: dict, names: Sequence[str], table: str, error) -> str | None:
    """The one of the alternative fields `names` of `table` that is given (None if none is); two
    given: error(path, expected) raised."""
    given = [name for name in names if name in fields]
    if len(given) > 1:
        raise error(f"{table}.{given[1]}", f"only one of {', '.join(f'{table}.{n}' for n in names)} "
                    f"(both {given[0]} and {given[1]} given)")
    return given[0] if given else None


def validate(raw: dict, source: str, overridden: frozenset[str] = frozenset()) -> dict[str, dict[str, Any]]:
    """Check every key, type, unit and range; return {table: {field: value}} with only the given
    fields, numbers in the unit each field declares (SI: a number with a unit converted, a bare
    number read in the deck's `units` system). The keys of a design spectrum and the entries of
    a suite are checked here too (design_spectra.check_keys, suites.check_entry).

    Every error is found before any is raised: one error as it is, several as one
    errors.InputErrors (one line each). Values that came from `--set` are reported with source
    "--set".
    """
    values: dict[str, dict[str, Any]] = {table: {} for table in TABLES}
    gathered: list[InputError] = []

    def error_for(path: str):  # a value that came from a --set (or inside one) names "--set"
        def error(expected: str):
            raiser("--set" if set_by_override(path, overridden) else source)(path)(expected)
        return error

    system = raw.get("units", "si") if raw.get("units", "si") in SYSTEMS else "si"

    def walk(table: str, mapping: dict) -> None:
        fields = TABLES[table]
        for key, value in mapping.items():
            path = dotted(table, key)
            if path in TABLES and SUBTABLES.get(path, "") == table:
                if isinstance(value, dict):
                    walk(path, value)
                else:
                    gather(gathered, error_for(path), f"a table [{path}], got {value!r}")
                continue
            if key not in fields:
                names = list(fields) + [name.rsplit(".", 1)[-1] for name, parent in SUBTABLES.items()
                                        if parent == table]
                if table == "":
                    names += [name for name in TABLES if name and "." not in name]
                where = f"[{table}]" if table else "the top level"
                gather(gathered, error_for(path), f"a known field of {where}{suggestion(key, names)}; unknown key "
                       f"{key!r}")
                continue
            checked = gather(gathered, check_value, fields[key], value, error_for(path), system)
            if checked is not None:
                values[table][key] = gather(gathered, _nested, path, checked, source, error_for)

    walk("", raw)
    raise_all(gathered)
    return values


def _nested(path: str, value: Any, source: str, error_for) -> Any:
    """A design spectrum's keys and a suite's entries, checked by their own fields (the values,
    converted); other values as they are."""
    if path == "ground_motion.design_spectrum":
        return check_keys(value, source, path, error_for)
    if path == "ground_motion.suite" and isinstance(value, list):
        gathered: list[InputError] = []
        entries = [item if isinstance(item, str) else gather(gathered, check_entry, item, source, f"{path}[{k}]",
                                                             error_for) for k, item in enumerate(value)]
        raise_all(gathered)
        return entries
    return value


def plausibility(values: dict[str, dict[str, Any]], source: str, overridden=frozenset()) -> list[str]:
    """One warning per validated field whose value lies outside the range of building practice
    its declaration gives (Field.plausible; the design spectrum's keys too), naming the deck
    ('(--set)' after it for a value of --set) and the field: 'inputs/a.toml: building.floor_mass:
    300 kg is far outside ...'."""
    from ..motion.spectrum_fields import SPECTRUM_FIELDS

    found = [(dotted(table, name), TABLES[table][name], value) for table, fields in values.items()
             for name, value in fields.items()]
    spectrum = values.get("ground_motion", {}).get("design_spectrum") or {}
    found += [(f"ground_motion.design_spectrum.{key}", SPECTRUM_FIELDS[key], value) for key, value in spectrum.items()
              if key in SPECTRUM_FIELDS]
    system = values[""].get("units", "si")
    warnings = []
    for path, field, value in found:
        words = implausible(field, value, system)
        if words:
            warnings.append(f"{source}{' (--set)' if set_by_override(path, overridden) else ''}: {path}: {words}")
    return warnings


def si_mapping(raw: dict, values: dict[str, dict[str, Any]]) -> dict:
    """The deck as a mapping whose numbers are all bare SI numbers: every value given with a
    unit, or under `units = "us"`, replaced by its checked SI value, and `units` dropped (the
    resolved deck, docs/provenance.md). A deck written in SI with bare numbers is `raw` itself
    (not copied: sweeps build a deck per case)."""
    changed = []
    for table, fields in values.items():
        given = raw
        for part in table.split(".") if table else []:
            given = given.get(part, {})
        for name, value in fields.items():
            value = list(value) if isinstance(value, tuple) else value
            if (TABLES[table][name].kind in NUMERIC or name in ("design_spectrum", "suite")) \
                    and given.get(name) != value:
                changed.append((table, name, value))
    if not changed and "units" not in raw:
        return raw
    result = {key: value for key, value in raw.items() if key != "units"}
    for table, name, value in changed:
        target = result
        for part in table.split(".") if table else []:
            target[part] = dict(target[part])  # copied on the way down: raw is left as it was
            target = target[part]
        target[name] = value
    return result
