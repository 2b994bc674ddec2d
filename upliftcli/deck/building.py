"""The deck's [building] and [foundation] tables -> model.building.Building and model.system.System:
the building from the uniform shorthand, per-story arrays or a stiffness matrix (scaled to
building.period), the mat half-width b (or h_1*/b), its mass and inertia, the foundation
(model/foundations.py) and its rocking stiffness checked at the fixed-base w_1. Every mistake is
error(dotted field, expected): the deck's or --set's (deck.build_deck).
"""

from __future__ import annotations

import math

import numpy as np

from ..model.bearing import CAPACITY_NAMES
from ..model.building import Building, modal_analysis, scale_to_period, shear_building
from ..model.foundations import FOUNDATIONS, DeckContext
from ..model.system import System
from ..runtime.limits import MAX_STORIES
from . import schema
from .overrides import ALTERNATIVES, FOUNDATION_FIELDS


def building_from_fields(fields: dict, error) -> Building:
    """Building from the uniform shorthand, per-story arrays or a stiffness matrix."""
    if not fields:
        raise error("building", "a [building] table")
    lengths = {name: len(fields[name]) for name in ("masses", "story_heights", "story_stiffnesses",
                                                    "stiffness_matrix") if name in fields}
    if isinstance(fields.get("damping"), list):
        lengths["damping"] = len(fields["damping"])
    n = fields.get("stories")
    for name, length in lengths.items():
        if n is None:
            n = length
        elif length != n:
            raise error(f"building.{name}", f"{n} values, one per story, got {length}")
    if n is None:
        raise error("building.stories", "the number of stories (or per-story arrays: masses, story_heights)")
    if n > MAX_STORIES:
        name = next(iter(lengths), "stories")
        raise error(f"building.{name}", f"at most {MAX_STORIES} stories (limit of the tool), got {n}")

    def per_story(scalar: str, array: str, unit: str) -> np.ndarray:
        name = schema.exactly_one(fields, [scalar, array], "building", error)
        if name is None:
            raise error(f"building.{scalar}", f"a positive number [{unit}] (missing; or give building.{array})")
        return np.full(n, fields[scalar]) if name == scalar else np.asarray(fields[array], dtype=float)

    masses = per_story("floor_mass", "masses", "kg")
    story_heights = per_story("story_height", "story_heights", "m")
    damping = fields.get("damping", schema.default("building", "damping"))
    stiffness_name = schema.exactly_one(fields, ["story_stiffness", "story_stiffnesses", "stiffness_matrix"],
                                  "building", error)
    period = fields.get("period")
    if stiffness_name is None and period is None:
        raise error("building.story_stiffness", "a story stiffness [N/m] (missing; or give building.period "
                    "[s], building.story_stiffnesses or building.stiffness_matrix)")
    if stiffness_name == "stiffness_matrix":
        matrix = np.asarray(fields["stiffness_matrix"], dtype=float)
        if not np.allclose(matrix, matrix.T, rtol=1e-9, atol=1e-12 * np.abs(matrix).max()):
            raise error("building.stiffness_matrix", "a symmetric matrix [N/m]")
        if np.linalg.eigvalsh(matrix)[0] <= 0.0:
            raise error("building.stiffness_matrix", "a positive-definite matrix [N/m]")
        heights = np.cumsum(story_heights)
        xi = np.broadcast_to(np.asarray(damping, dtype=float), masses.shape).copy()
        building = Building(masses, heights, matrix, xi, None)
    else:
        if stiffness_name == "story_stiffness":
            story_stiffness = np.full(n, fields["story_stiffness"])
        elif stiffness_name == "story_stiffnesses":
            story_stiffness = np.asarray(fields["story_stiffnesses"], dtype=float)
        else:
            story_stiffness = np.ones(n)
        building = shear_building(masses, story_heights, story_stiffness, np.asarray(damping, dtype=float))
    if period is not None:
        building = scale_to_period(building, period)
    stiffness_field = "building.period" if period is not None else f"building.{stiffness_name}"
    if not (np.all(np.isfinite(building.stiffness)) and np.all(np.isfinite(building.heights))):
        raise error(stiffness_field, "a value giving finite story stiffnesses and heights (check the magnitudes "
                    "of the [building] fields)")
    try:
        modes = modal_analysis(building)
    except (ValueError, np.linalg.LinAlgError, ArithmeticError):
        modes = None
    if modes is None or not (np.all(np.isfinite(modes.omega)) and np.all(modes.omega > 0.0)
                             and np.all(np.isfinite(modes.effective_height))
                             and modes.effective_height[0] > 0.0):
        raise error(stiffness_field, "a value giving finite positive frequencies and effective heights "
                    "(the stiffness matrix is not positive definite in double precision: check the "
                    "magnitudes of the [building] fields)")
    return building


