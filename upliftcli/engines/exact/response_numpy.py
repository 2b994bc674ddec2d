"""The numpy twins of the post-processing loops (_signals.c, _peaks.c, _contact.c; energy_numpy.py twins _energy.c): the
same functions with the same arguments (response_kernels.py documents them), outputs written in
place as the C loops write them, vectorised over the samples (tests/test_response_kernels.py,
tests/test_backend_agreement.py).

They agree with the loops to round-off: the products of the signal and response rows with the
states are BLAS products (another order of the same sums); the rest is the loops' own arithmetic
elementwise, in their order (contact_response gives the loop's bits). hermite_peaks refines
every interval whose sampled ends reach the threshold and whose Bernstein hull reaches the
largest sample, where the loop compares with the running peak: it refines a few more, and takes
the same largest value at the same first interval.
"""

from __future__ import annotations

import numpy as np

# ----------------------------------------------------------------------------- signals (_signals.c)


def evaluate_signals(states, ids, rows, values, slopes, ends) -> None:
    """Signal values and slopes at every sample, each with its sample's contact state's rows (S, k + k_s, n_aug);
    the left limits at the end of every interval that ends at a transition (the old state's rows at the next
    sample), in order; the samples of a negative id and the left limits at the end of their intervals left as they
    are."""
    rows_t = np.ascontiguousarray(rows.transpose(0, 2, 1))
    k = values.shape[1]
    for state in np.flatnonzero(np.bincount(ids[ids >= 0], minlength=rows_t.shape[0])):
        at = np.flatnonzero(ids == state)
        out = states[at] @ rows_t[state]
        values[at], slopes[at] = out[:, :k], out[:, k:]
    switches = np.flatnonzero(ids[1:] != ids[:-1])
    for state in np.unique(ids[switches][ids[switches] >= 0]):
        at = switches[ids[switches] == state]
        ends[np.searchsorted(switches, at)] = states[at + 1] @ rows_t[state]


def derivatives(x, ids, matrices, first, second) -> None:
    """X' = A X and X'' = A X' of each state x[i] with its own state's A (matrices[ids[i]])."""
    for state in np.unique(ids):
        at = np.flatnonzero(ids == state)
        first[at] = x[at] @ matrices[state].T
        second[at] = first[at] @ matrices[state].T


# ----------------------------------------------------------------------------- peaks (_peaks.c)


def _quintic_coefficients(p0, p1, d0, d1, c0, c1):
    """a2..a5 of p(s) = p0 + d0 s + a2 s^2 + ... + a5 s^5 (the loop's expressions)."""
    a2 = 0.5 * c0
    a3 = -1.5 * c0 + 0.5 * c1 - 6.0 * d0 - 4.0 * d1 - 10.0 * p0 + 10.0 * p1
    a4 = 1.5 * c0 - c1 + 8.0 * d0 + 7.0 * d1 + 15.0 * p0 - 15.0 * p1
    a5 = -0.5 * c0 + 0.5 * c1 - 3.0 * d0 - 3.0 * d1 - 6.0 * p0 + 6.0 * p1
    return a2, a3, a4, a5


