"""Compiled loops of the response spectra (numba): the exact Nigam-Jennings step, the bound
that finds the steps where a peak can lie between samples, and the exact turning points
there (see spectra.py for the method). Each loop runs over many oscillators at once.
"""

from __future__ import annotations

import math

import numba
import numpy as np

_FASTMATH = {"contract", "reassoc", "nsz"}  # FMA and reordering; no NaN/inf assumptions


@numba.njit(cache=True, inline="always")
def _closed_form_step(u0, v0, a0, a1, w, sigma, wd, h, e, c, s):
    """Exact state after one step h of piecewise-linear ground acceleration a0 -> a1."""
    slope = (a1 - a0) / h
    c1 = -slope / (w * w)
    c0 = -a0 / (w * w) - 2.0 * sigma * c1 / (w * w)
    amp_a = u0 - c0
    amp_b = (v0 - c1 + sigma * amp_a) / wd
    u1 = c0 + c1 * h + e * (amp_a * c + amp_b * s)
    v1 = c1 + e * ((amp_b * wd - sigma * amp_a) * c - (amp_a * wd + sigma * amp_b) * s)
    return u1, v1


@numba.njit(cache=True)
def _step_coefficients(w, xi, h):
    """Matrices of the recurrence [u1, v1] = A [u0, v0] + B [a0, a1] (Nigam-Jennings)."""
    sigma = xi * w
    wd = w * math.sqrt(1.0 - xi * xi)
    e = math.exp(-sigma * h)
    c = math.cos(wd * h)
    s = math.sin(wd * h)
    coefficients = np.empty(8)
    unit = ((1.0, 0.0, 0.0, 0.0), (0.0, 1.0, 0.0, 0.0), (0.0, 0.0, 1.0, 0.0), (0.0, 0.0, 0.0, 1.0))
    for k in range(4):
        u1, v1 = _closed_form_step(unit[k][0], unit[k][1], unit[k][2], unit[k][3], w, sigma, wd, h, e, c, s)
        coefficients[2 * k] = u1
        coefficients[2 * k + 1] = v1
    return coefficients


@numba.njit(cache=True)
def _root_value(l0, l1, pa, qa, pd, qd, pdd, qdd, sigma, wd, lo, hi, d_lo, d_hi):
    """|f| at the root of f' in (lo, hi), f'(lo) = d_lo and f'(hi) = d_hi of opposite sign, for
    f = l0 + l1 t + exp(-sigma t)(pa cos wd t + qa sin wd t), f' = l1 + exp(-sigma t)(pd cos + qd sin),
    f'' = exp(-sigma t)(pdd cos + qdd sin): safeguarded Newton from the secant estimate. The value at
    a turning point is stationary, so t to 1e-9 of the bracket is far below rounding."""
    width = hi - lo
    t = lo + width * d_lo / (d_lo - d_hi)
    for _ in range(40):
        ex = math.exp(-sigma * t)
        co = math.cos(wd * t)
        si = math.sin(wd * t)
        d = l1 + ex * (pd * co + qd * si)
        if d == 0.0:
            break
        if (d > 0.0) == (d_lo > 0.0):
            lo = t
        else:
            hi = t
        dd = ex * (pdd * co + qdd * si)
        t_new = t - d / dd if dd != 0.0 else 0.5 * (lo + hi)
        if not (lo < t_new < hi):
            t_new = 0.5 * (lo + hi)
        converged = abs(t_new - t) <= 1e-9 * width
        t = t_new
        if converged or hi - lo <= 1e-9 * width:
            break
    ex = math.exp(-sigma * t)
    return abs(l0 + l1 * t + ex * (pa * math.cos(wd * t) + qa * math.sin(wd * t)))


