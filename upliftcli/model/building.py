"""Shear building (or frame) on a fixed base: matrices, modes, effective modal quantities.

Everything here is docs/theory.md sections 1 and 5 (paper Eqs. 6, 9, 10). SI units:
kg, m, N/m, s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Building:
    """Lumped-mass building above a rigid mat.

    masses: floor masses m_j [kg], floor 1 (lowest) first, shape (N,).
    heights: floor heights h_j above the mat [m], increasing, shape (N,).
    stiffness: lateral stiffness matrix K [N/m], symmetric positive definite, (N, N).
    damping: modal damping ratios xi_n [-], shape (N,).
    story_stiffness: story stiffnesses k_j [N/m] when K is a shear building, else None.
    story_strength: story yield strengths V_yj [N] (inf: a story that stays elastic), None for an
        elastic building (docs/theory.md section 15); needs story_stiffness.
    hardening_ratio: alpha, post-yield over elastic story stiffness (bilinear kinematic hardening).
    """

    masses: np.ndarray
    heights: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    story_stiffness: np.ndarray | None = None
    story_strength: np.ndarray | None = None
    hardening_ratio: float = 0.0

    @property
    def n_stories(self) -> int:
        return int(self.masses.size)

    @property
    def story_heights(self) -> np.ndarray:
        """Story heights h_j - h_{j-1} [m]."""
        return np.diff(np.concatenate(([0.0], self.heights)))

    @property
    def yields(self) -> bool:
        """Whether some story has a finite strength (docs/theory.md section 15)."""
        return self.story_strength is not None and bool(np.any(np.isfinite(self.story_strength)))

    @property
    def yield_drift(self) -> np.ndarray:
        """Yield drifts V_yj / k_j [m] (inf for a story that stays elastic); needs story_strength."""
        return self.story_strength / self.story_stiffness


def eigh_diagonal_mass(stiffness: np.ndarray, masses: np.ndarray, eigvals_only: bool = False):
    """Solve K phi = w^2 M phi [6] for a diagonal mass matrix M = diag(masses) [kg].

    The standard symmetric problem C y = w^2 y with C = M^-1/2 K M^-1/2 and phi = M^-1/2 y
    (numpy.linalg.eigh: no scipy.linalg import for commands that run no history engine).
    Returns the eigenvalues w^2 [rad^2/s^2], ascending, and (unless eigvals_only) the
    mass-normalised shapes phi (phi^T M phi = 1) as columns (column-major). The scaling is the one LAPACK's
    generalized solver applies to a diagonal M (scipy.linalg.eigh(K, M)), whose results it
    reproduces to rounding (bit for bit on the example decks)."""
    root = np.sqrt(np.asarray(masses, dtype=float))
    scaled = (np.asarray(stiffness, dtype=float) / root[None, :]) / root[:, None]
    if eigvals_only:
        return np.linalg.eigvalsh(scaled)
    eigenvalues, vectors = np.linalg.eigh(scaled)
    # column-major like LAPACK's output: the products with the shapes take the same BLAS paths
    return eigenvalues, np.asfortranarray(vectors * (1.0 / root)[:, None])


def shear_building_stiffness(story_stiffness: np.ndarray) -> np.ndarray:
    """Tridiagonal stiffness matrix [N/m] of a shear building; story j joins floor j-1 and j."""
    k = np.asarray(story_stiffness, dtype=float)
    k_below = k
    k_above = np.append(k[1:], 0.0)
    return np.diag(k_below + k_above) - np.diag(k[1:], 1) - np.diag(k[1:], -1)


def shear_building(
    masses: np.ndarray,
    story_heights: np.ndarray,
    story_stiffness: np.ndarray,
    damping: float | np.ndarray = 0.05,
) -> Building:
    """Building from per-story arrays: masses [kg], story heights [m], stiffnesses [N/m]."""
    masses = np.asarray(masses, dtype=float)
    story_stiffness = np.asarray(story_stiffness, dtype=float)
    heights = np.cumsum(np.asarray(story_heights, dtype=float))
    xi = np.broadcast_to(np.asarray(damping, dtype=float), masses.shape).copy()
    return Building(masses, heights, shear_building_stiffness(story_stiffness), xi, story_stiffness)


def uniform_building(
    n_stories: int,
    floor_mass: float,
    story_height: float,
    story_stiffness: float | None = None,
    period: float | None = None,
    damping: float | np.ndarray = 0.05,
) -> Building:
    """Uniform shear building; give the story stiffness [N/m] or the fundamental period T_1 [s]."""
    if (story_stiffness is None) == (period is None):
        raise ValueError("give exactly one of story_stiffness and period")
    n = int(n_stories)
    masses = np.full(n, float(floor_mass))
    heights = np.full(n, float(story_height))
    if story_stiffness is None:
        unit = shear_building(masses, heights, np.ones(n), damping)
        omega_unit = np.sqrt(eigh_diagonal_mass(unit.stiffness, masses, eigvals_only=True)[0])
        story_stiffness = (2.0 * np.pi / float(period) / omega_unit) ** 2
    return shear_building(masses, heights, np.full(n, float(story_stiffness)), damping)


def scale_to_period(building: Building, period: float) -> Building:
    """Same building with its stiffness scaled so that T_1 = period [s] (modes unchanged)."""
    omega_target = 2.0 * np.pi / period
    omega_now = np.sqrt(eigh_diagonal_mass(building.stiffness, building.masses, eigvals_only=True)[0])
    factor = (omega_target / omega_now) ** 2
    story = None if building.story_stiffness is None else building.story_stiffness * factor
    return Building(building.masses, building.heights, building.stiffness * factor, building.damping, story,
                    building.story_strength, building.hardening_ratio)


@dataclass(frozen=True)
class Modes:
    """Fixed-base modes of a building (docs/theory.md section 5).

    omega: circular frequencies w_n [rad/s], ascending, shape (n,).
    shapes: mode shapes phi_n as columns, normalised to phi_n^T M phi_n = 1, (N, n).
    shapes_star: re-normalised shapes phi_n* = (L_n^h / M_n) phi_n [10], (N, n).
    participation_h: L_n^h = phi_n^T M 1 [kg] (mass-normalised shapes).
    participation_theta: L_n^theta = phi_n^T M h [kg m].
    effective_mass: m_n* = (L_n^h)^2 / M_n [kg] [9].
    effective_height: h_n* = L_n^theta / L_n^h [m] [9].
    damping: xi_n [-].
    """

    omega: np.ndarray
    shapes: np.ndarray
    shapes_star: np.ndarray
    participation_h: np.ndarray
    participation_theta: np.ndarray
    effective_mass: np.ndarray
    effective_height: np.ndarray
    damping: np.ndarray

    @property
    def periods(self) -> np.ndarray:
        """Fixed-base periods T_n [s]."""
        return 2.0 * np.pi / self.omega

    @property
    def n_modes(self) -> int:
        return int(self.omega.size)

    def truncated(self, n_modes: int) -> Modes:
        """The first n_modes modes."""
        s = slice(0, n_modes)
        return Modes(
            self.omega[s], self.shapes[:, s], self.shapes_star[:, s], self.participation_h[s],
            self.participation_theta[s], self.effective_mass[s], self.effective_height[s],
            self.damping[s],
        )


#: modes of the buildings analysed last in this process (a sweep over foundation fields
#: meets one building many times), keyed by the building's content
_MODES_CACHE: dict[tuple, Modes] = {}
_MODES_CACHE_SIZE = 64


def building_key(building: Building) -> tuple:
    """The building's content (masses, heights, stiffness, damping; with story strengths also those and
    the hardening ratio) as a hashable key."""
    arrays = (building.masses, building.heights, building.stiffness, building.damping)
    key = tuple(np.asarray(a, dtype=float).tobytes() for a in arrays)
    if building.story_strength is None:
        return key
    return (*key, np.asarray(building.story_strength, dtype=float).tobytes(), float(building.hardening_ratio))


def modal_analysis(building: Building) -> Modes:
    """Solve K phi = w^2 M phi [6] and the effective modal quantities [9, 10].

    The result is shared between calls for equal buildings (its arrays are read-only)."""
    key = building_key(building)
    modes = _MODES_CACHE.get(key)
    if modes is None:
        modes = _solve_modes(building)
        for array in vars(modes).values():
            array.flags.writeable = False
        if len(_MODES_CACHE) >= _MODES_CACHE_SIZE:
            _MODES_CACHE.pop(next(iter(_MODES_CACHE)))
        _MODES_CACHE[key] = modes
    return modes


def _solve_modes(building: Building) -> Modes:
    mass = np.diag(building.masses)
    eigenvalues, shapes = eigh_diagonal_mass(building.stiffness, building.masses)
    if eigenvalues[0] <= 0.0:
        raise ValueError("the lateral stiffness matrix is not positive definite")
    one = np.ones(building.n_stories)
    participation_h = shapes.T @ mass @ one
    # sign convention: positive participation (first mode all positive)
    sign = np.where(participation_h < 0.0, -1.0, 1.0)
    sign[participation_h == 0.0] = 1.0
    shapes = shapes * sign
    participation_h = participation_h * sign
    participation_theta = shapes.T @ mass @ building.heights
    effective_mass = participation_h**2  # M_n = 1
    with np.errstate(divide="ignore", invalid="ignore"):
        effective_height = np.where(participation_h != 0.0, participation_theta / participation_h, 0.0)
    shapes_star = shapes * participation_h
    return Modes(
        omega=np.sqrt(eigenvalues),
        shapes=shapes,
        shapes_star=shapes_star,
        participation_h=participation_h,
        participation_theta=participation_theta,
        effective_mass=effective_mass,
        effective_height=effective_height,
        damping=np.asarray(building.damping, dtype=float).copy(),
    )


def modes_for_mass_target(modes: Modes, total_mass: float, target: float) -> int:
    """Smallest number of modes whose effective masses reach target * total_mass."""
    cumulative = np.cumsum(modes.effective_mass) / total_mass
    return int(min(np.searchsorted(cumulative, target - 1e-12) + 1, modes.n_modes))
