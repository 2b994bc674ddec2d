"""The result of one run, folded chunk by chunk.

A run is stepped in chunks of samples (stepping.CHUNK_SAMPLES): each chunk is post-processed
as soon as it is full (its signals, peaks between samples, reactions, uplift statistics,
work integrals and the requested histories, response.py and energy.py) and then dropped, so
the memory of a run is bounded whatever its length. Consecutive chunks share their boundary
sample, so every interval is in exactly one chunk: maxima and minima fold by max/min,
times and work integrals by sums, the stored energies are those of the run's first and last
samples. A run that fits in one chunk gives the same numbers as a single pass.
"""

from __future__ import annotations

import math

import numpy as np

from ...model.system import System
from ..options import ExactOptions
from ..quantities import YIELDING
from ..result import AnalysisResult
from .energy import balance, stored, work
from .mat_motion import MatMotion, plastic_quantities
from .response import (
    _STORY_AND_FLOOR,
    Signals,
    contact_response,
    histories,
    peak_search,
    response_rows,
    signal_layout,
    signals,
    time_at,
)
from .statespace import StateSpace
from .stepping import History
from .stories import hysteretic_work

#: how each uplift statistic of a chunk folds into the run's
_FOLDS = {"uplift_time": "sum", "episodes": "sum", "flight_time": "sum", "episodes_left": "sum",
          "episodes_right": "sum", "max_rotation": "max", "max_uplift_left": "max", "max_uplift_right": "max",
          "max_edge_displacement_left": "max", "max_edge_displacement_right": "max", "min_reaction_left": "min",
          "min_reaction_right": "min", "min_reaction": "min"}
#: the uplift statistics also given as intermediates of the result
_SUMMARY_INTERMEDIATES = ("uplift_time", "episodes", "max_rotation", "max_uplift_left", "max_uplift_right",
                          "min_reaction")


