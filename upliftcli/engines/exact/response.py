"""Response quantities of a simulated history (or of a chunk of one: digest.py folds them):
peaks between samples, reactions and impacts, uplift statistics and the histories
themselves; the energy balance is energy.py.

Everything is read off a few linear functionals of the state ("signals"), built from the
maps the state-space model already holds (History.space): the modal coordinates Y*, their
rates and second rates, theta, v, the ground acceleration, the input force rate, and each
element's displacement, velocity and relaxed top z_i. With X' = A X each signal's exact
time derivative at a sample is one more row, so:
- responses (paper Eqs. 12-14: floor displacements u = sum Y_n* phi_n*, drifts, story
  shears and overturning moments by statics (engines/statics.py), absolute floor
  accelerations -sum phi_n* (w_n^2 Y_n* + 2 xi_n w_n Y_n*') [11a]) and their peaks between
  samples come from the quintic Hermite interpolant through the sampled values and exact
  first and second derivatives (O(h^6) between samples);
- element reactions R_i = -(k_i v_i + c_i v_i') [3a] are searched between samples on the
  cubic Hermite interpolant of each contact interval (O(h^4)), in the same pass as the uplift
  statistics (contact_response).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...model.system import System
from ..quantities import HISTORY_QUANTITIES
from ..statics import story_maps
from . import response_kernels
from .signal_maps import curvature_columns, evaluated, signal_layout, used_states
from .statespace import StateSpace
from .stepping import History

#: the quantities whose peaks are linear in Y* (and Y*'), in the order of the response rows
_STORY_AND_FLOOR = ("displacement", "drift", "shear", "moment")


@dataclass(frozen=True)
class ResponseRows:
    """Maps from the modal coordinates to floor and story responses, each (N, n_m):
    displacement, drift, shear, moment per unit Y*; modal_base_shear diag(w^2 m*) (n_m, n_m);
    the absolute floor acceleration is acceleration @ Y* + acceleration_rate @ Y*'."""

    displacement: np.ndarray
    drift: np.ndarray
    shear: np.ndarray
    moment: np.ndarray
    modal_base_shear: np.ndarray
    acceleration: np.ndarray
    acceleration_rate: np.ndarray
    plastic: PlasticRows | None = None


@dataclass(frozen=True)
class PlasticRows:
    """What the plastic drifts p of the yielding stories add (docs/theory.md 15.1), per unit p_j (n_y
    columns): to the story shears and moments (N rows), the modal base shears (n_m rows: -Gamma) and the
    absolute floor accelerations (N rows: phi* diag(1/m*) Gamma)."""

    shear: np.ndarray
    moment: np.ndarray
    modal_base_shear: np.ndarray
    acceleration: np.ndarray


def response_rows(system: System, space: StateSpace) -> ResponseRows:
    """The statics of [12-14] applied to the modal forces m_j phi_jn* w_n^2 per unit Y_n* (and, with
    yielding stories, the restoring forces -A^T diag(k) p of their plastic drifts: _plastic_rows)."""
    model = space.model
    building = system.building
    shapes = system.modes.shapes_star[:, :model.n_modes]
    forces = building.masses[:, None] * shapes * model.omega**2
    maps = story_maps(building)
    return ResponseRows(shapes, maps.drift @ shapes, maps.shear @ forces, maps.moment @ forces,
                        np.diag(forces.sum(axis=0)), -shapes * model.omega**2,
                        -shapes * (2.0 * model.damping * model.omega),
                        _plastic_rows(space, shapes, maps) if space.layout.n_plastic else None)


def _plastic_rows(space: StateSpace, shapes: np.ndarray, maps) -> PlasticRows:
    """PlasticRows of a model with yielding stories: the floor forces -A^T diag(k) p (story s pulls floor s
    back by k_s p_s and floor s - 1 forward) through the statics, and the modal forcing Gamma p."""
    story = space.model.stories
    forces = np.zeros((shapes.shape[0], story.count))
    columns = np.arange(story.count)
    forces[story.story, columns] = -story.stiffness
    below = story.story > 0
    forces[story.story[below] - 1, columns[below]] = story.stiffness[below]
    gamma = story.drift.T * story.stiffness  # (n_m, n_y)
    return PlasticRows(maps.shear @ forces, maps.moment @ forces, -gamma,
                       shapes @ (gamma / space.model.effective_mass[:, None]))


