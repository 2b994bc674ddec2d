"""Response quantities of a simulated history: peaks between samples, uplift summary, energy.

Responses are linear in the state (paper Eqs. 12-14): floor displacements
u = sum Y_n* phi_n*, drifts, equivalent lateral forces f = M Phi* w^2 Y*, story shears
and overturning moments by statics. Peaks between samples come from the cubic Hermite
interpolant through the sampled values and their exact time derivatives (X' = A X),
which is accurate to O(h^4) between samples (THEORY.md section 9, last item).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..structure import Building
from .simulate import History
from .statespace import coordinate_masses, element_directions, modal_map, position_map, structure_matrices

#: samples whose value is within this fraction of the sampled peak are refined
_CANDIDATE_FRACTION = 0.8
_GAUSS_NODES = 0.5 * (1.0 + np.array([-np.sqrt(3.0 / 5.0), 0.0, np.sqrt(3.0 / 5.0)]))
_GAUSS_WEIGHTS = np.array([5.0, 8.0, 5.0]) / 18.0


@dataclass(frozen=True)
class ResponseMaps:
    """Maps from modal coordinates Y* (n_m) to floor responses, each (N, n_m)."""

    displacement: np.ndarray
    drift: np.ndarray
    shear: np.ndarray
    moment: np.ndarray
    modal_base_shear: np.ndarray  # diag(w^2 m*): base shear of each mode [N per m]


def response_maps(building: Building, shapes_star: np.ndarray, omega: np.ndarray) -> ResponseMaps:
    """Linear maps of [12], [13b], statics of story shear and overturning moment."""
    n = building.n_stories
    displacement = shapes_star
    below = np.vstack((np.zeros((1, shapes_star.shape[1])), shapes_star[:-1]))
    drift = shapes_star - below
    forces = building.masses[:, None] * shapes_star * omega**2
    above = np.triu(np.ones((n, n)))  # above[j, i] = 1 for i >= j
    shear = above @ forces
    base_of_story = np.concatenate(([0.0], building.heights[:-1]))
    lever = np.clip(building.heights[None, :] - base_of_story[:, None], 0.0, None) * above
    moment = lever @ forces
    modal_base_shear = np.diag(forces.sum(axis=0))
    return ResponseMaps(displacement, drift, shear, moment, modal_base_shear)


def state_derivatives(history: History) -> tuple[np.ndarray, np.ndarray]:
    """X' at the start and at the end of every interval, each with the interval's state matrix."""
    states, ids = history.states, history.state_ids
    start = np.empty_like(states)
    for s, contact in enumerate(history.contact):
        mask = ids == s
        if mask.any():
            start[mask] = states[mask] @ contact.matrix.T
    end = start[1:].copy()
    switch = np.nonzero(ids[1:] != ids[:-1])[0]
    for i in switch:
        end[i] = history.contact[ids[i]].matrix @ states[i + 1]
    return start[:-1], end


def hermite_peaks(values: np.ndarray, slopes_start: np.ndarray, slopes_end: np.ndarray,
                  lengths: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Peak |r| of each column of values (n, m) and the time index fraction where it occurs.

    slopes_start/end: dr/dt at the start and end of each interval (n-1, m); lengths (n-1,).
    Returns (peak (m,), location (m,) as interval index + fraction).
    """
    magnitude = np.abs(values)
    sampled = magnitude.max(axis=0)
    best = sampled.copy()
    where = magnitude.argmax(axis=0).astype(float)
    interval_max = np.maximum(magnitude[:-1], magnitude[1:])
    rows, cols = np.nonzero(interval_max >= _CANDIDATE_FRACTION * sampled)
    if rows.size == 0:
        return best, where
    r0, r1 = values[rows, cols], values[rows + 1, cols]
    length = lengths[rows]
    d0, d1 = slopes_start[rows, cols] * length, slopes_end[rows, cols] * length
    a = 2.0 * (r0 - r1) + d0 + d1
    b = 3.0 * (r1 - r0) - 2.0 * d0 - d1
    c = d0
    # roots of 3 a s^2 + 2 b s + c = 0 in (0, 1)
    disc = np.maximum(4.0 * b * b - 12.0 * a * c, 0.0)
    sq = np.sqrt(disc)
    with np.errstate(divide="ignore", invalid="ignore"):
        quadratic = np.abs(a) > 1e-14 * (np.abs(b) + np.abs(c) + 1e-300)
        s1 = np.where(quadratic, (-2.0 * b + sq) / (6.0 * a), -c / (2.0 * b))
        s2 = np.where(quadratic, (-2.0 * b - sq) / (6.0 * a), -c / (2.0 * b))
    for s in (s1, s2):
        s = np.where(np.isfinite(s) & (s > 0.0) & (s < 1.0), s, 0.0)
        value = np.abs(((a * s + b) * s + c) * s + r0)
        better = value > best[cols]
        # several candidates per column: keep the largest
        order = np.argsort(value)
        for k in order[better[order]]:
            if value[k] > best[cols[k]]:
                best[cols[k]] = value[k]
                where[cols[k]] = rows[k] + s[k]
    return best, where


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


