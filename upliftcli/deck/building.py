"""The deck's [building] and [foundation] tables -> model.building.Building and model.system.System:
the building from the uniform shorthand, per-story arrays or a stiffness matrix (scaled to
building.period), the mat half-width b (or h_1*/b), its mass and inertia, the foundation
(model/foundations.py) and its rocking stiffness checked at the fixed-base w_1. Every mistake is
error(dotted field, expected): the deck's or --set's (deck.build_deck).
"""

from __future__ import annotations

import math
from itertools import chain

import numpy as np

from ..errors import gather, raise_all
from ..model.bearing import CAPACITY_NAMES
from ..model.building import Building, Modes, modal_analysis, scale_to_period, shear_building
from ..model.foundations import FOUNDATIONS, DeckContext
from ..model.system import System
from ..runtime.limits import MAX_STORIES
from . import schema
from .overrides import ALTERNATIVES, FOUNDATION_FIELDS

#: the per-story arrays of [building] whose lengths give the number of stories (damping too, when an array)
PER_STORY_ARRAYS = ("masses", "story_heights", "story_stiffnesses", "stiffness_matrix", "damping", "story_strengths")


# ----------------------------------------------------------------------------- [building]

def building_from_fields(fields: dict, error) -> Building:
    """Building from the uniform shorthand, per-story arrays or a stiffness matrix."""
    if not fields:
        raise error("building", "a [building] table")
    n = _story_count(fields, error)
    gathered: list = []  # the masses, the heights and the stiffness: independent mistakes, reported together
    masses = gather(gathered, _per_story, fields, n, "floor_mass", "masses", "kg", error)
    story_heights = gather(gathered, _per_story, fields, n, "story_height", "story_heights", "m", error)
    stiffness_name = gather(gathered, _stiffness_name, fields, error)
    raise_all(gathered)
    damping = fields.get("damping", schema.default("building", "damping"))
    building = _unscaled_building(fields, stiffness_name, n, masses, story_heights, damping, error)
    building, stiffness_field = _scaled_to_period(building, fields.get("period"), stiffness_name)
    _check_finite(building, stiffness_field, error)
    _check_modes(building, stiffness_field, error)
    return building


def _story_count(fields: dict, error) -> int:
    """N: building.stories, else the length of the per-story arrays; at most MAX_STORIES."""
    lengths = _array_lengths(fields)
    n = fields.get("stories", next(iter(lengths.values()), None))
    _check_lengths(lengths, n, error)
    if n is None:
        raise error("building.stories", "the number of stories (or per-story arrays: masses, story_heights)")
    if n > MAX_STORIES:
        name = next(iter(lengths), "stories")
        raise error(f"building.{name}", f"at most {MAX_STORIES} stories (limit of the tool), got {n}")
    return n


def _array_lengths(fields: dict) -> dict[str, int]:
    """{name: length} of the per-story arrays given."""
    return {name: len(fields[name]) for name in PER_STORY_ARRAYS if isinstance(fields.get(name), list)}


def _check_lengths(lengths: dict[str, int], n: int | None, error) -> None:
    """Every per-story array of n values (each one that is not named)."""
    raise_all([error(f"building.{name}", f"{n} values, one per story, got {length}")
               for name, length in lengths.items() if length != n])


def _per_story(fields: dict, n: int, scalar: str, array: str, unit: str, error) -> np.ndarray:
    """The N values of the uniform field `scalar` or of the per-story array `array` (one of them given)."""
    name = schema.exactly_one(fields, [scalar, array], "building", error)
    if name is None:
        raise error(f"building.{scalar}", f"a positive number [{unit}] (missing; or give building.{array})")
    return np.full(n, fields[scalar]) if name == scalar else np.asarray(fields[array], dtype=float)


def _stiffness_name(fields: dict, error) -> str | None:
    """The stiffness field given (story_stiffness, story_stiffnesses or stiffness_matrix), or None when
    building.period alone sets a uniform story stiffness."""
    name = schema.exactly_one(fields, ["story_stiffness", "story_stiffnesses", "stiffness_matrix"], "building",
                              error)
    if name is None and fields.get("period") is None:
        raise error("building.story_stiffness", "a story stiffness [N/m] (missing; or give building.period "
                    "[s], building.story_stiffnesses or building.stiffness_matrix)")
    return name


