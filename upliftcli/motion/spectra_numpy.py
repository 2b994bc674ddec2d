"""The numpy twin of the response-spectrum loops of _spectra.c (same method, see spectra.py):
spectrum_kernel and history_kernel with the same arguments (spectra_kernels.py), vectorised over
the oscillators and over time instead of compiled.

It runs them when upliftcli.runtime.backend chooses numpy, and for response_spectrum(method="numpy");
the tests compare it with the compiled loop (tests/test_spectra.py, tests/test_spectra_numpy.py):
the results agree to rounding. Oscillators x sub-steps are taken NUMPY_BLOCK at a time (about
50 MB of arrays): oscillators in groups, a record too long for one oscillator in segments of
time, each starting from the state where the last ended.

Per oscillator of a group sharing one sub-step h = dt / nsub:

* the exact piecewise-linear step [u1, v1] = A [u0, v0] + B [a0, a1] (Nigam-Jennings) is a
  linear recurrence x_{k+1} = A x_k + b_k; all states are its prefix sums x_{k+1} = sum_j A^(k-j) b_j,
  in blocks of steps (one product per block with the powers of A, the blocks' starts in doubling
  passes y_k += A^s y_{k-s}, s = 1, 2, 4, ... with A^s = A(s h) in closed form: _states);
* peaks between samples: the steps where a turning point is possible (a sign change of f' or
  f'') and where the bound of max |f| (Bezier control points of the cubic Hermite interpolant
  plus its error (w h)^4 / 384 * amplitude) reaches the largest sampled |f| are solved on the
  closed form (the roots of f', safeguarded Newton); no other step can hold the peak;
* the free vibration after the record: its first turning point, in closed form.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

#: oscillators x sub-steps integrated at once (bounds the memory to some 50 MB)
NUMPY_BLOCK = 2**18
#: steps of one block of the state recurrence (its matrices grow as STATE_BLOCK^2)
STATE_BLOCK = 16


def _transition(omegas: np.ndarray, xis: np.ndarray, t) -> np.ndarray:
    """Coefficients (8, m) of [u1, v1] = A [u0, v0] + B [a0, a1] over a step t > 0: rows A_uu, A_vu,
    A_uv, A_vv, B_u0, B_v0, B_u1, B_v1 (the order of step_coefficients in _spectra.c); (8, n, m) for
    steps t of shape (n, 1)."""
    w = omegas
    sigma = xis * w
    wd = w * np.sqrt(1.0 - xis * xis)
    e = np.exp(-sigma * t)
    c = np.cos(wd * t)
    s = np.sin(wd * t)
    out = np.empty((8, *np.broadcast_shapes(np.shape(w), np.shape(t))))
    for k, (u0, v0, a0, a1) in enumerate(((1.0, 0.0, 0.0, 0.0), (0.0, 1.0, 0.0, 0.0), (0.0, 0.0, 1.0, 0.0),
                                          (0.0, 0.0, 0.0, 1.0))):
        slope = (a1 - a0) / t
        c1 = -slope / (w * w)
        c0 = -a0 / (w * w) - 2.0 * sigma * c1 / (w * w)
        amp_a = u0 - c0
        amp_b = (v0 - c1 + sigma * amp_a) / wd
        out[2 * k] = c0 + c1 * t + e * (amp_a * c + amp_b * s)
        out[2 * k + 1] = c1 + e * ((amp_b * wd - sigma * amp_a) * c - (amp_a * wd + sigma * amp_b) * s)
    return out


def _states(omegas: np.ndarray, xis: np.ndarray, h: float, a0: np.ndarray, a1: np.ndarray, u0=0.0, v0=0.0
            ) -> tuple[np.ndarray, np.ndarray]:
    """u, v (m, K + 1) at the ends of the K steps of ground acceleration a0 -> a1 (K,), from the
    state u0, v0 (m,) (rest by default).

    The step x_{k+1} = A x_k + b_k in blocks of STATE_BLOCK steps: inside a block the forced part
    sum_{i<j} A^(j-1-i) b_i is one product of the block's b with a lower-triangular Toeplitz matrix
    of A^l per oscillator; the blocks' starts follow s' = A^B s + (the block's forced end) in
    log2(blocks) doubling passes; every step adds A^j s (A^t in closed form, _transition)."""
    m, n_steps = omegas.size, a0.size
    size = min(STATE_BLOCK, n_steps)
    count = -(-n_steps // size)
    cf = _transition(omegas, xis, h)[:, :, None]
    b = np.zeros((2, m, count * size))
    b[0, :, :n_steps] = cf[4] * a0 + cf[6] * a1  # the step's forced response from rest
    b[1, :, :n_steps] = cf[5] * a0 + cf[7] * a1
    b = b.reshape(2, m, count, size)
    powers = np.empty((size + 1, 4, m))  # A^l, l = 0..size: rows uu, vu, uv, vv
    powers[0] = np.array([1.0, 0.0, 0.0, 1.0])[:, None]
    powers[1:] = _transition(omegas, xis, h * np.arange(1, size + 1)[:, None])[:4].transpose(1, 0, 2)
    lag = np.subtract.outer(np.arange(size), np.arange(size))  # row j - 1 (after step j), column i
    toeplitz = np.where(lag[:, :, None, None] >= 0, powers[np.maximum(lag, 0)], 0.0).transpose(2, 3, 1, 0)
    forced = [b[0] @ toeplitz[c] + b[1] @ toeplitz[c + 2] for c in (0, 1)]  # u, v: (m, count, size)
    # the blocks' starts: y_k = forced end of block k (+ A^B x_0 for the first), scanned
    y_u, y_v = forced[0][:, :, -1].copy(), forced[1][:, :, -1].copy()
    y_u[:, 0] += powers[size, 0] * u0 + powers[size, 2] * v0
    y_v[:, 0] += powers[size, 1] * u0 + powers[size, 3] * v0
    shift = 1
    while shift < count:
        p = _transition(omegas, xis, shift * size * h)[:4, :, None]  # (A^B)^shift in closed form
        back_u, back_v = y_u[:, :-shift], y_v[:, :-shift]
        add_u = p[0] * back_u + p[2] * back_v
        add_v = p[1] * back_u + p[3] * back_v
        y_u[:, shift:] += add_u
        y_v[:, shift:] += add_v
        shift *= 2
    start_u = np.concatenate((np.broadcast_to(u0, (m,))[:, None], y_u[:, :-1]), axis=1)[:, :, None]
    start_v = np.concatenate((np.broadcast_to(v0, (m,))[:, None], y_v[:, :-1]), axis=1)[:, :, None]
    after = powers[1:].transpose(1, 2, 0)[:, :, None, :]  # A^j for j = 1..size: (4, m, 1, size)
    u = (after[0] * start_u + after[2] * start_v + forced[0]).reshape(m, -1)[:, :n_steps]
    v = (after[1] * start_u + after[3] * start_v + forced[1]).reshape(m, -1)[:, :n_steps]
    first = np.zeros((2, m, 1))
    first[0, :, 0], first[1, :, 0] = u0, v0
    return np.concatenate((first[0], u), axis=1), np.concatenate((first[1], v), axis=1)


def _turning_values(l0, l1, pa, qa, sigma, wd, lo, hi, d_lo, d_hi) -> np.ndarray:
    """|f| at the root of f' in (lo, hi) (f' changes sign there), elementwise, for
    f = l0 + l1 t + exp(-sigma t)(pa cos wd t + qa sin wd t): safeguarded Newton from the secant
    estimate, as root_value in _spectra.c."""
    pd = qa * wd - sigma * pa
    qd = -pa * wd - sigma * qa
    pdd = qd * wd - sigma * pd
    qdd = -pd * wd - sigma * qd
    lo, hi = lo.copy(), hi.copy()
    width = hi - lo
    t = lo + width * d_lo / (d_lo - d_hi)
    active = np.ones(t.size, dtype=bool)
    for _ in range(40):
        index = np.flatnonzero(active)
        if index.size == 0:
            break
        ti = t[index]
        ex = np.exp(-sigma[index] * ti)
        co = np.cos(wd[index] * ti)
        si = np.sin(wd[index] * ti)
        d = l1[index] + ex * (pd[index] * co + qd[index] * si)
        root = d == 0.0
        same = (d > 0.0) == (d_lo[index] > 0.0)
        lo[index] = np.where(same, ti, lo[index])
        hi[index] = np.where(same, hi[index], ti)
        dd = ex * (pdd[index] * co + qdd[index] * si)
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = np.where(dd != 0.0, ti - d / dd, 0.5 * (lo[index] + hi[index]))
        newton = np.where((lo[index] < newton) & (newton < hi[index]), newton, 0.5 * (lo[index] + hi[index]))
        converged = np.abs(newton - ti) <= 1e-9 * width[index]
        t[index] = np.where(root, ti, newton)
        active[index] = ~(root | converged | (hi[index] - lo[index] <= 1e-9 * width[index]))
    return np.abs(l0 + l1 * t + np.exp(-sigma * t) * (pa * np.cos(wd * t) + qa * np.sin(wd * t)))


def _interior_peaks(l0, l1, pa, qa, sigma, wd, h, d0, d1) -> np.ndarray:
    """Largest |f| at the turning points inside (0, h) of each step (0 where none), as
    interior_peak in _spectra.c: one root of f' when f'(0), f'(h) differ in sign, else none or
    two around the root t_e of f'' (wd h < pi: at most one)."""
    pd = qa * wd - sigma * pa
    qd = -pa * wd - sigma * qa
    pdd = qd * wd - sigma * pd
    qdd = -pd * wd - sigma * qd
    one = d0 * d1 < 0.0
    theta = np.arctan2(-pdd, qdd)
    theta = np.where(theta < 0.0, theta + math.pi, theta)
    t_e = theta / wd
    d_e = l1 + np.exp(-sigma * t_e) * (pd * np.cos(wd * t_e) + qd * np.sin(wd * t_e))
    two = ~one & (t_e > 0.0) & (t_e < h) & (d_e * d0 < 0.0)
    out = np.zeros(d0.size)
    zero = np.zeros(d0.size)
    for chosen, lo, hi, d_lo, d_hi in ((one, zero, np.full(d0.size, h), d0, d1), (two, zero, t_e, d0, d_e),
                                       (two, t_e, np.full(d0.size, h), d_e, d1)):
        k = np.flatnonzero(chosen)
        if k.size:
            values = _turning_values(l0[k], l1[k], pa[k], qa[k], sigma[k], wd[k], lo[k], hi[k], d_lo[k], d_hi[k])
            out[k] = np.maximum(out[k], values)
    return out


def _free_vibration_peaks(pa, qa, sigma, wd) -> np.ndarray:
    """max |f| over t >= 0 of f = exp(-sigma t)(pa cos wd t + qa sin wd t): f(0) or the first turning point."""
    pd = qa * wd - sigma * pa
    qd = -pa * wd - sigma * qa
    theta = np.mod(np.arctan2(-pd, qd), math.pi)
    t = theta / wd
    return np.maximum(np.abs(pa), np.abs(np.exp(-sigma * t) * (pa * np.cos(wd * t) + qa * np.sin(wd * t))))


def _acceleration_terms(amp_a, amp_b, w2, sigma, wd):
    """(pa, qa) of the oscillating part of the absolute acceleration a_g + u'' for u's (amp_a, amp_b)."""
    return (-w2 * amp_a - 2.0 * sigma * (amp_b * wd - sigma * amp_a),
            -w2 * amp_b + 2.0 * sigma * (amp_a * wd + sigma * amp_b))


