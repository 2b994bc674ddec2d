"""The loops of the post-processing: signals at the samples (_signals.c), peaks between samples
(_peaks.c), element reactions and uplift statistics (_contact.c),
compiled (C, built at install) or their numpy twins (response_numpy.py), as upliftcli.runtime.backend
chooses.

Each C loop walks the samples (or the intervals between them) once; the twins work on whole
arrays (temporaries and strided reductions).
"""

from __future__ import annotations

import numpy as np

from ...runtime import backend


def _loops(name: str):
    """The module that runs loop module `name` (_signals, _peaks, _contact, _energy): itself (C) or
    response_numpy (upliftcli.runtime.backend)."""
    return backend.loops(f"{__package__}.{name}", f"{__package__}.response_numpy")


def quintic_extremum(p0: float, p1: float, d0: float, d1: float, c0: float, c1: float) -> tuple[float, float]:
    """Largest |p(s)| for s in [0, 1] of the quintic Hermite p with p, p', p'' given at both
    ends (slopes times the interval length, second derivatives times its square); returns
    (value, s). The stationary points are bracketed on 8 sub-intervals and bisected."""
    return _loops("_peaks").quintic_extremum(float(p0), float(p1), float(d0), float(d1), float(c0), float(c1))


def evaluate_signals(states: np.ndarray, ids: np.ndarray, rows: np.ndarray, values: np.ndarray,
                     slopes: np.ndarray, ends: np.ndarray) -> None:
    """Signal values and slopes at every sample, each sample with its own contact state's rows.

    rows (S, k + k_s, n_aug): the rows of every state (k value rows, then the slope rows of the
    first k_s signals; the loop transposes each state's once, the twin all); values (n, k), slopes
    (n, k_s) filled in place; ends
    (n_switch, k + k_s): the left limits at the end of every interval that ends at a
    transition, in order. The rows of each state used at least 32 times (its samples and left
    limits: _signals.c, SPLIT_USES) are split once per call. A sample whose id is negative is left as it is,
    and so is the left limit at the end of its interval (the caller's, signal_maps._mixed, which gives each
    such state its own negative id: the transitions count as ever). The rows are split: a row equal to an
    earlier one is copied (the slopes of Y*' are the values of Y*''), one with few nonzero coefficients sums them
    alone, the rest is one dense product; the other states' rows are multiplied whole (a yielding
    run meets hundreds of states, most at a few samples). Every way gives the bits of the dense
    product R x.
    """
    _loops("_signals").evaluate_signals(states, ids, rows, values, slopes, ends)


def derivatives(x: np.ndarray, ids: np.ndarray, matrices: list[np.ndarray], first: np.ndarray,
                second: np.ndarray) -> None:
    """The derivatives X' = A X and X'' = A X' of the states x (n, n_aug), each with the A of its contact state
    (matrices: S arrays (n_aug, n_aug), not stacked; ids (n,) int64), into first and second (n, n_aug). The loop
    multiplies one state at a time (product.h's transposed_product), the twin each state's rows in one matmul."""
    _loops("_signals").derivatives(x, ids, matrices, first, second)


def hermite_peaks(values, slopes, end_values, end_slopes, switch, value_columns, rate_columns, curvature_columns,
                  rows_t, lengths, fractions) -> tuple[np.ndarray, np.ndarray]:
    """Peak |r| of each response r = R s between samples and where it is (interval index +
    fraction), from the quintic Hermite interpolant through the samples with the exact first
    and second derivatives R s', R s'' at both ends (error O(h^6)).

    The basis signals s: s_q = values[:, value_columns[q]], its rate s_q' = values[:,
    rate_columns[q]] and curvature s_q'' = slopes[:, curvature_columns[q]] (Y* with its rate
    and curvature; for accelerations also Y*' with its own). end_values[switch[i]],
    end_slopes[switch[i]]: left limits at the end of an interval i that ends at a transition
    (rates may jump there); rows_t (n_basis, m) = R^T. The peak of response j can lie between
    two samples only if one of them is at least `fractions[j]` of its sampled peak
    (fractions[j] <= cos(omega h / 2) for the highest frequency omega that matters in
    response j): those intervals are searched, and every interval that ends at a transition
    (its left limit is not a sample).
    """
    m = rows_t.shape[1]
    best, where = np.zeros(m), np.zeros(m)
    _loops("_peaks").hermite_peaks(values, slopes, end_values, end_slopes, switch, value_columns, rate_columns,
                                   curvature_columns, rows_t, lengths, fractions, best, where)
    return best, where


#: the uplift statistics contact_response returns, in order (counts are whole numbers)
SUMMARY = ("max_rotation", "uplift_time", "episodes", "flight_time", "episodes_left", "episodes_right",
           "max_uplift_left", "max_uplift_right", "max_edge_displacement_left", "max_edge_displacement_right",
           "min_reaction_left", "min_reaction_right", "min_reaction")


def contact_response(values, slopes, end_values, end_slopes, switch, lifted, lengths, times, stiffness, damping,
                     rows) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Element reactions R = -(k v + c v') [3a] and uplift statistics in one pass over the samples.

    Per element: the largest compression between samples (the cubic Hermite interpolant of R in
    each interval the element is in contact) and its time [s]; the largest reaction at a
    recontact (the sample where a contact starts: the impact) and its time (NaN: none). And the
    statistics SUMMARY: largest |theta|, time with some element lifted and time with all lifted
    (flight) [s], uplift episodes (in all, at the left and right elements), largest uplift of the
    left and right edges (above the relaxed element top z, or the element's top) and their
    largest displacement [m], smallest reaction in contact (left, right, any) [N].

    values (n, k), slopes (n, k_s), end_values, end_slopes, switch: as for hermite_peaks;
    lifted (n, n_e) bool, valid from each sample on; lengths (n - 1,), times (n,) [s];
    stiffness, damping (n_e,); rows: the columns of the element displacements, the element
    velocities (whose slopes are in `slopes` at the same columns), z, and theta (-1: none).
    Returns (peak, peak_time, impact, impact_time, summary).
    """
    n_e = lifted.shape[1]
    peak, peak_time, impact, impact_time = (np.empty(n_e) for _ in range(4))
    summary = np.empty(len(SUMMARY))
    _loops("_contact").contact_response(values, slopes, end_values, end_slopes, switch, lifted, lengths, times,
                                        stiffness, damping, np.asarray(rows, dtype=np.int64), peak, peak_time, impact,
                                        impact_time, summary)
    return peak, peak_time, impact, impact_time, summary
