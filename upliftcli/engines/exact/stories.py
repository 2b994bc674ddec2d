"""Stories that yield (docs/theory.md section 15): bilinear kinematic hardening of each story with a
finite strength, the backbone of OpenSees' Steel01 without isotropic hardening.

Story j (k_j, V_yj, alpha) carries V_j = k_j (d_j - p_j), its plastic drift p_j a state entry
(Layout.plastic_indices, after the motion). Each story is elastic (E: p_j' = 0) or yields positive
(P) or negative (N): p_j' = (1 - alpha) d_j'. Two pattern bits per story above the foundation's
(bit base + 2 s: P, base + 2 s + 1: N) and two event rows (theory 15.2):

- row base + 2 s: in E the onset of positive yield, ((1 - alpha) k d - k p) / ((1 - alpha) V_y) - 1 > 0;
  in P the unloading, -d' > 0; in N never (-1);
- row base + 2 s + 1: in E the onset of negative yield; in N the unloading, d' > 0; in P never;

scaled by V_y (forces) and d_y w_1 (drift rates, d_y = V_y / k). The onset resets
p := (1 - alpha)(d -+ d_y): the force exactly on its bounding line alpha k d +- (1 - alpha) V_y.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class StoryYield:
    """The yielding stories of a model (those with a finite strength), each (n_y,) but drift (n_y, n_m):
    story: their indices (0: the lowest story); stiffness k_j [N/m]; strength V_yj [N]; alpha: the
    hardening ratio; drift: the map Y* -> d_j [m per unit Y*]; frequency: w_1 [rad/s] (event scale)."""

    story: np.ndarray
    stiffness: np.ndarray
    strength: np.ndarray
    alpha: float
    drift: np.ndarray
    frequency: float

    @property
    def count(self) -> int:
        return int(self.story.size)

    @property
    def yield_drift(self) -> np.ndarray:
        """d_y = V_y / k [m] of each yielding story."""
        return self.strength / self.stiffness


def story_yield(building, shapes_star: np.ndarray, omega: np.ndarray) -> StoryYield | None:
    """The StoryYield of a building with story strengths (None: elastic, or every strength infinite),
    from the modes kept (shapes phi_n* (N, n_m), frequencies [rad/s])."""
    if not building.yields:
        return None
    story = np.flatnonzero(np.isfinite(building.story_strength))
    drift = np.diff(np.vstack((np.zeros((1, shapes_star.shape[1])), shapes_star)), axis=0)
    stiffness, strength = building.story_stiffness[story], building.story_strength[story]
    return StoryYield(story, stiffness.astype(float), strength.astype(float), float(building.hardening_ratio),
                      drift[story], float(omega[0]))


def plastic_forcing(stories: StoryYield, to_modal: np.ndarray) -> np.ndarray:
    """The columns of the plastic drifts in the forcing of the p coordinates (n_p, n_y): the modal forcing
    Gamma p = Phi*^T A^T diag(k) p of [11a] (theory 15.1) mapped by T^T (Y* = T p)."""
    return to_modal.T @ (stories.drift.T * stories.stiffness)


#: the sign of a story by the field of its two bits in a contact pattern, P + 2 N: elastic, positive, negative,
#: and both (no such state: stories.valid_story_pattern), 0 as P - N
_SIGN_OF_FIELD = np.array([0, 1, -1, 0], dtype=np.int8)
#: where the field of story s starts in the pattern's story bits: 2 s (the 31 stories 62 bits hold)
_FIELD_SHIFTS = 2 * np.arange(31, dtype=np.int64)
#: bits 0, 2, .., 2 (n - 1) set, by n (the low bit of each of n stories' fields), not rebuilt per state
EVEN_BITS = tuple(int("01" * n, 2) if n else 0 for n in range(32))


def story_bits(pattern: int, base: int, count: int) -> np.ndarray:
    """The sign of each yielding story in a contact pattern: +1 yielding positive, -1 negative, 0 elastic
    (bits base + 2 s and base + 2 s + 1), from the field of each story's two bits."""
    return sign_of_fields(story_fields(pattern, base, count))


def story_fields(pattern: int, base: int, count: int) -> np.ndarray:
    """The field P + 2 N of each yielding story's two bits in a contact pattern (int64, n_y): 0 elastic, 1
    positive, 2 negative (3 both: no state), which is also the code of its sign, sign % 3 (story_states)."""
    return (np.int64(pattern >> base) >> _FIELD_SHIFTS[:count]) & 3


def sign_of_fields(fields: np.ndarray) -> np.ndarray:
    """The signs (int8: +1, -1, 0) of the stories whose fields story_fields gives."""
    return _SIGN_OF_FIELD.take(fields)


def valid_story_pattern(pattern: int, base: int, count: int) -> bool:
    """False where a story would yield both ways at once (no such state)."""
    bits = pattern >> base
    return not bits & (bits >> 1) & EVEN_BITS[count]


