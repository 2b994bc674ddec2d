"""Linear state-space form of the modal equations [11a-11c] for one contact state.

The exact and approximate engines are the same piecewise-linear system: in each contact
state (which elements touch the mat) the equations are linear (docs/theory.md sections 3-5).

Generalised coordinates p = [W_c, Y_u, theta, v]:
- W_c = Y_n* + h_n* theta for the modes coupled with the mat (all modes in the exact
  engine, mode 1 in the approximate one); in these coordinates the mass matrix is
  diagonal: diag(m_n*, I_theta, m_t), with I_theta = I_0 (+ the residual rotary inertia
  I_b - sum m_n* h_n*^2 of truncated modes if asked for) (docs/theory.md section 9);
- Y_u for fixed-base modes that do not interact with the mat (approximate engine);
- theta, the mat rotation [rad], and v, the vertical displacement of the mat centre [m].

When I_theta = 0 (massless mat, all modes), theta has no inertia and the rocking equation
is first order in theta: its theta' coefficient is sum 2 xi_n w_n m_n* h_n*^2 + sum c_i x_i^2
over the elements in contact (docs/theory.md section 9). That coordinate is "massless"; the
state then holds [p_a, p_a', theta, z] instead of [p, p', z]. z_i is the top of a lifted
element relaxing as k z + c z' = 0 (docs/theory.md section 4).

The state is augmented with [a_g, da_g/dt, 1] so that a piecewise-linear ground
acceleration and gravity make the system autonomous: X' = A X, X(t + tau) = expm(A tau) X.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...model.system import System
from ..options import ExactOptions
from .modal import ModalModel, governing_period, modal_model, resolve_modes
from .stories import plastic_forcing


@dataclass(frozen=True)
class Layout:
    """Index bookkeeping of the augmented state X."""

    n_p: int                 # generalised coordinates
    massive: np.ndarray      # indices into p of coordinates with mass
    massless: np.ndarray     # indices into p without mass (theta when I_theta = 0)
    n_x: int                 # state size without the 3 forcing entries
    n_elements: int
    n_settlements: int = 0   # plastic settlements s_i: n_elements with a bearing capacity, else 0
    n_plastic: int = 0       # plastic drifts p_j of the stories that yield (docs/theory.md 15), after the motion

    @property
    def n_aug(self) -> int:
        return self.n_x + 3

    @property
    def index_acceleration(self) -> int:
        return self.n_x

    @property
    def index_slope(self) -> int:
        return self.n_x + 1

    @property
    def index_one(self) -> int:
        return self.n_x + 2

    @property
    def z_indices(self) -> np.ndarray:
        """State indices of the element tops z_i (int64, one per element)."""
        end = self.n_x - self.n_settlements
        return np.arange(end - self.n_elements, end, dtype=np.int64)

    @property
    def plastic_indices(self) -> np.ndarray:
        """State indices of the plastic story drifts p_j [m] (int64, right after the motion: empty for an
        elastic building, docs/theory.md 15.1)."""
        start = self.n_x - self.n_settlements - self.n_elements - self.n_plastic
        return np.arange(start, start + self.n_plastic, dtype=np.int64)

    @property
    def settlement_indices(self) -> np.ndarray:
        """State indices of the plastic settlements s_i [m] (int64, one per element with a bearing
        capacity; empty without one: docs/theory.md 14.3)."""
        return np.arange(self.n_x - self.n_settlements, self.n_x, dtype=np.int64)


def layout(model: ModalModel) -> Layout:
    n_modes = model.n_modes
    n_pl = model.stories.count if model.stories is not None else 0
    if not model.flexible:
        return Layout(n_modes, np.arange(n_modes), np.array([], dtype=int), 2 * n_modes + n_pl, 0, 0, n_pl)
    n_p = n_modes + 2
    theta = n_modes
    masses = coordinate_masses(model)
    massless = np.array([theta]) if masses[theta] == 0.0 else np.array([], dtype=int)
    massive = np.array([i for i in range(n_p) if i not in set(massless.tolist())])
    n_e = model.elements.count
    n_s = n_e if model.elements.capacity is not None else 0
    n_x = 2 * massive.size + massless.size + n_pl + n_e + n_s
    return Layout(n_p, massive, massless, n_x, n_e, n_s, n_pl)


def coordinate_masses(model: ModalModel) -> np.ndarray:
    """Diagonal of the mass matrix in the p coordinates [kg, kg m^2]."""
    if not model.flexible:
        return model.effective_mass.copy()
    return np.concatenate((model.effective_mass, [model.theta_inertia, model.total_mass]))


def element_directions(model: ModalModel) -> np.ndarray:
    """Rows e_i with v_i = e_i . p, v_i = v - x_i theta [3b], shape (n_e, n_p)."""
    n_m = model.n_modes
    e = np.zeros((model.elements.count, n_m + 2))
    e[:, n_m] = -model.elements.positions
    e[:, n_m + 1] = 1.0
    return e


def modal_stiffness_damping(model: ModalModel) -> tuple[np.ndarray, np.ndarray]:
    """w_n^2 m_n* [N/m] and 2 xi_n w_n m_n* [N s/m] of each mode [11a]."""
    return model.effective_mass * model.omega**2, 2.0 * model.damping * model.omega * model.effective_mass


def structure_matrices(model: ModalModel, k_modal: np.ndarray, c_modal: np.ndarray
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Stiffness, damping and forcing (per unit a_g, per unit 1) of the structure alone in p,
    from the modal stiffness k_modal [N/m] and damping c_modal [N s/m] (modal_stiffness_damping)."""
    n_m = model.n_modes
    n_p = n_m + 2 if model.flexible else n_m
    # structural deformation Y = T p with T = [I, -h* (coupled)]
    transform = np.zeros((n_m, n_p))
    transform[:, :n_m] = np.eye(n_m)
    if model.flexible:
        transform[:, n_m] = -np.where(model.coupled, model.effective_height, 0.0)
    stiffness = transform.T @ np.diag(k_modal) @ transform
    damping = transform.T @ np.diag(c_modal) @ transform
    forcing_ground = np.zeros(n_p)
    forcing_ground[:n_m] = -model.effective_mass
    forcing_gravity = np.zeros(n_p)
    if model.flexible:
        forcing_ground[n_m] = -model.first_moment_residual
        forcing_gravity[n_m + 1] = -model.total_mass * model.gravity
    return stiffness, damping, forcing_ground, forcing_gravity


