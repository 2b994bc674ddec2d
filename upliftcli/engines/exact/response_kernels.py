"""Compiled loops of the post-processing (numba): signals at the samples, peaks between
samples and work integrals.

Each walks the samples (or the intervals between them) once; numpy versions of the same loops cost
5-10 times more on the ten-story example (temporaries and strided reductions).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .stepping_kernels import copy_into


@njit(cache=True)
def _quintic_extremum(p0, p1, d0, d1, c0, c1):
    """Largest |p(s)| for s in [0, 1] of the quintic Hermite p with p, p', p'' given at both
    ends (slopes times the interval length, second derivatives times its square); returns
    (value, s). The stationary points are bracketed on 8 sub-intervals and bisected."""
    a2 = 0.5 * c0
    a3 = -1.5 * c0 + 0.5 * c1 - 6.0 * d0 - 4.0 * d1 - 10.0 * p0 + 10.0 * p1
    a4 = 1.5 * c0 - c1 + 8.0 * d0 + 7.0 * d1 + 15.0 * p0 - 15.0 * p1
    a5 = -0.5 * c0 + 0.5 * c1 - 3.0 * d0 - 3.0 * d1 - 6.0 * p0 + 6.0 * p1
    best = abs(p0)
    where = 0.0
    if abs(p1) > best:
        best = abs(p1)
        where = 1.0
    lo = 0.0
    g_lo = d0
    for k in range(1, 9):
        hi = k / 8.0
        g_hi = (((5.0 * a5 * hi + 4.0 * a4) * hi + 3.0 * a3) * hi + 2.0 * a2) * hi + d0
        if (g_lo > 0.0) != (g_hi > 0.0) or g_hi == 0.0:
            left, right, g_left = lo, hi, g_lo
            for _ in range(40):
                mid = 0.5 * (left + right)
                g_mid = (((5.0 * a5 * mid + 4.0 * a4) * mid + 3.0 * a3) * mid + 2.0 * a2) * mid + d0
                if (g_mid > 0.0) == (g_left > 0.0) and g_mid != 0.0:
                    left, g_left = mid, g_mid
                else:
                    right = mid
            root = 0.5 * (left + right)
            value = abs((((((a5 * root + a4) * root + a3) * root + a2) * root + d0) * root) + p0)
            if value > best:
                best = value
                where = root
        lo, g_lo = hi, g_hi
    return best, where


@njit(cache=True)
def evaluate_signals(states, ids, rows_t, values, slopes, ends):
    """Signal values and slopes at every sample, each sample with its own contact state's rows.

    rows_t (S, n_aug, k + k_s): transposed rows of every state (k value rows, then the slope
    rows of the first k_s signals); values (n, k), slopes (n, k_s) filled in place; ends
    (n_switch, k + k_s): the left limits at the end of every interval that ends at a
    transition, in order. Accumulated column by column (vectorised; see kernel._matvec).
    """
    n = states.shape[0]
    k = values.shape[1]
    width = rows_t.shape[2]
    acc = np.empty(width)
    n_switch = 0
    for i in range(n):
        s = ids[i]
        _accumulate(states, i, rows_t[s], acc)
        copy_into(values[i], acc[:k])
        copy_into(slopes[i], acc[k:])
        if i + 1 < n and ids[i + 1] != s:
            _accumulate(states, i + 1, rows_t[s], acc)
            copy_into(ends[n_switch], acc)
            n_switch += 1


@njit(cache=True, inline="always")
def _accumulate(states, i, rows_t, out):
    """out = R x_i from R^T (n_aug, width), skipping zero state entries."""
    out[:] = 0.0
    for q in range(states.shape[1]):
        xq = states[i, q]
        if xq != 0.0:
            for r in range(out.size):
                out[r] += rows_t[q, r] * xq


@njit(cache=True)
def hermite_peaks(values, slopes, end_values, end_slopes, switch, value_columns, rate_columns, curvature_columns,
                  rows_t, lengths, fractions):
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
    (its left limit is not a sample). The responses at the samples are kept, (n, m) doubles.
    """
    n = values.shape[0]
    n_b, m = rows_t.shape
    best = np.zeros(m)
    where = np.zeros(m)
    r1 = np.empty(m)
    # pass 1: every response at every sample (kept) and its sampled peak
    sampled = np.empty((n, m))
    for i in range(n):
        _combine(values[i], value_columns, rows_t, sampled[i])
        for j in range(m):
            v = abs(sampled[i, j])
            if v > best[j]:
                best[j] = v
                where[j] = i
    # the samples within the fraction of the peak of some response
    threshold = fractions * best
    flagged = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        for j in range(m):
            if abs(sampled[i, j]) >= threshold[j]:
                flagged[i] = True
                break
    # pass 2: between samples, on the intervals with a flagged end or ending at a transition
    for i in range(n - 1):
        fix = switch[i]
        if not (flagged[i] or flagged[i + 1] or fix >= 0):
            continue
        r0 = sampled[i]
        if fix >= 0:  # the interval ends at a transition: its left limit
            _combine(end_values[fix], value_columns, rows_t, r1)
        else:
            copy_into(r1, sampled[i + 1])
        for j in range(m):
            if abs(r0[j]) < threshold[j] and abs(r1[j]) < threshold[j]:
                continue
            d0 = 0.0
            d1 = 0.0
            c0 = 0.0
            c1 = 0.0
            for q in range(n_b):
                d0 += rows_t[q, j] * values[i, rate_columns[q]]
                c0 += rows_t[q, j] * slopes[i, curvature_columns[q]]
                if fix >= 0:
                    d1 += rows_t[q, j] * end_values[fix, rate_columns[q]]
                    c1 += rows_t[q, j] * end_slopes[fix, curvature_columns[q]]
                else:
                    d1 += rows_t[q, j] * values[i + 1, rate_columns[q]]
                    c1 += rows_t[q, j] * slopes[i + 1, curvature_columns[q]]
            length = lengths[i]
            value, s = _quintic_extremum(r0[j], r1[j], d0 * length, d1 * length,
                                         c0 * length * length, c1 * length * length)
            if value > best[j]:
                best[j] = value
                where[j] = i + s
    return best, where


