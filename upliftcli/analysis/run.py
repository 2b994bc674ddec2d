"""Analysis runner: a Deck in, one AnalysisResult per (engine, support) out, through the
engine registry (engines/registry.py). On a record suite a response-history engine runs every
record and gives a SuiteResult (analysis/suite.py, engines/suite_result.py): the AnalysisResult
of the statistic the code asks for, with each record's result and the other statistics.

Used by `uplift analyze` and by sweeps; knows nothing of the terminal or files.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from ..deck.load import Deck
from ..engines.design import with_design
from ..engines.registry import ENGINES, Engine, capacity_refusal, strength_refusal
from ..engines.result import AnalysisResult
from ..errors import AnalysisError, InputError
from ..model.bearing import CAPACITY_NAMES
from ..motion.records import Record, is_suite
from ..runtime import limits
from . import residuals
from .level import with_level


def ground_motion_for(deck: Deck, engine: Engine) -> Any:
    """The deck's record or record suite for a response-history engine, its spectrum (.sa) for
    the simplified engine; InputError naming the deck field when the deck has not what the
    engine needs."""
    if not engine.needs_record:
        return _spectrum_for(deck, engine)
    if is_suite(deck.ground_motion):
        return deck.ground_motion
    if not isinstance(deck.ground_motion, Record):
        asked = "asked by --engine or --set analysis.engine; " if "analysis.engine" in deck.overridden else ""
        raise InputError(deck.source, "ground_motion.record", f"a record for the {engine.name} engine ({asked}a design "
                         "spectrum serves only the simplified engine)")
    return deck.ground_motion


def _spectrum_for(deck: Deck, engine: Engine) -> Any:
    """The deck's spectrum (a design spectrum, or a record's); InputError when it has none."""
    if deck.spectrum is None:
        raise InputError(deck.source, "ground_motion", f"a record or a design spectrum for the {engine.name} engine")
    return deck.spectrum


#: deck fields that set the building's frequencies (named for a period out of range)
BUILDING_PATHS = ("building.period", "building.story_stiffness", "building.story_stiffnesses",
                  "building.stiffness_matrix", "building.floor_mass", "building.masses", "building.stories")


def _foundation_paths(deck: Deck) -> list[str]:
    return [f"foundation.{name}" for name in type(deck.system.foundation).deck_fields] + \
        ["foundation.b", "foundation.slenderness", "foundation.mat_mass", "foundation.mat_rotary_inertia"]


def _stiffness_paths(deck: Deck) -> list[str]:
    """The foundation fields that set its periods (stiffness, size, mass): not its damping or capacity."""
    return [path for path in _foundation_paths(deck) if path not in CAPACITY_PATHS and not path.endswith(
        ("damping_ratio", ".c_f", ".c_w", "impedance_frequency"))]


#: the deck fields that give a foundation its bearing capacity (model/bearing.py)
CAPACITY_PATHS = tuple(f"foundation.{name}" for name in CAPACITY_NAMES)


def check_before_running(deck: Deck, engine: Engine, support: str, motion: Any) -> None:
    """More contact elements with a capacity than the engine steps (registry.capacity_refusal), check_resources,
    then the derived quantities: with the simplified engine and a flexible support, an
    effective damping xi1bar < 1 [23] (InputError naming the deck field)."""
    refusal = capacity_refusal(engine.name, deck.system, support)
    if refusal is not None:
        raise InputError(*deck.blame("foundation.elements"), refusal)
    check_yielding_stories(deck, engine, support)
    check_resources(deck, engine, support, motion)
    if not engine.needs_record and support != "rigid":
        _check_effective_damping(deck, support)


def _check_effective_damping(deck: Deck, support: str) -> None:
    """The simplified engine on a flexible support: an effective damping ratio xi1bar in [0, 1) [23]
    (InputError naming the foundation fields and building.damping; the engine reports a failure)."""
    from ..engines.simplified import effective_properties

    try:
        xi1bar = effective_properties(deck.system, deck.analysis.simplified.effective_properties)["xi1bar"]
    except (AnalysisError, ArithmeticError, ValueError):
        return  # the engine reports it
    if not (math.isfinite(xi1bar) and 0.0 <= xi1bar < 1.0):
        raise InputError(*deck.blame(*_foundation_paths(deck), "building.damping"),
                         f"a foundation giving an effective damping ratio xi1bar in [0, 1) [23] (simplified "
                         f"engine, {support} support), got xi1bar = {xi1bar:.6g}")


#: the deck fields that give the stories their strengths (docs/theory.md 15), and that keep fewer modes
STRENGTH_PATHS = ("building.story_strengths", "building.strength_coefficient")
MODES_PATHS = ("analysis.exact.n_modes", "analysis.modes", "analysis.mass_participation")


def check_yielding_stories(deck: Deck, engine: Engine, support: str) -> None:
    """A building whose stories yield: refused by an engine that does not model them, beyond the exact
    engine's contact pattern (registry.strength_refusal) or with fewer modes than stories (docs/theory.md
    15.4, 15.6): one InputError naming the deck field or --set."""
    building = deck.system.building
    if not building.yields:
        return
    refusal = strength_refusal(engine.name, deck.system, support)
    if refusal is not None:
        path = f"{refusal[0]}.{refusal[1]}"
        raise InputError(*deck.blame(*((path,) if path == "foundation.elements" else STRENGTH_PATHS)), refusal[2])
    n_modes = deck.analysis.exact.n_modes
    if n_modes is not None and n_modes < building.n_stories:
        raise InputError(*deck.blame(*MODES_PATHS), f"all {building.n_stories} modes with yielding stories (got "
                         f"{n_modes}): the plastic drifts load every mode (docs/theory.md 15.4)")


def check_resources(deck: Deck, engine: Engine, support: str, motion: Any) -> None:
    """The documented limits of one analysis, checked before an engine allocates anything
    (InputError naming the deck field or --set that exceeds them):
    - response-history engines: internal steps x states within limits.MAX_STEP_STATES;
    - simplified engine on a record: the modal periods within the record's spectrum range
      (limits.shortest_period)."""
    if engine.needs_record:
        for record in (motion.records if is_suite(motion) else [motion]):  # a suite: every record
            _check_step_states(deck, engine, support, record)
        return
    from ..motion.spectra import RecordSpectrum

    if isinstance(motion, RecordSpectrum):
        _check_modal_periods(deck, motion.record)


def _check_modal_periods(deck: Deck, record: Record) -> None:
    """The simplified engine on a record: the periods of the modes it keeps within the record's
    spectrum range (limits.period_problem)."""
    n_modes = int(deck.analysis.simplified.n_modes or deck.system.modes.n_modes)
    problem = limits.period_problem(deck.system.modes.periods[:n_modes], record.dt, record.npts)
    if problem:
        raise InputError(*deck.blame(*BUILDING_PATHS, "ground_motion.dt"), f"{problem} (modal periods)")


def _check_step_states(deck: Deck, engine: Engine, support: str, record: Record) -> None:
    """Internal steps x state size of the exact engine (or the approximate one), and the steps
    alone, estimated from the deck with the engine's own step rule (the shortest governing
    period, docs/exact-engine.md), against limits.MAX_STEP_STATES, MAX_STEPS and
    MAX_STEP_STATES_SQUARED."""
    from ..engines.approximate import approximate_model
    from ..engines.exact import engine as exact
    from ..engines.exact.statespace import exact_model

    options = deck.analysis.exact
    build = approximate_model if engine.name == "approximate" else exact_model
    try:
        space, samples, steps = exact.size_estimate(deck.system, record.dt, record.npts, support, options, build)
    except ValueError as error:
        raise InputError(deck.source, "analysis.exact.n_modes", str(error)) from None
    states = space.layout.n_aug
    problem = _step_problem(steps, states)
    if problem is None:
        return
    governing = space.governing_period
    by_foundation = governing < 0.999 * float(np.min(2.0 * math.pi / space.model.omega))  # vertical or rocking
    cause, knobs = _step_cause(deck, problem, steps, states, samples, by_foundation)
    stiff = (" (a foundation this stiff against the building: check its units)"
             if by_foundation and governing < 0.01 * 2.0 * math.pi / space.model.omega[0] else "")
    raise InputError(*deck.blame(*cause, *knobs), f"{problem}: the shortest governing period is {governing:.3g} s"
                     f"{stiff} and the record has {samples:,} samples at dt = {record.dt:g} s; set a longer "
                     "analysis.exact.time_step, lower analysis.exact.steps_per_period, keep fewer modes "
                     "(analysis.exact.n_modes) or shorten the record (ground_motion.window)")


#: the deck fields that set the number of internal steps of the exact engine, named with its cause
_STEP_KNOBS = ["analysis.exact.steps_per_period", "analysis.exact.free_vibration", "ground_motion.window",
               "ground_motion.dt"]


def _step_cause(deck: Deck, problem: str, steps: int, states: int, samples: int, by_foundation: bool
                ) -> tuple[list[str], list[str]]:
    """The deck fields that cause too many internal steps x states (the cause, then the knobs that
    also set them): an explicit time step, a raised step rate, the state size, the record's own
    length, or the periods of the building (and of the foundation when it governs)."""
    options = deck.analysis.exact
    default_rate = type(options)().steps_per_period
    if options.time_step:
        return ["analysis.exact.time_step"], _STEP_KNOBS
    if options.steps_per_period > default_rate and not _step_problem(steps * default_rate // options.steps_per_period,
                                                                     states):
        return ["analysis.exact.steps_per_period"], _STEP_KNOBS  # within the limits at the default rate
    if "states^2" in problem:  # the state size: modes kept, stories, contact elements
        return ["analysis.exact.n_modes", "building.stories", "building.masses", "foundation.elements"], _STEP_KNOBS
    if steps <= samples - 1:  # one step a record sample: the record's own length, whatever the knobs
        return ["ground_motion.window", "ground_motion.record", "ground_motion.dt"], []
    return (_stiffness_paths(deck) if by_foundation else []) + list(BUILDING_PATHS), _STEP_KNOBS


def _step_problem(steps: int, states: int) -> str | None:
    """The words of the first limit of the exact engine that `steps` internal steps of a state of
    `states` exceed (None: within them)."""
    return limits.step_states_problem(steps, states) or limits.steps_problem(steps, states)


def _spectrum_range_error(deck: Deck, result):
    """A design spectrum asked for a period outside its table (its own InputError names the
    spectrum's source and 'period', not a deck field): named as the deck field that gave the
    spectrum, or the building field that set the period."""
    if not (isinstance(result, InputError) and result.location == "period"
            and result.source == str(getattr(deck.spectrum, "source", None))):
        return result
    return InputError(*deck.blame("ground_motion.design_spectrum", *BUILDING_PATHS),
                      f"{result.expected} (a period of the building's modes or its effective period T1bar)")


def with_warnings(result: AnalysisResult, warnings: Sequence[str]) -> AnalysisResult:
    """The result with `warnings` before its own in details["warnings"]: a new result (a result is
    not changed once built, engines/result.py)."""
    return replace(result, details={**result.details, "warnings": [*warnings, *result.details.get("warnings", [])]})


def run_batch(decks: Sequence[Deck], engine: str, support: str,
              on_result: Callable[[int, AnalysisResult | Exception], None] | None = None, single: bool = False,
              ) -> list[AnalysisResult | Exception]:
    """One engine, one support ("rigid", "bonded" or "uplift") for several decks: the result
    of each or the error that stopped it, also passed to on_result(index, result) as soon as
    it is known.

    Decks that share the ground motion and the engine options are analysed together (the
    exact engine shares work across them); results equal one-at-a-time analysis, bit for bit.
    A suite is run one batch per record (analysis_suite.iter_suite_batch): decks whose suites
    have the same scaled records share those batches. The simplified engine's results carry the
    design spectrum's warning for a modal procedure (design_spectra.procedure_warning); every
    result carries its deck's warnings (Deck.warnings: values far outside building practice).
    Exact runs whose stories or soil yield are compared with a perturbed twin where their deck
    asks (analysis/residuals.py; single: one analysis, not a sweep's batch); their results are then
    passed to on_result once the twins are done. The twins start from the step operators of their
    originals (engines/exact/reuse.py: a store made here, dropped on return)."""
    chosen = _engine(decks, engine)
    if not residuals.asked(chosen.name, decks, single):
        return _run(decks, chosen, support, on_result)
    from ..engines.exact.reuse import OperatorStore  # the exact engine's: loaded when it runs

    store = OperatorStore()
    rerun = functools.partial(_run, chosen=chosen, support=support, store=store.twins())
    out = residuals.checked(decks, _run(decks, chosen, support, store=store), rerun, single)
    for k, result in enumerate(out if on_result else ()):
        on_result(k, result)
    return out


def _engine(decks: Sequence[Deck], engine: str) -> Engine:
    """The engine named `engine`; InputError naming analysis.engine if there is none."""
    if engine not in ENGINES:
        raise InputError(decks[0].source if decks else "engine", "analysis.engine",
                         f"one of {', '.join(ENGINES)}, got {engine!r}")
    return ENGINES[engine]


def _run(decks: Sequence[Deck], chosen: Engine, support: str,
         on_result: Callable[[int, AnalysisResult | Exception], None] | None = None,
         store: Any = None) -> list[AnalysisResult | Exception]:
    """run_batch without the check of the residuals (store: the exact engine's step operators kept
    for the twins, engines/exact/reuse.py)."""
    results = _Results(decks, on_result)
    groups, motions = _groups(decks, chosen, support, results)
    for (_, options), members in groups.items():
        _run_group(chosen, members, motions[members[0]], support, options, results, store)
    return results.out


class _Results:
    """The result (or the error) of each deck of a batch, in the decks' order, each passed to
    on_result(index, result) as soon as it is known."""

    def __init__(self, decks: Sequence[Deck], on_result: Callable[[int, AnalysisResult | Exception], None] | None):
        self.decks = decks
        self.on_result = on_result
        self.out: list[AnalysisResult | Exception] = [None] * len(decks)  # type: ignore[list-item]

    def keep(self, k: int, result: AnalysisResult | Exception) -> None:
        """Keep the result of deck k: a spectrum's period error named as a deck field, the deck's own
        warnings first (deck_schema.plausibility)."""
        deck = self.decks[k]
        result = _spectrum_range_error(deck, result)
        if isinstance(result, AnalysisResult):
            result = with_design(with_level(result, deck.ground_motion), deck.design)  # [design]: engines/design.py
        if isinstance(result, AnalysisResult) and deck.warnings:
            result = with_warnings(result, deck.warnings)
        self.out[k] = result
        if self.on_result:
            self.on_result(k, result)


def _groups(decks: Sequence[Deck], chosen: Engine, support: str, results: _Results
            ) -> tuple[dict[tuple, list[int]], dict[int, Any]]:
    """The decks that can run, grouped by (ground motion, engine options), and the ground motion of
    each; a deck that cannot (ground_motion_for, check_before_running) has its error kept."""
    groups: dict[tuple, list[int]] = {}
    motions: dict[int, Any] = {}
    for k, deck in enumerate(decks):
        try:
            motions[k] = ground_motion_for(deck, chosen)
            check_before_running(deck, chosen, support, motions[k])
        except InputError as error:
            results.keep(k, error)
            continue
        motion = motions[k]
        key = _suite_key(motion) if is_suite(motion) else id(motion)
        groups.setdefault((key, getattr(deck.analysis, chosen.options)), []).append(k)
    return groups, motions


def _run_group(chosen: Engine, members: list[int], motion: Any, support: str, options: Any, results: _Results,
               store: Any = None) -> None:
    """Run the decks `members` (indices into results.decks) that share a ground motion and engine
    options, keeping each result; AnalysisError for an arithmetic or memory error on the way."""
    decks = [results.decks[k] for k in members]
    try:
        for j, result in _group_batch(chosen, decks, motion, support, options, store):
            results.keep(members[j], result)
    except (ArithmeticError, MemoryError) as error:  # the last guard: magnitudes the checks let through
        raise AnalysisError(f"{decks[0].source}: the {chosen.name} analysis ({support}) failed with "
                            f"{type(error).__name__} ({error}); check the magnitudes of the deck's fields"
                            ) from None


def _group_batch(chosen: Engine, decks: list[Deck], motion: Any, support: str, options: Any,
                 store: Any = None):
    """The (index in decks, result) pairs of one group: one batch per record of a suite
    (analysis_suite.iter_suite_batch), else the engine's own batch."""
    if is_suite(motion):
        from . import suite as analysis_suite  # a record suite's: loaded with its deck

        return analysis_suite.iter_suite_batch(chosen, decks, motion, support, options, store)
    return chosen.iter_batch([deck.system for deck in decks], motion, support, options, store)


def run_one(deck: Deck, engine: str, support: str, single: bool = True) -> AnalysisResult:
    """One engine, one support condition; raises the error that stopped it. single: a single
    analysis, whose residuals are checked (analysis/residuals.py); False for a reference run."""
    (result,) = run_batch([deck], engine, support, single=single)
    if not isinstance(result, AnalysisResult):
        raise result
    return result


def run(deck: Deck, engine: str | Sequence[str] | None = None,
        supports: str | Sequence[str] | None = None) -> list[AnalysisResult]:
    """Every requested engine x support (default: those of the deck), engines outermost."""
    engines = _names(engine, deck.analysis.engines)
    support_list = _names(supports, deck.analysis.supports)
    return [run_one(deck, name, support) for name in engines for support in support_list]


def _names(asked: str | Sequence[str] | None, default: Sequence[str]) -> list[str]:
    """One name or several as a list; the default when none is asked."""
    return [asked] if isinstance(asked, str) else list(asked or default)


def _suite_key(motion) -> Any:
    """A suite's key among the motions of a batch (analysis/suite.motion_key)."""
    from .suite import motion_key

    return motion_key(motion)
