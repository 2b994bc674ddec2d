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

    values: responses at the samples (n, m), continuous in time; their slopes are rows @ rates
    (rates (n, k) at the samples; end_rates[switch[i]] (k,) at the end of an interval i that
    ends at a transition), evaluated only on the intervals that can hold the peak.
    """
    n, m = values.shape
    k = rows.shape[1]
    best = np.zeros(m)
    where = np.zeros(m)
    for i in range(n):
        for j in range(m):
            v = abs(values[i, j])
            if v > best[j]:
                best[j] = v
                where[j] = i
    threshold = CANDIDATE_FRACTION * best
    for i in range(n - 1):
        fix = switch[i]
        for j in range(m):
            r0 = values[i, j]
            r1 = values[i + 1, j]
            if abs(r0) < threshold[j] and abs(r1) < threshold[j]:
                continue
            d0 = 0.0
            d1 = 0.0
            for q in range(k):
                d0 += rows[j, q] * rates[i, q]
                if fix >= 0:
                    d1 += rows[j, q] * end_rates[fix, q]
                else:
                    d1 += rows[j, q] * rates[i + 1, q]
            value, s = _hermite_extremum(r0, r1, d0 * lengths[i], d1 * lengths[i])
            if value > best[j]:
                best[j] = value
                where[j] = i + s
    return best, where


@njit(cache=True, inline="always")
def _hermite(v0, v1, d0, d1, s):
    s2 = s * s
    s3 = s2 * s
    return (2 * s3 - 3 * s2 + 1) * v0 + (s3 - 2 * s2 + s) * d0 + (-2 * s3 + 3 * s2) * v1 + (s3 - s2) * d1


@njit(cache=True)
def work_integrals(values, slopes, switch, end_values, end_slopes, lengths, lifted,
                   row_a, row_input, row_ydot, n_modes, row_vel, row_z, n_elements,
                   modal_damping, element_stiffness, element_damping):
    """Input work, structural and foundation damping energy [J] by 3-point Gauss quadrature
    on the cubic Hermite interpolants of the signals in every interval.

    values, slopes: (n, k), one row per sample (interval-local access keeps it in cache)."""
    nodes = np.array([0.5 * (1.0 - np.sqrt(0.6)), 0.5, 0.5 * (1.0 + np.sqrt(0.6))])
    weights = np.array([5.0, 8.0, 5.0]) / 18.0
    basis = np.empty((3, 4))  # Hermite basis h00, h10, h01, h11 at the Gauss nodes
    for g in range(3):
        basis[g, 0] = _hermite(1.0, 0.0, 0.0, 0.0, nodes[g])
        basis[g, 1] = _hermite(0.0, 0.0, 1.0, 0.0, nodes[g])
        basis[g, 2] = _hermite(0.0, 1.0, 0.0, 0.0, nodes[g])
        basis[g, 3] = _hermite(0.0, 0.0, 0.0, 1.0, nodes[g])
    k = values.shape[1]
    gauss = np.empty((3, k))
    work_in = 0.0
    damp_struct = 0.0
    damp_found = 0.0
    for i in range(lengths.size):
        length = lengths[i]
        fix = switch[i]
        for q in range(k):
            v0 = values[i, q]
            d0 = slopes[i, q] * length
            if fix >= 0:
                v1 = end_values[fix, q]
                d1 = end_slopes[fix, q] * length
            else:
                v1 = values[i + 1, q]
                d1 = slopes[i + 1, q] * length
            for g in range(3):
                gauss[g, q] = basis[g, 0] * v0 + basis[g, 1] * d0 + basis[g, 2] * v1 + basis[g, 3] * d1
        for g in range(3):
            w = weights[g] * length
            work_in += w * gauss[g, row_a] * gauss[g, row_input]
            acc = 0.0
            for m in range(n_modes):
                yd = gauss[g, row_ydot + m]
                acc += modal_damping[m] * yd * yd
            damp_struct += w * acc
            acc = 0.0
            for e in range(n_elements):
                c = element_damping[e]
                if c <= 0.0:
                    continue
                if lifted[i, e]:
                    force = element_stiffness[e] * gauss[g, row_z + e]
                    acc += force * force / c
                else:
                    vel = gauss[g, row_vel + e]
                    acc += c * vel * vel
            damp_found += w * acc
    return work_in, damp_struct, damp_found