def quintic_extrema(p0, p1, d0, d1, c0, c1) -> tuple[np.ndarray, np.ndarray]:
    """Largest |p(s)|, s in [0, 1], of the quintic Hermite p with p, p', p'' at both ends (slopes
    times the interval length, curvatures times its square), elementwise; (value, s). Each
    sign change of p' on 8 sub-intervals is bisected 40 times, as in the loop (all at once)."""
    p0, p1, d0, d1, c0, c1 = np.broadcast_arrays(*(np.atleast_1d(np.asarray(a, dtype=float))
                                                   for a in (p0, p1, d0, d1, c0, c1)))
    a2, a3, a4, a5 = _quintic_coefficients(p0, p1, d0, d1, c0, c1)

    def slope(s, k):
        return (((5.0 * a5[k] * s + 4.0 * a4[k]) * s + 3.0 * a3[k]) * s + 2.0 * a2[k]) * s + d0[k]

    best = np.maximum(np.abs(p0), np.abs(p1))
    where = np.where(np.abs(p1) > np.abs(p0), 1.0, 0.0)
    every = np.arange(p0.size)
    g = np.stack([d0] + [slope(k / 8.0, every) for k in range(1, 9)], axis=1)  # p' at s = k / 8
    k, sub = np.nonzero(((g[:, :-1] > 0.0) != (g[:, 1:] > 0.0)) | (g[:, 1:] == 0.0))  # by interval, then s
    left, right, g_left = sub / 8.0, (sub + 1) / 8.0, g[k, sub]
    for _ in range(40):
        mid = 0.5 * (left + right)
        g_mid = slope(mid, k)
        keep = ((g_mid > 0.0) == (g_left > 0.0)) & (g_mid != 0.0)
        left, g_left, right = np.where(keep, mid, left), np.where(keep, g_mid, g_left), np.where(keep, right, mid)
    root = 0.5 * (left + right)
    value = np.abs((((((a5[k] * root + a4[k]) * root + a3[k]) * root + a2[k]) * root + d0[k]) * root) + p0[k])
    order = np.lexsort((sub, -value, k))  # per interval: the largest, at its first sub-interval
    first = order[np.r_[True, k[order][1:] != k[order][:-1]]] if k.size else order
    better = first[value[first] > best[k[first]]]
    best[k[better]], where[k[better]] = value[better], root[better]
    return best, where


def quintic_extremum(p0: float, p1: float, d0: float, d1: float, c0: float, c1: float) -> tuple[float, float]:
    """quintic_extrema of one interval: (value, s)."""
    value, where = quintic_extrema(p0, p1, d0, d1, c0, c1)
    return float(value[0]), float(where[0])


def _hermite_basis(s: np.ndarray) -> np.ndarray:
    """The quintic Hermite basis at s (len(s), 6), for [p0, d0, c0, c1, d1, p1]."""
    s = s[:, None]
    return np.hstack([1 - 10 * s**3 + 15 * s**4 - 6 * s**5, s - 6 * s**3 + 8 * s**4 - 3 * s**5,
                      0.5 * s**2 - 1.5 * s**3 + 1.5 * s**4 - 0.5 * s**5, 0.5 * s**3 - s**4 + 0.5 * s**5,
                      -4 * s**3 + 7 * s**4 - 3 * s**5, 10 * s**3 - 15 * s**4 + 6 * s**5])


_GRID_BASIS = _hermite_basis(np.arange(1, 16) / 16.0)


def _hull(p0, p1, d0, d1, c0, c1):
    """Largest |Bernstein coefficient| of the quintic Hermite p: a bound of max |p| on [0, 1]."""
    return np.max(np.abs([p0, p0 + d0 / 5.0, p0 + 2.0 * d0 / 5.0 + c0 / 20.0, p1 - 2.0 * d1 / 5.0 + c1 / 20.0,
                          p1 - d1 / 5.0, p1]), axis=0)


