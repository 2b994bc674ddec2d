"""The model and options entries of a provenance record (provenance/record.py): what the engines
analyse, derived from the deck (story stiffnesses after the period scaling, the modes, m_t,
h_1*, b, V_c and M_c [16a, 16b], the foundation's own parameters, its K_theta and C_theta at the
frequency the engines use, T1bar and xi1bar [21-25]), with their SI units; the design spectrum;
the engines, supports and every engine option. docs/provenance.md describes the keys.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from .values import plain

#: the foundation's dataclass attributes under their deck names (foundation.<name>)
FOUNDATION_NAMES = {"two-element": {"stiffness": "k_f", "damping": "c_f", "capacity": "element_capacity"},
                    "winkler": {"stiffness": "k_w", "damping": "c_w", "elements": "elements",
                                "capacity": "line_capacity"}}
#: units of the derived model's entries
MODEL_UNITS = {
    "masses": "kg", "elevations": "m", "story_heights": "m", "story_stiffnesses": "N/m", "stiffness_matrix": "N/m",
    "damping": "-", "periods": "s", "effective_masses": "kg", "effective_heights": "m", "total_mass": "kg",
    "mat_mass": "kg", "mat_rotary_inertia": "kg m^2", "half_width": "m", "h1_star": "m", "slenderness": "-",
    "gravity": "m/s^2", "weight": "N", "critical_base_shear": "N", "critical_base_moment": "N m",
    "T1bar": "s", "xi1bar": "-", "K_theta": "N m/rad", "C_theta": "N m s/rad", "omega_impedance": "rad/s",
    "k_element": "N/m", "c_element": "N s/m", "vertical_stiffness": "N/m", "vertical_damping": "N s/m",
    "Q_y": "N", "FS_v": "-",
}


def _own_parameters(foundation) -> dict[str, Any]:
    """The foundation's dataclass attributes that are set, under their deck names (FOUNDATION_NAMES);
    no bearing capacity: not an entry."""
    names = FOUNDATION_NAMES.get(foundation.kind, {})
    return {names.get(item.name, item.name): getattr(foundation, item.name)
            for item in dataclasses.fields(foundation) if getattr(foundation, item.name) is not None}


def _capacity_entry(system) -> dict[str, Any]:
    """Each contact element's Q_y [N] and the factor of safety FS_v [-] of a foundation with a
    bearing capacity (docs/theory.md 14); {} without one."""
    foundation = system.foundation
    if getattr(foundation, "capacity", None) is None:
        return {}
    return {"Q_y": plain(foundation.contact_elements(system.half_width).capacity),
            "FS_v": foundation.total_capacity(system.half_width) / system.weight}


def foundation_entry(system) -> dict[str, Any]:
    """The foundation's type and own parameters under their deck names (SI), its rocking
    stiffness K_theta [N m/rad] and damping C_theta [N m s/rad] at the frequency omega_impedance
    [rad/s] every engine uses (model/interaction.py), the equivalent edge elements and the
    vertical stiffness [N/m] and damping [N s/m] at that frequency."""
    from ..model.interaction import impedance

    foundation = system.foundation
    entry = {"type": foundation.kind, **plain(_own_parameters(foundation)), **_capacity_entry(system)}
    if hasattr(foundation, "shear_wave_velocity"):
        entry["shear_wave_velocity"] = float(foundation.shear_wave_velocity)
    rocking = impedance(system)
    omega = rocking["omega_impedance"]
    b = system.half_width
    return {**entry, **rocking, "vertical_stiffness": float(foundation.vertical_stiffness(b, omega)),
            "vertical_damping": float(foundation.vertical_damping(b, omega))}


def foundation_units(system) -> dict[str, str]:
    """Units of the foundation's own parameters (from its deck fields)."""
    fields = type(system.foundation).deck_fields
    units = {name: fields[name].unit for name in _own_parameters(system.foundation) if name in fields}
    if "shear_wave_velocity" in fields:
        units["shear_wave_velocity"] = "m/s"
    return units


