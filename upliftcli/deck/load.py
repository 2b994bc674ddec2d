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
from ..errors import InputError, gather, raise_all
from ..model.building import modes_for_mass_target
from ..model.design import Design
from ..model.system import System
from ..provenance.values import plain
from ..runtime.limits import MAX_DECK_BYTES, MAX_NESTING, read_input, too_deeply_nested
from . import schema
from .building import building_from_fields, check_foundation_type_fields, system_from_fields
from .criteria import Criteria
from .design import design_from_fields
from .failed import Failed
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
    resolved: `raw` with every number in bare SI (schema.si_mapping: the resolved deck);
    design: the code's design values of [design] (model/design.Design; None without the table).
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
    design: Design | None = None

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
        return check_nesting(tomllib.loads(text), source)
    except RecursionError:
        raise InputError(source, None, NESTING) from None
    except tomllib.TOMLDecodeError as error:
        raise _toml_error(error, source) from None


#: what a deck nested too deeply (the parser's recursion, or runtime/limits.MAX_NESTING) expected
NESTING = f"valid TOML (arrays or tables nested too deeply: at most {MAX_NESTING} levels)"


def check_nesting(raw, source: str):
    """The parsed deck (or mapping) as it is, else InputError: nested more than MAX_NESTING
    levels deep ([a.a.a...] 1,000 deep parses, then breaks every walk of the deck)."""
    if too_deeply_nested(raw):
        raise InputError(source, None, NESTING)
    return raw


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
    check_nesting(raw, source)
    raw, overridden = apply_overrides(plain(raw), [(path, plain(value)) for path, value in overrides])
    gathered: list[InputError] = []  # every mistake of the deck, reported at once (raise_all below)
    values = schema.validate(raw, source, overridden, gathered)
    checks = _Checks(gathered, Failed.of(gathered), schema.FieldErrors(source, overridden))
    system, analysis = _gather_structure(checks, values)
    ground_motion = spectrum = None
    if load_ground_motion:
        ground_motion, spectrum = _gather_motion(checks, values, source, system, analysis)
    _gather_criteria(checks, values)
    design = checks.run(("design",), design_from_fields, values["design"], system and system.building.n_stories)
    raise_all(gathered)
    criteria = Criteria(values["criteria"], values["criteria.sources"])
    return Deck(source, values[""].get("title", Path(source).stem), system, ground_motion, spectrum,
                analysis, criteria, raw, values, overridden,
                tuple(plausibility(values, source, overridden)), schema.si_mapping(raw, values), design)


@dataclass(frozen=True)
class _Checks:
    """The checks of a deck after the schema's: the mistakes gathered so far, the fields that failed
    the schema's checks (what rests on them is not checked: failed.Failed) and the deck's errors
    (schema.FieldErrors: a value that came from --set names it; ground_motion.suite[1].file came
    from --set ground_motion.suite)."""

    gathered: list[InputError]
    failed: Failed
    error: schema.FieldErrors

    def run(self, rests_on: tuple[str, ...], check, *args):
        """check(*args, error), its mistakes gathered (fields.gather), when no field it rests on failed
        the schema's checks; None when it failed or did not run."""
        if not self.failed.clear(*rests_on):
            return None
        return gather(self.gathered, check, *args, self.error)


def _gather_structure(checks: _Checks, values: dict) -> tuple[System | None, AnalysisSettings | None]:
    """Building, system and analysis settings, each built when what it rests on was (None
    otherwise); the foundation's fields of another type checked whatever else failed."""
    building = checks.run(("building",), building_from_fields, values["building"])
    if building is not None:
        building = checks.run(("building", "analysis"), strengths_from_fields, building, values["building"],
                              values["analysis"])
    typed = _gather_typed_fields(checks, values["foundation"])
    if building is None or not typed:
        return None, None
    system = checks.run(("foundation", "analysis.gravity"), system_from_fields, building, values["foundation"],
                        values["analysis"])
    if system is None:
        return None, None
    analysis = checks.run(("analysis",), _analysis, values["analysis"], values["analysis.exact"], system)
    if analysis is not None:
        checks.run((), _check_yielding_elements, system, analysis)
        checks.run((), _check_yielding_stories, system, analysis)
    return system, analysis


def _gather_typed_fields(checks: _Checks, foundation: dict) -> bool:
    """The [foundation] fields its type does not have (building.check_foundation_type_fields),
    checked when foundation.type passed the schema's checks; whether there were none."""
    count = len(checks.gathered)
    checks.run(("foundation.type",), check_foundation_type_fields, foundation)
    return len(checks.gathered) == count and checks.failed.clear("foundation.type")