@numba.njit(cache=True)
def _interior_peak(l0, l1, pa, qa, sigma, wd, h, d0, d1):
    """Largest |f| at the turning points of f = l0 + l1 t + exp(-sigma t)(pa cos wd t + qa sin wd t)
    inside (0, h), f'(0) = d0, f'(h) = d1 (0 if there is none).

    With wd h < pi, f'' (a damped sinusoid) has at most one root t_e in (0, h), so f' has one root
    when d0, d1 differ in sign, and otherwise none or two, two exactly when f'(t_e) has the other sign."""
    pd = qa * wd - sigma * pa
    qd = -pa * wd - sigma * qa
    pdd = qd * wd - sigma * pd
    qdd = -pd * wd - sigma * qd
    if d0 * d1 < 0.0:
        return _root_value(l0, l1, pa, qa, pd, qd, pdd, qdd, sigma, wd, 0.0, h, d0, d1)
    theta = math.atan2(-pdd, qdd)  # pdd cos + qdd sin = 0
    if theta < 0.0:
        theta += math.pi
    t_e = theta / wd
    if not (0.0 < t_e < h):
        return 0.0
    d_e = l1 + math.exp(-sigma * t_e) * (pd * math.cos(wd * t_e) + qd * math.sin(wd * t_e))
    if d_e * d0 >= 0.0:
        return 0.0
    first = _root_value(l0, l1, pa, qa, pd, qd, pdd, qdd, sigma, wd, 0.0, t_e, d0, d_e)
    second = _root_value(l0, l1, pa, qa, pd, qd, pdd, qdd, sigma, wd, t_e, h, d_e, d1)
    return max(first, second)


@numba.njit(cache=True)
def _free_vibration_peak(pa, qa, sigma, wd):
    """max |f| for t >= 0 of f = exp(-sigma t)(pa cos wd t + qa sin wd t): the first turning point."""
    pd = qa * wd - sigma * pa
    qd = -pa * wd - sigma * qa
    theta = math.atan2(-pd, qd)  # pd cos + qd sin = 0
    while theta < 0.0:
        theta += math.pi
    while theta >= math.pi:
        theta -= math.pi
    t = theta / wd
    value = abs(math.exp(-sigma * t) * (pa * math.cos(wd * t) + qa * math.sin(wd * t)))
    return max(abs(pa), value)


@numba.njit(cache=True)
def _refine_step(u0, v0, dat0, dat1, v1, a0, a1, w, sigma, wd, h, peak_u, peak_at, which):
    """Exact peaks of u (which & 1) and of the absolute acceleration (which & 2) inside one step,
    from the closed form of the step."""
    w2 = w * w
    slope = (a1 - a0) / h
    c1 = -slope / w2
    c0 = -(a0 + 2.0 * sigma * c1) / w2
    amp_a = u0 - c0
    amp_b = (v0 - c1 + sigma * amp_a) / wd
    if which & 1:
        peak_u = max(peak_u, _interior_peak(c0, c1, amp_a, amp_b, sigma, wd, h, v0, v1))
    if not which & 2:
        return peak_u, peak_at
    # absolute acceleration a_g + u'' = a0 + slope t + exp(-sigma t)(pa cos + qa sin)
    pa = -w2 * amp_a - 2.0 * sigma * (amp_b * wd - sigma * amp_a)
    qa = -w2 * amp_b + 2.0 * sigma * (amp_a * wd + sigma * amp_b)
    peak_at = max(peak_at, _interior_peak(a0, slope, pa, qa, sigma, wd, h, dat0, dat1))
    return peak_u, peak_at


# rows of the per-oscillator constant table used by _chunk_peaks
(_A_UU, _A_VU, _A_UV, _A_VV, _B_U0, _B_V0, _B_U1, _B_V1, _W2, _INV_W2, _TWO_SIGMA, _INV_WD, _AT_GAIN2,
 _HERMITE_ERROR2) = range(14)


