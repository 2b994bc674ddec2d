"""The linear system of each contact pattern: A of X' = A X, the velocity map and the event rows of
a batch of contact states (docs/theory.md sections 3-5; with a bearing capacity 14.2-14.3).

An elastic element is in contact or lifted; with a bearing capacity it is in elastic contact (C),
yields (Y) or is lifted (L) (yielding.py). Both are assembled here, by one vectorised function
over the batch axis: the structure plus the springs and dashpots of the elements on the mat, the
motion from statespace.dynamics, then the rows of the element tops z_i (and settlements s_i) and
the event rows (elastic: _elastic_events here; with a capacity: _soil_states.c or its twin
soil_states_numpy.py, yielding.py's rows).
"""

from __future__ import annotations

import numpy as np

from ...runtime import backend
from . import stories
from .kept import kept
from .modal import vertical_period
from .statespace import ContactState, Layout, StateSpace, dynamics, stacked


def contact_states(terms: list[StateSpace], lifted: np.ndarray, criterion: str,
                   yielding: np.ndarray | None = None, sign: np.ndarray | None = None) -> list[ContactState]:
    """Assemble A, the velocity map and the event rows of contact patterns: item r is the
    model of terms[r] (all with one layout) in the contact pattern lifted[r] (R, n_e) (and
    yielding[r] with a bearing capacity, all False if None; ignored without one; and the sign of each
    yielding story, sign[r] (R, n_y): +1, -1 or 0, all 0 if None; stories.py). The assembly is
    vectorised over the batch axis; every item gets the same bits as alone (products are per
    item, sums along contiguous rows). With a bearing capacity, by the compiled loop _soil_states.c or its
    twin soil_states_numpy.py (_soil_states). Raises ZeroDivisionError if a massless rotation has no
    damping in some item."""
    lay = terms[0].layout
    if lay.n_settlements:
        yielding = np.zeros_like(lifted) if yielding is None else np.asarray(yielding, dtype=bool)
        matrix, velocity, events = _soil_states(terms, np.asarray(lifted, dtype=bool), yielding, criterion)
    else:
        yielding = None
        stiffness, damping, forcing = _on_the_mat(terms, lifted)
        velocity, matrix = dynamics(lay, stiffness, damping, forcing, stacked(terms, "masses"), terms[0].position)
        events = np.zeros((len(terms), 0, lay.n_aug))
        if lay.n_elements:
            _relaxing_tops(lay, matrix, lifted, terms)
            events = _elastic_events(terms, lay, lifted, velocity, criterion)
    if lay.n_plastic:
        sign = np.zeros((len(terms), lay.n_plastic), dtype=np.int8) if sign is None else np.asarray(sign)
        events = np.concatenate((events, _yielding_stories(terms, lay, matrix, velocity, sign)), axis=1)
    return [ContactState(lifted[r].copy(), matrix[r], velocity[r], events[r],
                         None if yielding is None else yielding[r].copy(),
                         None if not lay.n_plastic else sign[r].copy()) for r in range(len(terms))]


def _loops():
    """The module that assembles the states of a foundation whose elements yield: _soil_states (C) or
    soil_states_numpy (upliftcli.runtime.backend)."""
    return backend.loops(f"{__package__}._soil_states", f"{__package__}.soil_states_numpy")


