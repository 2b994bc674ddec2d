"""Compiled loops of the post-processing (numba): peaks between samples and work integrals.

Both walk the intervals between samples once; numpy versions of the same loops cost
5-10 times more on the ten-story example (temporaries and strided reductions).
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: intervals whose end samples are within this fraction of the sampled peak are searched
CANDIDATE_FRACTION = 0.8


@njit(cache=True)
def _hermite_extremum(r0, r1, d0, d1):
    """Largest |p(s)| for s in [0, 1] of the cubic Hermite p with p(0)=r0, p(1)=r1,
    p'(0)=d0, p'(1)=d1 (slopes already multiplied by the interval length); returns (value, s)."""
    a = 2.0 * (r0 - r1) + d0 + d1
    b = 3.0 * (r1 - r0) - 2.0 * d0 - d1
    c = d0
    best = abs(r0)
    where = 0.0
    if abs(r1) > best:
        best = abs(r1)
        where = 1.0
    if abs(a) > 1e-12 * (abs(b) + abs(c)):
        disc = 4.0 * b * b - 12.0 * a * c
        if disc >= 0.0:
            root = np.sqrt(disc)
            for s in ((-2.0 * b + root) / (6.0 * a), (-2.0 * b - root) / (6.0 * a)):
                if 0.0 < s < 1.0:
                    value = abs(((a * s + b) * s + c) * s + r0)
                    if value > best:
                        best = value
                        where = s
    elif b != 0.0:
        s = -c / (2.0 * b)
        if 0.0 < s < 1.0:
            value = abs(((a * s + b) * s + c) * s + r0)
            if value > best:
                best = value
                where = s
    return best, where


@njit(cache=True)
def hermite_peaks(values, rates, end_rates, switch, rows, lengths):
    """Peak |r| of each response between samples and where it is (interval index + fraction).

    values: responses at the samples (m, n), continuous in time; their slopes are rows @ rates
    (rates (k, n) at the samples; end_rates[switch[i]] (k,) at the end of an interval i that
    ends at a transition), evaluated only on the intervals that can hold the peak.
    """
    m, n = values.shape
    k = rows.shape[1]
    best = np.zeros(m)
    where = np.zeros(m)
    for j in range(m):
        for i in range(n):
            v = abs(values[j, i])
            if v > best[j]:
                best[j] = v
                where[j] = i
    for j in range(m):
        threshold = CANDIDATE_FRACTION * best[j]
        for i in range(n - 1):
            r0 = values[j, i]
            r1 = values[j, i + 1]
            if abs(r0) < threshold and abs(r1) < threshold:
                continue
            d0 = 0.0
            d1 = 0.0
            for q in range(k):
                d0 += rows[j, q] * rates[q, i]
                if switch[i] >= 0:
                    d1 += rows[j, q] * end_rates[switch[i], q]
                else:
                    d1 += rows[j, q] * rates[q, i + 1]
            value, s = _hermite_extremum(r0, r1, d0 * lengths[i], d1 * lengths[i])
            if value > best[j]:
                best[j] = value
                where[j] = i + s
    return best, where


@njit(cache=True)
def _hermite(v0, v1, d0, d1, s):
    s2 = s * s
    s3 = s2 * s
    return (2 * s3 - 3 * s2 + 1) * v0 + (s3 - 2 * s2 + s) * d0 + (-2 * s3 + 3 * s2) * v1 + (s3 - s2) * d1


@njit(cache=True)
def _at(values, slopes, switch, end_values, end_slopes, row, i, length, s):
    """Hermite value of signal `row` at fraction s of interval i."""
    if switch[i] >= 0:
        v1 = end_values[switch[i], row]
        d1 = end_slopes[switch[i], row]
    else:
        v1 = values[i + 1, row]
        d1 = slopes[i + 1, row]
    return _hermite(values[i, row], v1, slopes[i, row] * length, d1 * length, s)


@njit(cache=True)
def work_integrals(values, slopes, switch, end_values, end_slopes, lengths, lifted,
                   row_a, row_input, row_ydot, n_modes, row_vel, row_z, n_elements,
                   modal_damping, element_stiffness, element_damping):
    """Input work, structural and foundation damping energy [J] by 3-point Gauss quadrature
    on the cubic Hermite interpolants of the signals in every interval.

    values, slopes: (n, k), one row per sample (interval-local access keeps it in cache)."""
    nodes = np.array([0.5 * (1.0 - np.sqrt(0.6)), 0.5, 0.5 * (1.0 + np.sqrt(0.6))])
    weights = np.array([5.0, 8.0, 5.0]) / 18.0
    work_in = 0.0
    damp_struct = 0.0
    damp_found = 0.0
    for i in range(lengths.size):
        length = lengths[i]
        for g in range(3):
            s = nodes[g]
            w = weights[g] * length
            a = _at(values, slopes, switch, end_values, end_slopes, row_a, i, length, s)
            f = _at(values, slopes, switch, end_values, end_slopes, row_input, i, length, s)
            work_in += w * a * f
            acc = 0.0
            for k in range(n_modes):
                yd = _at(values, slopes, switch, end_values, end_slopes, row_ydot + k, i, length, s)
                acc += modal_damping[k] * yd * yd
            damp_struct += w * acc
            acc = 0.0
            for e in range(n_elements):
                c = element_damping[e]
                if c <= 0.0:
                    continue
                if lifted[i, e]:
                    force = element_stiffness[e] * _at(values, slopes, switch, end_values, end_slopes,
                                                       row_z + e, i, length, s)
                    acc += force * force / c
                else:
                    vel = _at(values, slopes, switch, end_values, end_slopes, row_vel + e, i, length, s)
                    acc += c * vel * vel
            damp_found += w * acc
    return work_in, damp_struct, damp_found
