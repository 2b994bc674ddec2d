"""Exact engine: nonlinear response history of the N + 2 equations (docs/theory.md sections 3-5).

The modal equations [11a-11c] are linear in each contact state; each state is integrated
with its exact step operator (matrix exponential of the augmented state matrix, exact for
piecewise-linear ground acceleration), contact transitions are located inside the step
(stepping_kernels.py) and the step restarts from there in the new state. A massless mat
with all modes makes the rocking equation a first-order constraint, handled exactly in the
coordinates W = Y* + h* theta (statespace.py); no artificial inertia is added.

The walk of one run: the model and its state space (statespace.py), the stepping
(stepping.py), the responses and energy read off the history (response.py, energy.py).
See docs/exact-engine.md for the choices and their measurements.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from threadpoolctl import ThreadpoolController

from ...errors import AnalysisError, InputError
from ...model.building import building_key
from ...model.system import System
from ...runtime.limits import MAX_STEP_STATES, steps_problem
from ..options import ExactOptions
from ..registry import check_support
from ..result import AnalysisResult
from .digest import Digest
from .operators import Operators
from .reuse import OperatorStore, Twins, digest_for, store_key
from .statespace import StateSpace, exact_model
from .stepping import simulate

_controller: ThreadpoolController | None = None


def one_blas_thread():
    """Context manager limiting BLAS to one thread.

    The engine multiplies many small matrices; OpenBLAS threads on them cost up to 100x
    on a loaded 2-core machine. Parallelism belongs to the batch (sweep workers) instead.
    """
    global _controller
    if _controller is None:
        _controller = ThreadpoolController()
    return _controller.limit(limits=1, user_api="blas")


#: a step count beyond this cannot be afforded: the analysis is refused with a message
MAX_STEPS = 20_000_000


def substeps_for(space: StateSpace, dt: float, options: ExactOptions) -> int:
    """Internal steps per record step: the step is at most the governing period / steps_per_period."""
    target = options.time_step or space.governing_period / options.steps_per_period
    return max(1, math.ceil(dt / target - 1e-9))


def _checked_acceleration(acceleration: np.ndarray, dt: float, options: ExactOptions) -> np.ndarray:
    acceleration = np.asarray(acceleration, dtype=float)
    if acceleration.size < 2:
        raise AnalysisError("the record is too short: at least two samples are needed")
    if options.free_vibration > 0.0:
        acceleration = np.concatenate((acceleration, np.zeros(math.ceil(options.free_vibration / dt))))
    return acceleration


def _checked_substeps(space: StateSpace, samples: int, dt: float, options: ExactOptions) -> int:
    substeps = substeps_for(space, dt, options)
    if substeps * (samples - 1) > MAX_STEPS:
        raise AnalysisError(
            f"{substeps * (samples - 1):,} steps would be needed (more than {MAX_STEPS:,}); "
            "raise analysis.exact.time_step or lower steps_per_period"
        )
    return substeps


#: builds the state-space model of a system for a support (statespace.exact_model, or the
#: approximate engine's)
ModelBuilder = Callable[[System, str, ExactOptions], StateSpace]

#: the models built last, (id(system), support, options, builder) -> (system, model): the size
#: check before an analysis (size_estimate) and the analysis build each model once. The entry
#: holds the system, so its id cannot be reused while it is kept.
_MODELS: dict[tuple, tuple[System, StateSpace]] = {}
MODELS_KEPT = 16


def model_for(system: System, support: str, options: ExactOptions, model: ModelBuilder = exact_model) -> StateSpace:
    """model(system, support, options), built once for the last MODELS_KEPT requests."""
    key = (id(system), support, options, model)
    kept = _MODELS.get(key)
    if kept is not None and kept[0] is system:
        return kept[1]
    space = model(system, support, options)
    while len(_MODELS) >= MODELS_KEPT:
        _MODELS.pop(next(iter(_MODELS)))
    _MODELS[key] = (system, space)
    return space


def size_estimate(system: System, dt: float, samples: int, support: str, options: ExactOptions,
                  model: ModelBuilder = exact_model) -> tuple[StateSpace, int, int]:
    """(model, record samples with the free vibration, internal steps) of an analysis of a
    record of `samples` samples at step dt [s], before anything is allocated."""
    space = model_for(system, support, options, model)
    if options.free_vibration > 0.0:
        samples += math.ceil(options.free_vibration / dt)
    return space, samples, substeps_for(space, dt, options) * (samples - 1)


def _rigid_key(system: System) -> tuple:
    """What a fixed-base analysis depends on: the building, m_t, g (and I_0, kept for safety);
    never the foundation or the mat width (only V_c and M_c, replaced per system)."""
    return (*building_key(system.building), system.total_mass, system.gravity, system.mat_rotary_inertia)


def iter_batch(systems: list[System], record, support: str, options: ExactOptions | None = None, *,
               model: ModelBuilder = exact_model, name: str = "exact", refine: bool = True,
               operators: OperatorStore | Twins | None = None,
               ) -> Iterator[tuple[int, AnalysisResult | AnalysisError | InputError]]:
    """Peak responses of several systems to one record, one support: yields (index, result
    or the error that stopped it) as each is known; the others go on. Same results, bit for
    bit, as analyze one at a time; the work the systems share is done once:
    - rigid base: one analysis per distinct building (and m_t, g, I_0), whatever the foundation;
    - the fine ground-motion grid per step size;
    - the runs are stepped together in rounds and the contact states they reach in a round
      are assembled and exponentiated vectorised over the batch (operators.add_states).
    model: the state-space model of a system (exact_model; the approximate engine couples
    mode 1 only); name: the engine named in the results; refine: halve the step where the
    energy balance does not close (_refined); operators: a check of the residuals' store of step
    operators (reuse.py): an OperatorStore keeps those of the runs that yield, its twins() start each run
    from its original's (each gives its residuals only: reuse.digest_for); None: each run builds its own."""
    options = options or ExactOptions()
    check_support(support)
    acceleration = _checked_acceleration(record.acceleration, record.dt, options)
    shared = _shared_analyses(systems, support)
    with one_blas_thread():
        runs: list[tuple[int, StateSpace, int]] = []  # (system, its model, sub-steps per record step)
        for k in shared:
            try:
                space = model_for(systems[k], support, options, model)
                runs.append((k, space, _checked_substeps(space, acceleration.size, record.dt, options)))
            except (AnalysisError, InputError) as error:
                yield from _outcomes(systems, shared, k, error)
        fold = digest_for(operators)  # a twin's: its residuals only (reuse.py)
        digests = [fold(systems[k], space, options) for k, space, _ in runs]
        kept = _Kept(operators, systems, runs, record.dt, support, options, model)
        histories = simulate([space for _, space, _ in runs], [substeps for _, _, substeps in runs], acceleration,
                             record.dt, options.criterion, uplift=support == "uplift",
                             allow_flight=options.flight == "allow", on_chunk=[d.add for d in digests],
                             operators=kept.starts)
        for j, history in histories:
            k = runs[j][0]
            outcome = _finished(systems[k], digests[j], history, record, support, options, model, name, refine)
            digests[j] = None  # its histories go with its result
            kept.done(j, outcome)
            yield from _outcomes(systems, shared, k, outcome)