def _soil_states(terms: list[StateSpace], lifted: np.ndarray, yielding: np.ndarray, criterion: str
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A (R, n_aug, n_aug), the velocity map (R, n_p, n_aug) and the 2 n_e event rows (R, 2 n_e, n_aug) of
    patterns with a bearing capacity (soil_states_numpy.soil_states: the elements on the mat, the rows of
    the yielding settlements and of the relaxing tops, yielding.py's event rows)."""
    lay, count = terms[0].layout, len(terms)
    if count == 1:
        items = kept(terms[0], _soil_terms)
    else:
        items = tuple(np.concatenate(parts) for parts in zip(*(kept(t, _soil_terms) for t in terms), strict=True))
    matrix = np.empty((count, lay.n_aug, lay.n_aug))
    velocity = np.empty((count, lay.n_p, lay.n_aug))
    events = np.empty((count, 2 * lay.n_elements, lay.n_aug))
    massive, massless = kept(terms[0], _coordinates)
    _loops().soil_states(*items[:4], terms[0].position, *items[4:], np.ascontiguousarray(lifted),
                         np.ascontiguousarray(yielding), massive, massless, lay.z_indices, lay.settlement_indices,
                         criterion == "reaction", matrix, velocity, events)
    return matrix, velocity, events


def _soil_terms(space: StateSpace) -> tuple[np.ndarray, ...]:
    """The arguments of soil_states of one model with a batch axis of 1 (kept.kept): stiffness, damping,
    forcing, masses, directions, element stiffness, damping and capacity, displacement rows, and its scales
    (the weight, the static settlement and the bonded vertical frequency)."""
    names = ("stiffness", "damping", "forcing", "masses", "directions", "element_stiffness", "element_damping",
             "element_capacity", "displacement_rows")
    scales = np.array([[space.weight, space.settlement, 2.0 * np.pi / vertical_period(space.model)]])
    return (*(np.ascontiguousarray(getattr(space, name)[None]) for name in names), scales)


def _coordinates(space: StateSpace) -> tuple[np.ndarray, np.ndarray]:
    """The indices of the coordinates of p with and without mass (int64, kept.kept)."""
    lay = space.layout
    return np.asarray(lay.massive, dtype=np.int64), np.asarray(lay.massless, dtype=np.int64)


def _yielding_stories(terms: list[StateSpace], lay: Layout, matrix: np.ndarray, velocity: np.ndarray,
                      sign: np.ndarray) -> np.ndarray:
    """The rows of the plastic drifts p_j in A (in place: (1 - alpha) d_j' while story j yields) and the
    2 n_y story event rows of each item (stories.event_rows; docs/theory.md 15.2)."""
    rows = np.empty((len(terms), 2 * lay.n_plastic, lay.n_aug))
    for r, term in enumerate(terms):  # each item its own building (a batch shares a layout only)
        story = term.model.stories
        drift_rate = (story.drift @ term.to_modal @ velocity[r])[None]  # X -> d_j'
        matrix[r, lay.plastic_indices] = stories.plastic_rows(story, drift_rate, sign[r:r + 1])[0]
        rows[r] = stories.event_rows(story, term.drift_rows, drift_rate, sign[r:r + 1], lay.plastic_indices,
                                     lay.index_one)[0]
    return rows


def _on_the_mat(terms: list[StateSpace], lifted: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Stiffness, damping (R, n_p, n_p) and forcing (R, n_p, n_aug) of the structure with the elastic elements
    on the mat: k_i e_i^T e_i and c_i e_i^T e_i in contact (with a capacity: soil_states_numpy)."""
    stiffness, damping, forcing = stacked(terms, "stiffness"), stacked(terms, "damping"), stacked(terms, "forcing")
    if not terms[0].layout.n_elements:
        return stiffness, damping, forcing
    e, k_el, c_el = stacked(terms, "directions"), stacked(terms, "element_stiffness"), stacked(terms, "element_damping")
    e_t = np.swapaxes(e, 1, 2)
    stiffness = stiffness + (e_t * np.where(lifted, 0.0, k_el)[:, None, :]) @ e
    damping = damping + (e_t * np.where(lifted, 0.0, c_el)[:, None, :]) @ e
    return stiffness, damping, forcing


def _relaxing_tops(lay: Layout, matrix: np.ndarray, lifted: np.ndarray, terms: list[StateSpace]) -> None:
    """The rows of the lifted element tops with a dashpot in A (in place): k_i z_i + c_i z_i' = 0
    (docs/theory.md section 4; with a capacity: soil_states_numpy); the other tops stay (z_i' = 0)."""
    k_el, c_el = stacked(terms, "element_stiffness"), stacked(terms, "element_damping")
    rows, cols = np.nonzero(lifted & (c_el > 0.0))
    z = lay.z_indices[cols]
    matrix[rows, z, z] = -(k_el[rows, cols] / c_el[rows, cols])


def _elastic_events(terms: list[StateSpace], lay: Layout, lifted: np.ndarray, velocity: np.ndarray,
                    criterion: str) -> np.ndarray:
    """The n_e event rows of elastic elements (> 0: the element switches), dimensionless (forces by
    m_t g, displacements by the static settlement): a lifted element recontacts when the edge comes
    down to its top, z_i - v_i > 0; one in contact lifts off at a tensile force F_i = k v_i + c v_i' > 0
    [4a] ("reaction") or with the edge above its unstressed position, v_i > 0 [4b]."""
    weight = np.array([t.weight for t in terms])[:, None, None]
    settlement = np.array([t.settlement for t in terms])[:, None, None]
    k_el, c_el = stacked(terms, "element_stiffness"), stacked(terms, "element_damping")
    disp_rows = stacked(terms, "displacement_rows")  # (R, n_e, n_aug): element displacement v_i
    rows, cols = np.nonzero(lifted & (c_el > 0.0))  # the tops that relax: z_i is a state entry
    recontact = -disp_rows / settlement
    recontact[rows, cols, lay.z_indices[cols]] += 1.0 / settlement[rows, 0, 0]
    if criterion == "reaction":
        e = stacked(terms, "directions")
        separation = (k_el[:, :, None] * disp_rows + c_el[:, :, None] * (e @ velocity)) / weight
    else:
        separation = disp_rows / settlement
    return np.where(lifted[:, :, None], recontact, separation)