def hermite_peaks(values, slopes, end_values, end_slopes, switch, value_columns, rate_columns, curvature_columns,
                  rows_t, lengths, fractions, best, where) -> None:
    """Peak |r| of each response r = R s and where (interval index + fraction) into best, where
    (response_kernels.hermite_peaks): sampled peaks, then the quintic between samples on the
    intervals with an end within `fractions` of the sampled peak or ending at a transition."""
    n, m = values.shape[0], rows_t.shape[1]
    sampled = values[:, value_columns] @ rows_t
    magnitude = np.abs(sampled)
    first = np.argmax(magnitude, axis=0) if n else np.zeros(m, dtype=np.int64)
    best[:] = magnitude[first, np.arange(m)] if n else 0.0
    where[:] = first
    threshold = fractions * best
    flagged = (magnitude >= threshold).any(axis=1)
    fix = np.asarray(switch[:max(n - 1, 0)])
    intervals = np.flatnonzero(flagged[:-1] | flagged[1:] | (fix >= 0))
    fix = fix[intervals]
    ends = fix >= 0
    r0, r1 = sampled[intervals], sampled[intervals + 1]
    r1[ends] = end_values[fix[ends]][:, value_columns] @ rows_t
    i, j = np.nonzero((np.abs(r0) >= threshold) | (np.abs(r1) >= threshold))
    interval, r0, r1, fix = intervals[i], r0[i, j], r1[i, j], fix[i]
    ends = fix >= 0
    after = np.where(ends, fix, interval + 1)
    d0 = c0 = d1 = c1 = 0.0
    for q in range(rows_t.shape[0]):  # the loop's sums, term by term in its order
        rq = rows_t[q, j]
        d0 = d0 + rq * values[interval, rate_columns[q]]
        c0 = c0 + rq * slopes[interval, curvature_columns[q]]
        d1 = d1 + rq * np.where(ends, end_values[fix, rate_columns[q]] if end_values.size else 0.0,
                                values[np.where(ends, 0, after), rate_columns[q]])
        c1 = c1 + rq * np.where(ends, end_slopes[fix, curvature_columns[q]] if end_slopes.size else 0.0,
                                slopes[np.where(ends, 0, after), curvature_columns[q]])
    length = lengths[interval]
    e0, e1, f0, f1 = d0 * length, d1 * length, c0 * length * length, c1 * length * length
    # a lower bound of each response's peak from its quintics on a grid (Hermite basis at s = k / 16):
    # an interval whose Bernstein hull stays below it cannot hold the peak (the loop compares with
    # its running peak, 1e-9 above round-off)
    hull = _hull(r0, r1, e0, e1, f0, f1)
    lower = best.copy()
    np.maximum.at(lower, j, np.abs(_GRID_BASIS @ np.array([r0, e0, f0, f1, e1, r1])).max(axis=0))
    keep = ~(hull * (1.0 + 1e-9) < lower[j])
    interval, j = interval[keep], j[keep]
    value, s = quintic_extrema(r0[keep], r1[keep], e0[keep], e1[keep], f0[keep], f1[keep])
    higher = value > best[j]
    if higher.any():
        interval, j, value, s = interval[higher], j[higher], value[higher], s[higher]
        order = np.lexsort((interval, -value, j))  # per response: the largest value, at its first interval
        first = order[np.r_[True, j[order][1:] != j[order][:-1]]]
        best[j[first]] = value[first]
        where[j[first]] = interval[first] + s[first]


# ----------------------------------------------------------------------------- reactions and uplift (_contact.c)