def system_from_fields(building: Building, fields: dict, analysis: dict, error) -> System:
    """Mat half-width, mat mass and inertia, and the foundation."""
    kind = fields.get("type", schema.default("foundation", "type"))
    if kind == "halfspace":
        for name in CAPACITY_NAMES:
            if name in fields:
                raise error(f"foundation.{name}", "no bearing capacity for the half-space foundation: the "
                            "yielding-soil model (docs/theory.md section 14) is for type \"two-element\" or "
                            "\"winkler\"")
    for name in fields:
        owners = [k for k, names in FOUNDATION_FIELDS.items() if name in names]
        if owners and kind not in owners:
            raise error(f"foundation.{name}", f"no {name} for foundation type {kind!r} "
                        f"(it belongs to type {owners[0]!r})")
    modes = modal_analysis(building)
    effective_height = float(modes.effective_height[0])
    which = schema.exactly_one(fields, ["b", "slenderness"], "foundation", error)
    if which is None:
        raise error("foundation.b", "the mat half-width b > 0 [m] (missing; or give foundation.slenderness "
                    "= h_1*/b)")
    b = fields["b"] if which == "b" else effective_height / fields["slenderness"]
    if not (np.isfinite(b) and b > 0.0):
        raise error(f"foundation.{which}", f"a value giving a finite mat half-width b > 0 [m], got b = {b:g} m")
    mat_mass = fields.get("mat_mass", 0.0)
    total_mass = float(building.masses.sum() + mat_mass)
    for group_table, groups in ALTERNATIVES:
        if group_table == "foundation":
            schema.exactly_one(fields, [name for group in groups for name in group], "foundation", error)

    def missing(name: str, expected: str):
        raise error(f"foundation.{name}", expected)

    gravity = float(analysis.get("gravity", schema.default("analysis", "gravity")))
    context = DeckContext(float(b), total_mass, float(modes.omega[0]), missing, gravity)
    foundation = FOUNDATIONS[kind].from_deck(fields, context)
    system = System(building, foundation, float(b), float(mat_mass), float(fields.get("mat_rotary_inertia", 0.0)),
                    gravity)
    vars(system)["modes"] = modes  # System.modes (a cached property) of this very building: not solved twice
    _check_impedance(system, fields, which, error)
    return system


def _check_impedance(system: System, fields: dict, half_width: str, error) -> None:
    """The foundation's rocking stiffness K_theta > 0 and finite at the fixed-base w_1, the highest
    frequency the engines evaluate it at (model/interaction.py: the flexible-base w1bar <= w_1),
    where the half-space's K_theta(w) of NIST GCR 12-917-21 Table 2-3a, decreasing in w, is
    lowest: it turns negative for a mat about 2,000 times longer than wide. The error names the
    foundation field that set the shape (half_length, else b or slenderness)."""
    omega = float(system.modes.omega[0])
    try:
        rocking = system.foundation.rocking_stiffness(system.half_width, omega)
    except (ValueError, ArithmeticError):
        rocking = math.nan
    if math.isfinite(rocking) and rocking > 0.0:
        return
    name = "half_length" if "half_length" in fields else half_width
    length = getattr(system.foundation, "half_length", None)
    shape = f"{2 * system.half_width:.4g} m wide" + (f", {2 * length:.4g} m long" if length else "")
    raise error(f"foundation.{name}", f"a foundation giving a finite rocking stiffness K_theta > 0 at the fixed-base "
                f"w_1 = {omega:.4g} rad/s, got K_theta = {rocking:.4g} N m/rad (the mat is {shape}; check its "
                "dimensions and the soil)")
