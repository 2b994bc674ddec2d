"""Spectral matching in the time domain: wavelet adjustments (Al Atik & Abrahamson 2010).

Each iteration finds, for every control period T_i, the peak of the oscillator's response, its
time t_i and sign p_i, and adds to the record a sum of improved tapered cosine wavelets, one per
control period,

    f_j(t) = cos(w'_j (t - t_j + dt_j)) exp(-((t - t_j + dt_j) / gamma_j)^2),
    w'_j = w_j sqrt(1 - beta^2), gamma_j = 1.178 f_j^-0.93, dt_j = atan(sqrt(1 - beta^2) / beta) / w'_j

(Al Atik & Abrahamson 2010, Eqs. 9-11), whose amplitudes b solve C b = p (Q - |R|): Q the
target, R the peak pseudo-acceleration w^2 u(t_i), C_ij the response of oscillator i at t_i to
wavelet j. C takes the effect of each wavelet on each oscillator at the peak that sets its
spectral ordinate (over the record and the free vibration after it). Wavelet j is placed at that
peak when it is above the target and inside the record; otherwise (a peak to raise) at the
largest response of oscillator j within the strong motion (t_5 to t_95 of the Arias intensity),
so the record is changed where it is already strong and its duration is kept. The wavelets are
multiplied by a ramp that is 0 until the record's 1 % Arias time and 1 from its 5 % time, so
nothing is added before the first arrival, and tapered to 0 over the first and last second, so
the first and last samples are kept (docs/suites.md measures all this on the FEMA P695
records). The improved wavelet integrates to zero velocity and displacement; the pinned
baseline correction (baseline.py) removes what the tapers leave.

Responses are exact for the piecewise-linear record (spectra.sdof_history, short periods on the
record resampled to T/8, which is the same piecewise-linear record); C is evaluated by the
trapezoidal rule on a grid of T_i/8 (it only steers the iteration). The linear system is
solved with a Levenberg-Marquardt damping (DAMPING x its diagonal), which keeps it well posed
when neighbouring oscillators peak at the same instant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .baseline import baseline_correct
from .measures import arias_times
from .spectra import sdof_history

TWO_PI = 2.0 * math.pi
#: control periods per octave of the wavelet iteration
PER_OCTAVE = 16
#: Levenberg-Marquardt damping of the normal equations, relative to their diagonal
DAMPING = 0.02
#: periods of the response history that C takes into account (exp(-2 pi 0.05 x 16) = 0.7 %)
MEMORY_CYCLES = 16
#: the wavelets are tapered to zero over this time [s] at both ends of the record: no offset there
END_TAPER = 1.0
#: fractions of the Arias intensity of the strong motion where peaks below the target are raised
STRONG_MOTION = (0.05, 0.95)
#: fractions of the record's Arias intensity that bound what the wavelets may change: 0 before
#: the first and after the last, half-cosine ramps between the first two and the last two, 1 in
#: between: nothing is added before the first arrival nor after the coda (character.keep_shares
#: then returns the weak start and the coda their 5 % shares, issue 36). A ramp inside the strong
#: motion (t_5 to t_10) was tried: a record whose motion peaks there got wavelets of 20-30 Hz
#: that the ramp cut into steps (Fourier ratio 15-40 / 1-3 Hz 0.11)
WINDOW = (0.01, 0.05, 0.95, 0.99)
#: iterations without a better largest misfit after which the iteration stops
PATIENCE = 10

def tapered_cosine(t: np.ndarray, period: float, damping: float, peak_time: float) -> np.ndarray:
    """The improved tapered cosine wavelet [-] at times t [s] for the oscillator of period [s] and
    damping [-] whose response it moves at peak_time [s] (module docstring)."""
    frequency = 1.0 / period
    root = math.sqrt(1.0 - damping**2)
    omega_d = TWO_PI * frequency * root
    gamma = 1.178 * frequency**-0.93
    shift = math.atan2(root, damping) / omega_d
    s = np.asarray(t, dtype=float) - peak_time + shift
    return np.cos(omega_d * s) * np.exp(-((s / gamma) ** 2))

def wavelet_columns(t: np.ndarray, periods: np.ndarray, damping: float, peak_times: np.ndarray) -> np.ndarray:
    """(samples, periods): the wavelet of each control period at its peak time, evaluated where
    its Gaussian exceeds exp(-25) and 0 elsewhere."""
    out = np.zeros((t.size, periods.size))
    dt = t[1] - t[0]
    for j, (period, time) in enumerate(zip(periods, peak_times, strict=True)):
        reach = 5.0 * 1.178 * period**0.93 + period
        first, last = max(0, math.floor((time - reach) / dt)), min(t.size, math.ceil((time + reach) / dt) + 1)
        out[first:last, j] = tapered_cosine(t[first:last], float(period), damping, float(time))
    return out

def _resampled(acceleration: np.ndarray, dt: float, factor: int) -> np.ndarray:
    """The piecewise-linear record at step dt/factor (the same function of time)."""
    if factor == 1:
        return acceleration
    n = acceleration.size
    fine = np.arange((n - 1) * factor + 1) / factor
    return np.interp(fine, np.arange(n), acceleration)

def peak_responses(acceleration: np.ndarray, dt: float, periods: np.ndarray, damping: float,
                   window: tuple[float, float] | None = None) -> np.ndarray:
    """(6, n_periods): the signed peak pseudo-acceleration w^2 u [m/s^2] of each oscillator and
    its time [s], over the record and the free vibration after it (the ground at rest for 0.6 T,
    as spectra.response_spectrum counts it); the same within `window` [s] (default: the record);
    and the largest one of the other sign within the window and its time. Periods shorter than
    8 dt on the record resampled to T/8."""
    out = np.empty((6, periods.size))
    for k, period in enumerate(periods):
        factor = max(1, math.ceil(8.0 * dt / period))
        step = dt / factor
        record = _resampled(acceleration, dt, factor)
        padded = np.concatenate((record, np.zeros(math.ceil(0.6 * period / step))))
        u, _ = sdof_history(padded, step, float(period), damping)
        peak = int(np.argmax(np.abs(u)))
        first, last = (0, record.size) if window is None else (round(window[0] / step), round(window[1] / step) + 1)
        part = u[first:last]
        inside = first + int(np.argmax(np.abs(part)))
        other = first + int(np.argmin(part) if u[peak] > 0.0 else np.argmax(part))
        scale = (TWO_PI / period) ** 2
        out[:, k] = (scale * u[peak], peak * step, scale * u[inside], inside * step, scale * u[other],
                     other * step)
    return out

def response_matrix(dt: float, periods: np.ndarray, damping: float, peak_times: np.ndarray,
                    wavelets: np.ndarray) -> np.ndarray:
    """C_ij [m/s^2 per unit amplitude]: pseudo-acceleration w_i^2 u_i(t_i) of oscillator i at its
    peak time t_i [s] due to wavelet j (columns of `wavelets`, sampled at dt, piecewise linear):
    the Duhamel integral by the trapezoidal rule on a step of at most T_i/8, over the
    MEMORY_CYCLES periods before t_i (the impulse response has decayed to exp(-5) by then at 5 %)."""
    matrix = np.empty((periods.size, wavelets.shape[1]))
    root = math.sqrt(1.0 - damping**2)
    last = wavelets.shape[0] - 1
    for i, (period, time) in enumerate(zip(periods, peak_times, strict=True)):
        factor = max(1, math.ceil(8.0 * dt / period))
        step = dt / factor
        omega = TWO_PI / period
        memory = MEMORY_CYCLES * period if damping > 0.0 else math.inf
        first = max(0, math.floor((time - memory) / dt))
        end = min(last, math.ceil(time / dt))
        if end <= first:
            matrix[i] = 0.0
            continue
        block = _resampled_columns(wavelets[first:end + 1], factor)
        tau = first * dt + np.arange(block.shape[0]) * step
        lag = np.maximum(time - tau, 0.0)
        kernel = np.exp(-damping * omega * lag) * np.sin(omega * root * lag) / (omega * root)
        kernel[0] *= 0.5
        matrix[i] = -(omega**2 * step) * (kernel @ block)
    return matrix

def _resampled_columns(values: np.ndarray, factor: int) -> np.ndarray:
    """The rows of `values` (samples of piecewise-linear columns) at factor times the rate."""
    if factor == 1 or values.shape[0] < 2:
        return values
    n = values.shape[0]
    position = np.arange((n - 1) * factor + 1) / factor
    low = np.minimum(position.astype(int), n - 2)
    weight = (position - low)[:, None]
    return (1.0 - weight) * values[low] + weight * values[low + 1]

@dataclass(frozen=True)
class WaveletResult:
    """acceleration [m/s^2]; iterations done; misfit: the largest |ln(S_a/target)| at the control
    periods reached [-]."""

    acceleration: np.ndarray
    iterations: int
    misfit: float

def wavelet_match(acceleration, dt: float, periods, target, damping: float = 0.05, tolerance: float = 0.03,
                  max_iterations: int = 30) -> WaveletResult:
    """Adjust the record [m/s^2] by wavelets until its S_a at the control periods [s] is within
    exp(+-tolerance) of target [m/s^2] (module docstring); the best iterate, baseline-corrected.
    BLAS runs on one thread: the iteration takes discrete decisions (which peak, which instant),
    so the last bits of its products must not depend on the threads (a record is reproducible
    from its seed)."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        return _wavelet_match(acceleration, dt, periods, target, damping, tolerance, max_iterations)