def chunk_peaks(acc: np.ndarray, dt: float, omegas: np.ndarray, xis: np.ndarray, nsub: int,
                free_vibration: bool) -> tuple[np.ndarray, np.ndarray]:
    """Peak |u| [m] and |absolute acceleration| [m/s^2] of oscillators w [rad/s] > 0, xi in [0, 1)
    sharing the sub-step count nsub, under the ground acceleration acc [m/s^2] at step dt [s]
    (piecewise linear; with free_vibration, then linearly to zero over dt and free vibration).
    At most NUMPY_BLOCK oscillator sub-steps at once: the record in segments of time."""
    acc = np.asarray(acc, dtype=float)
    omegas = np.asarray(omegas, dtype=float)
    length = max(NUMPY_BLOCK // (nsub * max(omegas.size, 1)), 2)  # samples per segment (sharing its ends)
    peak_u = peak_at = np.zeros(omegas.size)
    u0 = v0 = np.zeros(omegas.size)
    for start in range(0, acc.size - 1, length - 1):
        last = start + length >= acc.size
        segment_u, segment_at, u0, v0 = _segment_peaks(acc[start:start + length], dt, omegas, xis, nsub,
                                                       free_vibration and last, u0, v0)
        peak_u, peak_at = np.maximum(peak_u, segment_u), np.maximum(peak_at, segment_at)
    return peak_u, peak_at


def _segment_peaks(acc, dt, omegas, xis, nsub, free_vibration, u0, v0):
    """chunk_peaks over one segment of the record from the state u0, v0: (peak_u, peak_at, u, v at its end)."""
    omegas = np.asarray(omegas, dtype=float)
    xis = np.asarray(xis, dtype=float)
    g0 = acc[:-1]
    g1 = acc[1:]
    if free_vibration and acc[-1] != 0.0:  # the ramp to zero after the record
        g0 = np.append(g0, acc[-1])
        g1 = np.append(g1, 0.0)
    fractions = np.arange(nsub + 1) / nsub  # the kernel's sub-step ends g0 + (g1 - g0) (j / nsub)
    a0 = (g0[:, None] + (g1 - g0)[:, None] * fractions[None, :-1]).ravel()
    a1 = (g0[:, None] + (g1 - g0)[:, None] * fractions[None, 1:]).ravel()
    h = dt / nsub
    u, v = _states(omegas, xis, h, a0, a1, u0, v0)
    col = (slice(None), None)
    w = omegas[col]
    sigma = (xis * omegas)[col]
    wd = (omegas * np.sqrt(1.0 - xis * xis))[col]
    w2 = w * w
    at = -w2 * u - 2.0 * sigma * v  # absolute acceleration at the step ends
    mu, mv, mat = np.abs(u), np.abs(v), np.abs(at)
    sampled_u = np.max(mu, axis=1)
    sampled_at = np.max(mat[:, 1:], axis=1)
    slope = (a1 - a0) / h
    margin = 1.0 - 1e-9  # no step whose bound is below the largest sample can hold the peak
    # The steps whose bound (below) can reach the largest sample: first by a cheaper upper bound of
    # it (the amplitude of the closed form over the whole segment), 1e-12 above round-off
    c1_most = np.abs(slope).max(initial=0.0) / w2
    c0_most = (np.maximum(np.abs(a0).max(initial=0.0), np.abs(a1).max(initial=0.0)) + 2.0 * sigma * c1_most) / w2
    most_a = mu.max(axis=1, keepdims=True) + c0_most
    error_most = (w * h) ** 4 / 384.0 * (most_a + (mv.max(axis=1, keepdims=True) + c1_most + sigma * most_a) / wd)
    pair = np.maximum  # of the two ends of every step
    ground = pair(np.abs(a0), np.abs(a1))
    near_u = pair(mu[:, :-1], mu[:, 1:]) + h / 3.0 * pair(mv[:, :-1], mv[:, 1:]) + error_most
    near_at = (pair(mat[:, :-1], mat[:, 1:]) + h / 3.0 * (w2 * pair(mv[:, :-1], mv[:, 1:])
               + 2.0 * sigma * (pair(mat[:, :-1], mat[:, 1:]) + ground)) + error_most * w * (w + 2.0 * sigma))
    slack = 1.0 + 1e-12
    rows, steps = np.nonzero((near_u * slack >= margin * sampled_u[col])
                             | (near_at * slack >= margin * sampled_at[col]))
    # there, the bounds of the C loop: control points of the cubic Hermite interpolant + its error
    w, sigma, wd, w2 = w[rows, 0], sigma[rows, 0], wd[rows, 0], w2[rows, 0]
    u0, u1, v0, v1, at0, at1 = u[rows, steps], u[rows, steps + 1], v[rows, steps], v[rows, steps + 1], \
        at[rows, steps], at[rows, steps + 1]
    a0, a1, slope = a0[steps], a1[steps], slope[steps]
    dat0 = -w2 * v0 - 2.0 * sigma * (at0 - a0)  # slope of the absolute acceleration
    dat1 = -w2 * v1 - 2.0 * sigma * (at1 - a1)
    c1 = -slope / w2  # u = c0 + c1 t + exp(-sigma t)(amp_a cos wd t + amp_b sin wd t) over the step
    c0 = -(a0 + 2.0 * sigma * c1) / w2
    amp_a = u0 - c0
    amp_b = (v0 - c1 + sigma * amp_a) / wd
    error = (w * h) ** 4 / 384.0 * np.hypot(amp_a, amp_b)  # cubic Hermite error bound on u
    bound_u = np.maximum(np.abs(u0 + h / 3.0 * v0), np.abs(u1 - h / 3.0 * v1)) + error
    bound_at = np.maximum(np.abs(at0 + h / 3.0 * dat0), np.abs(at1 - h / 3.0 * dat1)) + error * w * (w + 2.0 * sigma)
    rel0, rel1 = at0 - a0, at1 - a1  # u''
    jerk0 = -w2 * rel0 + 2.0 * sigma * (slope + 2.0 * sigma * rel0 + w2 * v0)  # a_t''
    jerk1 = -w2 * rel1 + 2.0 * sigma * (slope + 2.0 * sigma * rel1 + w2 * v1)
    flag_u = ((v0 * v1 < 0.0) | (rel0 * rel1 < 0.0)) & (bound_u >= margin * sampled_u[rows])
    flag_at = ((dat0 * dat1 < 0.0) | (jerk0 * jerk1 < 0.0)) & (bound_at >= margin * sampled_at[rows])
    peak_u, peak_at = sampled_u.copy(), sampled_at.copy()
    for flags, peaks in ((flag_u, peak_u), (flag_at, peak_at)):
        k = np.flatnonzero(flags)
        if k.size == 0:
            continue
        pa, qa = amp_a[k], amp_b[k]
        if peaks is peak_u:
            values = _interior_peaks(c0[k], c1[k], pa, qa, sigma[k], wd[k], h, v0[k], v1[k])
        else:
            pa, qa = _acceleration_terms(pa, qa, w2[k], sigma[k], wd[k])
            values = _interior_peaks(a0[k], slope[k], pa, qa, sigma[k], wd[k], h, dat0[k], dat1[k])
        np.maximum.at(peaks, rows[k], values)
    col = (slice(None), None)
    sigma, wd, w2 = (xis * omegas)[col], (omegas * np.sqrt(1.0 - xis * xis))[col], (omegas * omegas)[col]
    if free_vibration:
        s, d, q2 = sigma[:, 0], wd[:, 0], w2[:, 0]
        amp_a = u[:, -1]
        amp_b = (v[:, -1] + s * amp_a) / d
        peak_u = np.maximum(peak_u, _free_vibration_peaks(amp_a, amp_b, s, d))
        pa, qa = _acceleration_terms(amp_a, amp_b, q2, s, d)
        peak_at = np.maximum(peak_at, _free_vibration_peaks(pa, qa, s, d))
    return peak_u, peak_at, u[:, -1], v[:, -1]


def spectrum_kernel(acc, dt, omegas, xis, nsubs, chunk_starts, free_vibration, out_u, out_at) -> None:
    """Peaks |u| and |a_t| into out_u, out_at, chunk by chunk (spectra_kernels.spectrum_kernel):
    the oscillators of a chunk share the sub-step count of its first; NUMPY_BLOCK sub-steps of
    oscillators at a time."""
    for first, end in itertools.pairwise(chunk_starts):
        nsub = int(nsubs[first])
        group = max(NUMPY_BLOCK // (nsub * acc.size), 1)
        for start in range(first, end, group):
            k = slice(start, min(start + group, end))
            out_u[k], out_at[k] = chunk_peaks(acc, dt, omegas[k], xis[k], nsub, bool(free_vibration))


def history_kernel(acc, dt, w, xi, u_out, v_out) -> None:
    """Relative displacement and velocity at the samples of acc, from rest (spectra_kernels.history_kernel)."""
    acc = np.asarray(acc, dtype=float)
    if acc.size < 2:
        u_out[:], v_out[:] = 0.0, 0.0
        return
    u, v = _states(np.array([float(w)]), np.array([float(xi)]), float(dt), acc[:-1], acc[1:])
    u_out[:], v_out[:] = u[0], v[0]