@dataclass
class Signals:
    """Signals at the samples, one row per sample: values (n, k) and, for the first k_s
    signals (those with rates: the work integrals and the peak search need them), slopes
    (n, k_s), taken in the state valid from each sample on. At a contact transition the
    rates (theta', v', element velocities) jump: `switch[i]` >= 0 marks an interval i that
    ends at a transition, and `end_values[switch[i]]` (k,), `end_slopes[switch[i]]` (k_s,)
    hold its left limits. The slopes' last columns hold the second derivatives of the input
    signal and the element velocities (those of Y*' are the slopes of Y*''): `curvatures` names
    the slope columns of each signal the work integrals interpolate (energy.py); `slope_rows`
    (S, k_c) each curvature row's coefficient on the ground slope in each state `state_index`
    (n,) (a left limit's curvature is read with the next sample's ground slope: energy.py).
    """

    values: np.ndarray
    slopes: np.ndarray
    switch: np.ndarray
    end_values: np.ndarray
    end_slopes: np.ndarray
    rows: dict[str, slice]
    curvatures: dict[str, slice]
    state_index: np.ndarray
    slope_rows: np.ndarray

    def __getitem__(self, name: str) -> np.ndarray:
        """The signal's columns (n, k_name)."""
        return self.values[:, self.rows[name]]


def signals(history: History) -> Signals:
    """Evaluate the signal rows of every contact state at its samples (signal_maps), the rows built for the states the
    samples use only, all at once (a yielding run meets hundreds: theory 14.3)."""
    lay = history.space.layout
    names = signal_layout(history.space.model.n_modes, lay.n_elements, lay.n_plastic)
    curved = curvature_columns(names)
    used, ids = used_states(history.state_ids, len(history.contact))
    at = np.nonzero(ids[1:] != ids[:-1])[0]
    switch = np.full(max(ids.size - 1, 0), -1, dtype=np.int64)
    switch[at] = np.arange(at.size)
    values, slopes, end_values, end_slopes, slope_rows = evaluated(history, used, ids, at)
    return Signals(values, slopes, switch, end_values, end_slopes, names, curved, ids,
                   _slope_rows(slope_rows, names, curved))


def _slope_rows(slope_rows: np.ndarray, names: dict[str, slice], curved: dict[str, slice]) -> np.ndarray:
    """(S, k_c): the coefficient on the ground slope of each curvature row of curvature_columns (0 for a_g,
    linear inside each interval), from those of the slope rows (S, k_s)."""
    out = np.zeros((slope_rows.shape[0], names["z"].start))
    for name, columns in curved.items():
        out[:, names[name]] = slope_rows[:, columns]
    return out


