"""Read an `uplift` deck (TOML), apply `--set` overrides and build the analysis inputs.

    deck = load_deck("inputs/ten_story_elcentro.toml", ["building.period=0.5"])
    deck.system, deck.spectrum, deck.analysis ...

Field names, units and defaults: deck_schema.TABLES and docs/deck.md. Every bad input
raises errors.InputError naming the file (or "--set"), the dotted field and what was
expected; nothing here prints or exits.
"""

from __future__ import annotations

import math
import os
import re
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import deck_schema as schema
from .criteria import Criteria
from .deck_overrides import ALTERNATIVES, FOUNDATION_FIELDS, apply_overrides, parse_override, set_by_override
from .engines.options import ExactOptions, SimplifiedOptions, deck_fields
from .engines.quantities import ROCKING
from .errors import InputError, deck_relative_path, not_found
from .fields import gather, raise_all
from .limits import MAX_DECK_BYTES, MAX_STORIES, read_input
from .model.bearing import CAPACITY_FIELDS
from .model.building import Building, modal_analysis, modes_for_mass_target, scale_to_period, shear_building
from .model.foundations import FOUNDATIONS, DeckContext
from .model.system import System


@dataclass
class AnalysisSettings:
    """What to run: engines, supports, modes and the engines' options."""

    engines: list[str]
    supports: list[str]
    n_modes: int
    simplified: SimplifiedOptions
    exact: ExactOptions
    check_band: tuple[float, float] = (0.8, 1.25)
    check_band_motion: tuple[float, float] = (0.5, 2.0)


@dataclass
class Deck:
    """A validated deck.

    source: the deck file; title: its label; system: building + mat + foundation;
    ground_motion: a records.Record, a design spectrum, a motion.suites.Suite (whose target is
        the design spectrum), or None (not loaded / not given);
    spectrum: object with .sa(periods [s], damping [-]) -> S_a [m/s^2] for the simplified engine;
    analysis: AnalysisSettings; criteria: acceptance limits {name: value} (deck_schema "criteria"), with
        their sources (criteria.Criteria.sources, [criteria.sources]);
    raw: the TOML mapping after the overrides; values: validated {table: {field: value}} (SI);
    overridden: the dotted paths set by `--set` (errors about them name "--set");
    warnings: one line per value far outside building practice (deck_schema.plausibility);
    resolved: `raw` with every number in bare SI (deck_schema.si_mapping: the resolved deck).
    """

    source: str
    title: str
    system: System
    ground_motion: Any
    spectrum: Any
    analysis: AnalysisSettings
    criteria: dict[str, Any]
    raw: dict
    values: dict[str, dict[str, Any]] = field(repr=False, default_factory=dict)
    overridden: frozenset[str] = frozenset()
    warnings: tuple[str, ...] = ()
    resolved: dict = field(repr=False, default_factory=dict)

    def blame(self, *paths: str) -> tuple[str, str]:
        """(source, field) to name for a problem produced by the first of `paths` that was
        set: by `--set` first, then in the deck file; the first path if none was given."""
        for path in paths:
            if path in self.overridden:
                return "--set", path
        for path in paths:
            table, _, name = path.rpartition(".")
            if name in self.values.get(table, {}):
                return self.source, path
        return self.source, paths[0]


# ----------------------------------------------------------------------------- loading

def read_toml(path: str | Path) -> dict:
    """Parse a TOML file; InputError with the line on malformed TOML."""
    source = str(path)
    data = read_input(path, MAX_DECK_BYTES, source, None, "deck file")
    try:
        text = data.decode("utf-8-sig")  # a byte-order mark is accepted
    except UnicodeDecodeError as error:
        raise InputError(source, None, f"a readable UTF-8 TOML file ({error})") from None
    try:
        return tomllib.loads(text)
    except RecursionError:
        raise InputError(source, None, "valid TOML (arrays or tables nested too deeply)") from None
    except tomllib.TOMLDecodeError as error:
        message = str(error)
        match = re.search(r"\(at line (\d+), column \d+\)", message)
        line = getattr(error, "lineno", None) or (int(match.group(1)) if match else None)
        location = f"line {line}" if line else None
        reason = message[: match.start()].strip() if match else message
        raise InputError(source, location, f"valid TOML ({reason})") from None


def load_deck(path: str | Path, overrides: Sequence[str] = (), *, load_ground_motion: bool = True) -> Deck:
    """Read, override (`--set` strings 'path=value'), validate and build a deck."""
    parsed = [parse_override(text) for text in overrides]
    raw = read_toml(path)
    return build_deck(raw, str(path), parsed, load_ground_motion=load_ground_motion)


def plain(value: Any) -> Any:
    """A deck mapping built in code as TOML would give it: numpy arrays and tuples as lists,
    numpy scalars as Python numbers, paths as strings."""
    if isinstance(value, dict):
        return {key: plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(item) for item in value]
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    return value


