"""Report sections on what went in: the deck as given and as resolved after --set, the derived
model (story stiffnesses after period scaling, mat, foundation: k_f, c_f, K_theta, C_theta, b),
the ground motion and the fixed-base modes."""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

from ..deck import schema
from ..display import file_unit, heading, label, show
from ..engines.quantities import INTERMEDIATES
from ..model.system import fixed_base_mode_rows
from ..motion.design_spectra import KEY_UNITS
from ..provenance.files import record_sha256
from ..units import STANDARD_GRAVITY
from .document import Pre, Section, Table, Text, number
from .provenance import relative_path


def _flatten(value, prefix: str):
    if isinstance(value, dict):
        for key, item in value.items():
            yield from _flatten(item, f"{prefix}.{key}" if prefix else key)
    else:
        yield prefix, value


def inputs_section(deck, deck_text: str, overrides: Sequence[str], units: str = "si") -> Section:
    """The deck file as given, the --set overrides and every validated field with its unit (in the
    display units: SI as the engines read it, or US customary, display.file_unit)."""
    blocks: list = [Pre("deck-as-given", f"The deck as given ({os.path.basename(deck.source)})", deck_text),
                    _overrides_text(overrides),
                    Table("table-resolved", "The deck as resolved: every field given (after the overrides)",
                          ["field", "value", "unit", "from", "meaning"], _resolved_rows(deck, units),
                          "Fields not listed take their defaults (docs/deck.md).")]
    return Section("inputs", "Inputs", blocks)


def _overrides_text(overrides: Sequence[str]) -> Text:
    if overrides:
        return Text(["Overrides given on the command line (--set, --engine, --support), applied before "
                     "validation:"], [str(o) for o in overrides])
    return Text(["No overrides (--set, --engine, --support) were given."])


def _resolved_rows(deck, units: str = "si") -> list[list[str]]:
    """A row per field of the deck (a table field: per key): field, value, unit, from, meaning."""
    return [row for table, fields in deck.values.items() for name, value in fields.items()
            for row in _field_rows(deck, table, name, value, units)]


def _field_rows(deck, table: str, name: str, value, units: str) -> list[list[str]]:
    """The rows of one field; a table field (the design spectrum's) a row per key, with the key's unit."""
    declared = schema.TABLES.get(table, {}).get(name)
    path = f"{table}.{name}" if table else name
    return [[key, *_shown(item, file_unit(_field_unit(declared, key, path), _display_kind(declared), units)),
             _given(deck, key, path), declared.doc if declared and key == path else ""]
            for key, item in _flatten(value, path)]


def _display_kind(declared) -> str:
    """A field's display kind: 'mm' for a displacement (in under US units), else its SI unit's ('')."""
    return "mm" if declared is not None and declared.quantity_kind == "displacement" else ""


def _shown(value, unit) -> list[str]:
    """(value, unit label) of a resolved field in a display.file_unit (numbers converted; lists each)."""
    if unit.factor == 1.0 or isinstance(value, (bool, str)) or value is None:
        return [number(value), unit.label]
    if isinstance(value, (list, tuple)):
        return [", ".join(_shown(v, unit)[0] for v in value), unit.label]
    return [number(float(value) * unit.factor), unit.label]


def _field_unit(declared, key: str, path: str) -> str:
    """The unit of a field (schema.TABLES) or of a key of a table field (design_spectra.KEY_UNITS)."""
    if key != path:  # a key of a table field (the design spectrum's)
        return KEY_UNITS.get(key.rsplit(".", 1)[-1], "")
    return declared.unit if declared else ""


def _given(deck, key: str, path: str) -> str:
    """Where a field's value comes from: "--set" or "deck"."""
    return "--set" if key in deck.overridden or path in deck.overridden else "deck"


def _foundation_meanings(entry: dict) -> dict[str, str]:
    """The meaning of each foundation parameter that is not a deck field."""
    return {"vertical_stiffness": "vertical stiffness of the foundation at omega_impedance",
            "vertical_damping": "vertical damping of the foundation at omega_impedance",
            "shear_wave_velocity": "V_s = sqrt(G / rho)",
            **{name: INTERMEDIATES[name][1] for name in INTERMEDIATES if name in entry}}


def _foundation_rows(system, units: str = "si") -> list[list[str]]:
    """The foundation as the engines use it (provenance_model.foundation_entry): its own parameters,
    K_theta, C_theta, k_v, c_v and the contact elements at the frequency omega_impedance every
    engine evaluates them at (model/interaction.py), in the display units."""
    from ..provenance.model import MODEL_UNITS, foundation_entry, foundation_units

    entry = foundation_entry(system)
    si_units = {**foundation_units(system), **MODEL_UNITS}
    fields = type(system.foundation).deck_fields
    meanings = _foundation_meanings(entry)
    rows = [["foundation type", str(entry.pop("type")), "-", ""]]
    for name, value in entry.items():
        meaning = fields[name].doc if name in fields else meanings.get(name, "")
        rows.append([name, *_parameter_cells(value, si_units.get(name, "-"), units), meaning])
    rows.append(_contact_row(system, units))
    return rows