@dataclass(frozen=True)
class PeakSearch:
    """What hermite_peaks needs of some responses, prepared once for every chunk of a run: R^T (n_basis, m), the
    signal columns of the basis values, rates and curvatures, the shortest period that matters in each [s]."""

    rows_t: np.ndarray
    value_columns: np.ndarray
    rate_columns: np.ndarray
    curvature_columns: np.ndarray
    periods: np.ndarray

    def run(self, sig: Signals, lengths: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Peaks and where they are (response_kernels.hermite_peaks) in one chunk."""
        step = float(lengths.max()) if lengths.size else 0.0
        fractions = 0.9 * np.cos(np.minimum(np.pi * step / self.periods, 0.5 * np.pi))
        return response_kernels.hermite_peaks(sig.values, sig.slopes, sig.end_values, sig.end_slopes, sig.switch,
                                              self.value_columns, self.rate_columns, self.curvature_columns,
                                              self.rows_t, lengths, fractions)


def peak_search(names: dict[str, slice], rows: np.ndarray, periods: np.ndarray,
                rates: np.ndarray | None = None, plastic: np.ndarray | None = None) -> PeakSearch:
    """The PeakSearch of the responses rows @ Y* (+ rates @ Y*') (+ plastic @ P, the plastic drifts of
    yielding stories) in the signal layout `names`."""
    y, ydot, yddot = (np.arange(names[k].start, names[k].stop, dtype=np.int64) for k in ("Y", "Ydot", "Yddot"))
    if rates is None:
        basis, value_cols, rate_cols, curvature_cols = rows, y, ydot, ydot
    else:
        basis = np.hstack((rows, rates))
        value_cols, rate_cols, curvature_cols = np.concatenate((y, ydot)), np.concatenate((ydot, yddot)), \
            np.concatenate((ydot, yddot))
    if plastic is not None:
        p, pdot = (np.arange(names[k].start, names[k].stop, dtype=np.int64) for k in ("P", "Pdot"))
        basis = np.hstack((basis, plastic))
        value_cols, rate_cols = np.concatenate((value_cols, p)), np.concatenate((rate_cols, pdot))
        curvature_cols = np.concatenate((curvature_cols, pdot))
    return PeakSearch(np.ascontiguousarray(basis.T), value_cols, rate_cols, curvature_cols,
                      np.asarray(periods, dtype=float))


def hermite_peaks(sig: Signals, rows: np.ndarray, lengths: np.ndarray, periods: np.ndarray,
                  rates: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Peak |r| of each response r = rows @ Y* (+ rates @ Y*') between samples, and where
    (interval index + fraction), from the quintic Hermite interpolant through the samples with
    the exact first and second derivatives (response_kernels.hermite_peaks). periods (m,) [s]:
    the shortest period that matters in each response; with the step it sets which intervals
    can hold the peak."""
    return peak_search(sig.rows, rows, periods, rates).run(sig, lengths)


def time_at(history: History, locations: np.ndarray) -> np.ndarray:
    """Times [s] at interval indices + fractions (the last sample's time at or past the end)."""
    times = history.times
    locations = np.asarray(locations, dtype=float)
    i = np.minimum(np.floor(locations).astype(np.int64), times.size - 1)
    inside = i < times.size - 1
    j = np.where(inside, i + 1, i)
    return np.where(inside, times[i] + (locations - i) * (times[j] - times[i]), times[-1])


def element_reactions(history: History, sig: Signals) -> tuple[np.ndarray, np.ndarray]:
    """Reactions R_i = -(k_i v_i + c_i v_i') [3a] at the samples (0 where lifted) and their
    rates, (n, n_e) each."""
    space = history.space
    k, c = space.element_stiffness, space.element_damping
    lifted = history.lifted
    velocity = sig["element_velocity"]
    acceleration = sig.slopes[:, sig.rows["element_velocity"]]
    force = sig["element_displacement"] * k + velocity * c
    return np.where(lifted, 0.0, -force), np.where(lifted, 0.0, -(velocity * k + acceleration * c))


def contact_response(history: History, sig: Signals) -> tuple[dict[str, tuple[np.ndarray, np.ndarray]], dict]:
    """The element reactions [3a] and the uplift statistics (docs/theory.md section 4) of a
    history, in one compiled pass (response_kernels.contact_response):
    - {"reaction": largest compression of each element between samples, on the cubic Hermite
      interpolant of R in each interval in contact; "impact": largest at a recontact (the
      reaction right after the edge comes down onto the element)}, (peaks [N], times [s]) each;
    - episodes, time uplifted and in flight, largest edge uplift and displacement, rotation and
      smallest reaction ({} without a flexible foundation)."""
    space = history.space
    if not space.layout.n_elements:
        return {"reaction": (np.zeros(0), np.zeros(0)), "impact": (np.zeros(0), np.zeros(0))}, {}
    rows = sig.rows
    flexible = space.model.flexible
    columns = (rows["element_displacement"].start, rows["element_velocity"].start, rows["z"].start,
               rows["theta"].start if flexible else -1)
    peak, peak_time, impact, impact_time, values = response_kernels.contact_response(
        sig.values, sig.slopes, sig.end_values, sig.end_slopes, sig.switch, history.lifted, history.lengths,
        history.times, space.element_stiffness, space.element_damping, columns)
    summary: dict = {}
    if flexible:
        summary = {name: int(value) if name.startswith("episodes") else float(value)
                   for name, value in zip(response_kernels.SUMMARY, values, strict=True)}
    return {"reaction": (peak, peak_time), "impact": (impact, impact_time)}, summary


def histories(history: History, rows: ResponseRows, sig: Signals, settlements: dict[str, np.ndarray] | None = None
              ) -> dict[str, np.ndarray]:
    """Time histories at every sample (SI units) for --histories: the signals of
    quantities.HISTORY_SIGNALS, then one column per story or element of each quantity of
    quantities.HISTORY_QUANTITIES, with a capacity each element's plastic settlement -s_i
    (plastic_settlement_<element>, >= 0) and with yielding stories each story's shear (shear_<story>,
    docs/theory.md 15.5). settlements: the mat's settlement series of the
    flexible supports (mat_motion.MatMotion.histories), placed after the signals."""
    y = sig["Y"]
    out = {
        "time": history.times,
        "ground_acceleration": sig["a"][:, 0],
        "base_shear": y @ rows.shear[0],
        "base_moment": y @ rows.moment[0],
        "roof_displacement": y @ rows.displacement[-1],
    }
    if rows.plastic is not None:  # the yielding stories' restoring forces (docs/theory.md 15.1)
        out["base_shear"] = out["base_shear"] + sig["P"] @ rows.plastic.shear[0]
        out["base_moment"] = out["base_moment"] + sig["P"] @ rows.plastic.moment[0]
    if history.space.model.flexible:
        out.update(_mat_histories(history, sig))
        out.update(settlements or {})
    places = _places(history, rows, sig)
    for name in (*HISTORY_QUANTITIES, "plastic_settlement", "shear"):
        for j in range(places[name].shape[1] if name in places else 0):
            out[f"{name}_{j + 1}"] = places[name][:, j]
    return out


def _mat_histories(history: History, sig: Signals) -> dict[str, np.ndarray]:
    """The mat's histories on a flexible support: theta, v, the edge displacements (the edges themselves
    with a capacity, where the signal is the spring's v_i - s_i) and the contact pattern."""
    edges = sig["element_displacement"][:, [0, -1]]
    if history.space.layout.n_settlements:
        edges = history.states @ history.space.displacement_rows[[0, -1]].T
    patterns = np.array([sum(int(f) << i for i, f in enumerate(c.lifted)) for c in history.contact])
    return {"theta": sig["theta"][:, 0], "v": sig["v"][:, 0], "left_edge_displacement": edges[:, 0],
            "right_edge_displacement": edges[:, 1], "contact_state": patterns[history.state_ids]}


def _places(history: History, rows: ResponseRows, sig: Signals) -> dict[str, np.ndarray]:
    """Quantities with one column per story, floor or element: drifts, floor accelerations, element
    reactions and, with a capacity, plastic settlements -s_i (>= 0)."""
    y, ydot = sig["Y"], sig["Ydot"]
    places = {"drift": y @ rows.drift.T,
              "floor_acceleration": y @ rows.acceleration.T + ydot @ rows.acceleration_rate.T}
    if rows.plastic is not None:  # with yielding stories also the story shears (their hysteresis with the drifts)
        places["floor_acceleration"] = places["floor_acceleration"] + sig["P"] @ rows.plastic.acceleration.T
        places["shear"] = y @ rows.shear.T + sig["P"] @ rows.plastic.shear.T
    if history.space.layout.n_elements:
        places["reaction"] = element_reactions(history, sig)[0]
    if history.space.layout.n_settlements:
        places["plastic_settlement"] = -history.states[:, history.space.layout.settlement_indices] + 0.0
    return places