def build_deck(raw: dict, source: str = "<mapping>", overrides: Sequence[tuple[str, Any]] = (), *,
               load_ground_motion: bool = True) -> Deck:
    """Build a Deck from a parsed mapping (used by load_deck and by sweeps; from Python, any
    mapping of the deck's tables, numpy arrays and scalars accepted). source: the deck's file,
    which relative paths are relative to (default "<mapping>": the working directory)."""
    raw, overridden = apply_overrides(plain(raw), [(path, plain(value)) for path, value in overrides])
    values = schema.validate(raw, source, overridden)

    def error(path: str, expected: str):  # ground_motion.suite[1].file came from --set ground_motion.suite
        return InputError("--set" if set_by_override(path, overridden) else source, path, expected)

    gathered: list[InputError] = []  # the mistakes of the building, the foundation and the ground motion at once
    building = gather(gathered, _building, values["building"], error)
    system = None if building is None else gather(gathered, _system, building, values["foundation"],
                                                  values["analysis"], error)
    analysis = None if system is None else gather(gathered, _analysis, values["analysis"], values["analysis.exact"],
                                                  system, error)
    if analysis is not None:
        gather(gathered, _check_yielding_elements, system, analysis, error)
    if analysis is None and load_ground_motion:
        gather(gathered, _motion_fields, values["ground_motion"], source, error)
    raise_all(gathered)
    ground_motion = spectrum = None
    if load_ground_motion:
        ground_motion, spectrum = _ground_motion(values["ground_motion"], source, error, system,
                                                 analysis.simplified.effective_properties)
    _check_rocking_criteria(values["criteria"], analysis, error)
    for name in values["criteria.sources"]:
        if name not in values["criteria"]:
            raise error(f"criteria.sources.{name}", f"the source of a limit the deck sets (criteria.{name} is not set)")
    criteria = Criteria(values["criteria"], values["criteria.sources"])
    return Deck(source, values[""].get("title", Path(source).stem), system, ground_motion, spectrum,
                analysis, criteria, raw, values, overridden,
                tuple(schema.plausibility(values, source, overridden)), schema.si_mapping(raw, values))


def _check_yielding_elements(system: System, analysis: AnalysisSettings, error) -> None:
    """A capacity on more contact elements than the deck's history engines step in an uplift
    analysis (limits.MAX_YIELDING_ELEMENTS, registry.capacity_refusal), refused up front; the
    simplified engine alone has no such bound (docs/deck.md, bearing capacity)."""
    from .engines.registry import capacity_refusal

    if "uplift" not in analysis.supports:
        return
    for name in analysis.engines:
        refusal = capacity_refusal(name, system, "uplift")
        if refusal is not None:
            raise error("foundation.elements", refusal)


def _check_rocking_criteria(criteria: dict, analysis: AnalysisSettings, error) -> None:
    """A limit on a rocking quantity (engines/quantities.ROCKING) needs the analysis that reports
    it: the exact engine and the uplift support (with or without a bearing capacity)."""
    for name in criteria:
        if name not in ROCKING:
            continue
        missing = [what for what, ok in (("the exact engine in analysis.engine", "exact" in analysis.engines),
                                         ("the uplift support in analysis.supports", "uplift" in analysis.supports))
                   if not ok]
        if missing:
            raise error(f"criteria.{name}", f"a limit the exact engine reports for an uplift analysis (docs/theory.md "
                        f"14.7); the deck has not {' and '.join(missing)}")


def _default(table: str, name: str) -> Any:
    return schema.TABLES[table][name].default


def _exactly_one(fields: dict, names: Sequence[str], table: str, error) -> str | None:
    given = [name for name in names if name in fields]
    if len(given) > 1:
        raise error(f"{table}.{given[1]}", f"only one of {', '.join(f'{table}.{n}' for n in names)} "
                    f"(both {given[0]} and {given[1]} given)")
    return given[0] if given else None