def _parameter_cells(value, kind: str, units: str) -> list[str]:
    """(value, unit) of a foundation parameter in the display units (a word as it is)."""
    return [show(value, kind, units) if not isinstance(value, str) else value, label(kind, units)]


def _stated(value: float, kind: str, units: str) -> str:
    """A value with its unit, in the display units."""
    return f"{show(value, kind, units)} {label(kind, units)}"


def _contact_row(system, units: str) -> list[str]:
    """The contact elements of the exact engine: count, positions, stiffness and damping of each."""
    from ..model.interaction import impedance

    elements = system.foundation.contact_elements(system.half_width, impedance(system)["omega_impedance"])
    first = "" if np.ptp(elements.stiffness) == 0 else " (first element)"
    where = f"{_stated(elements.positions.min(), 'm', units)} .. {_stated(elements.positions.max(), 'm', units)}"
    each = f"k_i = {_stated(elements.stiffness[0], 'N/m', units)}, c_i = {_stated(elements.damping[0], 'N s/m', units)}"
    return ["contact elements", str(elements.count), "-", f"at x = {where}, {each} each{first} (exact engine)"]


def model_section(deck, results: Sequence = (), units: str = "si") -> Section:
    """The derived model: per story (elevation, mass, stiffness after the period scaling),
    the whole system (m_t, b, h_1*, V_c, M_c ...) and the foundation (k_f, c_f, K_theta, C_theta),
    in the display units."""
    system = deck.system
    rows = [[name, show(value, kind, units), label(kind, units), meaning]
            for name, value, kind, meaning in _system_scalars(system) + _engine_scalars(results)]
    return Section("model", "Derived model", [
        Table("table-building", "Building: floors and stories (story j joins floor j-1 and floor j)",
              ["story", heading("elevation h_j", "m", units), heading("story height", "m", units),
               heading("floor mass m_j", "kg", units), heading("story stiffness k_j", "N/m", units)],
              _story_rows(system.building, units), _stiffness_note(deck)),
        Table("table-system", "The system: mat, totals and critical values", ["quantity", "value", "unit", "meaning"],
              rows),
        Table("table-foundation", "Foundation", ["quantity", "value", "unit", "meaning"],
              _foundation_rows(system, units)),
    ])


def _story_rows(building, units: str) -> list[list[str]]:
    """Per story: elevation, story height, floor mass and story stiffness ("-" without one)."""
    stiffness = building.story_stiffness
    return [[str(j + 1), show(building.heights[j], "m", units), show(building.story_heights[j], "m", units),
             show(building.masses[j], "kg", units), show(stiffness[j], "N/m", units) if stiffness is not None else "-"]
            for j in range(building.n_stories)]


def _stiffness_note(deck) -> str:
    """Where the story stiffnesses come from."""
    if deck.system.building.story_stiffness is None:
        return "A stiffness matrix was given (no story stiffnesses)."
    if "period" in deck.values.get("building", {}):
        return "Story stiffnesses after scaling to building.period."
    return "Story stiffnesses as given."


def _system_scalars(system) -> list[list]:
    """[name, SI value, SI unit, meaning] of the system's totals and critical values."""
    building = system.building
    h1 = system.effective_height
    return [
        ["m_t", system.total_mass, "kg", "total mass (floors and mat)"],
        ["m_0", system.mat_mass, "kg", "mat mass"],
        ["I_0", system.mat_rotary_inertia, "kg m^2", "mat rotary inertia about its centre"],
        ["I_b", float(np.sum(building.masses * building.heights**2)) + system.mat_rotary_inertia, "kg m^2",
         "rotary inertia about the mat, sum m_j h_j^2 + I_0"],
        ["L_0", system.first_moment, "kg m", "sum m_j h_j"],
        ["b", system.half_width, "m", "mat half-width"],
        ["h_1*", h1, "m", "first-mode effective height [9]"],
        ["h_1*/b", h1 / system.half_width, "-", "slenderness"],
        ["T_1", system.modes.periods[0], "s", "fixed-base fundamental period"],
        ["V_c", system.critical_base_shear, "N", "critical base shear m_t g b / h_1* [16a]"],
        ["M_c", system.critical_base_moment, "N m", "critical base moment m_t g b [16b]"],
        ["g", system.gravity, "m/s^2", "gravity"],
    ]


#: the foundation's intermediates of the engines listed with the system (the first engine's that gives each)
ENGINE_SCALARS = ("K_theta", "C_theta", "T1bar", "xi1bar", "xi_f")