def _gather_motion(checks: _Checks, values: dict, source: str, system: System | None,
                   analysis: AnalysisSettings | None) -> tuple[Any, Any]:
    """(ground motion, spectrum) read when the system and the analysis were built (a suite is
    scaled to the structure); else its fields checked without reading it."""
    if analysis is None:
        checks.run(("ground_motion",), check_motion_fields, values["ground_motion"], source)
        return None, None
    read = checks.run(("ground_motion",), _motion, values["ground_motion"], source, system,
                      analysis.simplified.effective_properties)
    return read or (None, None)


def _motion(fields: dict, source: str, system: System, effective_properties: str, error) -> tuple[Any, Any]:
    """motion.read_ground_motion, the error last."""
    return read_ground_motion(fields, source, error, system, effective_properties)


def _gather_criteria(checks: _Checks, values: dict) -> None:
    """The limits of [criteria] checked against the engines and supports of [analysis], and their
    sources against the limits."""
    checks.run(("analysis.engine", "analysis.supports", "criteria"), _check_criteria_have_their_analysis,
               values["criteria"], _Chosen.of(values["analysis"]))
    checks.run(("criteria",), _check_sources_have_their_limits, values["criteria"], values["criteria.sources"])


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


@dataclass(frozen=True)
class _Chosen:
    """The engines and supports that [analysis] chooses (the defaults where it does not)."""

    engines: list[str]
    supports: list[str]

    @classmethod
    def of(cls, fields: dict) -> _Chosen:
        return cls(list(fields.get("engine", schema.default("analysis", "engine"))),
                   list(fields.get("supports", schema.default("analysis", "supports"))))


def _check_criteria_have_their_analysis(criteria: dict, analysis: _Chosen, error) -> None:
    """A limit on a rocking quantity (engines/quantities.ROCKING) needs the analysis that reports
    it: the exact engine and the uplift support (with or without a bearing capacity); a limit on
    the simplified engine's accuracy (simplified_error) needs the simplified engine, else it would
    pass unchecked. Every such limit named."""
    gathered: list[InputError] = []
    gather(gathered, _check_accuracy_limit_has_its_engine, criteria, analysis, error)
    gather(gathered, _check_rocking_limits_have_their_analysis, criteria, analysis, error)
    raise_all(gathered)


def _check_accuracy_limit_has_its_engine(criteria: dict, analysis: _Chosen, error) -> None:
    """criteria.simplified_error needs the simplified engine."""
    if "simplified_error" in criteria and "simplified" not in analysis.engines:
        raise error("criteria.simplified_error", "a limit on the accuracy check of the simplified engine against the "
                    "exact engine (docs/accuracy.md); the deck has not the simplified engine in analysis.engine")


def _check_rocking_limits_have_their_analysis(criteria: dict, analysis: _Chosen, error) -> None:
    """A limit on a rocking quantity needs the exact engine and the uplift support (each limit named)."""
    missing = _missing_for_rocking(analysis)
    limits = [name for name in criteria if name in ROCKING] if missing else []
    raise_all([error(f"criteria.{name}", f"a limit the exact engine reports for an uplift analysis (docs/theory.md "
                     f"14.7); the deck has not {' and '.join(missing)}") for name in limits])


def _missing_for_rocking(analysis: _Chosen) -> list[str]:
    """What the analysis lacks to report the rocking quantities (the exact engine, the uplift support)."""
    missing = []
    if "exact" not in analysis.engines:
        missing.append("the exact engine in analysis.engine")
    if "uplift" not in analysis.supports:
        missing.append("the uplift support in analysis.supports")
    return missing


def _check_sources_have_their_limits(criteria: dict, sources: dict, error) -> None:
    """A source in [criteria.sources] only for a limit the deck sets (each one named)."""
    raise_all([error(f"criteria.sources.{name}", f"the source of a limit the deck sets (criteria.{name} is not set)")
               for name in sources if name not in criteria])


def _analysis(fields: dict, exact: dict, system: System, error) -> AnalysisSettings:
    """The [analysis] and [analysis.exact] settings: engines, supports, modes and options."""
    which = schema.exactly_one(fields, ["modes", "mass_participation"], "analysis", error)
    n_modes = _mode_count(fields, which, system, error)
    _check_exact_modes(exact, system.building.n_stories, error)
    chosen = _Chosen.of(fields)
    return AnalysisSettings(
        engines=chosen.engines,
        supports=chosen.supports,
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