@dataclass(frozen=True)
class ContactState:
    """Linear system of one contact state: lifted[i] is True where element i is off the mat
    (and, with a bearing capacity, yielding[i] where it yields: docs/theory.md 14.2).

    matrix: A of X' = A X (n_aug, n_aug).
    velocity: map X -> p' (n_p, n_aug).
    events: rows g = events @ X; an element changes state when its g becomes positive
        (scaled to be dimensionless: forces by m_t g, displacements by the static settlement).
    """

    lifted: np.ndarray
    matrix: np.ndarray
    velocity: np.ndarray
    events: np.ndarray
    yielding: np.ndarray | None = None  # True where element i yields (a foundation with a capacity)
    story_sign: np.ndarray | None = None  # +1 / -1 / 0 per yielding story (docs/theory.md 15), None: elastic


@dataclass(frozen=True)
class StateSpace:
    """What the state-space form of a model is built from, once per model: every later stage
    (contact states, stepping, responses, energy) reads it from here.

    stiffness, damping (n_p, n_p): of the structure alone in p; forcing (n_p, n_aug): the a_g
    and gravity columns; masses (n_p,): diagonal of the mass matrix in p; position (n_p, n_aug):
    X -> p; to_modal (n_m, n_p): p -> Y*; modal (n_m, n_aug): X -> Y*; k_modal, c_modal (n_m,): w_n^2 m_n* [N/m],
    2 xi_n w_n m_n* [N s/m]; per element: directions e_i (n_e, n_p) with v_i = e_i . p,
    element_stiffness k_i [N/m], element_damping c_i [N s/m], displacement_rows (n_e, n_aug):
    X -> v_i; weight m_t g [N]; settlement: static settlement m_t g / sum k_i [m];
    governing_period: the shortest period the sampling must resolve [s]; rest: the augmented
    state at rest under gravity, all elements in contact; element_capacity: the bearing
    capacity Q_i [N] of each element (None: elastic, docs/theory.md 14.1).
    """

    model: ModalModel
    layout: Layout
    stiffness: np.ndarray
    damping: np.ndarray
    forcing: np.ndarray
    masses: np.ndarray
    position: np.ndarray
    to_modal: np.ndarray
    modal: np.ndarray
    k_modal: np.ndarray
    c_modal: np.ndarray
    directions: np.ndarray
    element_stiffness: np.ndarray
    element_damping: np.ndarray
    displacement_rows: np.ndarray
    weight: float
    settlement: float
    governing_period: float
    rest: np.ndarray
    element_capacity: np.ndarray | None = None
    drift_rows: np.ndarray | None = None  # X -> d_j of the stories that yield (n_y, n_aug), docs/theory.md 15