def _wavelet_match(acceleration, dt: float, periods, target, damping: float, tolerance: float,
                   max_iterations: int) -> WaveletResult:
    a = np.array(acceleration, dtype=float)
    periods = np.asarray(periods, dtype=float)
    target = np.asarray(target, dtype=float)
    t = np.arange(a.size) * dt
    start, end = arias_times(a, dt, STRONG_MOTION)
    ends = end_taper(a.size, dt) * strong_window(t, arias_times(a, dt, WINDOW))
    window = (start, end)
    best = (math.inf, a, 0)
    relax, previous = 1.0, math.inf
    stalled = np.zeros(periods.size, dtype=int)
    last_ratio = np.full(periods.size, -math.inf)
    for iteration in range(max_iterations + 1):
        values, times, _, strong_times, other, other_times = peak_responses(a, dt, periods, damping, window)
        if not np.all(values != 0.0):
            break
        log_ratio = np.log(np.abs(values) / target)
        misfit, rms = float(np.max(np.abs(log_ratio))), float(np.sqrt(np.mean(log_ratio**2)))
        if misfit < best[0]:
            best = (misfit, a, iteration)
        if _finished(best, iteration, tolerance, max_iterations):
            break
        relax, previous = _relaxed(relax, rms, previous), rms
        # a peak below the target is raised at the oscillator's largest response within the strong
        # motion (so the record keeps its duration), or, once that has stalled for two iterations
        # (a narrow valley of the spectrum that neighbouring oscillators hold down at the same
        # instant), at its largest response of the other sign; a peak above it is brought down
        # where it is, when inside the record
        low = log_ratio < 0.0
        stalled = np.where(low & (log_ratio < last_ratio + 0.005), stalled + 1, 0)
        last_ratio = log_ratio
        switch = low & (stalled >= 2) & (other != 0.0)
        rows = np.where(switch, other_times, times)
        values = np.where(switch, other, values)
        high = ~low & (times <= t[-1] - END_TAPER - 0.25 * periods)
        places = np.where(switch, other_times, np.where(high, times, strong_times))
        change = np.sign(values) * target - values
        wavelets = ends[:, None] * wavelet_columns(t, periods, damping, places)
        matrix = response_matrix(dt, periods, damping, rows, wavelets)
        a = a + relax * (wavelets @ wavelet_amplitudes(matrix, change))
    misfit, a, iteration = best
    return WaveletResult(baseline_correct(a, dt), iteration, misfit)