@numba.njit(cache=True, fastmath=_FASTMATH)
def _chunk_peaks(acc, dt, omegas, xis, nsub, free_vibration, out_u, out_at):
    """Peak |u| [m] and |absolute acceleration| [m/s^2] of oscillators sharing one sub-step count.

    Time loop outside, oscillators inside. The inner loop has no branch, so it runs in SIMD
    lanes: it advances every oscillator, keeps the sampled peaks and flags the steps where a
    turning point is possible and a rigorous bound of max |f| reaches the running peak (see the
    module docstring); only flagged steps are refined (_refine_step)."""
    m = omegas.size
    h = dt / nsub
    cf = np.empty((14, m))
    for k in range(m):
        w = omegas[k]
        sigma = xis[k] * w
        cf[0:8, k] = _step_coefficients(w, xis[k], h)
        cf[_W2, k] = w * w
        cf[_INV_W2, k] = 1.0 / (w * w)
        cf[_TWO_SIGMA, k] = 2.0 * sigma
        cf[_INV_WD, k] = 1.0 / (w * math.sqrt(1.0 - xis[k] * xis[k]))
        cf[_AT_GAIN2, k] = (w * (w + 2.0 * sigma)) ** 2  # amplitude of a_t's oscillation <= this^0.5 * u's
        cf[_HERMITE_ERROR2, k] = ((w * h) ** 4 / 384.0) ** 2  # cubic Hermite error / amplitude, squared
    u = np.zeros(m)
    v = np.zeros(m)
    u_old = np.zeros(m)
    v_old = np.zeros(m)
    flag = np.zeros(m)
    peak_u = np.zeros(m)
    peak_at = np.zeros(m)
    n = acc.size
    last = n - 1 + (1 if (free_vibration and acc[n - 1] != 0.0) else 0)
    inv_h = 1.0 / h
    h_third = h / 3.0
    for i in range(last):
        g0 = acc[i]
        g1 = acc[i + 1] if i + 1 < n else 0.0
        for j in range(nsub):
            a0 = g0 + (g1 - g0) * (j / nsub)
            a1 = g0 + (g1 - g0) * ((j + 1) / nsub)
            slope_h = a1 - a0  # ground-acceleration slope times h
            slope = slope_h * inv_h
            n_flag = 0.0
            for k in range(m):
                u0 = u[k]
                v0 = v[k]
                u1 = cf[_A_UU, k] * u0 + cf[_A_UV, k] * v0 + cf[_B_U0, k] * a0 + cf[_B_U1, k] * a1
                v1 = cf[_A_VU, k] * u0 + cf[_A_VV, k] * v0 + cf[_B_V0, k] * a0 + cf[_B_V1, k] * a1
                w2 = cf[_W2, k]
                two_sigma = cf[_TWO_SIGMA, k]
                at0 = -w2 * u0 - two_sigma * v0  # absolute acceleration
                at1 = -w2 * u1 - two_sigma * v1
                dat0 = -w2 * v0 - two_sigma * (at0 - a0)  # its slope
                dat1 = -w2 * v1 - two_sigma * (at1 - a1)
                p_u = max(peak_u[k], abs(u1))
                p_at = max(peak_at[k], abs(at1))
                # closed form over the step: u = c0 + c1 t + hom(t), |hom| <= sqrt(A^2 + B^2)
                c1h = -slope_h * cf[_INV_W2, k]
                c0 = -(a0 + two_sigma * c1h * inv_h) * cf[_INV_W2, k]
                amp_a = u0 - c0
                amp_b = (v0 - c1h * inv_h + 0.5 * two_sigma * amp_a) * cf[_INV_WD, k]
                r2 = amp_a * amp_a + amp_b * amp_b
                # max |f| over the step <= max |Bezier control points of the cubic Hermite interpolant|
                # + its error bound (w h)^4 / 384 * amplitude; the end points are in the peaks already
                room_u = p_u - max(abs(u0 + h_third * v0), abs(u1 - h_third * v1))
                room_at = p_at - max(abs(at0 + h_third * dat0), abs(at1 - h_third * dat1))
                error2 = cf[_HERMITE_ERROR2, k] * r2
                # an interior turning point needs a sign change of f' (one root) or of f'' (two roots)
                rel0 = at0 - a0  # u''
                rel1 = at1 - a1
                jerk0 = -w2 * rel0 + two_sigma * (slope + two_sigma * rel0 + w2 * v0)  # a_t''
                jerk1 = -w2 * rel1 + two_sigma * (slope + two_sigma * rel1 + w2 * v1)
                turn_u = (v0 * v1 < 0.0) | (rel0 * rel1 < 0.0)
                turn_at = (dat0 * dat1 < 0.0) | (jerk0 * jerk1 < 0.0)
                f_u = turn_u & ((room_u <= 0.0) | (error2 > room_u * room_u))
                f_at = turn_at & ((room_at <= 0.0) | (error2 * cf[_AT_GAIN2, k] > room_at * room_at))
                f = (1.0 if f_u else 0.0) + (2.0 if f_at else 0.0)  # which quantities to refine
                flag[k] = f
                n_flag += f
                u_old[k] = u0
                v_old[k] = v0
                u[k] = u1
                v[k] = v1
                peak_u[k] = p_u
                peak_at[k] = p_at
            if n_flag > 0.0:
                for k in range(m):
                    if flag[k] > 0.0:
                        sigma = 0.5 * cf[_TWO_SIGMA, k]
                        w2 = cf[_W2, k]
                        at0 = -w2 * u_old[k] - 2.0 * sigma * v_old[k]
                        at1 = -w2 * u[k] - 2.0 * sigma * v[k]
                        peak_u[k], peak_at[k] = _refine_step(
                            u_old[k], v_old[k], -w2 * v_old[k] - 2.0 * sigma * (at0 - a0),
                            -w2 * v[k] - 2.0 * sigma * (at1 - a1), v[k], a0, a1, omegas[k], sigma,
                            1.0 / cf[_INV_WD, k], h, peak_u[k], peak_at[k], int(flag[k]))
    for k in range(m):
        if free_vibration:
            sigma = 0.5 * cf[_TWO_SIGMA, k]
            wd = 1.0 / cf[_INV_WD, k]
            w2 = cf[_W2, k]
            amp_a = u[k]
            amp_b = (v[k] + sigma * u[k]) / wd
            peak_u[k] = max(peak_u[k], _free_vibration_peak(amp_a, amp_b, sigma, wd))
            pa = -w2 * amp_a - 2.0 * sigma * (amp_b * wd - sigma * amp_a)
            qa = -w2 * amp_b + 2.0 * sigma * (amp_a * wd + sigma * amp_b)
            peak_at[k] = max(peak_at[k], _free_vibration_peak(pa, qa, sigma, wd))
        out_u[k] = peak_u[k]
        out_at[k] = peak_at[k]