@njit(cache=True, inline="always")
def _combine(row, columns, rows_t, out):
    """out = R y with y = row[columns], from R^T (n_basis, m)."""
    out[:] = 0.0
    for q in range(rows_t.shape[0]):
        yq = row[columns[q]]
        for j in range(out.size):
            out[j] += rows_t[q, j] * yq


@njit(cache=True, inline="always")
def _hermite(v0, v1, d0, d1, s):
    s2 = s * s
    s3 = s2 * s
    return (2 * s3 - 3 * s2 + 1) * v0 + (s3 - 2 * s2 + s) * d0 + (-2 * s3 + 3 * s2) * v1 + (s3 - s2) * d1


@njit(cache=True)
def work_integrals(values, slopes, switch, end_values, end_slopes, lengths, lifted, n_interpolated,
                   row_a, row_input, row_ydot, n_modes, row_vel, row_z, n_elements,
                   modal_damping, element_stiffness, element_damping):
    """Input work, structural and foundation damping energy [J] by 3-point Gauss quadrature
    on the cubic Hermite interpolants of the signals in every interval (the dashpots of
    lifted elements exactly: k (z0^2 - z1^2) / 2).

    values (n, k), slopes (n, k_s): one row per sample (interval-local access keeps it in
    cache); only the first n_interpolated signals (they have slopes) are interpolated."""
    nodes = np.array([0.5 * (1.0 - np.sqrt(0.6)), 0.5, 0.5 * (1.0 + np.sqrt(0.6))])
    weights = np.array([5.0, 8.0, 5.0]) / 18.0
    basis = np.empty((3, 4))  # Hermite basis h00, h10, h01, h11 at the Gauss nodes
    for g in range(3):
        basis[g, 0] = _hermite(1.0, 0.0, 0.0, 0.0, nodes[g])
        basis[g, 1] = _hermite(0.0, 0.0, 1.0, 0.0, nodes[g])
        basis[g, 2] = _hermite(0.0, 1.0, 0.0, 0.0, nodes[g])
        basis[g, 3] = _hermite(0.0, 0.0, 0.0, 1.0, nodes[g])
    k = n_interpolated  # the signals the integrals need come first in values and slopes
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
            elif q == row_a:
                # the ground acceleration is linear inside the interval (its slope jumps at samples)
                v1 = values[i + 1, q]
                d1 = d0
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
                if c > 0.0 and not lifted[i, e]:
                    vel = gauss[g, row_vel + e]
                    acc += c * vel * vel
            damp_found += w * acc
        # a lifted element relaxes on its own, k z + c z' = 0: its dashpot dissipates exactly the
        # spring energy released, k (z0^2 - z1^2) / 2 (no quadrature: z may decay within the step)
        for e in range(n_elements):
            if element_damping[e] > 0.0 and lifted[i, e]:
                z0 = values[i, row_z + e]
                z1 = end_values[fix, row_z + e] if fix >= 0 else values[i + 1, row_z + e]
                damp_found += 0.5 * element_stiffness[e] * (z0 * z0 - z1 * z1)
    return work_in, damp_struct, damp_found
