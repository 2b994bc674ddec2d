"""Read an `uplift` deck (TOML), apply `--set` overrides and build the analysis inputs.

    deck = load_deck("inputs/ten_story_elcentro.toml", ["building.period=0.5"])
    deck.system, deck.spectrum, deck.analysis ...

Field names, units and defaults: deck/schema.TABLES and docs/deck.md. The [building] and
[foundation] tables are built in deck/building.py, [ground_motion] in deck/motion.py (a suite:
deck/suite.py), --set in deck/overrides.py; this module builds [analysis] and [criteria] and
assembles the Deck. Every bad input raises errors.InputError naming the file (or "--set"), the
dotted field and what was expected; nothing here prints or exits.
"""

from __future__ import annotations

import re
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..engines.options import ExactOptions, SimplifiedOptions, deck_fields
from ..engines.quantities import ROCKING
from ..errors import InputError
from ..model.building import modes_for_mass_target
from ..model.system import System
from ..provenance.record import plain
from ..runtime.limits import MAX_DECK_BYTES, read_input
from . import schema
from .building import building_from_fields, system_from_fields
from .criteria import Criteria
from .fields import gather, raise_all
from .motion import check_motion_fields, read_ground_motion
from .overrides import apply_overrides, parse_override
from .practice import plausibility
from .strengths import strengths_from_fields


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
    analysis: AnalysisSettings; criteria: acceptance limits {name: value} (schema.TABLES["criteria"]), with
        their sources (criteria.Criteria.sources, [criteria.sources]);
    raw: the TOML mapping after the overrides; values: validated {table: {field: value}} (SI);
    overridden: the dotted paths set by `--set` (errors about them name "--set");
    warnings: one line per value far outside building practice (practice.plausibility);
    resolved: `raw` with every number in bare SI (schema.si_mapping: the resolved deck).
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
        return self.source, next((path for path in paths if self._given(path)), paths[0])

    def _given(self, path: str) -> bool:
        """Whether the deck (or --set) gives the field at the dotted `path`."""
        table, _, name = path.rpartition(".")
        return name in self.values.get(table, {})


# ----------------------------------------------------------------------------- loading

def read_toml(path: str | Path) -> dict:
    """Parse a TOML file; InputError with the line on malformed TOML."""
    source = str(path)
    data = read_input(path, MAX_DECK_BYTES, source, None, "deck file")
    return _parse_toml(_decoded(data, source), source)


def _decoded(data: bytes, source: str) -> str:
    """The deck's text: UTF-8, a byte-order mark accepted."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        raise InputError(source, None, f"a readable UTF-8 TOML file ({error})") from None


def _parse_toml(text: str, source: str) -> dict:
    try:
        return tomllib.loads(text)
    except RecursionError:
        raise InputError(source, None, "valid TOML (arrays or tables nested too deeply)") from None
    except tomllib.TOMLDecodeError as error:
        raise _toml_error(error, source) from None


def _toml_error(error: tomllib.TOMLDecodeError, source: str) -> InputError:
    """The error of malformed TOML: the line, and the parser's reason without its position."""
    message = str(error)
    match = re.search(r"\(at line (\d+), column \d+\)", message)
    line = _error_line(error, match)
    reason = message[: match.start()].strip() if match else message
    return InputError(source, f"line {line}" if line else None, f"valid TOML ({reason})")


def _error_line(error: tomllib.TOMLDecodeError, match: re.Match | None) -> int | None:
    """The line of a TOML error: its lineno (Python 3.14 on), else the one its message names."""
    lineno = getattr(error, "lineno", None)
    if lineno:
        return lineno
    return int(match.group(1)) if match else None


def load_deck(path: str | Path, overrides: Sequence[str] = (), *, load_ground_motion: bool = True) -> Deck:
    """Read, override (`--set` strings 'path=value'), validate and build a deck."""
    parsed = [parse_override(text) for text in overrides]
    raw = read_toml(path)
    return build_deck(raw, str(path), parsed, load_ground_motion=load_ground_motion)