def wavelet_amplitudes(matrix: np.ndarray, change: np.ndarray) -> np.ndarray:
    """The amplitudes b of the wavelets: C b = change in the least-squares sense, the normal
    equations damped by DAMPING x their diagonal (Levenberg-Marquardt). A wavelet that moves no
    oscillator (a zero column of C: it is 0 wherever it would act, before the record's onset or
    within its end tapers) gets amplitude 0 and the others are solved without it: its diagonal
    is 0 and the damped system would be singular (issue 38, T9: a constant record)."""
    normal = matrix.T @ matrix
    active = np.diag(normal) > 0.0
    amplitudes = np.zeros(matrix.shape[1])
    if np.any(active):
        system = normal[np.ix_(active, active)]
        system[np.diag_indices_from(system)] *= 1.0 + DAMPING
        amplitudes[active] = np.linalg.solve(system, (matrix.T @ change)[active])
    return amplitudes


def _finished(best: tuple[float, np.ndarray, int], iteration: int, tolerance: float, max_iterations: int) -> bool:
    """Whether the iteration ends: the best misfit (best: misfit, record, iteration) within the
    tolerance, no better iterate for PATIENCE iterations, or the last iteration."""
    return best[0] <= tolerance or iteration - best[2] >= PATIENCE or iteration == max_iterations


def _relaxed(relax: float, rms: float, previous: float) -> float:
    """The next step factor: a step that made it worse overall (rms above the previous one) halves
    it, down to 0.25; a better one raises it by half again, up to 1."""
    return max(0.25, 0.5 * relax) if rms > previous else min(1.0, 1.5 * relax)


def strong_window(t: np.ndarray, times: np.ndarray) -> np.ndarray:
    """The window [-] that the wavelets are multiplied by: 0 before times[0] and after times[3],
    half-cosine ramps up to times[1] and down from times[2], 1 in between (WINDOW)."""
    rise = onset_ramp(t, float(times[0]), float(times[1]))
    fall = 1.0 - onset_ramp(t, float(times[2]), float(times[3]))
    return rise * fall


def onset_ramp(t: np.ndarray, begin: float, end: float) -> np.ndarray:
    """0 before `begin` [s], a half-cosine up to 1 at `end` [s], 1 after."""
    if end <= begin:
        return (t >= begin).astype(float)
    x = np.clip((t - begin) / (end - begin), 0.0, 1.0)
    return 0.5 - 0.5 * np.cos(math.pi * x)

def end_taper(n: int, dt: float, length: float = END_TAPER) -> np.ndarray:
    """Half-cosine taper [-] from 0 at both ends to 1 over `length` [s] (at most a tenth of the record)."""
    ramp = max(1, min(round(length / dt), n // 10))
    window = np.ones(n)
    rise = 0.5 - 0.5 * np.cos(math.pi * np.arange(ramp) / ramp)
    window[:ramp] = rise
    window[n - ramp:] = rise[::-1]
    return window

def control_periods(period_range: tuple[float, float], per_octave: int = PER_OCTAVE) -> np.ndarray:
    """Control periods [s] of the wavelet iteration, evenly in log T, both bounds included."""
    lower, upper = period_range
    count = max(math.ceil(math.log2(upper / lower) * per_octave) + 1, 4)
    return np.geomspace(lower, upper, count)
