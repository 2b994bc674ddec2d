"""What a sweep's deck gives its figures: the deck's own value of the varied field (marked as a
line) and its ground motion (named in the titles). Pure functions of the plan (sweep/plan.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError
from ..figures.spec import Line
from .plan import SweepPlan
from .values import deck_field

NOMINAL_COLOR = "#666666"


def nominal_value(plan: SweepPlan, path: str, to_si: float = 1.0) -> float | None:
    """The deck's own value of a field (after --set) in SI: as the deck gives it (a bare number
    times `to_si`, the factor from the deck's units), else derived from its model
    (building.period: T_1; foundation.b, slenderness; the two-element k_f, c_f, frequency_ratio,
    damping_ratio), else the field's default; None if unknown or not a number."""
    value = _given_value(plan, path)
    if is_number(value):
        return float(value) * to_si
    if value is None:
        try:
            system = plan.base_deck.system
        except InputError:
            return None
        value = _derived(system, path)
    if value is None:
        value = _default_value(path)
    return float(value) if is_number(value) else None


def is_number(value) -> bool:
    """An int or a float, not a bool."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _given_value(plan: SweepPlan, path: str):
    """The value the deck (after --set) gives a dotted path, or None."""
    from ..deck.overrides import apply_overrides

    value, _ = apply_overrides(plan.raw, plan.base_overrides)
    for part in path.split("."):
        value = value.get(part) if isinstance(value, dict) else None
    return value


def _default_value(path: str):
    """The declared default of a deck field, or None."""
    found = deck_field(path)
    return found.default if found else None


def _derived(system, path: str) -> float | None:
    values = {
        "building.period": float(system.modes.periods[0]),
        "foundation.b": system.half_width,
        "foundation.slenderness": system.effective_height / system.half_width,
        **_two_element_values(system),
    }
    return values.get(path)


def _two_element_values(system) -> dict[str, float]:
    """k_f, c_f, frequency_ratio and damping_ratio of a two-element foundation (none otherwise)."""
    foundation = system.foundation
    if getattr(foundation, "kind", "") != "two-element":
        return {}
    omega_1 = float(system.modes.omega[0])
    m_t = system.total_mass
    k_f, c_f = getattr(foundation, "stiffness", None), getattr(foundation, "damping", None)
    omega_v = np.sqrt(2.0 * k_f / m_t)
    return {"foundation.k_f": k_f, "foundation.c_f": c_f, "foundation.frequency_ratio": omega_v / omega_1,
            "foundation.damping_ratio": c_f / (m_t * omega_v)}


def nominal_line(value: float | None, name: str, unit: str = "") -> list[Line]:
    """A vertical dotted line at the deck's value of the varied field (none if unknown)."""
    if value is None:
        return []
    unit = f" {unit}" if unit and unit != "-" else ""
    return [Line(value, f"deck: {name} = {value:.4g}{unit}", "x", ":", NOMINAL_COLOR)]


def motion_label(raw: dict, source: str) -> str:
    """The ground motion of a deck, for figure titles: 'record <file stem>', 'design spectrum
    <name>' or 'suite <folder>, target <name>' (raw: the parsed deck after --set)."""
    motion = raw.get("ground_motion", {})
    if not isinstance(motion, dict):
        return ""
    if "record" in motion:
        return f"record {Path(str(motion['record'])).stem}"
    if "design_spectrum" not in motion:
        return ""
    name = _spectrum_name(motion["design_spectrum"], source)
    if "suite" in motion:
        return f"suite {_suite_name(motion['suite'])}, target {name}"
    return f"design spectrum {name}"


def _spectrum_name(spectrum, source: str) -> str:
    """The name of a deck's design spectrum; its type if it is not valid."""
    from ..motion.design_spectra import from_mapping

    try:
        return from_mapping(spectrum, source, "ground_motion.design_spectrum").name
    except InputError:
        return str(spectrum.get("type", "")) if isinstance(spectrum, dict) else ""


def _suite_name(suite) -> str:
    """A suite's folder name, or 'of N records' for a list of records."""
    return Path(suite).name if isinstance(suite, str) else f"of {len(suite)} records"


def plan_motion_label(plan: SweepPlan) -> str:
    """motion_label of the plan's deck after its --set overrides."""
    from ..deck.overrides import apply_overrides

    return motion_label(apply_overrides(plan.raw, plan.base_overrides)[0], plan.source)