def build_deck(raw: dict, source: str = "<mapping>", overrides: Sequence[tuple[str, Any]] = (), *,
               load_ground_motion: bool = True) -> Deck:
    """Build a Deck from a parsed mapping (used by load_deck and by sweeps; from Python, any
    mapping of the deck's tables, numpy arrays and scalars accepted). source: the deck's file,
    which relative paths are relative to (default "<mapping>": the working directory)."""
    raw, overridden = apply_overrides(plain(raw), [(path, plain(value)) for path, value in overrides])
    values = schema.validate(raw, source, overridden)
    error = schema.FieldErrors(source, overridden)  # ground_motion.suite[1].file came from --set ground_motion.suite
    system, analysis = _system_and_analysis(values, source, error, load_ground_motion)
    ground_motion = spectrum = None
    if load_ground_motion:
        ground_motion, spectrum = read_ground_motion(values["ground_motion"], source, error, system,
                                                     analysis.simplified.effective_properties)
    _check_criteria_have_their_analysis(values["criteria"], analysis, error)
    _check_sources_have_their_limits(values["criteria"], values["criteria.sources"], error)
    criteria = Criteria(values["criteria"], values["criteria.sources"])
    return Deck(source, values[""].get("title", Path(source).stem), system, ground_motion, spectrum,
                analysis, criteria, raw, values, overridden,
                tuple(plausibility(values, source, overridden)), schema.si_mapping(raw, values))


def _system_and_analysis(values: dict, source: str, error, load_ground_motion: bool
                         ) -> tuple[System, AnalysisSettings]:
    """The system and the analysis settings, with the mistakes of the building, the foundation, the
    analysis and (when these are not all built) the ground motion reported at once."""
    gathered: list[InputError] = []
    system, analysis = _gather_structure(gathered, values, error)
    if analysis is None and load_ground_motion:
        gather(gathered, check_motion_fields, values["ground_motion"], source, error)
    raise_all(gathered)
    return system, analysis


def _gather_structure(gathered: list[InputError], values: dict, error
                      ) -> tuple[System | None, AnalysisSettings | None]:
    """Building, system and analysis settings, each built when what it rests on was (None
    otherwise); their mistakes appended to `gathered`."""
    building = gather(gathered, building_from_fields, values["building"], error)
    if building is not None:
        building = gather(gathered, strengths_from_fields, building, values["building"], values["analysis"], error)
    if building is None:
        return None, None
    system = gather(gathered, system_from_fields, building, values["foundation"], values["analysis"], error)
    if system is None:
        return None, None
    analysis = gather(gathered, _analysis, values["analysis"], values["analysis.exact"], system, error)
    if analysis is not None:
        gather(gathered, _check_yielding_elements, system, analysis, error)
        gather(gathered, _check_yielding_stories, system, analysis, error)
    return system, analysis


def _check_yielding_elements(system: System, analysis: AnalysisSettings, error) -> None:
    """A capacity on more contact elements than the deck's history engines step in an uplift
    analysis (limits.MAX_YIELDING_ELEMENTS, registry.capacity_refusal), refused up front; the
    simplified engine alone has no such bound (docs/deck.md, bearing capacity)."""
    from ..engines.registry import capacity_refusal

    if "uplift" not in analysis.supports:
        return
    for name in analysis.engines:
        refusal = capacity_refusal(name, system, "uplift")
        if refusal is not None:
            raise error("foundation.elements", refusal)


def _check_yielding_stories(system: System, analysis: AnalysisSettings, error) -> None:
    """Yielding stories whose pattern bits, with the foundation's, do not fit the exact engine's contact
    pattern (limits.MAX_PATTERN_BITS, registry.strength_refusal), refused up front when the deck runs the
    exact engine; the other engines' refusal of yielding stories is theirs, at run time (docs/theory.md
    15.6), so that a deck with strengths still serves the commands that run no engine."""
    from ..engines.registry import strength_refusal

    if "exact" not in analysis.engines:
        return
    for support in analysis.supports:
        refusal = strength_refusal("exact", system, support)
        if refusal is not None:
            raise error(f"{refusal[0]}.{refusal[1]}", refusal[2])


def _check_criteria_have_their_analysis(criteria: dict, analysis: AnalysisSettings, error) -> None:
    """A limit on a rocking quantity (engines/quantities.ROCKING) needs the analysis that reports
    it: the exact engine and the uplift support (with or without a bearing capacity); a limit on
    the simplified engine's accuracy (simplified_error) needs the simplified engine, else it would
    pass unchecked."""
    _check_accuracy_limit_has_its_engine(criteria, analysis, error)
    _check_rocking_limits_have_their_analysis(criteria, analysis, error)