def plastic_rows(stories: StoryYield, drift_rate: np.ndarray, sign: np.ndarray) -> np.ndarray:
    """The rows of p_j in A of a batch of states (R, n_y, n_aug): (1 - alpha) d_j' while yielding, else
    zero; drift_rate (R, n_y, n_aug): X -> d_j' in each state, sign (R, n_y)."""
    return np.where((sign != 0)[:, :, None], (1.0 - stories.alpha) * drift_rate, 0.0)


def event_rows(stories: StoryYield, drift_rows: np.ndarray, drift_rate: np.ndarray, sign: np.ndarray,
               plastic: np.ndarray, one: int) -> np.ndarray:
    """The 2 n_y event rows of a batch of states (R, 2 n_y, n_aug), story by story (onset or unloading,
    positive then negative; module docstring); drift_rows (n_y, n_aug): X -> d_j, plastic: the state
    indices of p_j, one: that of the constant 1."""
    n_aug = drift_rows.shape[1]
    onset_up, onset_down, rate, never = event_candidates(stories, drift_rows, drift_rate, plastic, one)
    elastic = (sign == 0)[:, :, None]
    up = np.where(elastic, onset_up, np.where((sign > 0)[:, :, None], -rate, never))
    down = np.where(elastic, onset_down, np.where((sign < 0)[:, :, None], rate, never))
    rows = np.empty((sign.shape[0], 2 * stories.count, n_aug))
    rows[:, 0::2], rows[:, 1::2] = up, down
    return rows


def event_candidates(stories: StoryYield, drift_rows: np.ndarray, drift_rate: np.ndarray, plastic: np.ndarray,
                     one: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The rows event_rows chooses from (module docstring): the onsets of positive and negative yield
    (n_y, n_aug), the scaled drift rates (R, n_y, n_aug: -rate is the unloading from P, rate from N) and
    the constant -1 of a row that cannot cross (broadcast to the rates' shape)."""
    unit = np.eye(drift_rows.shape[1])
    k, scale = stories.stiffness[:, None], stories.strength[:, None]
    force = (k * drift_rows - k / (1.0 - stories.alpha) * unit[plastic]) / scale
    rate = drift_rate / (stories.yield_drift * stories.frequency)[None, :, None]
    return force - unit[one], -force - unit[one], rate, np.broadcast_to(-unit[one], rate.shape)


def resets(stories: StoryYield, drift_rows: np.ndarray, plastic: np.ndarray, one: int
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(index, rows, with_row) of the 2 n_y story event rows (stepping_kernels.Elements): at the onset of
    yield p_j := (1 - alpha)(d_j -+ d_y), the force on its bounding line (theory 15.2)."""
    n_aug = drift_rows.shape[1]
    shift = np.zeros((stories.count, n_aug))
    shift[:, one] = stories.yield_drift
    rows = np.empty((2 * stories.count, n_aug))
    rows[0::2] = (1.0 - stories.alpha) * (drift_rows - shift)
    rows[1::2] = (1.0 - stories.alpha) * (drift_rows + shift)
    return np.repeat(plastic, 2), rows, np.ones(2 * stories.count, dtype=bool)


def hysteretic_work(stories: StoryYield, drifts: np.ndarray, sign: np.ndarray, yields: np.ndarray | None = None
                    ) -> np.ndarray:
    """Hysteretic energy int V_j dp_j [J] of each yielding story over the intervals of a history, exact
    from the drifts d_j at the samples (n, n_y) and the sign valid from each sample on (n, n_y): while
    yielding V = alpha k d +- (1 - alpha) V_y and dp = (1 - alpha) dd (theory 15.3). yields (n,): whether some
    story yields from each sample on (sign.any(axis=1), which the caller may know cheaper)."""
    if drifts.shape[0] < 2:
        return np.zeros(stories.count)
    # the work of the intervals where some story yields (a sixth of them in the README example at El Centro x2),
    # the others' zero: the same terms summed in the same order as over every interval (numpy sums the rows of
    # several stories one after the other, so the zero rows change nothing; one story's column pairwise, so its
    # zeros stay in it)
    rows = np.flatnonzero(sign[:-1].any(axis=1) if yields is None else yields[:-1])
    d0, d1, s = drifts[rows], drifts[rows + 1], sign[rows]
    a = stories.alpha
    per = (1.0 - a) * (0.5 * a * stories.stiffness * (d1**2 - d0**2) + s * (1.0 - a) * stories.strength * (d1 - d0))
    terms = np.where(s != 0, per, 0.0)
    if stories.count == 1:
        every = np.zeros((drifts.shape[0] - 1, 1))
        every[rows] = terms
        terms = every
    return terms.sum(axis=0)


def stored_strain(stories: StoryYield, drifts: np.ndarray, plastic: np.ndarray) -> float:
    """The change of the strain energy of the yielding stories due to their plastic drifts [J]:
    sum k (d - p)^2 / 2 - sum k d^2 / 2 = sum k (p^2 / 2 - d p) (theory 15.3); 0 with p = 0."""
    return float(np.sum(stories.stiffness * (0.5 * plastic**2 - drifts * plastic)))
