"""Statics shared by every engine (docs/theory.md section 5, paper Eqs. 13-14, 32-34).

- Story maps: linear maps from floor forces to story shears and overturning moments, and
  from floor displacements to story drifts. The simplified engine applies them to each
  mode's equivalent lateral forces [32]; the history engines to the modal forces of Y*.
- Reactions of a rigid mat on its contact elements under its weight and an overturning
  moment, with the elements bilateral (bonded) or unable to pull (uplift).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.building import Building


@dataclass(frozen=True)
class StoryMaps:
    """shear (N, N): V = shear @ f, V_j = sum_(i >= j) f_i [N];
    moment (N, N): M = moment @ f, M_j = sum_(i >= j) f_i (h_i - h_(j-1)) [N m] about the
    bottom of story j; drift (N, N): Delta = drift @ u, Delta_j = u_j - u_(j-1) [m]."""

    shear: np.ndarray
    moment: np.ndarray
    drift: np.ndarray


def story_maps(building: Building) -> StoryMaps:
    """The story maps of a building (floor 0, the mat, at elevation 0)."""
    n = building.n_stories
    above = np.triu(np.ones((n, n)))  # above[j, i] = 1 for floors i >= j
    base_of_story = np.concatenate(([0.0], building.heights[:-1]))
    lever = np.clip(building.heights[None, :] - base_of_story[:, None], 0.0, None) * above
    drift = np.eye(n) - np.eye(n, k=-1)
    return StoryMaps(above, lever, drift)


def static_reactions(positions: np.ndarray, stiffness: np.ndarray, weight: float, moment: float,
                     tension: bool, capacity: np.ndarray | None = None) -> np.ndarray:
    """Upward reactions R_i [N] of contact elements (positions x_i [m], stiffnesses k_i [N/m])
    under a rigid mat carrying its weight W [N] and an overturning moment M [N m] (positive:
    pressing the side x > 0): R_i = k_i (d + x_i phi) with sum R_i = W and sum x_i R_i = M.

    tension=False (a mat that may lift off): elements that would pull are dropped and the
    rest solved again until none pulls; when M exceeds what the outermost element can take
    (W |x|: the mat tips, no static solution) that element carries the whole weight.
    capacity: each element's bearing capacity Q_y [N] (docs/theory.md section 14), or None:
    an element that would carry more carries Q_y and the rest are solved again; beyond the
    moment capacity (no static solution) the elements keep at most Q_y."""
    x = np.asarray(positions, dtype=float)
    k = np.asarray(stiffness, dtype=float)
    active = np.ones(x.size, dtype=bool)
    yielded = np.zeros(x.size, dtype=bool)
    limit = None if capacity is None else np.asarray(capacity, dtype=float)
    cap = np.zeros(x.size) if limit is None else limit
    while True:
        carried = np.where(yielded, cap, 0.0)
        load, turning = weight - carried.sum(), moment - (x * carried).sum()
        if not active.any() or np.ptp(x[active]) == 0.0:  # one element (or several at one point) left
            return _at_one_point(k, active, load, carried, limit)
        reactions = _rigid_mat(k, x, active, load, turning)
        over = _over_capacity(reactions, active, limit)
        if not over.any() and (tension or reactions.min() >= -1e-12 * weight):  # none pulls, none yields
            return _settled(reactions, carried, limit, tension)
        if over.any():  # the most loaded elements yield first: carry Q_y, solve the rest again
            yielded |= over
            active &= ~over
        else:  # drop the pulling elements on the far side of the moment and solve again
            active &= reactions > 0.0


def _over_capacity(reactions: np.ndarray, active: np.ndarray, capacity: np.ndarray | None) -> np.ndarray:
    """Where an active element carries more than its capacity [N] (nowhere without one)."""
    if capacity is None:
        return np.zeros(reactions.size, dtype=bool)
    return active & (reactions > capacity)


def _settled(reactions: np.ndarray, carried: np.ndarray, capacity: np.ndarray | None, tension: bool) -> np.ndarray:
    """The reactions [N] of a solution where none pulls and none yields, with those the yielded elements
    carry (carried, with a capacity); an element that cannot pull reports no negative round-off."""
    reactions = reactions if capacity is None else reactions + carried
    return reactions if tension else np.maximum(reactions, 0.0)


def _at_one_point(k: np.ndarray, active: np.ndarray, load: float, carried: np.ndarray,
                  capacity: np.ndarray | None) -> np.ndarray:
    """Reactions [N] when the elements left (active) stand at one point, or none is left: they share the
    load [N] by stiffness, the yielded ones carry theirs (carried), none more than its capacity."""
    share = np.where(active, load * k / k[active].sum(), 0.0) if active.any() else 0.0
    reactions = carried + share
    return reactions if capacity is None else np.minimum(reactions, capacity)


def _rigid_mat(k: np.ndarray, x: np.ndarray, active: np.ndarray, load: float, turning: float) -> np.ndarray:
    """Reactions R_i = k_i (d + x_i phi) [N] of the active elements (0 for the others) under a rigid mat
    carrying the vertical load [N] and the moment `turning` [N m]."""
    ka, xa = k[active], x[active]
    matrix = np.array([[ka.sum(), (ka * xa).sum()], [(ka * xa).sum(), (ka * xa**2).sum()]])
    d, phi = np.linalg.solve(matrix, [load, turning])
    return np.where(active, k * (d + x * phi), 0.0)


def largest_compression(positions: np.ndarray, stiffness: np.ndarray, weight: float, moment: float,
                        tension: bool, capacity: np.ndarray | None = None) -> np.ndarray:
    """Largest reaction of each element [N] when the moment |M| [N m] acts either way
    (capacity: each element's Q_y [N], static_reactions)."""
    return np.maximum(static_reactions(positions, stiffness, weight, abs(moment), tension, capacity),
                      static_reactions(positions, stiffness, weight, -abs(moment), tension, capacity))
