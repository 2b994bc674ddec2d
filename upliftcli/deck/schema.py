"""The deck schema: every table and field of an `uplift` deck, with its unit, default and check.

The fields of each foundation type come from its class (model/foundations.py), the engine
options from engines/options.py, the engine and support names from engines/registry.py and
the record formats from motion/records.py. docs/deck.md documents the same fields (a test
keeps the two in step). Validation here is purely about types and ranges of single fields
(and exactly_one: at most one of a table's alternative fields); how fields combine is decided
in deck/load.py, deck/building.py and deck/motion.py.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from dataclasses import field as dc_field
from functools import partial
from typing import Any, NoReturn

from ..engines.options import ExactOptions, SimplifiedOptions, deck_fields
from ..engines.quantities import QUANTITIES, ROCKING, SCALARS
from ..engines.registry import ENGINES, SUPPORTS
from ..errors import InputError, gather, raise_all
from ..model.design import DESIGN_FIELDS
from ..model.foundations import FOUNDATIONS
from ..motion.code_rules import RULES, SCALINGS
from ..motion.records import RECORD_FIELDS
from ..motion.suite_files import check_entry
from ..units import STANDARD_GRAVITY, SYSTEMS
from .fields import NUMERIC, Field, check_value, suggestion

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
        "story_strengths": Field("numbers", "N", "story yield strengths V_y1..V_yN (story shear at yield), lowest "
                                 "story first: the stories yield (bilinear, docs/theory.md section 15)", "positive"),
        "strength_coefficient": Field("number", "-", "base-shear strength over the building's weight, distributed "
                                      "over the height as ASCE 7-22 12.8.3 (instead of story_strengths)",
                                      "positive"),
        "hardening_ratio": Field("number", "-", "post-yield over elastic story stiffness alpha of the yielding "
                                 "stories (with a strength; default 0: elastic-perfectly plastic)", "fraction"),
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
    "design": DESIGN_FIELDS,  # ASCE 7-22 R, Cd, Omega0, Ie, risk category, Table 12.12-1 row: model/design.py
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
                                  "accuracy check: its band becomes [1/(1+e), 1+e] (the motion band widened to hold "
                                  "it) and a ratio it flags fails",
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
        field = TABLES.get(".".join(parts[:depth]), {}).get(parts[depth])
        if field is not None:
            return depth == len(parts) - 1 or field.kind == "table"
    return False


def all_paths() -> list[str]:
    return [dotted(table, name) for table, fields in TABLES.items() for name in fields]


def set_by_override(path: str, overridden) -> bool:
    """Whether the field at `path` came from a --set: the path itself or a table or array it is
    in (ground_motion.design_spectrum.sds, ground_motion.suite[1].file) was overridden."""
    if not overridden:
        return False
    return any(container in overridden for container in _containers(path))


def _containers(path: str) -> list[str]:
    """The path and the tables and arrays it lies in: 'a.b[1].c' -> a.b[1].c, a, a.b, a.b[1]."""
    return [path, *(path[:i] for i, ch in enumerate(path) if ch in ".[")]


@dataclass(frozen=True)
class FieldErrors:
    """The errors of the deck `source`'s fields: each names "--set" for a value that came from an
    override (or lies inside one, set_by_override), else the deck."""

    source: str
    overridden: frozenset[str] = frozenset()

    def __call__(self, path: str, expected: str) -> InputError:
        """The InputError of the field at `path` (to raise)."""
        return InputError("--set" if set_by_override(path, self.overridden) else self.source, path, expected)

    def raise_at(self, path: str, expected: str) -> NoReturn:
        """Raise the InputError of the field at `path`."""
        raise self(path, expected)

    def raiser(self, path: str) -> Callable[[str], NoReturn]:
        """error(expected) that raises the field's InputError (the error_for of fields.check_mapping)."""
        return partial(self.raise_at, path)


def default(table: str, name: str) -> Any:
    """The default of the deck field table.name."""
    return TABLES[table][name].default


