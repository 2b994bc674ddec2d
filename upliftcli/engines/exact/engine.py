"""Exact engine: nonlinear response history of the N + 2 equations (THEORY.md sections 3-5).

The modal equations [11a-11c] are linear in each contact state; each state is integrated
with its exact step operator (matrix exponential of the augmented state matrix, exact for
piecewise-linear ground acceleration), contact transitions are located inside the step
(kernel.py) and the step restarts from there in the new state. A massless mat with all
modes makes the rocking equation a first-order constraint, handled exactly in the
coordinates W = Y* + h* theta (statespace.py); no artificial inertia is added.
See docs/exact-engine.md for the choices and their measurements.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Iterator
from dataclasses import replace
from typing import Any

import numpy as np

from ...errors import AnalysisError, InputError
from ...model.building import building_key
from ...model.system import System
from .. import one_blas_thread
from ..options import ExactOptions
from ..registry import check_support
from ..result import AnalysisResult
from .response import (
    energy_balance,
    hermite_peaks,
    interval_lengths,
    lifted_flags,
    response_maps,
    signals,
    time_at,
    uplift_summary,
)
from .statespace import ModalModel
from .stepping import History, Run, ground_grid, simulate_many

#: intermediates of the response-history engines: name -> (unit, meaning)
INTERMEDIATES = {
    "T1": ("s", "fixed-base fundamental period T_1"),
    "n_modes": ("-", "fixed-base modes in the model"),
    "time_step": ("s", "internal step h (exact step operator; crossings located inside it)"),
    "criterion": ("-", "uplift criterion [4a] reaction or [4b] displacement"),
    "rotation_inertia": ("kg m^2", "inertia of the mat rotation (0: first-order rocking constraint)"),
    "samples": ("-", "history samples: every step plus every contact transition"),
    "transitions": ("-", "contact transitions (lift-off and recontact of elements)"),
    "base_shear_time": ("s", "time of the peak base shear"),
    "base_moment_time": ("s", "time of the peak base moment"),
    "uplift_time": ("s", "total time with at least one element lifted"),
    "episodes": ("-", "uplift episodes (contact lost after full contact)"),
    "max_rotation": ("rad", "largest mat rotation |theta|"),
    "max_uplift_left": ("m", "largest gap under the left edge"),
    "max_uplift_right": ("m", "largest gap under the right edge"),
    "min_reaction": ("N", "smallest reaction of an element in contact (< 0: tension)"),
    "energy_residual": ("-", "energy balance residual / input energy"),
}
#: a step count beyond this cannot be afforded: the analysis is refused with a message
MAX_STEPS = 20_000_000


def modal_model(system: System, support: str, n_modes: int, coupled_modes: int | None = None,
                residual_inertia: str = "neglect", approximate: bool = False) -> ModalModel:
    """ModalModel of the N + 2 equations [11] (or of the paper's approximation [17-20])."""
    modes = system.modes.truncated(n_modes)
    flexible = support != "rigid"
    coupled = np.zeros(n_modes, dtype=bool)
    if flexible:
        coupled[: (n_modes if coupled_modes is None else coupled_modes)] = True
    mh = modes.effective_mass * modes.effective_height
    b = system.building
    structure_inertia = float(np.sum(b.masses * b.heights**2))
    theta_inertia = system.mat_rotary_inertia
    first_moment_residual = 0.0
    if flexible and not approximate and residual_inertia == "include":
        theta_inertia += max(structure_inertia - float(np.sum(mh * modes.effective_height)), 0.0)
        first_moment_residual = system.first_moment - float(np.sum(mh))
    if theta_inertia < 1e-12 * structure_inertia:
        theta_inertia = 0.0
    if abs(first_moment_residual) < 1e-12 * system.first_moment:
        first_moment_residual = 0.0
    elements = system.foundation.contact_elements(system.half_width, float(modes.omega[0])) if flexible else None
    return ModalModel(modes.omega, modes.damping, modes.effective_mass, modes.effective_height, coupled,
                      theta_inertia, first_moment_residual, system.total_mass, system.gravity, elements)


def governing_period(system: System, model: ModalModel) -> float:
    """Shortest period the sampling must resolve [s]: T_1, the bonded vertical period, and
    every mode with at least 1 % of the total mass."""
    periods = [2.0 * math.pi / model.omega[0]]
    heavy = model.effective_mass >= 0.01 * system.total_mass
    periods.extend((2.0 * math.pi / model.omega[heavy]).tolist())
    if model.flexible:
        periods.append(2.0 * math.pi * math.sqrt(system.total_mass / model.elements.stiffness.sum()))
        if model.theta_inertia > 0.0:
            rocking = float(np.sum(model.elements.stiffness * model.elements.positions**2))
            periods.append(2.0 * math.pi * math.sqrt(model.theta_inertia / rocking))
    return min(periods)


def substeps_for(system: System, model: ModalModel, dt: float, options: ExactOptions) -> int:
    target = options.time_step or governing_period(system, model) / options.steps_per_period
    return max(1, math.ceil(dt / target - 1e-9))


def resolve_modes(system: System, n_modes: int | None) -> int:
    n = system.building.n_stories
    if n_modes is None:
        return n
    if not 1 <= int(n_modes) <= n:
        raise ValueError(f"n_modes must be an integer from 1 to {n}, got {n_modes!r}")
    return int(n_modes)


def _checked_acceleration(acceleration: np.ndarray, dt: float, options: ExactOptions) -> np.ndarray:
    acceleration = np.asarray(acceleration, dtype=float)
    if acceleration.size < 2:
        raise AnalysisError("the record is too short: at least two samples are needed")
    if options.free_vibration > 0.0:
        acceleration = np.concatenate((acceleration, np.zeros(math.ceil(options.free_vibration / dt))))
    return acceleration


def _checked_substeps(system: System, model: ModalModel, samples: int, dt: float, options: ExactOptions) -> int:
    substeps = substeps_for(system, model, dt, options)
    if substeps * (samples - 1) > MAX_STEPS:
        raise AnalysisError(
            f"{substeps * (samples - 1):,} steps would be needed (more than {MAX_STEPS:,}); "
            "raise analysis.exact.time_step or lower steps_per_period"
        )
    return substeps


def summarize(system: System, history: History, support: str, engine: str, options: ExactOptions,
              shapes_star: np.ndarray) -> AnalysisResult:
    """Peak responses, uplift summary, energy balance and (optionally) histories."""
    model = history.model
    maps = response_maps(system.building, shapes_star, model.omega)
    sig = signals(history)
    modal = maps.modal_base_shear
    # peaks of the instant-by-instant sums of modes 1..k (paper Fig. 7)
    rows = np.vstack((maps.stacked(), np.tril(np.ones_like(modal)) @ modal))
    n = system.building.n_stories
    # shortest period that matters in each response: the governing one, or the mode's own
    # period for a single mode's base shear (modes above the governing band are searched more)
    mode_periods = 2.0 * math.pi / model.omega
    governing = governing_period(system, model)
    periods = np.concatenate((np.full(4 * n, governing), mode_periods, np.maximum(mode_periods, governing)))
    peaks, where = hermite_peaks(sig, rows, interval_lengths(history), periods)
    displacement, drift, shear, moment = (peaks[k * n:(k + 1) * n] for k in range(4))
    modal_shear = peaks[4 * n:4 * n + model.n_modes]
    cumulative_shear = peaks[4 * n + model.n_modes:]
    summary = uplift_summary(history, sig)
    uplifted = bool(lifted_flags(history).any()) if history.layout.n_elements else False
    energy = energy_balance(history, sig)
    details = {
        "modal_base_shear": modal_shear.tolist(),
        "cumulative_modal_base_shear": cumulative_shear.tolist(),
        "uplift_summary": summary,
        "energy": energy,
    }
    if options.histories:
        details["histories"] = histories(system, history, maps, sig)
    intermediates = {
        "T1": float(system.modes.periods[0]),
        "n_modes": model.n_modes,
        "time_step": history.time_step,
        "criterion": options.criterion,
        "rotation_inertia": model.theta_inertia,
        "samples": int(history.times.size),
        "transitions": int(np.count_nonzero(np.diff(history.state_ids))),
        "base_shear_time": time_at(history, where[2 * n]),
        "base_moment_time": time_at(history, where[3 * n]),
        "energy_residual": energy["relative_residual"],
    }
    for name in ("uplift_time", "episodes", "max_rotation", "max_uplift_left", "max_uplift_right", "min_reaction"):
        if name in summary:
            intermediates[name] = summary[name]
    return AnalysisResult(
        engine=engine, support=support, heights=system.building.heights.copy(),
        displacement=displacement, drift=drift, drift_ratio=drift / system.building.story_heights,
        shear=shear, moment=moment, base_shear=float(shear[0]), base_moment=float(moment[0]),
        critical_base_shear=system.critical_base_shear, critical_base_moment=system.critical_base_moment,
        weight=system.weight, effective_height=system.effective_height, uplift=uplifted,
        periods=system.modes.periods[: model.n_modes].copy(), intermediates=intermediates, details=details,
    )


def histories(system: System, history: History, maps, sig) -> dict[str, np.ndarray]:
    """Time histories at every sample (SI units) for --histories."""
    model = history.model
    y = sig["Y"]
    out = {
        "time": history.times,
        "ground_acceleration": sig["a"][:, 0],
        "base_shear": y @ maps.shear[0],
        "base_moment": y @ maps.moment[0],
        "roof_displacement": y @ maps.displacement[-1],
    }
    if model.flexible:
        out["theta"] = sig["theta"][:, 0]
        out["v"] = sig["v"][:, 0]
        out["left_edge_displacement"] = sig["element_displacement"][:, 0]
        out["right_edge_displacement"] = sig["element_displacement"][:, -1]
        patterns = np.array([sum(int(f) << i for i, f in enumerate(c.lifted)) for c in history.contact])
        out["contact_state"] = patterns[history.state_ids]
    drifts = y @ maps.drift.T
    for j in range(system.building.n_stories):
        out[f"drift_{j + 1}"] = drifts[:, j]
    return out


def exact_model(system: System, support: str, options: ExactOptions) -> ModalModel:
    """The exact engine's model: every mode kept is coupled with the mat [11a-11c]."""
    n_modes = resolve_modes(system, options.n_modes)
    return modal_model(system, support, n_modes, residual_inertia=options.residual_inertia)


#: builds the modal model of a system for a support (exact_model, or the approximate engine's)
ModelBuilder = Callable[[System, str, ExactOptions], ModalModel]


def _rigid_key(system: System) -> tuple:
    """What a fixed-base analysis depends on: the building, m_t, g (and I_0, kept for safety);
    never the foundation or the mat width (only V_c and M_c, replaced per system)."""
    return (*building_key(system.building), system.total_mass, system.gravity, system.mat_rotary_inertia)


#: memory allowed for the sample buffers of the runs of a batch stepped together [bytes]
BATCH_MEMORY = 256 * 2**20


def iter_batch(systems: list[System], record, support: str, options: ExactOptions | None = None, *,
               model: ModelBuilder = exact_model, name: str = "exact",
               ) -> Iterator[tuple[int, AnalysisResult | AnalysisError | InputError]]:
    """Peak responses of several systems to one record, one support: yields (index, result
    or the error that stopped it) as each is known; the others go on. Same results, bit for
    bit, as analyze one at a time; the work the systems share is done once:
    - rigid base: one analysis per distinct building (and m_t, g, I_0), whatever the foundation;
    - the fine ground-motion grid per step size;
    - the runs are stepped together in rounds and the contact states they reach in a round
      are assembled and exponentiated vectorised over the batch (simulate.add_states).
    model: the modal model of a system (exact_model; the approximate engine couples mode 1
    only); name: the engine named in the results."""
    options = options or ExactOptions()
    check_support(support)
    acceleration = _checked_acceleration(record.acceleration, record.dt, options)
    shared: dict[int, list[int]] = {k: [] for k in range(len(systems))}  # representative -> the same analysis
    if support == "rigid":
        groups: dict[tuple, list[int]] = {}
        for k, system in enumerate(systems):
            groups.setdefault(_rigid_key(system), []).append(k)
        shared = {members[0]: members[1:] for members in groups.values()}

    def outcomes(k: int, outcome) -> Iterator[tuple[int, Any]]:
        yield k, outcome
        for other in shared[k]:
            yield other, _for_system(outcome, systems[other]) if isinstance(outcome, AnalysisResult) else outcome

    with one_blas_thread():
        grids: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        pending: list[tuple[int, Run]] = []
        for k in shared:
            try:
                built = model(systems[k], support, options)
                substeps = _checked_substeps(systems[k], built, acceleration.size, record.dt, options)
                if substeps not in grids:
                    grids[substeps] = ground_grid(acceleration, substeps, record.dt)
                pending.append((k, Run(built, *grids[substeps], record.dt / substeps, options.criterion,
                                       uplift=support == "uplift", allow_flight=options.flight == "allow")))
            except (AnalysisError, InputError) as error:
                yield from outcomes(k, error)
        while pending:
            size, used = 1, pending[0][1].buffer_bytes
            while size < len(pending) and used + pending[size][1].buffer_bytes <= BATCH_MEMORY:
                used += pending[size][1].buffer_bytes
                size += 1
            order = [k for k, _ in pending[:size]]
            histories = simulate_many([run for _, run in pending[:size]])
            del pending[:size]  # the runs live in simulate_many only: each one's buffers go when it ends
            for j, history in histories:
                k = order[j]
                if not isinstance(history, AnalysisError):
                    history = summarize(systems[k], history, support, name, options,
                                        systems[k].modes.shapes_star[:, :history.model.n_modes])
                yield from outcomes(k, history)


def analyze_batch(systems: list[System], record, support: str, options: ExactOptions | None = None,
                  **model) -> list[AnalysisResult | AnalysisError | InputError]:
    """iter_batch as a list in the order of `systems`."""
    out: list = [None] * len(systems)
    for k, result in iter_batch(systems, record, support, options, **model):
        out[k] = result
    return out


def _for_system(result: AnalysisResult, system: System) -> AnalysisResult:
    """A fixed-base result for another system with the same building: its own V_c and M_c."""
    return replace(result, heights=result.heights.copy(), critical_base_shear=system.critical_base_shear,
                   critical_base_moment=system.critical_base_moment, intermediates=dict(result.intermediates),
                   details=copy.deepcopy(result.details))


def analyze(system: System, record, support: str, options: ExactOptions | None = None, **model) -> AnalysisResult:
    """Exact peak response of the system to the record (acceleration [m/s^2], dt [s])."""
    (result,) = analyze_batch([system], record, support, options, **model)
    if not isinstance(result, AnalysisResult):
        raise result
    return result
