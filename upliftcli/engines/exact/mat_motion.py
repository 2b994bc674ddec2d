"""The motion of the mat that ASCE 41-17 section 8.4 judges a rocking foundation by
(docs/theory.md 14.7), folded chunk by chunk as digest.py folds the other peaks:

- the mat rotation |theta| [rad], its peak between samples and its value at the end of the
  analysis (the residual);
- the settlement [m], the downward displacement from the rest position under gravity,
  -(v - x theta - (v_st - x theta_st)), of the left edge (x = -b), the centre (x = 0) and the
  right edge (x = +b): its peak between samples and its residual.

theta and v are continuous in time; between two samples each is the cubic Hermite
interpolant through its sampled values and exact rates (the rates of the state valid in the
interval: the left limit at an interval that ends at a transition, response.Signals), O(h^4),
as the element reactions are searched (response.contact_response). The extremum of a cubic
on [0, 1] is at a root of its quadratic derivative: found in closed form, for every interval
at once (pure numpy: the compiled and numpy back ends give the same bits from the same signals).
A peak reached at rest (0 at the first sample) is 0: a mat that only rises has no settlement.
"""

from __future__ import annotations

import numpy as np

from .response import Signals, time_at
from .statespace import StateSpace
from .stepping import History


def _geometry(space: StateSpace, half_width: float) -> tuple[np.ndarray, np.ndarray]:
    """(weights (4, 2) on (theta, v), offsets (4,)): the series theta and the settlement of the
    left edge, the centre and the right edge = weights @ (theta, v) + offsets."""
    n_m = space.model.n_modes
    theta_rest = float(space.position[n_m] @ space.rest)
    v_rest = float(space.position[n_m + 1] @ space.rest)
    x = np.array([-half_width, 0.0, half_width])
    weights = np.vstack(([1.0, 0.0], np.column_stack((x, -np.ones(3)))))
    offsets = np.concatenate(([0.0], v_rest - x * theta_rest))
    return weights, offsets