class _Kept:
    """The step operators the runs of iter_batch start from, and what becomes of them, with a store
    (reuse.py; without one every run builds its own: starts is None). runs: (system index, model,
    sub-steps per record step) of each run."""

    def __init__(self, store: OperatorStore | Twins | None, systems: list[System],
                 runs: list[tuple[int, StateSpace, int]], dt: float, support: str, options: ExactOptions,
                 model: ModelBuilder):
        self.store = store
        self.systems = [systems[k] for k, _, _ in runs]
        self.keys: list[tuple] = []
        self.starts: list[Operators | None] | None = None
        if store is not None:
            self._started(store, runs, dt, support, options, model)

    def _started(self, store: OperatorStore | Twins, runs: list[tuple[int, StateSpace, int]], dt: float,
                 support: str, options: ExactOptions, model: ModelBuilder) -> None:
        """The key of each run (reuse.store_key) and the operators it starts from (_start)."""
        self.keys = [store_key(system, support, options, model, dt / substeps)
                     for system, (_, _, substeps) in zip(self.systems, runs, strict=True)]
        self.starts = [_start(store, key, system, space, dt / substeps, options.criterion, support)
                       for key, system, (_, space, substeps) in zip(self.keys, self.systems, runs, strict=True)]

    def done(self, j: int, outcome: Any) -> None:
        """Run j has ended with `outcome`: its operators to the store (its done), and dropped here."""
        if self.starts is not None:
            self.store.done(self.keys[j], self.systems[j], self.starts[j], outcome)
            self.starts[j] = None