def _unscaled_building(fields: dict, stiffness_name: str | None, n: int, masses: np.ndarray,
                       story_heights: np.ndarray, damping, error) -> Building:
    """A frame of building.stiffness_matrix, or a shear building of story stiffnesses (before building.period)."""
    if stiffness_name == "stiffness_matrix":
        return _frame_building(fields["stiffness_matrix"], masses, story_heights, damping, error)
    stiffness = _story_stiffness(fields, stiffness_name, n)
    return shear_building(masses, story_heights, stiffness, np.asarray(damping, dtype=float))


def _frame_building(given, masses: np.ndarray, story_heights: np.ndarray, damping, error) -> Building:
    """The building of a frame's lateral stiffness matrix K (symmetric positive definite) [N/m]."""
    matrix = np.asarray(given, dtype=float)
    _check_stiffness_matrix(matrix, error)
    heights = np.cumsum(story_heights)
    xi = np.broadcast_to(np.asarray(damping, dtype=float), masses.shape).copy()
    return Building(masses, heights, matrix, xi, None)


def _check_stiffness_matrix(matrix: np.ndarray, error) -> None:
    """building.stiffness_matrix symmetric and positive definite."""
    if not np.allclose(matrix, matrix.T, rtol=1e-9, atol=1e-12 * np.abs(matrix).max()):
        raise error("building.stiffness_matrix", "a symmetric matrix [N/m]")
    if np.linalg.eigvalsh(matrix)[0] <= 0.0:
        raise error("building.stiffness_matrix", "a positive-definite matrix [N/m]")


def _story_stiffness(fields: dict, name: str | None, n: int) -> np.ndarray:
    """k_j [N/m]: building.story_stiffness on every story, building.story_stiffnesses, or 1 (none given:
    building.period sets the scale)."""
    if name == "story_stiffness":
        return np.full(n, fields["story_stiffness"])
    if name == "story_stiffnesses":
        return np.asarray(fields["story_stiffnesses"], dtype=float)
    return np.ones(n)


def _scaled_to_period(building: Building, period: float | None, stiffness_name: str | None
                      ) -> tuple[Building, str]:
    """The building scaled to building.period (when given), and the field that set its stiffness
    (named by the checks that follow)."""
    if period is None:
        return building, f"building.{stiffness_name}"
    return scale_to_period(building, period), "building.period"


def _check_finite(building: Building, stiffness_field: str, error) -> None:
    """Finite story stiffnesses and heights."""
    if not (np.all(np.isfinite(building.stiffness)) and np.all(np.isfinite(building.heights))):
        raise error(stiffness_field, "a value giving finite story stiffnesses and heights (check the magnitudes "
                    "of the [building] fields)")


def _check_modes(building: Building, stiffness_field: str, error) -> None:
    """Finite positive frequencies and effective heights (the modes solved in double precision)."""
    if not _sound_modes(_modes_or_none(building)):
        raise error(stiffness_field, "a value giving finite positive frequencies and effective heights "
                    "(the stiffness matrix is not positive definite in double precision: check the "
                    "magnitudes of the [building] fields)")


def _modes_or_none(building: Building) -> Modes | None:
    """The building's modes, or None if they cannot be solved."""
    try:
        return modal_analysis(building)
    except (ValueError, np.linalg.LinAlgError, ArithmeticError):
        return None


def _sound_modes(modes: Modes | None) -> bool:
    """Modes with finite positive frequencies and finite effective heights, the first one positive."""
    if modes is None:
        return False
    return bool(np.all(np.isfinite(modes.omega)) and np.all(modes.omega > 0.0)
                and np.all(np.isfinite(modes.effective_height)) and modes.effective_height[0] > 0.0)


# ----------------------------------------------------------------------------- [foundation]

def check_foundation_type_fields(fields: dict, error) -> None:
    """The fields of [foundation] that its type does not have: a bearing capacity on the half-space,
    a field of another type (each one named). They rest on foundation.type alone (checked before
    the building is built, or when it cannot be)."""
    kind = _kind(fields)
    gathered: list = []
    gather(gathered, _check_no_capacity, fields, kind, error)
    gather(gathered, _check_fields_of_type, fields, kind, error)
    raise_all(gathered)


def _kind(fields: dict) -> str:
    """foundation.type, or its default."""
    return fields.get("type", schema.default("foundation", "type"))