def _building(fields: dict, error) -> Building:
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
        name = _exactly_one(fields, [scalar, array], "building", error)
        if name is None:
            raise error(f"building.{scalar}", f"a positive number [{unit}] (missing; or give building.{array})")
        return np.full(n, fields[scalar]) if name == scalar else np.asarray(fields[array], dtype=float)

    masses = per_story("floor_mass", "masses", "kg")
    story_heights = per_story("story_height", "story_heights", "m")
    damping = fields.get("damping", _default("building", "damping"))
    stiffness_name = _exactly_one(fields, ["story_stiffness", "story_stiffnesses", "stiffness_matrix"],
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


def _system(building: Building, fields: dict, analysis: dict, error) -> System:
    """Mat half-width, mat mass and inertia, and the foundation."""
    kind = fields.get("type", _default("foundation", "type"))
    if kind == "halfspace":
        for name in ("element_capacity", "line_capacity", *CAPACITY_FIELDS):
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
    which = _exactly_one(fields, ["b", "slenderness"], "foundation", error)
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
            _exactly_one(fields, [name for group in groups for name in group], "foundation", error)

    def missing(name: str, expected: str):
        raise error(f"foundation.{name}", expected)

    gravity = float(analysis.get("gravity", _default("analysis", "gravity")))
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


def _analysis(fields: dict, exact: dict, system: System, error) -> AnalysisSettings:
    n_total = system.building.n_stories
    which = _exactly_one(fields, ["modes", "mass_participation"], "analysis", error)
    if which == "modes":
        if fields["modes"] > n_total:
            raise error("analysis.modes", f"at most {n_total} modes (the building has {n_total} stories), "
                        f"got {fields['modes']}")
        n_modes = fields["modes"]
    elif which == "mass_participation":
        n_modes = modes_for_mass_target(system.modes, float(system.building.masses.sum()),
                                        fields["mass_participation"])
    else:
        n_modes = n_total
    if exact.get("n_modes", 0) > n_total:
        raise error("analysis.exact.n_modes", f"at most {n_total} modes, got {exact['n_modes']}")
    simplified = SimplifiedOptions(n_modes=n_modes, **{name: fields[name] for name in deck_fields(SimplifiedOptions)
                                                       if name in fields})
    exact_values = dict(exact)
    exact_values.setdefault("n_modes", n_modes if which else None)
    return AnalysisSettings(
        engines=list(fields.get("engine", _default("analysis", "engine"))),
        supports=list(fields.get("supports", _default("analysis", "supports"))),
        n_modes=n_modes,
        simplified=simplified,
        exact=ExactOptions(**exact_values),
        check_band=_check_band(fields, "check_band", error),
        check_band_motion=_check_band(fields, "check_band_motion", error),
    )


def _check_band(fields: dict, name: str, error) -> tuple[float, float]:
    """analysis.check_band(_motion): a band [low, high] around 1 of the ratios simplified / exact."""
    low, high = fields.get(name, _default("analysis", name))
    if not low < 1.0 < high:
        raise error(f"analysis.{name}", f"[low, high] with low < 1 < high (ratios simplified / exact), got "
                    f"[{low:g}, {high:g}]")
    return (float(low), float(high))


def _motion_fields(fields: dict, source: str, error):
    """The [ground_motion] fields checked as a whole, before anything is read: a record or a design
    spectrum, the suite fields with a design spectrum, the record file existing. The record's
    path, or None for a design spectrum."""
    if not fields:
        raise error("ground_motion", "a [ground_motion] table with a record (path) or a design_spectrum")
    from .deck_suite import SUITE_ONLY

    suite_fields = {"suite", *SUITE_ONLY, "period_range", "statistics"}
    if "design_spectrum" in fields:
        extra = sorted(set(fields) - {"design_spectrum"} - suite_fields)
        if extra:
            raise error(f"ground_motion.{extra[0]}", "no record fields together with a design_spectrum")
        for name in SUITE_ONLY if "suite" not in fields else ():
            if name in fields:
                raise error(f"ground_motion.{name}", "a ground_motion.suite to scale (none given)")
        return None
    given = sorted(suite_fields & set(fields))
    if given:
        raise error("ground_motion.design_spectrum", f"a design spectrum, the target of ground_motion.{given[0]} "
                    "(or no suite fields with a record)")
    if "record" not in fields:
        raise error("ground_motion.record", "the path of a record file (missing; or give "
                    "ground_motion.design_spectrum)")
    path = deck_relative_path(fields["record"], source)
    if not path.exists():  # the folder a relative path was resolved from: the deck's (its target's, a link)
        raise error("ground_motion.record", not_found(path, fields["record"], source,
                                                      folder=deck_relative_path(".", source)))
    return path


def _ground_motion(fields: dict, source: str, error, system: System | None = None,
                   effective_properties: str = "formula") -> tuple[Any, Any]:
    """(record, design spectrum or suite, spectrum for the simplified engine)."""
    path = _motion_fields(fields, source, error)
    if path is None:
        from .deck_suite import load_suite, suite_plan, target_spectrum

        spectrum = target_spectrum(fields, source, error)
        if "suite" not in fields:
            return spectrum, spectrum
        plan = suite_plan(fields, spectrum, system, effective_properties, source, error)
        return load_suite(fields, plan, source, error), plan.target  # the simplified engine on the suite's target
    from .motion import records, spectra

    try:
        record = records.read_record(path, fields.get("format"), fields.get("units"), fields.get("dt"),
                                     fields.get("scale", 1.0), fields.get("window"),
                                     fields.get("override_header_units", False))
    except InputError as bad:
        # a deck field that does not suit the file is the deck's (or --set's) mistake, not the file's
        if bad.source == str(path) and bad.location in RECORD_OPTIONS and bad.location in fields:
            raise error(f"ground_motion.{bad.location}", bad.expected) from None
        raise
    return record, spectra.RecordSpectrum(record)


#: record options of read_record that are deck fields of [ground_motion]
RECORD_OPTIONS = ("format", "units", "dt", "scale", "window", "override_header_units")