def _start(store: OperatorStore | Twins, key: tuple, system: System, space: StateSpace, h: float, criterion: str,
           support: str) -> Operators:
    """The operators a run starts from: a twin's, a fork of its original's (Twins.start), else new ones, made
    as stepping.Run makes them."""
    taken = store.start(key, system)
    return Operators(space, h, criterion, support == "uplift") if taken is None else taken


def _finished(system: System, digest: Digest, history: Any, record, support: str, options: ExactOptions,
              model: ModelBuilder, name: str, refine: bool) -> AnalysisResult | AnalysisError:
    """The result of a run from its digest and its last chunk `history` (iter_batch), with the step refined
    (_refined) if asked and the energy balance does not close; the error that stopped the run as it is."""
    if isinstance(history, AnalysisError):
        return history
    digest.add(history)  # the last chunk
    result = digest.result(support, name)
    if refine and result.intermediates["energy_residual"] > ENERGY_TOLERANCE:
        return _refined(system, record, support, options, model, name, result)
    return result


def _shared_analyses(systems: list[System], support: str) -> dict[int, list[int]]:
    """Representative system -> the others that share its analysis: on a rigid base every system of one
    building (and m_t, g, I_0: _rigid_key), whatever the foundation; none on a flexible one."""
    if support != "rigid":
        return {k: [] for k in range(len(systems))}
    groups: dict[tuple, list[int]] = {}
    for k, system in enumerate(systems):
        groups.setdefault(_rigid_key(system), []).append(k)
    return {members[0]: members[1:] for members in groups.values()}


def _outcomes(systems: list[System], shared: dict[int, list[int]], k: int, outcome: Any
              ) -> Iterator[tuple[int, Any]]:
    """(index, outcome) of system k and of the systems that share its analysis (a result made theirs)."""
    yield k, outcome
    for other in shared[k]:
        yield other, outcome.for_system(systems[other]) if isinstance(outcome, AnalysisResult) else outcome


#: the energy balance must close to this fraction of the input work; beyond, the step is refined
ENERGY_TOLERANCE = 1e-3
#: a halving of the internal step that leaves more than this fraction of the residual shows the
#: step is not the cause (the residual of a converging step falls by 4 or more): no further
#: halving is tried. The runs of one analysis are bounded by limits.MAX_STEP_STATES in all and
#: by limits.MAX_STEPS and MAX_STEP_STATES_SQUARED each (runtime/limits.py)
MIN_PROGRESS = 0.9


def _work(system: System, record, support: str, options: ExactOptions, model: ModelBuilder) -> int:
    """Internal steps x (state size + 2) of one run (limits.step_states_problem's measure)."""
    space, _, steps = size_estimate(system, record.dt, np.asarray(record.acceleration).size, support, options, model)
    return steps * (space.layout.n_aug + 2)


def _run_problem(system: System, record, support: str, options: ExactOptions, model: ModelBuilder) -> str | None:
    """The words of the limit one run with `options` would exceed (limits.steps_problem), or None."""
    space, _, steps = size_estimate(system, record.dt, np.asarray(record.acceleration).size, support, options, model)
    return steps_problem(steps, space.layout.n_aug)


def finer_options(system: System, record, support: str, options: ExactOptions, model: ModelBuilder = exact_model
                  ) -> ExactOptions:
    """`options` with steps_per_period doubled until the internal step is finer: where the record's
    step governs (one internal step a sample), doubling 6 to 12 steps per period leaves the step
    as it was, and its residual with it (issue 36: such a deck was refused, 24 ran)."""
    space = model_for(system, support, options, model)
    current = substeps_for(space, record.dt, options)
    finer = replace(options, steps_per_period=options.steps_per_period * 2)
    while substeps_for(space, record.dt, finer) == current:
        finer = replace(finer, steps_per_period=finer.steps_per_period * 2)
    return finer


@dataclass
class _Refinement:
    """The state of the step refinement of one analysis (_refined): its options, its last result
    and residual, the residual it started from, the work spent and why it stopped."""

    options: ExactOptions
    result: AnalysisResult
    first: float
    spent: int
    stopped: str = ""

    @property
    def residual(self) -> float:
        return self.result.intermediates["energy_residual"]


