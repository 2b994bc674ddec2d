"""The numpy twin of the compiled assembly of the contact states of a foundation whose elements yield
(_soil_states.c; upliftcli.runtime.backend chooses between the two): A, the velocity map and the event
rows of a batch of patterns, vectorised over the batch axis (docs/theory.md 14.2-14.3; the arguments:
patterns._soil_states; the elements' states C, Y and L: yielding.py)."""

from __future__ import annotations

import numpy as np

from .statespace import Layout, dynamics


def soil_states(stiffness: np.ndarray, damping: np.ndarray, forcing: np.ndarray, masses: np.ndarray,
                position: np.ndarray, directions: np.ndarray, element_stiffness: np.ndarray,
                element_damping: np.ndarray, element_capacity: np.ndarray, displacement_rows: np.ndarray,
                scales: np.ndarray, lifted: np.ndarray, yielding: np.ndarray, massive: np.ndarray,
                massless: np.ndarray, tops: np.ndarray, settlements: np.ndarray, reaction: bool,
                matrix: np.ndarray, velocity: np.ndarray, events: np.ndarray) -> None:
    """matrix (R, n_aug, n_aug), velocity (R, n_p, n_aug) and events (R, 2 n_e, n_aug) := A, the velocity
    map and the event rows of each item r: the structure (stiffness, damping (R, n_p, n_p), forcing
    (R, n_p, n_aug), masses (R, n_p); position (n_p, n_aug): X -> p) with the elements (directions
    (R, n_e, n_p), element_* (R, n_e), displacement_rows (R, n_e, n_aug)) in the pattern (lifted[r],
    yielding[r]); scales (R, 3): the weight [N], the static settlement [m] and the bonded vertical
    frequency w_v [rad/s]; massive, massless: the coordinates of p with and without mass; tops, settlements:
    the indices of z_i and s_i in X. Raises ZeroDivisionError if a massless rotation has no damping."""
    n_p, n_aug = forcing.shape[1:]
    lay = Layout(n_p, massive, massless, n_aug - 3, lifted.shape[1], lifted.shape[1])
    contact = ~lifted & ~yielding
    k_el, c_el = element_stiffness, element_damping
    e_t = np.swapaxes(directions, 1, 2)
    k_contact = np.where(contact, k_el, 0.0)
    stiffness = stiffness + (e_t * k_contact[:, None, :]) @ directions
    damping = damping + (e_t * np.where(lifted, 0.0, c_el)[:, None, :]) @ directions
    forcing = forcing.copy()
    forcing[:, :, settlements] += e_t * k_contact[:, None, :]
    forcing[:, :, n_aug - 1] += (e_t * np.where(yielding, element_capacity, 0.0)[:, None, :]).sum(axis=2)
    velocity[:], matrix[:] = dynamics(lay, stiffness, damping, forcing, masses, position)
    edge_velocity = directions @ velocity  # (R, n_e, n_aug): X -> v_i'
    rows, cols = np.nonzero(yielding)  # s_i' = v_i' while yielding
    matrix[rows, settlements[cols]] = edge_velocity[rows, cols]
    rows, cols = np.nonzero(lifted & (c_el > 0.0))  # k_i (z_i - s_i) + c_i z_i' = 0 (theory 14.3)
    rate = k_el[rows, cols] / c_el[rows, cols]
    matrix[rows, tops[cols], tops[cols]] = -rate
    matrix[rows, tops[cols], settlements[cols]] = rate
    events[:] = event_rows(lifted, yielding, edge_velocity, k_el, c_el, element_capacity, displacement_rows,
                           scales, tops, settlements, reaction)


def event_rows(lifted: np.ndarray, yielding: np.ndarray, edge_velocity: np.ndarray, k_el: np.ndarray,
               c_el: np.ndarray, q_el: np.ndarray, displacement_rows: np.ndarray, scales: np.ndarray,
               tops: np.ndarray, settlements: np.ndarray, reaction: bool) -> np.ndarray:
    """The 2 n_e event rows of each item of a batch of patterns (lifted, yielding) (R, n_e) with a
    bearing capacity (theory 14.2; > 0: the element switches), edge_velocity (R, n_e, n_aug): X -> v_i';
    dimensionless: forces by W, displacements by the static settlement delta_st, velocities by g / w_v
    (scales (R, 3): W, delta_st, w_v)."""
    contact = ~lifted & ~yielding
    n_aug = displacement_rows.shape[2]
    unit = np.eye(n_aug)
    s_rows, z_rows, one = unit[settlements], unit[tops], unit[n_aug - 1]
    weight, settlement, vertical = (scales[:, k, None, None] for k in range(3))
    k_el, c_el, q_el = k_el[:, :, None], c_el[:, :, None], q_el[:, :, None]
    spring = displacement_rows - s_rows  # v_i - s_i
    # lift-off: F_i > 0 [4a] or v_i - s_i > 0 [4b]
    separation = (k_el * spring + c_el * edge_velocity) / weight if reaction else spring / settlement
    top = np.where(c_el > 0.0, z_rows, s_rows)  # where a lifted element's top is
    recontact = (top - displacement_rows) / settlement
    onset = -(k_el * spring + q_el * one) / weight
    unloading = edge_velocity / (settlement * vertical)  # delta_st w_v = g / w_v
    never = np.broadcast_to(-one, spring.shape)
    first = np.where(lifted[:, :, None], recontact, np.where(yielding[:, :, None], never, separation))
    second = np.where(contact[:, :, None], onset, np.where(yielding[:, :, None], unloading, never))
    return np.concatenate((first, second), axis=1)