def system_from_fields(building: Building, fields: dict, analysis: dict, error) -> System:
    """Mat half-width, mat mass and inertia, and the foundation (its fields of its type only:
    check_foundation_type_fields)."""
    kind = _kind(fields)
    modes = modal_analysis(building)
    which, b = _half_width(fields, float(modes.effective_height[0]), error)
    mat_mass = fields.get("mat_mass", 0.0)
    total_mass = float(building.masses.sum() + mat_mass)
    _check_foundation_alternatives(fields, error)

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


def _check_no_capacity(fields: dict, kind: str, error) -> None:
    """No bearing capacity on the half-space foundation."""
    if kind != "halfspace":
        return
    raise_all([error(f"foundation.{name}", "no bearing capacity for the half-space foundation: the yielding-soil "
                     "model (docs/theory.md section 14) is for type \"two-element\" or \"winkler\"")
               for name in CAPACITY_NAMES if name in fields])


def _check_fields_of_type(fields: dict, kind: str, error) -> None:
    """No field that belongs to another foundation type than `kind` only (each one named)."""
    foreign = {name: owners for name in fields if (owners := _owners(name)) and kind not in owners}
    raise_all([error(f"foundation.{name}", f"no {name} for foundation type {kind!r} (it belongs to type {owners[0]!r})")
               for name, owners in foreign.items()])


def _owners(name: str) -> list[str]:
    """The foundation types with the field `name` of their own."""
    return [kind for kind, names in FOUNDATION_FIELDS.items() if name in names]


def _half_width(fields: dict, effective_height: float, error) -> tuple[str, float]:
    """(the field that set it, b [m]): foundation.b, or h_1* / foundation.slenderness."""
    which = schema.exactly_one(fields, ["b", "slenderness"], "foundation", error)
    if which is None:
        raise error("foundation.b", "the mat half-width b > 0 [m] (missing; or give foundation.slenderness "
                    "= h_1*/b)")
    b = fields["b"] if which == "b" else effective_height / fields["slenderness"]
    _check_half_width(b, which, error)
    return which, b


def _check_half_width(b: float, which: str, error) -> None:
    """b finite and > 0 (h_1*/slenderness may overflow or vanish)."""
    if not (np.isfinite(b) and b > 0.0):
        raise error(f"foundation.{which}", f"a value giving a finite mat half-width b > 0 [m], got b = {b:g} m")


def _check_foundation_alternatives(fields: dict, error) -> None:
    """At most one field of each group of alternatives of [foundation] (overrides.ALTERNATIVES)."""
    for table, groups in ALTERNATIVES:
        if table == "foundation":
            schema.exactly_one(fields, list(chain.from_iterable(groups)), "foundation", error)


def _check_impedance(system: System, fields: dict, half_width: str, error) -> None:
    """The foundation's rocking stiffness K_theta > 0 and finite at the fixed-base w_1, the highest
    frequency the engines evaluate it at (model/interaction.py: the flexible-base w1bar <= w_1),
    where the half-space's K_theta(w) of NIST GCR 12-917-21 Table 2-3a, decreasing in w, is
    lowest: it turns negative for a mat about 2,000 times longer than wide. The error names the
    foundation field that set the shape (half_length, else b or slenderness)."""
    omega = float(system.modes.omega[0])
    rocking = _rocking_stiffness(system, omega)
    if math.isfinite(rocking) and rocking > 0.0:
        return
    name = "half_length" if "half_length" in fields else half_width
    raise error(f"foundation.{name}", f"a foundation giving a finite rocking stiffness K_theta > 0 at the fixed-base "
                f"w_1 = {omega:.4g} rad/s, got K_theta = {rocking:.4g} N m/rad (the mat is {_mat_shape(system)}; "
                "check its dimensions and the soil)")


def _rocking_stiffness(system: System, omega: float) -> float:
    """K_theta(omega) [N m/rad] of the foundation, NaN if it cannot be evaluated."""
    try:
        return system.foundation.rocking_stiffness(system.half_width, omega)
    except (ValueError, ArithmeticError):
        return math.nan


def _mat_shape(system: System) -> str:
    """'2.4 m wide' and, for a foundation with a half-length, ', 9.6 m long'."""
    length = getattr(system.foundation, "half_length", None)
    return f"{2 * system.half_width:.4g} m wide" + (f", {2 * length:.4g} m long" if length else "")