def uplift_summary(history: History) -> dict:
    """Episodes, time uplifted, maximum edge uplift, rotation, minimum reaction (THEORY.md 4)."""
    model, lay = history.model, history.layout
    if not model.flexible:
        return {}
    p = history.states @ position_map(model, lay).T
    summary: dict = {"max_rotation": float(np.abs(p[:, model.n_modes]).max())}
    lifted = lifted_flags(history)
    lengths = interval_lengths(history)
    edges = {"left": 0, "right": lay.n_elements - 1}
    e = element_directions(model)
    v_elem = p @ e.T
    z = history.states[:, [lay.z_index(i) for i in range(lay.n_elements)]]
    gap = np.where(lifted, v_elem - np.where(model.elements.damping > 0.0, z, 0.0), 0.0)
    any_lifted = lifted.any(axis=1)
    summary["uplift_time"] = float(lengths[any_lifted[:-1]].sum())
    summary["episodes"] = int(np.count_nonzero(any_lifted[1:] & ~any_lifted[:-1]))
    summary["flight_time"] = float(lengths[lifted.all(axis=1)[:-1]].sum()) if lay.n_elements > 1 else 0.0
    for name, i in edges.items():
        summary[f"episodes_{name}"] = int(np.count_nonzero(lifted[1:, i] & ~lifted[:-1, i]))
        summary[f"max_uplift_{name}"] = float(max(gap[:, i].max(), 0.0))
        summary[f"max_edge_displacement_{name}"] = float(v_elem[:, i].max())
    # reactions R_i = -(k v_i + c v_i') of elements in contact [3a]
    reactions = np.full(lifted.shape, np.inf)
    k, c = model.elements.stiffness, model.elements.damping
    for s, contact in enumerate(history.contact):
        mask = history.state_ids == s
        if not mask.any():
            continue
        velocity = history.states[mask] @ contact.velocity.T @ e.T
        force = v_elem[mask] * k + velocity * c
        reactions[mask] = np.where(contact.lifted, np.inf, -force)
    summary["min_reaction_left"] = float(reactions[:, 0].min())
    summary["min_reaction_right"] = float(reactions[:, -1].min())
    summary["min_reaction"] = float(reactions.min())
    return summary


def energy_balance(history: History, start: np.ndarray, end: np.ndarray) -> dict:
    """Input = kinetic + strain + damping + foundation (+ gravity) energies [J].

    Work integrals use 3-point Gauss quadrature on the cubic Hermite interpolant of the
    state in every interval (O(h^4)); stored energies are exact at the last sample.
    """
    model, lay = history.model, history.layout
    x0, x1 = history.states[:-1], history.states[1:]
    lengths = interval_lengths(history)[:, None]
    ids = history.state_ids[:-1]
    _, damping, forcing_ground, _ = structure_matrices(model)
    ymap = modal_map(model, lay)
    c_modal = 2.0 * model.damping * model.omega * model.effective_mass
    k_modal = model.effective_mass * model.omega**2
    has_elements = lay.n_elements > 0
    if has_elements:
        e = element_directions(model)
        k_el, c_el = model.elements.stiffness, model.elements.damping
        z_cols = [lay.z_index(i) for i in range(lay.n_elements)]
    work_in = damp_struct = damp_found = 0.0
    for node, weight in zip(_GAUSS_NODES, _GAUSS_WEIGHTS):
        s = node
        h00, h10, h01, h11 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
        xg = h00 * x0 + h10 * lengths * start + h01 * x1 + h11 * lengths * end
        pdot = np.empty((xg.shape[0], lay.n_p))
        for sid, contact in enumerate(history.contact):
            mask = ids == sid
            if mask.any():
                pdot[mask] = xg[mask] @ contact.velocity.T
        accel = xg[:, lay.index_acceleration]
        work_in += weight * np.sum(lengths[:, 0] * accel * (pdot @ forcing_ground))
        ydot = pdot @ ymap.T
        damp_struct += weight * np.sum(lengths[:, 0] * (ydot**2 @ c_modal))
        if has_elements:
            lifted = np.array([c.lifted for c in history.contact])[ids]
            vdot = pdot @ e.T
            zg = xg[:, z_cols]
            with np.errstate(divide="ignore", invalid="ignore"):
                relax = np.where(c_el > 0.0, (k_el * zg) ** 2 / c_el, 0.0)
            power = np.where(lifted, relax, c_el * vdot**2)
            damp_found += weight * np.sum(lengths[:, 0] * power.sum(axis=1))

    def stored(x: np.ndarray, sid: int) -> tuple[float, float, float, float]:
        contact = history.contact[sid]
        p = position_map(model, lay) @ x
        pdot = contact.velocity @ x
        kinetic = 0.5 * np.sum(coordinate_masses(model) * pdot**2)
        y = ymap @ p
        strain = 0.5 * np.sum(k_modal * y**2)
        foundation = gravity = 0.0
        if has_elements:
            v = e @ p
            zz = np.where(c_el > 0.0, x[z_cols], 0.0)
            foundation = 0.5 * np.sum(k_el * np.where(contact.lifted, zz, v) ** 2)
            gravity = model.total_mass * model.gravity * p[model.n_modes + 1]
        return kinetic, strain, foundation, gravity

    k0, s0, f0, g0 = stored(history.states[0], history.state_ids[0])
    k1, s1, f1, g1 = stored(history.states[-1], history.state_ids[-1])
    terms = {
        "input": float(work_in),
        "kinetic": float(k1 - k0),
        "strain": float(s1 - s0),
        "structural_damping": float(damp_struct),
        "foundation_elastic": float(f1 - f0),
        "foundation_damping": float(damp_found),
        "gravity": float(g1 - g0),
    }
    balance = sum(v for k, v in terms.items() if k != "input")
    scale = max(abs(work_in), damp_struct + damp_found, 1e-300)
    terms["residual"] = float(work_in - balance)
    terms["relative_residual"] = float(abs(work_in - balance) / scale)
    return terms