@numba.njit(cache=True, parallel=True)
def spectrum_kernel(acc, dt, omegas, xis, nsubs, chunk_starts, n_workers, free_vibration, out_u, out_at):
    """Run the chunks [chunk_starts[c], chunk_starts[c+1]) (equal sub-step count inside a chunk,
    costliest first) dealt round-robin to the threads."""
    n_chunks = chunk_starts.size - 1
    n_workers = min(n_workers, n_chunks)
    for worker in numba.prange(n_workers):
        for c in range(worker, n_chunks, n_workers):
            lo = chunk_starts[c]
            hi = chunk_starts[c + 1]
            _chunk_peaks(acc, dt, omegas[lo:hi], xis[lo:hi], nsubs[lo], free_vibration, out_u[lo:hi], out_at[lo:hi])


@numba.njit(cache=True)
def history_kernel(acc, dt, w, xi, u_out, v_out):
    k = _step_coefficients(w, xi, dt)
    u = 0.0
    v = 0.0
    u_out[0] = 0.0
    v_out[0] = 0.0
    for i in range(acc.size - 1):
        a0 = acc[i]
        a1 = acc[i + 1]
        u, v = (k[0] * u + k[2] * v + k[4] * a0 + k[6] * a1, k[1] * u + k[3] * v + k[5] * a0 + k[7] * a1)
        u_out[i + 1] = u
        v_out[i + 1] = v