def exactly_one(fields: dict, names: Sequence[str], table: str, error) -> str | None:
    """The one of the alternative fields `names` of `table` that is given (None if none is); two
    given: error(path, expected) raised."""
    given = [name for name in names if name in fields]
    if len(given) > 1:
        raise error(f"{table}.{given[1]}", f"only one of {_listed(table, names)} (both {given[0]} and {given[1]} "
                    "given)")
    return next(iter(given), None)


def _listed(table: str, names: Sequence[str]) -> str:
    return ", ".join(f"{table}.{name}" for name in names)  # 'table.a, table.b'


# ----------------------------------------------------------------------------- validation

def validate(raw: dict, source: str, overridden: frozenset[str] = frozenset(),
             gathered: list[InputError] | None = None) -> dict[str, dict[str, Any]]:
    """Check every key, type, unit and range; return {table: {field: value}} with only the given
    fields, numbers in the unit each field declares (SI: a number with a unit converted, a bare
    number read in the deck's `units` system). The keys of a design spectrum and the entries of
    a suite are checked here too (design_spectra.check_keys, suites.check_entry).

    Every error is found before any is raised: one error as it is, several as one
    errors.InputErrors (one line each). Values that came from `--set` are reported with source
    "--set". With a list `gathered`, the errors are appended to it instead, and the values of the
    fields that passed returned (deck/load.build_deck goes on with the checks they allow).
    """
    walk = _Validation(source, unit_system(raw), FieldErrors(source, overridden).raiser)
    walk.table("", raw)
    if gathered is None:
        raise_all(walk.gathered)
    else:
        gathered.extend(walk.gathered)
    return walk.values


def unit_system(raw: dict) -> str:
    """The deck's unit system, `units` (an unknown one is reported by its field: read as SI meanwhile)."""
    system = raw.get("units", "si")
    return system if system in SYSTEMS else "si"


def _no_values() -> dict[str, dict[str, Any]]:
    return {table: {} for table in TABLES}  # {table: {}} for every table of the deck


@dataclass
class _Validation:
    """One pass of `validate` over a deck: the checked values {table: {field: value}} and the
    errors gathered. error_for(path) -> error(expected) naming the deck or "--set"."""

    source: str
    system: str
    error_for: Callable[[str], Callable[[str], NoReturn]]
    values: dict[str, dict[str, Any]] = dc_field(default_factory=_no_values)
    gathered: list[InputError] = dc_field(default_factory=list)

    def table(self, table: str, mapping: dict) -> None:
        """Every key of the table `table` (a subtable in turn)."""
        for key, value in mapping.items():
            self.entry(table, key, value)

    def entry(self, table: str, key: str, value: Any) -> None:
        """One key of `table`: a subtable, an unknown key or a field."""
        path = dotted(table, key)
        if _is_subtable(path, table):
            self.subtable(path, value)
        elif key not in TABLES[table]:
            self.unknown(table, key, path)
        else:
            self.field(table, key, value)

    def subtable(self, path: str, value: Any) -> None:
        """A table inside a table (its keys in turn), else an error."""
        if isinstance(value, dict):
            self.table(path, value)
        else:
            gather(self.gathered, self.error_for(path), f"a table [{path}], got {value!r}")

    def unknown(self, table: str, key: str, path: str) -> None:
        """An unknown key: the closest known name suggested."""
        where = f"[{table}]" if table else "the top level"
        gather(self.gathered, self.error_for(path), f"a known field of {where}{suggestion(key, _known_names(table))}; "
               f"unknown key {key!r}")

    def field(self, table: str, key: str, value: Any) -> None:
        """The value checked (check_value) and, inside it, a design spectrum's keys or a suite's entries."""
        path = dotted(table, key)
        checked = gather(self.gathered, check_value, TABLES[table][key], value, self.error_for(path), self.system)
        if checked is not None:
            self.values[table][key] = gather(self.gathered, _nested, path, checked, self.source, self.error_for)