class Digest:
    """Accumulates the peaks (with their instants), reactions and impacts, uplift summary,
    energy and (optionally) histories of one run of `system`'s model `space`."""

    def __init__(self, system: System, space: StateSpace, options: ExactOptions):
        self.system, self.space, self.options = system, space, options
        model = space.model
        n = system.building.n_stories
        self.rows = response_rows(system, space)
        modal = self.rows.modal_base_shear
        # peaks of the instant-by-instant sums of modes 1..k (paper Fig. 7)
        stacked = np.vstack([getattr(self.rows, name) for name in _STORY_AND_FLOOR]
                            + [modal, np.tril(np.ones_like(modal)) @ modal])
        # shortest period that matters in each response [s]: the governing one, or the mode's own
        # period for a single mode's base shear (modes above the governing band are searched more);
        # accelerations weigh the higher modes by w_n^2: searched with the shortest mode period too
        mode_periods = 2.0 * math.pi / model.omega
        governing = space.governing_period
        periods = np.concatenate((np.full(4 * n, governing), mode_periods, np.maximum(mode_periods, governing)))
        names = signal_layout(model.n_modes, space.layout.n_elements, space.layout.n_plastic)
        plastic = self.rows.plastic
        self.searches = (peak_search(names, stacked, periods, None, _stacked_plastic(plastic, n)),
                         peak_search(names, self.rows.acceleration, np.full(n, min(governing, mode_periods.min())),
                                     self.rows.acceleration_rate, None if plastic is None else plastic.acceleration))
        self.stories = StoryDigest(space) if space.layout.n_plastic else None
        self.peaks = {}  # name -> (values, instants [s])
        self.summary: dict = {}
        self.works = (0.0, 0.0, 0.0)
        self.first = self.last = None
        self.samples = self.transitions = self.chunks = 0
        self.uplifted = False
        self.yielded = np.zeros(space.layout.n_settlements, dtype=bool)  # per element with a capacity
        self.final_state: np.ndarray | None = None
        self.time_step = 0.0
        self.pieces: list[dict[str, np.ndarray]] = []
        self.mat = MatMotion(space, system.half_width) if model.flexible else None
        self.end_time = 0.0

    def _keep(self, name: str, values: np.ndarray, instants: np.ndarray) -> None:
        if name not in self.peaks:
            self.peaks[name] = (values.copy(), instants.copy())
            return
        best, when = self.peaks[name]
        better = values > best
        best[better], when[better] = values[better], instants[better]

    def add(self, chunk: History) -> None:
        """Fold in one chunk (its first sample is the previous chunk's last)."""
        sig = signals(chunk)
        self._fold_responses(chunk, sig)
        self.works = tuple(a + b for a, b in zip(self.works, work(chunk, sig), strict=True))
        if self.stories is not None:
            self.stories.add(chunk, sig, self.rows.drift)
        if self.first is None:
            self.first = stored(chunk, sig, 0)
        self.last = stored(chunk, sig, -1)
        self._fold_contact(chunk)
        if self.mat is not None:
            self.mat.add(chunk, sig)
        self.end_time = float(chunk.times[-1])
        self.samples += chunk.times.size - (1 if self.chunks else 0)
        self.transitions += sig.end_values.shape[0]  # one left limit per interval that ends at a transition
        self.time_step = chunk.time_step
        if self.options.histories:
            self._keep_histories(chunk, sig)
        self.chunks += 1

    def _fold_responses(self, chunk: History, sig: Signals) -> None:
        """Fold a chunk's peaks (searched between samples), reactions and uplift statistics into the run's."""
        for name, search in zip(("stacked", "floor_acceleration"), self.searches, strict=True):
            peaks, where = search.run(sig, chunk.lengths)
            self._keep(name, peaks, time_at(chunk, where))
        reactions, summary = contact_response(chunk, sig)
        for name, (peak, when) in reactions.items():
            self._keep(name, peak, when)
        self._fold_summary(summary)

    def _keep_histories(self, chunk: History, sig: Signals) -> None:
        """Keep a chunk's response histories (its first sample dropped but in the first chunk)."""
        piece = histories(chunk, self.rows, sig, None if self.mat is None else self.mat.histories(sig))
        self.pieces.append({k: np.array(v[1:] if self.chunks else v) for k, v in piece.items()})

    def _fold_summary(self, summary: dict) -> None:
        """Fold a chunk's uplift statistics into the run's (_FOLDS: sums, maxima, minima)."""
        for name, value in summary.items():
            fold = _FOLDS[name]
            old = self.summary.get(name)
            self.summary[name] = value if old is None else {"sum": old + value, "max": max(old, value),
                                                            "min": min(old, value)}[fold]

    def _fold_contact(self, chunk: History) -> None:
        """Whether the mat lifted, which elements yielded, and the last state (for the settlements)."""
        if self.space.layout.n_elements:
            self.uplifted |= bool(chunk.lifted.any())
        if chunk.yielding is not None:
            self.yielded |= chunk.yielding.any(axis=0)
            self.final_state = chunk.states[-1].copy()

    def yielding(self, energy: dict) -> dict:
        """What a run on yielding soil leaves (docs/theory.md 14.7): the plastic settlement s_i of
        each element at the end [m] (<= 0, left edge first), whether each element yielded, the
        plastic work W_p [J] and the capacities Q_i [N]."""
        settlement = self.final_state[self.space.layout.settlement_indices]
        return {"plastic_settlement": settlement.tolist(), "yielded": self.yielded.tolist(),
                "plastic_work": energy["plastic_work"], "capacity": self.space.element_capacity.tolist()}

    def result(self, support: str, engine: str) -> AnalysisResult:
        """The run's AnalysisResult (after its last chunk)."""
        system, model = self.system, self.space.model
        values, instants, stacked = self._peaks(support, engine)
        hysteretic = None if self.stories is None else float(self.stories.hysteretic.sum())
        energy = balance(self.space, self.works, self.first, self.last, hysteretic)
        details = self._details(stacked, energy)
        if self.stories is not None:  # docs/theory.md 15.5: quantities.YIELDING
            values.update(self.stories.quantities(system.building, values["drift"]))
            instants.update({name: np.full(values[name].size, self.end_time) for name in YIELDING
                             if name in values})
        if "rotation" in values and "yielding" in details:  # the exact engine's uplift run on yielding soil
            values.update(plastic_quantities(details["yielding"]))
        histories = ({k: np.concatenate([piece[k] for piece in self.pieces]) for k in self.pieces[0]}
                     if self.options.histories else {})
        return AnalysisResult.of(system, engine, support, values, uplift=self.uplifted,
                                 periods=system.modes.periods[:model.n_modes], elements=model.elements,
                                 times=instants, intermediates=self._intermediates(instants, energy),
                                 details=details, histories=histories)

    def _peaks(self, support: str, engine: str) -> tuple[dict, dict, np.ndarray]:
        """(values, instants [s]) of every peak of the run by name, and the stacked story and floor peaks
        with the modal base shears and their cumulative sums (Digest.__init__); the mat's rocking
        quantities for the exact engine's uplift run."""
        n = self.system.building.n_stories
        stacked, stacked_times = self.peaks.pop("stacked")
        values = {name: stacked[k * n:(k + 1) * n] for k, name in enumerate(_STORY_AND_FLOOR)}
        instants = {name: stacked_times[k * n:(k + 1) * n] for k, name in enumerate(_STORY_AND_FLOOR)}
        values["drift_ratio"] = values["drift"] / self.system.building.story_heights
        instants["drift_ratio"] = instants["drift"]
        for name, (peak, when) in self.peaks.items():
            values[name], instants[name] = peak, when
        if self.mat is not None and support == "uplift" and engine == "exact":
            rocking, rocking_times = self.mat.quantities(self.end_time)  # quantities.ROCKING
            values.update(rocking)
            instants.update(rocking_times)
        return values, instants, stacked

    def _details(self, stacked: np.ndarray, energy: dict) -> dict:
        """The result's details: the flight warning, the modal base shears (and their cumulative sums),
        the uplift summary, the energy balance and, on yielding soil, what the run leaves (yielding)."""
        n, n_modes = self.system.building.n_stories, self.space.model.n_modes
        details = {
            "warnings": _flight_warnings(self.summary),
            "modal_base_shear": stacked[4 * n:4 * n + n_modes].tolist(),
            "cumulative_modal_base_shear": stacked[4 * n + n_modes:].tolist(),
            "uplift_summary": self.summary,
            "energy": energy,
        }
        if self.space.layout.n_settlements:
            details["yielding"] = self.yielding(energy)
        return details

    def _intermediates(self, instants: dict, energy: dict) -> dict:
        """The run's intermediates: T_1, the modes, the step, the criterion, I_theta, samples and transitions,
        when V_b and M_b peak, the energy residual, the foundation model and the uplift statistics."""
        system, model, summary = self.system, self.space.model, self.summary
        intermediates = {
            "T1": float(system.modes.periods[0]),
            "n_modes": model.n_modes,
            "time_step": self.time_step,
            "criterion": self.options.criterion,
            "rotation_inertia": model.theta_inertia,
            "samples": self.samples,
            "transitions": self.transitions,
            "base_shear_time": float(instants["shear"][0]),
            "base_moment_time": float(instants["moment"][0]),
            "energy_residual": energy["relative_residual"],
        }
        if model.flexible:
            intermediates.update(model.impedance)  # the foundation model of every engine, as built
        if model.flexible and getattr(system.foundation, "capacity", None) is not None:
            intermediates["M_tip"] = system.tipping_moment  # M_c is the capacity's (theory 14.4)
        intermediates.update({name: summary[name] for name in _SUMMARY_INTERMEDIATES if name in summary})
        return intermediates