def state_space(model: ModalModel) -> StateSpace:
    """The layout and the pattern-independent terms of the model's contact states."""
    lay = layout(model)
    k_modal, c_modal = modal_stiffness_damping(model)
    stiffness, damping, forcing_ground, forcing_gravity = structure_matrices(model, k_modal, c_modal)
    forcing = np.zeros((lay.n_p, lay.n_aug))
    forcing[:, lay.index_acceleration] = forcing_ground
    forcing[:, lay.index_one] = forcing_gravity
    position = position_map(model, lay)
    weight = model.total_mass * model.gravity
    if lay.n_elements:
        directions = element_directions(model)
        k_el, c_el = model.elements.stiffness, model.elements.damping
        settlement = weight / k_el.sum()
    else:
        directions, k_el, c_el, settlement = np.zeros((0, lay.n_p)), np.zeros(0), np.zeros(0), 0.0
    to_modal = modal_map(model, lay)
    drift_rows = None
    if lay.n_plastic:  # the plastic drifts load the motion (theory 15.1)
        forcing[:, lay.plastic_indices] = plastic_forcing(model.stories, to_modal)
        drift_rows = model.stories.drift @ to_modal @ position
    return StateSpace(model, lay, stiffness, damping, forcing, coordinate_masses(model), position, to_modal,
                      to_modal @ position, k_modal, c_modal, directions, k_el, c_el, directions @ position,
                      weight, settlement, governing_period(model), static_state(model, lay),
                      model.elements.capacity if lay.n_settlements else None, drift_rows)


def stacked(terms: list[StateSpace], name: str) -> np.ndarray:
    """The attribute `name` of every item of terms, stacked along a first (batch) axis."""
    return getattr(terms[0], name)[None] if len(terms) == 1 else np.stack([getattr(t, name) for t in terms])


