"""Response quantities of a simulated history: peaks between samples, uplift summary, energy.

Everything is read off a few linear functionals of the state ("signals"): the modal
coordinates Y* and their rates, theta, v, the ground acceleration, the input force
rate, and each element's displacement, velocity and relaxed top z_i. With X' = A X each
signal's exact time derivative at a sample is one more row, so:
- responses (paper Eqs. 12-14: floor displacements u = sum Y_n* phi_n*, drifts,
  equivalent lateral forces, story shears and overturning moments by statics) and
  their peaks between samples come from the quintic Hermite interpolant through the
  sampled values and exact first and second derivatives (O(h^6) between samples);
- work integrals of the energy balance use 3-point Gauss quadrature on the cubic
  Hermite interpolants of the signals (O(h^4)).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...model.building import Building
from . import response_kernels as postkernel
from .statespace import coordinate_masses, element_directions, modal_map, position_map, structure_matrices
from .stepping import History


@dataclass(frozen=True)
class ResponseMaps:
    """Maps from modal coordinates Y* (n_m) to floor responses, each (N, n_m)."""

    displacement: np.ndarray
    drift: np.ndarray
    shear: np.ndarray
    moment: np.ndarray
    modal_base_shear: np.ndarray  # diag(w^2 m*): base shear of each mode [N per m]

    def stacked(self) -> np.ndarray:
        return np.vstack((self.displacement, self.drift, self.shear, self.moment, self.modal_base_shear))


def response_maps(building: Building, shapes_star: np.ndarray, omega: np.ndarray) -> ResponseMaps:
    """Linear maps of [12], [13b], and statics of story shear and overturning moment."""
    n = building.n_stories
    below = np.vstack((np.zeros((1, shapes_star.shape[1])), shapes_star[:-1]))
    forces = building.masses[:, None] * shapes_star * omega**2
    above = np.triu(np.ones((n, n)))  # above[j, i] = 1 for floors i >= j
    base_of_story = np.concatenate(([0.0], building.heights[:-1]))
    lever = np.clip(building.heights[None, :] - base_of_story[:, None], 0.0, None) * above
    return ResponseMaps(shapes_star, shapes_star - below, above @ forces, lever @ forces,
                        np.diag(forces.sum(axis=0)))


@dataclass
class Signals:
    """Signals at the samples, one row per sample: values (n, k) and, for the first k_s
    signals (those the work integrals need), slopes (n, k_s), taken in the state valid from
    each sample on. At a contact transition the rates (theta', v', element velocities) jump:
    `switch[i]` >= 0 marks an interval i that ends at a transition, and
    `end_values[switch[i]]` (k,), `end_slopes[switch[i]]` (k_s,) hold its left limits.
    """

    values: np.ndarray
    slopes: np.ndarray
    switch: np.ndarray
    end_values: np.ndarray
    end_slopes: np.ndarray
    rows: dict[str, slice]

    def __getitem__(self, name: str) -> np.ndarray:
        """The signal's columns (n, k_name)."""
        return self.values[:, self.rows[name]]


def signals(history: History) -> Signals:
    """Evaluate the signal rows of every contact state at its samples (postkernel.evaluate_signals)."""
    model, lay = history.model, history.layout
    n_m, n_e = model.n_modes, lay.n_elements
    position = position_map(model, lay)
    to_modal = modal_map(model, lay)
    _, _, forcing_ground, _ = structure_matrices(model)
    # signals with slopes first (work integrals), then values only
    with_slopes = [("Ydot", n_m), ("a", 1), ("input", 1), ("element_velocity", n_e), ("z", n_e)]
    values_only = [("Y", n_m), ("theta", 1), ("v", 1), ("element_displacement", n_e)]
    n_slopes = sum(size for _, size in with_slopes)
    names, start = {}, 0
    for name, size in with_slopes + values_only:
        names[name] = slice(start, start + size)
        start += size
    e = element_directions(model) if n_e else np.zeros((0, lay.n_p))
    rows_by_state = []
    for contact in history.contact:
        rows = np.zeros((start, lay.n_aug))
        rows[names["Y"]] = to_modal @ position
        rows[names["Ydot"]] = to_modal @ contact.velocity
        if model.flexible:
            rows[names["theta"]] = position[n_m]
            rows[names["v"]] = position[n_m + 1]
        rows[names["a"].start, lay.index_acceleration] = 1.0
        rows[names["input"]] = forcing_ground @ contact.velocity
        rows[names["element_velocity"]] = e @ contact.velocity
        rows[names["element_displacement"]] = e @ position
        for i in range(n_e):
            rows[names["z"].start + i, lay.z_index(i)] = 1.0
        rows_by_state.append(np.vstack((rows, rows[:n_slopes] @ contact.matrix)).T)
    states, ids = history.states, history.state_ids
    at = np.nonzero(ids[1:] != ids[:-1])[0]
    switch = np.full(max(ids.size - 1, 0), -1, dtype=np.int64)
    switch[at] = np.arange(at.size)
    values = np.empty((ids.size, start))
    slopes = np.empty((ids.size, n_slopes))
    ends = np.empty((at.size, start + n_slopes))
    postkernel.evaluate_signals(states, ids, np.ascontiguousarray(rows_by_state), values, slopes, ends)
    return Signals(values, slopes, switch, np.ascontiguousarray(ends[:, :start]),
                   np.ascontiguousarray(ends[:, start:]), names)