def _stacked_plastic(plastic, n: int) -> np.ndarray | None:
    """The plastic drifts' part of the stacked story and floor responses (Digest.__init__): nothing in the
    displacements and drifts, the restoring forces in the shears, moments and modal base shears."""
    if plastic is None:
        return None
    modal = plastic.modal_base_shear
    return np.vstack((np.zeros((2 * n, modal.shape[1])), plastic.shear, plastic.moment, modal,
                      np.cumsum(modal, axis=0)))


class StoryDigest:
    """What the yielding stories of a run leave (docs/theory.md 15.3, 15.5), folded chunk by chunk: the
    hysteretic energy of each, whether it yielded, and the drifts at the last sample."""

    def __init__(self, space: StateSpace):
        self.space = space
        self.hysteretic = np.zeros(space.layout.n_plastic)
        self.yielded = np.zeros(space.layout.n_plastic, dtype=bool)
        self.final_drift: np.ndarray | None = None

    def add(self, chunk: History, sig: Signals, drift_rows: np.ndarray) -> None:
        """Fold one chunk: int V dp over its intervals (stories.hysteretic_work), the stories that yielded in it,
        the drifts of every story at its last sample (drift_rows: Y* -> d of every story)."""
        drifts = chunk.states @ self.space.drift_rows.T
        starts = np.r_[0, np.flatnonzero(sig.switch >= 0) + 1]  # a state's signs hold from its first sample on
        first = chunk.story_sign[starts]
        yields = np.repeat(first.any(axis=1), np.diff(np.r_[starts, chunk.story_sign.shape[0]]))
        self.hysteretic += hysteretic_work(self.space.model.stories, drifts, chunk.story_sign, yields)
        self.yielded |= first.any(axis=0)
        self.final_drift = drift_rows @ sig["Y"][-1]

    def residual_drift_ratio(self, building) -> np.ndarray:
        """|d_end| / h of every story [-] (the drifts at the last sample folded)."""
        return np.abs(self.final_drift) / building.story_heights

    def quantities(self, building, peak_drift: np.ndarray) -> dict[str, np.ndarray]:
        """quantities.YIELDING of the run: per story the ductility (peak |drift| / yield drift, 0 where the
        strength is infinite), the residual drift ratio |d_end| / h, the hysteretic energy [J] and the
        yielded flag; per result the yielded stories and the base-shear strength V_y1 [N]."""
        story = self.space.model.stories.story
        n = building.n_stories
        hysteretic, yielded = np.zeros(n), np.zeros(n)
        hysteretic[story], yielded[story] = self.hysteretic, self.yielded
        return {"ductility": peak_drift / building.yield_drift,
                "residual_drift_ratio": self.residual_drift_ratio(building),
                "hysteretic_energy": hysteretic, "story_yielded": yielded,
                "yielded_stories": np.array([float(yielded.sum())]),
                "base_shear_strength": np.array([float(building.story_strength[0])])}


def _flight_warnings(summary: dict) -> list[str]:
    """The warning of a run whose mat flew (both edges off the foundation), or none."""
    if not summary.get("flight_time", 0.0) > 0.0:
        return []
    return [f"both edges of the mat were off the foundation for {summary['flight_time']:.3g} s (flight): the "
            "impacts of the massless mat on the elements then drive the peaks, which can exceed the bonded "
            "ones several times over; this is a property of the model (the step is converged), see "
            "docs/exact-engine.md"]