def _building_entry(building, modes) -> dict[str, Any]:
    """Floors, story stiffnesses after the period scaling (a frame: its stiffness matrix), modal
    damping and the fixed-base modes (T_n, m_n*, h_n*)."""
    stiffness = ({"story_stiffnesses": plain(building.story_stiffness)} if building.story_stiffness is not None
                 else {"stiffness_matrix": plain(building.stiffness)})
    return {"stories": building.n_stories, "masses": plain(building.masses), "elevations": plain(building.heights),
            "story_heights": plain(building.story_heights), **stiffness,
            "damping": plain(building.damping), "periods": plain(modes.periods),
            "effective_masses": plain(modes.effective_mass), "effective_heights": plain(modes.effective_height)}


def _bonded_entry(system, effective_properties: str) -> dict[str, Any]:
    """T1bar [s] and xi1bar [-] of the bonded system [21-25]; {} for an overdamped one, which has
    no T1bar (the engines say so)."""
    from ..errors import AnalysisError
    from ..model.interaction import effective_properties as properties

    try:
        bonded = properties(system, effective_properties)
    except AnalysisError:
        return {}
    return {"T1bar": float(bonded["T1bar"]), "xi1bar": float(bonded["xi1bar"])}


def _units_of(entries: dict[str, Any]) -> dict[str, str]:
    """The units (MODEL_UNITS) of the entries that have one."""
    return {name: unit for name, unit in MODEL_UNITS.items() if name in entries}


def derived_model(system, effective_properties: str = "formula") -> dict[str, Any]:
    """What the engines analyse, derived from the deck (SI, see MODEL_UNITS and
    "foundation_units"): floors, story stiffnesses after the period scaling (a frame: its
    stiffness matrix), modal damping, the fixed-base modes (T_n, m_n*, h_n*), m_t, h_1*, b,
    h_1*/b, V_c, M_c [16a, 16b], the foundation (foundation_entry) and T1bar, xi1bar of the
    bonded system [21-25] by the deck's analysis.effective_properties."""
    model: dict[str, Any] = {
        **_building_entry(system.building, system.modes),
        "total_mass": system.total_mass, "mat_mass": system.mat_mass, "mat_rotary_inertia": system.mat_rotary_inertia,
        "half_width": system.half_width, "h1_star": system.effective_height,
        "slenderness": system.effective_height / system.half_width, "gravity": system.gravity, "weight": system.weight,
        "critical_base_shear": system.critical_base_shear, "critical_base_moment": system.critical_base_moment,
        "foundation": foundation_entry(system), **_bonded_entry(system, effective_properties),
    }
    model["units"] = {**_units_of(model), "foundation": {**foundation_units(system), **_units_of(model["foundation"])}}
    return model


def spectrum_entry(spectrum) -> dict[str, Any] | None:
    """A design spectrum's name and, for a table, its damping [-], the damping correction used
    for other dampings and its period range [s] (None for a record's own spectrum)."""
    if spectrum is None or hasattr(spectrum, "record"):
        return None
    entry: dict[str, Any] = {"name": getattr(spectrum, "name", type(spectrum).__name__)}
    for name in ("damping", "damping_correction", "units", "period_range"):
        if hasattr(spectrum, name):
            entry[name] = plain(getattr(spectrum, name))
    return entry


def _option_units(options, given: dict[str, Any]) -> dict[str, str]:
    """The units of the options given (from their deck fields: engines/options.py)."""
    from ..engines.options import deck_fields

    return {name: field.unit for name, field in deck_fields(type(options)).items() if name in given}


def engine_options(analysis) -> dict[str, Any]:
    """The engines and supports of a deck and every option of the simplified and the
    response-history engines (engines/options.py), with the units of the options (their deck fields)."""
    simplified = dataclasses.asdict(analysis.simplified)
    exact = {k: v for k, v in dataclasses.asdict(analysis.exact).items() if k != "histories"}
    units = {"simplified": _option_units(analysis.simplified, simplified),
             "exact": _option_units(analysis.exact, exact)}
    return {"engines": list(analysis.engines), "supports": list(analysis.supports), "n_modes": analysis.n_modes,
            "simplified": plain(simplified), "exact": plain(exact), "units": units}