def _engine_scalars(results: Sequence) -> list[list]:
    """[name, SI value, SI unit, meaning] of ENGINE_SCALARS, each from the first result that gives it."""
    found: dict[str, list] = {}
    for result in results:
        for name in ENGINE_SCALARS:
            if name in result.intermediates and name not in found:
                found[name] = [name, result.intermediates[name], INTERMEDIATES[name][0],
                               f"{INTERMEDIATES[name][1]}, as used by the {result.engine} engine"]
    return list(found.values())


def motion_section(deck) -> Section:
    """The ground motion: a record (file, SHA-256, dt, duration, PGA), a suite (each record, its
    factor, the target) or a design spectrum."""
    from ..motion.records import Record
    from ..motion.suites import Suite

    motion = deck.ground_motion
    folder = os.path.dirname(os.path.abspath(deck.source))
    if isinstance(motion, Record):
        blocks = [Table("table-motion", "Ground motion record", MOTION_HEADERS, _record_rows(motion, folder))]
    elif isinstance(motion, Suite):
        blocks = _suite_blocks(motion, folder)
    elif motion is None:
        blocks = [Text(["No ground motion was loaded."])]
    else:
        blocks = [Table("table-motion", "Design spectrum", MOTION_HEADERS, _design_rows(deck, motion))]
    return Section("motion", "Ground motion", blocks)


MOTION_HEADERS = ["quantity", "value", "unit"]


def _record_rows(motion, folder: str) -> list[list[str]]:
    """A record: name, file, SHA-256, units, scale, time step, points, duration, PGA."""
    g = STANDARD_GRAVITY
    return [["record", motion.name, ""], ["file", relative_path(motion.source, folder), ""],
            ["SHA-256", record_sha256(motion) or "-", ""],
            ["units of the file", motion.units, ""], ["scale factor", number(motion.scale), "-"],
            ["time step dt", number(motion.dt), "s"], ["points", str(motion.npts), "-"],
            ["duration", number(motion.duration), "s"], ["PGA", number(motion.pga / g, 4), "g"]]


def _suite_blocks(motion, folder: str) -> list:
    """A suite in words (target, period range, scaling, design value, warnings) and its records."""
    g = STANDARD_GRAVITY
    rows = [[str(k + 1), record.name, relative_path(record.source, folder), number(factor, 4),
             number(record.pga * factor / g, 4), record_sha256(record) or "-"]
            for k, (record, factor) in enumerate(zip(motion.records, motion.factors, strict=True))]
    text = Text([f"Suite of {motion.count} records, target {motion.target.name}, period range "
                 f"{number(motion.period_range[0], 4)}-{number(motion.period_range[1], 4)} s, scaling "
                 f"\"{motion.scaling}\", design value: the {motion.statistic} ({motion.rule.label})."],
                list(motion.warnings))
    return [text, Table("table-motion", "Records of the suite", ["record", "name", "file", "factor [-]",
                                                                 "scaled PGA [g]", "SHA-256"], rows)]


def _design_rows(deck, motion) -> list[list[str]]:
    """A design spectrum: its name and S_a at the building's T_1 and xi_1."""
    g = STANDARD_GRAVITY
    xi = float(deck.system.building.damping[0])
    t1 = float(deck.system.modes.periods[0])
    return [["design spectrum", motion.name, ""], ["S_a(T_1, xi_1)", number(float(motion.sa([t1], xi)[0]) / g, 4), "g"],
            ["T_1", number(t1), "s"], ["xi_1", number(xi, 3), "-"]]


def _mode_row(row: dict, units: str) -> list[str]:
    return [str(row["mode"]), number(row["period"]), number(row["frequency_ratio"], 4),
            number(row["effective_mass_ratio"], 4), number(row["cumulative_mass_ratio"], 4),
            show(row["effective_height"], "m", units), number(row["effective_height_over_b"], 4),
            number(row["damping"], 3)]


def modes_section(deck, units: str = "si") -> Section:
    """Fixed-base modes: T_n, w_n/w_1, m_n*/m_t (and cumulative), h_n*, h_n*/b [6, 9]."""
    system = deck.system
    m_t = system.total_mass
    rows = [_mode_row(row, units) for row in fixed_base_mode_rows(system)]
    note = "" if system.mat_mass == 0 else (f"m_t includes the mat mass m_0: the m_n* add up to the building mass, "
                                            f"{1 - system.mat_mass / m_t:.4f} m_t.")
    return Section("modes", "Fixed-base modes", [Table(
        "table-modes", "Fixed-base modes [6, 9]", ["mode", "T_n [s]", "w_n/w_1 [-]", "m_n*/m_t [-]", "cumulative [-]",
                                                   heading("h_n*", "m", units), "h_n*/b [-]", "damping xi_n [-]"],
        rows, note)])
