"""An independent response spectrum for the tests: none of upliftcli.motion.spectra (neither its
compiled loop nor its numpy twin, nor their between-sample peak search). The record is
interpolated linearly on a step of at most T/per_period, the oscillator discretised exactly for
that piecewise-linear input by scipy (signal.cont2discrete, first-order hold) and run by
signal.lfilter, followed by a zero tail of 2 T (the free vibration that response spectra include),
and the peak |u| taken at the fine samples. A sampled peak is never above the true one; it misses
it by about 1 - cos(pi / per_period) for a free oscillation (1.2e-4 at 200 steps a period), more
where the ground acceleration bends the response at its peak (measured on El Centro N-S: 1.7e-4
at 200 steps, T = 1 s, 2 %; 1e-6 at 2,000 steps): an ordinate that passes a lower bound here
passes it exactly, and an upper bound is checked with the allowance UNDERSHOOT.

    sa = pseudo_acceleration(acceleration, dt, periods, damping)   # w^2 max|u| [m/s^2]
"""

from __future__ import annotations

import math

import numpy as np
from scipy import signal
from threadpoolctl import threadpool_limits

#: fine steps per oscillator period, and the allowance for the sampled peak's shortfall at that
#: step [-]: twice a free oscillation's (module docstring: 1.4 times measured)
PER_PERIOD = 200
UNDERSHOOT = 2.0 * (1.0 - math.cos(math.pi / PER_PERIOD))


def peak_displacement(acceleration, dt: float, period: float, damping: float, per_period: int = PER_PERIOD) -> float:
    """max |u| [m] of the oscillator (period [s], damping ratio) at rest at t = 0 under the ground
    acceleration [m/s^2] sampled at dt [s] (module docstring). A record that does not start at
    zero starts with a ramp from 0 over one fine step (the FOH filter starts from a zero input)."""
    refine = max(1, math.ceil(per_period * dt / period))
    return _fine_peak(_fine_record(acceleration, refine), dt / refine, period, damping)


def pseudo_acceleration(acceleration, dt: float, periods, damping: float, per_period: int = PER_PERIOD
                        ) -> np.ndarray:
    """S_a = w^2 max|u| [m/s^2] at each period [s] (peak_displacement; the record interpolated once
    for every periods that share a fine step)."""
    periods = np.asarray(periods, dtype=float)
    refines = np.maximum(1, np.ceil(per_period * dt / periods)).astype(int)
    peaks = np.empty(periods.size)
    with threadpool_limits(1):  # a 4 x 4 expm a period: BLAS threads made it 19 ms instead of 20 us
        for refine in np.unique(refines):
            fine_a = _fine_record(acceleration, int(refine))
            for k in np.flatnonzero(refines == refine):
                peaks[k] = _fine_peak(fine_a, dt / refine, float(periods[k]), damping)
    return (2.0 * math.pi / periods) ** 2 * peaks


def _fine_record(acceleration, refine: int) -> np.ndarray:
    """The record linearly interpolated on dt/refine, after one zero sample."""
    acceleration = np.asarray(acceleration, dtype=float)
    coarse = np.arange(acceleration.size, dtype=float)
    fine_a = np.interp(np.arange((acceleration.size - 1) * refine + 1) / refine, coarse, acceleration)
    return np.concatenate(([0.0], fine_a))


def _fine_peak(fine_a: np.ndarray, fine_dt: float, period: float, damping: float) -> float:
    """max |u| [m] under the fine record (step fine_dt [s]) followed by a zero tail of 2 T."""
    omega = 2.0 * math.pi / period
    system = (np.array([[0.0, 1.0], [-omega**2, -2.0 * damping * omega]]), np.array([[0.0], [-1.0]]),
              np.array([[1.0, 0.0]]), np.zeros((1, 1)))
    ad, bd, cd, dd, _ = signal.cont2discrete(system, fine_dt, method="foh")
    num, den = signal.ss2tf(ad, bd, cd, dd)
    tail = np.zeros(math.ceil(2.0 * period / fine_dt) + 1)
    return float(np.max(np.abs(signal.lfilter(num[0], den, np.concatenate((fine_a, tail))))))