def _is_subtable(path: str, table: str) -> bool:
    """Whether `path` names a table inside `table` (a top-level table inside the top level "")."""
    return path in TABLES and SUBTABLES.get(path, "") == table


def _known_names(table: str) -> list[str]:
    """The names a key of `table` may take (its fields, its subtables; at the top level, the tables)."""
    names = list(TABLES[table]) + [name.rsplit(".", 1)[-1] for name, parent in SUBTABLES.items() if parent == table]
    return names + _top_tables() if table == "" else names


def _top_tables() -> list[str]:
    """The tables of the top level ([building], [foundation] ...)."""
    return [name for name in TABLES if name and "." not in name]


def _nested(path: str, value: Any, source: str, error_for) -> Any:
    """A design spectrum's keys and a suite's entries, checked by their own fields (the values,
    converted); other values as they are."""
    if path == "ground_motion.design_spectrum":
        from ..motion.design_spectra import check_keys  # the code spectra: only for a deck that has one

        return check_keys(value, source, path, error_for)
    if path == "ground_motion.suite" and isinstance(value, list):
        return _suite_entries(path, value, source, error_for)
    return value


def _suite_entries(path: str, value: list, source: str, error_for) -> list:
    """The entries of a suite: a path as it is, a table checked (suites.check_entry); every error gathered."""
    gathered: list[InputError] = []
    entries = [item if isinstance(item, str) else gather(gathered, check_entry, item, source, f"{path}[{k}]",
                                                         error_for) for k, item in enumerate(value)]
    raise_all(gathered)
    return entries


# ----------------------------------------------------------------------------- the resolved deck

def si_mapping(raw: dict, values: dict[str, dict[str, Any]]) -> dict:
    """The deck as a mapping whose numbers are all bare SI numbers: every value given with a
    unit, or under `units = "us"`, replaced by its checked SI value, and `units` dropped (the
    resolved deck, docs/provenance.md). A deck written in SI with bare numbers is `raw` itself
    (not copied: sweeps build a deck per case)."""
    changed = _all_changed(raw, values)
    if not changed and "units" not in raw:
        return raw
    return _resolved(raw, changed)


def _all_changed(raw: dict, values: dict[str, dict[str, Any]]) -> list[tuple[str, str, Any]]:
    """(table, name, checked value) of every field to replace, table by table."""
    return [item for table, fields in values.items() for item in _changed(table, fields, _given(raw, table))]


def _resolved(raw: dict, changed: list[tuple[str, str, Any]]) -> dict:
    """A copy of `raw` without `units`, with the changed values (the tables on their way copied)."""
    result = {key: value for key, value in raw.items() if key != "units"}
    for table, name, value in changed:
        _copied_table(result, table)[name] = value
    return result


def _changed(table: str, fields: dict[str, Any], given: dict) -> list[tuple[str, str, Any]]:
    """(table, name, checked value) of the numeric fields (and the design spectrum and suite) whose
    checked value differs from the one given."""
    changed = []
    for name, value in fields.items():
        value = list(value) if isinstance(value, tuple) else value
        if _resolved_field(table, name) and given.get(name) != value:
            changed.append((table, name, value))
    return changed


def _resolved_field(table: str, name: str) -> bool:
    """Whether the resolved deck carries the checked value of the field (numbers, the design spectrum, the suite)."""
    return TABLES[table][name].kind in NUMERIC or name in ("design_spectrum", "suite")


def _parts(table: str) -> list[str]:
    """The names on the way down to a (dotted) table; none for the top level."""
    return table.split(".") if table else []


def _given(raw: dict, table: str) -> dict:
    """The table as the deck gives it ({} if it does not)."""
    given = raw
    for part in _parts(table):
        given = given.get(part, {})
    return given


def _copied_table(result: dict, table: str) -> dict:
    """The table in `result`, copied on the way down (raw is left as it was)."""
    target = result
    for part in _parts(table):
        target[part] = dict(target[part])
        target = target[part]
    return target