def cubic_extrema(p0: np.ndarray, p1: np.ndarray, m0: np.ndarray, m1: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Largest and smallest value of the cubic Hermite p(s), s in [0, 1], with p(0) = p0,
    p(1) = p1, p'(0) = m0, p'(1) = m1 (rates times the interval's length), elementwise:
    (largest, its s, smallest, its s), the interval's ends included."""
    a = 6.0 * (p0 - p1) + 3.0 * (m0 + m1)
    b = 6.0 * (p1 - p0) - 4.0 * m0 - 2.0 * m1
    c = m0
    high, high_s = np.where(p1 > p0, p1, p0), np.where(p1 > p0, 1.0, 0.0)
    low, low_s = np.where(p1 < p0, p1, p0), np.where(p1 < p0, 1.0, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(np.maximum(b * b - 4.0 * a * c, 0.0))
        q = -0.5 * (b + np.where(b >= 0.0, root, -root))  # the stable pair of roots q/a, c/q
        linear = np.abs(a) <= 1e-12 * (np.abs(b) + np.abs(c))
        candidates = (np.where(linear, -c / b, q / a), np.where(linear, np.nan, c / q))
    for s in candidates:
        inside = (s > 0.0) & (s < 1.0) & (b * b - 4.0 * a * c >= 0.0)
        s = np.where(inside, s, 0.0)
        value = (((2.0 * s - 3.0) * s * s + 1.0) * p0 + ((s - 2.0) * s + 1.0) * s * m0
                 + (3.0 - 2.0 * s) * s * s * p1 + (s - 1.0) * s * s * m1)
        up, down = inside & (value > high), inside & (value < low)
        high, high_s = np.where(up, value, high), np.where(up, s, high_s)
        low, low_s = np.where(down, value, low), np.where(down, s, low_s)
    return high, high_s, low, low_s


def _series(sig: Signals, weights: np.ndarray, columns: np.ndarray) -> np.ndarray:
    """weights @ (theta, v) of every row of columns (n, k) (sig.values' or sig.slopes'), one series a row
    (4, n): each term as the product weights @ (theta, v).T sums them (w_0 theta, then + w_1 v); theta and
    v taken out of the rows first (contiguous, the products run along them)."""
    theta = np.ascontiguousarray(columns[:, sig.rows["theta"].start])
    v = np.ascontiguousarray(columns[:, sig.rows["v"].start])
    return weights[:, :1] * theta + weights[:, 1:] * v


def _end_rates(chunk: History, sig: Signals, rates: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """The rates (4, n - 1) at the end of each interval, times its length: the next sample's, or at an
    interval that ends at a transition its left limit (sig.end_slopes)."""
    ends = rates[:, 1:] * chunk.lengths
    at_end = np.flatnonzero(sig.switch >= 0)
    if at_end.size:
        ends[:, at_end] = _series(sig, weights, sig.end_slopes[sig.switch[at_end]]) * chunk.lengths[at_end]
    return ends


def _searched(values: np.ndarray, magnitude: np.ndarray, start_rates: np.ndarray, end_rates: np.ndarray,
              floor: np.ndarray) -> np.ndarray:
    """The intervals whose cubic can exceed `floor` (4,) in some series (|theta| for the first: its
    `magnitude`, the settlements their signed values): on [0, 1] a cubic Hermite lies within
    max(|p0|, |p1|) + 4/27 (|m0| + |m1|) (the largest |value| of its slope basis functions is 4/27)."""
    ends = np.maximum(values[:, :-1], values[:, 1:])
    ends[0] = np.maximum(magnitude[:-1], magnitude[1:])
    bound = ends + (4.0 / 27.0) * (np.abs(start_rates) + np.abs(end_rates))
    return np.flatnonzero(np.logical_or.reduce(bound > floor[:, None], axis=0))


def _sampled_peaks(values: np.ndarray, magnitude: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(largest sampled value (4,): |theta|, then each settlement; its sample index, as a float)."""
    at = np.concatenate(([np.argmax(magnitude)], np.argmax(values[1:], axis=1)))
    return np.concatenate((magnitude[at[:1]], values[_SIGNALS[1:], at[1:]])), at.astype(float)


def _interval_peaks(values: np.ndarray, start_rates: np.ndarray, end_rates: np.ndarray, rows: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray]:
    """(largest value (4,), where: interval + fraction) of each series over the intervals `rows` (|theta| for
    the first: the larger of its largest and minus its smallest)."""
    high, high_s, low, low_s = cubic_extrema(values[:, rows], values[:, rows + 1], start_rates[:, rows],
                                             end_rates[:, rows])
    flip = -low[0] > high[0]
    high[0, flip], high_s[0, flip] = -low[0, flip], low_s[0, flip]
    k = np.argmax(high, axis=1)
    return high[_SIGNALS, k], rows[k] + high_s[_SIGNALS, k]


#: the four series of MatMotion: |theta|, the settlement of the left edge, the centre, the right edge
_SIGNALS = np.arange(4)


class MatMotion:
    """Peaks (with their instants) and the last values of the mat rotation and of the
    settlement of its edges and centre, over the chunks of one run."""

    def __init__(self, space: StateSpace, half_width: float):
        self.weights, self.offsets = _geometry(space, half_width)
        self.peaks = np.full(4, -np.inf)  # |theta|, then the three settlements
        self.instants = np.zeros(4)
        self.last = np.zeros(4)  # theta (signed), the three settlements at the last sample

    def add(self, chunk: History, sig: Signals) -> None:
        """Fold in one chunk (its first sample is the previous chunk's last). The sampled peaks
        first; then only the intervals whose cubic can exceed them are searched (_searched), the
        others cannot hold the peak. One series a row (4, n), each contiguous."""
        values = _series(sig, self.weights, sig.values) + self.offsets[:, None]
        magnitude = np.abs(values[0])  # |theta|; a settlement: its (signed) value
        best, where = _sampled_peaks(values, magnitude)
        if values.shape[1] > 1:
            rates = _series(sig, self.weights, sig.slopes)
            start_rates = rates[:, :-1] * chunk.lengths
            end_rates = _end_rates(chunk, sig, rates, self.weights)
            rows = _searched(values, magnitude, start_rates, end_rates, np.maximum(best, self.peaks))
            if rows.size:
                found, found_where = _interval_peaks(values, start_rates, end_rates, rows)
                better = found > best
                best[better], where[better] = found[better], found_where[better]
        better = best > self.peaks
        self.peaks[better] = best[better]
        self.instants[better] = time_at(chunk, where)[better]
        self.last = values[:, -1].copy()

    def add_last(self, sig: Signals) -> None:
        """Fold in a chunk's last values only (a twin's residuals: residual_digest.py): `add`'s `last`, the
        same elementwise products and sums on the last sample alone, so the same bits."""
        self.last = (_series(sig, self.weights, sig.values[-1:]) + self.offsets[:, None])[:, -1].copy()

    def residuals(self) -> dict[str, np.ndarray]:
        """quantities.ROCKING's residual_rotation [rad] and residual_settlement [m] (left edge, centre,
        right edge) from the last values folded."""
        return {"residual_rotation": np.abs(self.last[:1]), "residual_settlement": self.last[1:].copy()}

    def histories(self, sig: Signals) -> dict[str, np.ndarray]:
        """The settlement [m] of the left edge, the centre and the right edge at every sample of a
        chunk (quantities.HISTORY_SIGNALS: left_edge_settlement, ...; down +, from the rest
        position under gravity), the series whose peaks and last values `add` folds."""
        columns = (sig.rows["theta"].start, sig.rows["v"].start)
        values = sig.values[:, columns] @ self.weights[1:].T + self.offsets[1:]
        return {f"{key}_settlement": values[:, k].copy() for k, key in enumerate(("left_edge", "centre",
                                                                                  "right_edge"))}

    def quantities(self, end_time: float) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
        """(values, instants [s]) of quantities.ROCKING's rotation, residual_rotation, settlement
        (left edge, centre, right edge: quantities.MAT_PLACES) and residual_settlement (instants:
        the end of the run)."""
        settlement = np.maximum(self.peaks[1:], 0.0)
        values = {"rotation": self.peaks[:1].copy(), "settlement": settlement, **self.residuals()}
        instants = {"rotation": self.instants[:1].copy(), "residual_rotation": np.array([end_time]),
                    "settlement": np.where(self.peaks[1:] > 0.0, self.instants[1:], 0.0),
                    "residual_settlement": np.full(3, end_time)}
        return values, instants


def plastic_quantities(yielding: dict) -> dict[str, np.ndarray]:
    """quantities.ROCKING's plastic_settlement -s_i of each element [m] (>= 0, left to right),
    yielded_elements (how many yielded) and plastic_work W_p [J] (docs/theory.md 14.5), from what
    the engine reports of a run on yielding soil (the result's details["yielding"]: the final
    s_i <= 0, the yielded flags, W_p)."""
    return {"plastic_settlement": -np.asarray(yielding["plastic_settlement"], dtype=float) + 0.0,
            "yielded_elements": np.array([float(np.count_nonzero(yielding["yielded"]))]),
            "plastic_work": np.array([float(yielding["plastic_work"])])}