def _check_accuracy_limit_has_its_engine(criteria: dict, analysis: AnalysisSettings, error) -> None:
    """criteria.simplified_error needs the simplified engine."""
    if "simplified_error" in criteria and "simplified" not in analysis.engines:
        raise error("criteria.simplified_error", "a limit on the accuracy check of the simplified engine against the "
                    "exact engine (docs/accuracy.md); the deck has not the simplified engine in analysis.engine")


def _check_rocking_limits_have_their_analysis(criteria: dict, analysis: AnalysisSettings, error) -> None:
    """A limit on a rocking quantity needs the exact engine and the uplift support."""
    missing = _missing_for_rocking(analysis)
    if not missing:
        return
    for name in criteria:
        if name in ROCKING:
            raise error(f"criteria.{name}", f"a limit the exact engine reports for an uplift analysis (docs/theory.md "
                        f"14.7); the deck has not {' and '.join(missing)}")


def _missing_for_rocking(analysis: AnalysisSettings) -> list[str]:
    """What the analysis lacks to report the rocking quantities (the exact engine, the uplift support)."""
    missing = []
    if "exact" not in analysis.engines:
        missing.append("the exact engine in analysis.engine")
    if "uplift" not in analysis.supports:
        missing.append("the uplift support in analysis.supports")
    return missing


def _check_sources_have_their_limits(criteria: dict, sources: dict, error) -> None:
    """A source in [criteria.sources] only for a limit the deck sets."""
    for name in sources:
        if name not in criteria:
            raise error(f"criteria.sources.{name}", f"the source of a limit the deck sets (criteria.{name} is not set)")


def _analysis(fields: dict, exact: dict, system: System, error) -> AnalysisSettings:
    """The [analysis] and [analysis.exact] settings: engines, supports, modes and options."""
    which = schema.exactly_one(fields, ["modes", "mass_participation"], "analysis", error)
    n_modes = _mode_count(fields, which, system, error)
    _check_exact_modes(exact, system.building.n_stories, error)
    return AnalysisSettings(
        engines=list(fields.get("engine", schema.default("analysis", "engine"))),
        supports=list(fields.get("supports", schema.default("analysis", "supports"))),
        n_modes=n_modes,
        simplified=_simplified_options(fields, n_modes),
        exact=_exact_options(exact, n_modes if which else None),
        check_band=_band(fields, "check_band"),
        check_band_motion=_band(fields, "check_band_motion"),
    )


def _mode_count(fields: dict, which: str | None, system: System, error) -> int:
    """The number of modes: analysis.modes (at most N), the fewest reaching analysis.mass_participation,
    or all N."""
    n_total = system.building.n_stories
    if which == "modes":
        if fields["modes"] > n_total:
            raise error("analysis.modes", f"at most {n_total} modes (the building has {n_total} stories), "
                        f"got {fields['modes']}")
        return fields["modes"]
    if which == "mass_participation":
        return modes_for_mass_target(system.modes, float(system.building.masses.sum()), fields["mass_participation"])
    return n_total


def _check_exact_modes(exact: dict, n_total: int, error) -> None:
    """analysis.exact.n_modes at most N."""
    if exact.get("n_modes", 0) > n_total:
        raise error("analysis.exact.n_modes", f"at most {n_total} modes, got {exact['n_modes']}")


def _simplified_options(fields: dict, n_modes: int) -> SimplifiedOptions:
    """The simplified engine's options of [analysis]."""
    return SimplifiedOptions(n_modes=n_modes, **{name: fields[name] for name in deck_fields(SimplifiedOptions)
                                                 if name in fields})


def _exact_options(exact: dict, n_modes: int | None) -> ExactOptions:
    """The exact engine's options of [analysis.exact], n_modes those of [analysis] unless it sets its own."""
    values = dict(exact)
    values.setdefault("n_modes", n_modes)
    return ExactOptions(**values)


def _band(fields: dict, name: str) -> tuple[float, float]:
    """analysis.check_band(_motion): a band [low, high] around 1 of the ratios simplified / exact
    (checked with the field: fields.CHECKS["band-around-one"]), or its default."""
    low, high = fields.get(name, schema.default("analysis", name))
    return (float(low), float(high))