def hermite_peaks(sig: Signals, rows: np.ndarray, lengths: np.ndarray, periods: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Peak |r| of each response r = rows @ Y* between samples, and where (interval index +
    fraction), from the quintic Hermite interpolant through the samples with the exact first and
    second derivatives (postkernel.hermite_peaks). periods (m,) [s]: the shortest period that
    matters in each response; with the step it sets which intervals can hold the peak."""
    step = float(lengths.max()) if lengths.size else 0.0
    fractions = 0.9 * np.cos(np.minimum(np.pi * step / np.asarray(periods, dtype=float), 0.5 * np.pi))
    return postkernel.hermite_peaks(sig.values, sig.slopes, sig.rows["Y"].start, sig.rows["Ydot"].start,
                                    sig.end_values, sig.end_slopes, sig.switch, np.ascontiguousarray(rows.T),
                                    lengths, fractions)


def interval_lengths(history: History) -> np.ndarray:
    return np.diff(history.times)


def time_at(history: History, location: float) -> float:
    """Time [s] at an interval index + fraction."""
    i = int(np.floor(location))
    if i >= history.times.size - 1:
        return float(history.times[-1])
    return float(history.times[i] + (location - i) * (history.times[i + 1] - history.times[i]))


def lifted_flags(history: History) -> np.ndarray:
    """(n_samples, n_elements) True where the element is lifted (valid from the sample on)."""
    table = np.array([c.lifted for c in history.contact], dtype=bool).reshape(len(history.contact), -1)
    return table[history.state_ids]


def uplift_summary(history: History, sig: Signals) -> dict:
    """Episodes, time uplifted, maximum edge uplift, rotation, minimum reaction (THEORY.md 4)."""
    model, lay = history.model, history.layout
    if not model.flexible:
        return {}
    summary: dict = {"max_rotation": float(np.abs(sig["theta"]).max())}
    displacement = sig["element_displacement"]
    velocity = sig["element_velocity"]
    lifted = lifted_flags(history)
    lengths = interval_lengths(history)
    damped = model.elements.damping > 0.0
    gap = np.where(lifted, displacement - np.where(damped, sig["z"], 0.0), 0.0)
    any_lifted = lifted.any(axis=1)
    summary["uplift_time"] = float(lengths[any_lifted[:-1]].sum())
    summary["episodes"] = int(np.count_nonzero(any_lifted[1:] & ~any_lifted[:-1]))
    summary["flight_time"] = float(lengths[lifted.all(axis=1)[:-1]].sum()) if lay.n_elements > 1 else 0.0
    for name, i in (("left", 0), ("right", lay.n_elements - 1)):
        summary[f"episodes_{name}"] = int(np.count_nonzero(lifted[1:, i] & ~lifted[:-1, i]))
        summary[f"max_uplift_{name}"] = float(max(gap[:, i].max(), 0.0))
        summary[f"max_edge_displacement_{name}"] = float(displacement[:, i].max())
    # reactions R_i = -(k v_i + c v_i') of the elements in contact [3a]
    force = displacement * model.elements.stiffness + velocity * model.elements.damping
    reactions = np.where(lifted, np.inf, -force)
    summary["min_reaction_left"] = float(reactions[:, 0].min())
    summary["min_reaction_right"] = float(reactions[:, -1].min())
    summary["min_reaction"] = float(reactions.min())
    return summary


def energy_balance(history: History, sig: Signals) -> dict:
    """Input = kinetic + strain + damping + foundation (+ gravity) energies [J].

    Work integrals: 3-point Gauss quadrature on the cubic Hermite interpolants of the
    signals (O(h^4)); stored energies exact at the first and last samples.
    """
    model, lay = history.model, history.layout
    lengths = interval_lengths(history)
    c_modal = 2.0 * model.damping * model.omega * model.effective_mass
    k_modal = model.effective_mass * model.omega**2
    lifted = np.ascontiguousarray(lifted_flags(history)[:-1])
    k_el = model.elements.stiffness if lay.n_elements else np.zeros(0)
    c_el = model.elements.damping if lay.n_elements else np.zeros(0)
    rows = sig.rows
    work_in, damp_struct, damp_found = postkernel.work_integrals(
        sig.values, sig.slopes, sig.switch, sig.end_values, sig.end_slopes, lengths, lifted,
        rows["a"].start, rows["input"].start, rows["Ydot"].start, model.n_modes,
        rows["element_velocity"].start, rows["z"].start, lay.n_elements, c_modal, k_el, c_el,
    )

    masses = coordinate_masses(model)

    def stored(index: int) -> tuple[float, float, float, float]:
        x = history.states[index]
        contact = history.contact[history.state_ids[index]]
        kinetic = 0.5 * np.sum(masses * (contact.velocity @ x) ** 2)
        strain = 0.5 * np.sum(k_modal * sig["Y"][index] ** 2)
        foundation = gravity = 0.0
        if lay.n_elements:
            z = np.where(c_el > 0.0, sig["z"][index], 0.0)
            deformation = np.where(contact.lifted, z, sig["element_displacement"][index])
            foundation = 0.5 * np.sum(k_el * deformation**2)
            gravity = model.total_mass * model.gravity * sig["v"][index, 0]
        return kinetic, strain, foundation, gravity

    first, last = stored(0), stored(-1)
    terms = {"input": float(work_in)}
    for k, name in enumerate(("kinetic", "strain", "foundation_elastic", "gravity")):
        terms[name] = float(last[k] - first[k])
    terms["structural_damping"] = float(damp_struct)
    terms["foundation_damping"] = float(damp_found)
    balance = sum(v for k, v in terms.items() if k != "input")
    scale = max(abs(work_in), damp_struct + damp_found, 1e-300)
    terms["residual"] = float(work_in - balance)
    terms["relative_residual"] = float(abs(work_in - balance) / scale)
    return terms