def cubic_maximum(p0, p1, d0, d1) -> tuple[np.ndarray, np.ndarray]:
    """Largest value of the cubic Hermite p(s), s in [0, 1], with p(0) = p0, p(1) = p1,
    p'(0) = d0, p'(1) = d1 (slopes times the interval length), elementwise; (value, s)."""
    a = 2.0 * (p0 - p1) + d0 + d1
    b = 3.0 * (p1 - p0) - 2.0 * d0 - d1
    best = np.maximum(p0, p1)
    where = np.where(p1 > p0, 1.0, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        disc = b * b - 3.0 * a * d0
        root = np.sqrt(np.maximum(disc, 0.0))
        quadratic = np.abs(a) > 1e-14 * (np.abs(b) + np.abs(d0))
        candidates = [np.where(quadratic, (-b + root) / (3.0 * a), np.where(b != 0.0, -d0 / (2.0 * b), -1.0)),
                      np.where(quadratic, (-b - root) / (3.0 * a), -1.0)]
    for s in candidates:
        inside = (s > 0.0) & (s < 1.0) & (disc >= 0.0)
        value = ((a * s + b) * s + d0) * s + p0
        better = inside & (value > best)
        best = np.where(better, value, best)
        where = np.where(better, s, where)
    return best, where


def contact_response(values, slopes, end_values, end_slopes, switch, lifted, lengths, times, stiffness, damping,
                     rows, peak, peak_time, impact, impact_time, summary) -> None:
    """Element reactions between samples, impacts and the uplift statistics into peak, peak_time,
    impact, impact_time, summary (response_kernels.contact_response), with the loop's arithmetic."""
    disp, vel, z, theta = (int(r) for r in rows)
    elements = (disp, vel, lifted.shape[1], stiffness, damping)
    in_contact, rate = _reactions(values, slopes, elements)
    r, d = np.where(lifted, 0.0, in_contact), np.where(lifted, 0.0, rate)
    _peak_reactions(r, d, end_values, end_slopes, switch, lifted, lengths, times, elements, peak, peak_time)
    _impacts(r, lifted, times, impact, impact_time)
    summary[:] = _uplift_summary(values, lifted, lengths, in_contact, disp, z, theta, damping)


def _reactions(v, s, elements) -> tuple[np.ndarray, np.ndarray]:
    """The reactions of the elements in contact and their rates at the samples v with slopes s; elements:
    (row of the first element displacement, of the first element velocity, n_e, k_i, c_i)."""
    disp, vel, n_e, k, c = elements
    return -(v[:, disp:disp + n_e] * k + v[:, vel:vel + n_e] * c), -(v[:, vel:vel + n_e] * k
                                                                     + s[:, vel:vel + n_e] * c)


def _peak_reactions(r, d, end_values, end_slopes, switch, lifted, lengths, times, elements, peak, peak_time) -> None:
    """The largest reaction of each element between samples (cubic through the values r and rates d of the
    interval's ends, the left limit where it ends at a transition) and its instant, into peak, peak_time."""
    n_e = lifted.shape[1]
    r1, d1 = r[1:].copy(), d[1:].copy()
    ends = switch[:len(r1)] >= 0
    if ends.any():
        r1[ends], d1[ends] = _reactions(end_values[switch[:len(r1)][ends]], end_slopes[switch[:len(r1)][ends]],
                                        elements)
    contact = ~lifted[:-1]
    r1, d1 = np.where(contact, r1, 0.0), np.where(contact, d1, 0.0)
    value, fraction = cubic_maximum(r[:-1], r1, d[:-1] * lengths[:len(r1), None], d1 * lengths[:len(r1), None])
    value = np.where(contact, value, 0.0)
    if not len(r1):
        peak[:], peak_time[:] = 0.0, 0.0
        return
    interval = np.argmax(value, axis=0)
    columns = np.arange(n_e)
    peak[:] = np.maximum(value[interval, columns], 0.0)
    peak_time[:] = times[interval] + fraction[interval, columns] * lengths[interval]


def _impacts(r, lifted, times, impact, impact_time) -> None:
    """The largest reaction of each element at a recontact (the sample after it) and its instant (NaN
    without one), into impact, impact_time."""
    n_e = lifted.shape[1]
    recontact = lifted[:-1] & ~lifted[1:]
    at_impact = np.where(recontact, r[1:], -np.inf)
    hit = recontact.any(axis=0)
    if len(r[1:]):
        sample = np.argmax(at_impact, axis=0)
        largest = at_impact[sample, np.arange(n_e)]
    else:
        sample, largest = np.zeros(n_e, dtype=np.int64), 0.0
    impact[:] = np.where(hit, np.maximum(largest, 0.0), 0.0)
    impact_time[:] = np.where(hit, times[np.minimum(sample + 1, times.size - 1)], np.nan)


def _uplift_summary(values, lifted, lengths, in_contact, disp, z, theta, damping) -> list:
    """The uplift statistics in the order of response_kernels.SUMMARY."""
    n_e = lifted.shape[1]
    displacement = values[:, disp:disp + n_e]
    gap = np.where(lifted, displacement - np.where(damping > 0.0, values[:, z:z + n_e], 0.0), 0.0)
    any_lifted = lifted.any(axis=1)
    in_contact = np.where(lifted, np.inf, in_contact)
    interval_lengths = lengths[:max(len(values) - 1, 0)]
    return [np.abs(values[:, theta]).max() if theta >= 0 else 0.0,
            interval_lengths[any_lifted[:-1]].sum(), np.count_nonzero(any_lifted[1:] & ~any_lifted[:-1]),
            interval_lengths[lifted.all(axis=1)[:-1]].sum() if n_e > 1 else 0.0,
            *(np.count_nonzero(lifted[1:, i] & ~lifted[:-1, i]) for i in (0, -1)),
            *(max(gap[:, i].max(), 0.0) for i in (0, -1)), *(displacement[:, i].max() for i in (0, -1)),
            in_contact[:, 0].min(), in_contact[:, -1].min(), in_contact.min()]