def dynamics(lay: Layout, stiffness: np.ndarray, damping: np.ndarray, forcing: np.ndarray, masses: np.ndarray,
             position: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The velocity map X -> p' and the matrix A (without the rows of z and s that the caller
    adds) of a batch of contact states from their stiffness, damping (R, n_p, n_p), forcing
    (R, n_p, n_aug), masses (R, n_p) and the map X -> p. Raises ZeroDivisionError if a massless
    rotation has no damping in some item."""
    count, n_p, n_aug = stiffness.shape[0], lay.n_p, lay.n_aug
    a_idx, b_idx = lay.massive, lay.massless
    n_a, n_b = a_idx.size, b_idx.size
    # maps from X to p' (p' of massless coordinates from the first-order equation)
    velocity = np.zeros((count, n_p, n_aug))
    velocity[:, a_idx, n_a + np.arange(n_a)] = 1.0
    if n_b:
        c_bb = damping[:, b_idx][:, :, b_idx]
        if np.any(np.linalg.eigvalsh(c_bb) <= 0.0):
            raise ZeroDivisionError("massless rotation with no damping")
        rhs = forcing[:, b_idx] - damping[:, b_idx][:, :, a_idx] @ velocity[:, a_idx] - stiffness[:, b_idx] @ position
        velocity[:, b_idx] = np.linalg.solve(c_bb, rhs)
    matrix = np.zeros((count, n_aug, n_aug))
    matrix[:, :n_a] = velocity[:, a_idx]
    accel = forcing[:, a_idx] - damping[:, a_idx] @ velocity - stiffness[:, a_idx] @ position
    matrix[:, n_a:2 * n_a] = accel / masses[:, a_idx, None]
    if n_b:
        matrix[:, 2 * n_a:2 * n_a + n_b] = velocity[:, b_idx]
    matrix[:, lay.index_acceleration, lay.index_slope] = 1.0
    return velocity, matrix


def position_map(model: ModalModel, lay: Layout) -> np.ndarray:
    """Map X -> p (n_p, n_aug)."""
    position = np.zeros((lay.n_p, lay.n_aug))
    n_a = lay.massive.size
    position[lay.massive, np.arange(n_a)] = 1.0
    position[lay.massless, 2 * n_a + np.arange(lay.massless.size)] = 1.0
    return position


def modal_map(model: ModalModel, lay: Layout) -> np.ndarray:
    """Map p -> Y* (n_m, n_p): Y = W - h* theta for coupled modes."""
    n_m = model.n_modes
    out = np.zeros((n_m, lay.n_p))
    out[:, :n_m] = np.eye(n_m)
    if model.flexible:
        out[:, n_m] = -np.where(model.coupled, model.effective_height, 0.0)
    return out


def static_state(model: ModalModel, lay: Layout) -> np.ndarray:
    """Augmented state at rest under gravity, all elements in contact (v = -m_t g / sum k_i)."""
    x = np.zeros(lay.n_aug)
    x[lay.index_one] = 1.0
    if model.flexible:
        elements = model.elements
        k_sum = elements.stiffness.sum()
        k_moment = (elements.stiffness * elements.positions).sum()
        k_rot = (elements.stiffness * elements.positions**2).sum()
        weight = model.total_mass * model.gravity
        # solve [k_sum, -k_moment; -k_moment, k_rot] [v, theta] = [-W, 0] (symmetric mats: theta = 0)
        v, theta = np.linalg.solve(np.array([[k_sum, -k_moment], [-k_moment, k_rot]]), [-weight, 0.0])
        n_m = model.n_modes
        p = np.zeros(lay.n_p)
        p[n_m] = theta
        p[n_m + 1] = v
        p[:n_m] = np.where(model.coupled, model.effective_height, 0.0) * theta
        n_a = lay.massive.size
        x[:n_a] = p[lay.massive]
        x[2 * n_a:2 * n_a + lay.massless.size] = p[lay.massless]
    return x


def exact_model(system: System, support: str, options: ExactOptions) -> StateSpace:
    """The exact engine's model: every mode kept is coupled with the mat [11a-11c]. A building whose stories
    yield takes all its modes (docs/theory.md 15.4): a truncation is refused (InputError)."""
    n_modes = resolve_modes(system, options.n_modes)
    if system.building.yields and n_modes < system.building.n_stories:
        raise InputError("analysis", "modes", f"all {system.building.n_stories} modes with yielding stories (got "
                         f"{n_modes}): the plastic drifts load every mode (docs/theory.md 15.4); leave analysis.modes, "
                         "analysis.mass_participation and analysis.exact.n_modes unset")
    return state_space(modal_model(system, support, n_modes, residual_inertia=options.residual_inertia))