def _halved(refinement: _Refinement, system: System, record, support: str, model: ModelBuilder,
            name: str) -> AnalysisError | None:
    """One halving of the internal step in `refinement` (its options, result and work), or the
    reason it cannot be run (refinement.stopped); an AnalysisError of the finer run as it is."""
    finer = finer_options(system, record, support, refinement.options, model)
    cost = _work(system, record, support, finer, model)
    problem = _run_problem(system, record, support, finer, model)
    if problem is None and refinement.spent + cost > MAX_STEP_STATES:
        problem = (f"at most {MAX_STEP_STATES:,} internal steps x states of one analysis, its refinements "
                   f"included, got {refinement.spent + cost:,}")
    if problem is not None:
        refinement.stopped = f"{finer.steps_per_period} steps per period would exceed the limits ({problem})"
        return None
    ((_, result),) = tuple(iter_batch([system], record, support, finer, model=model, name=name, refine=False))
    if not isinstance(result, AnalysisResult):
        return result
    previous = refinement.residual
    refinement.options, refinement.result, refinement.spent = finer, result, refinement.spent + cost
    if refinement.residual > MIN_PROGRESS * previous:
        refinement.stopped = f"a halving of the step left it at {refinement.residual / previous:.3g} of its value"
    return None


def _refined(system: System, record, support: str, options: ExactOptions, model: ModelBuilder, name: str,
             result: AnalysisResult) -> AnalysisResult | AnalysisError:
    """The analysis again with the internal step halved (finer_options) until the energy balance
    closes to ENERGY_TOLERANCE (never a silent large residual), within the limits of
    runtime/limits.py; an AnalysisError naming the field to set when it does not, or when the
    user fixed the step (analysis.exact.time_step). A halving that does not lower the residual
    (MIN_PROGRESS) ends the refinement (a contact chatter with almost no damping ran 16 s per
    run and 240 s in all, its residual unchanged)."""
    if options.time_step is not None:
        return AnalysisError(f"the energy balance closes only to {result.intermediates['energy_residual']:.2g} of the "
                             f"input work (tolerance {ENERGY_TOLERANCE:g}) with analysis.exact.time_step = "
                             f"{options.time_step:g} s: set a finer analysis.exact.time_step")
    refinement = _Refinement(options, result, result.intermediates["energy_residual"],
                             _work(system, record, support, options, model))
    while refinement.residual > ENERGY_TOLERANCE and not refinement.stopped:
        error = _halved(refinement, system, record, support, model, name)
        if error is not None:
            return error
    if refinement.residual > ENERGY_TOLERANCE:
        return AnalysisError(_unreached(refinement, options, system, record, support, model))
    steps = refinement.options.steps_per_period
    refined = (f"the energy balance closed to {refinement.residual:.2g} only after refining the step to {steps} "
               f"steps per governing period (analysis.exact.steps_per_period = {options.steps_per_period})")
    result = refinement.result
    return replace(result, intermediates={**result.intermediates, "steps_per_period": steps},
                   details={**result.details, "warnings": [*result.details.get("warnings", []), refined]})


def _unreached(refinement: _Refinement, options: ExactOptions, system: System, record, support: str,
               model: ModelBuilder) -> str:
    """The words of a refinement that did not close the balance: what it reached, why it stopped,
    and the field that would close it (a larger steps_per_period, if one run of it fits the limits)."""
    steps = refinement.options.steps_per_period
    head = (f"the energy balance closes only to {refinement.residual:.2g} of the input work (tolerance "
            f"{ENERGY_TOLERANCE:g}) with {steps} steps per governing period")
    if steps > options.steps_per_period:
        head += f" (refined from {options.steps_per_period}, where it was {refinement.first:.2g})"
    if steps > options.steps_per_period and refinement.residual > MIN_PROGRESS * refinement.first:
        return f"{head}; {refinement.stopped}: the step is not the cause"
    finer = finer_options(system, record, support, refinement.options, model)
    if _run_problem(system, record, support, finer, model) is None and _work(
            system, record, support, finer, model) <= MAX_STEP_STATES:
        return f"{head}; {refinement.stopped}: set analysis.exact.steps_per_period = {finer.steps_per_period}"
    return (f"{head}; {refinement.stopped}: no step within the limits reaches it (a finer step fits them "
            "only on a shorter record: ground_motion)")


def analyze_batch(systems: list[System], record, support: str, options: ExactOptions | None = None,
                  **model) -> list[AnalysisResult | AnalysisError | InputError]:
    """iter_batch as a list in the order of `systems`."""
    out: list = [None] * len(systems)
    for k, result in iter_batch(systems, record, support, options, **model):
        out[k] = result
    return out


def analyze(system: System, record, support: str, options: ExactOptions | None = None, **model) -> AnalysisResult:
    """Exact peak response of the system to the record (acceleration [m/s^2], dt [s])."""
    (result,) = analyze_batch([system], record, support, options, **model)
    if not isinstance(result, AnalysisResult):
        raise result
    return result
