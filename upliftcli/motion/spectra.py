"""Linear SDOF response and response spectra of a ground-acceleration record.

One exact method serves the CLI and both engines: the ground acceleration is taken as
piecewise linear between samples and each step is integrated in closed form (the
Nigam-Jennings recurrence; Chopra, Dynamics of Structures, section 5.2). The equation is
u'' + 2 xi w u' + w^2 u = -a_g(t), u relative displacement; w = 2 pi / T.

Peaks are exact, not sampled:
* inside a step the response has the closed form f(t) = l0 + l1 t + exp(-xi w t)(A cos wd t + B sin wd t)
  (f = u, or the absolute acceleration a_g + u''). The SIMD loop bounds max |f| over the step by
  the Bezier control points of the cubic Hermite interpolant plus its error bound
  (w h)^4 / 384 * sqrt(A^2 + B^2); only where that bound reaches the running peak and f' or f''
  changes sign in the step (a turning point is possible) are the roots of f' solved on the
  closed form (safeguarded Newton) and the turning values used;
* steps are cut into sub-steps of at most T / `min_steps_per_period` (4 by default, w h <= pi / 2)
  so that f'' has at most one root per step and f' at most two: short periods (T < 4 dt) are
  integrated with sub-steps, every period has exact peaks;
* after the record the ground acceleration goes linearly to zero over one dt and the oscillator
  vibrates freely; the largest free-vibration peak is the first turning point, found in closed
  form. This equals any free-vibration tail of half a damped period or more, in particular the
  "2T tail" used for the sample-read reference values of records/README.md. (Those reference
  values were read at the record samples, hence lower than exact at short periods: 5 % S_a at
  0.1 s is 0.608 g sampled, 0.649 g exact; see tests/test_spectra.py.)

Two implementations of these loops agree to rounding (about 1e-12 relative, the rounding of the
step coefficients at long periods; tests/test_spectra.py): compiled (C, _spectra.c), one
oscillator chunk after the other in one thread; vectorised in numpy (spectra_numpy.py), its twin.
spectra_kernels.py runs the one upliftcli.runtime.backend chooses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..runtime import backend

TWO_PI = 2.0 * math.pi
CHUNK = 32  # oscillators integrated side by side
#: "auto" (the loops upliftcli.runtime.backend chooses, the default), "compiled" (C), "numpy" (the vectorised
#: twin: El Centro, 1560 samples, 1 ms for one oscillator, 16 ms for 16)
METHODS = backend.CHOICES


def _check_damping(damping: float) -> float:
    damping = float(damping)
    if not (0.0 <= damping < 1.0):
        raise ValueError(f"damping ratio must be in [0, 1) (fraction of critical), got {damping}")
    return damping


def sdof_history(acceleration: np.ndarray, dt: float, period: float, damping: float
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Relative displacement u [m] and velocity v [m/s] of a linear SDOF at the record samples.

    acceleration: ground acceleration [m/s^2] at uniform step dt [s], piecewise linear between samples;
    period [s] > 0; damping: ratio of critical [-], 0 <= damping < 1. Zero initial conditions;
    exact (Nigam-Jennings) for any dt.
    """
    from .spectra_kernels import history_kernel

    acc = np.ascontiguousarray(acceleration, dtype=float)
    if not period > 0.0:
        raise ValueError(f"period must be > 0 s, got {period}")
    u = np.empty(acc.size)
    v = np.empty(acc.size)
    history_kernel(acc, float(dt), TWO_PI / float(period), _check_damping(damping), u, v)
    return u, v


@dataclass
class Spectrum:
    """Response spectra, arrays of shape (n_damping, n_period).

    periods [s]; dampings [-]; displacement S_d [m]; pseudo_velocity w S_d [m/s];
    pseudo_acceleration S_a = w^2 S_d [m/s^2]; absolute_acceleration max |u'' + a_g| [m/s^2].
    """

    periods: np.ndarray
    dampings: np.ndarray
    displacement: np.ndarray
    pseudo_velocity: np.ndarray
    pseudo_acceleration: np.ndarray
    absolute_acceleration: np.ndarray


def substeps(dt: float, periods: np.ndarray, min_steps_per_period: int = 4) -> np.ndarray:
    """Sub-steps per record step so that the integration step is at most T / min_steps_per_period."""
    periods = np.asarray(periods, dtype=float)
    with np.errstate(divide="ignore"):
        count = np.ceil(min_steps_per_period * dt / np.where(periods > 0, periods, np.inf) - 1e-9)
    return np.maximum(count, 1).astype(np.int64)


def response_spectrum(acceleration: np.ndarray, dt: float, periods, dampings, *, free_vibration: bool = True,
                      min_steps_per_period: int = 4, method: str = "auto") -> Spectrum:
    """Exact linear response spectra of a piecewise-linear ground acceleration.

    acceleration [m/s^2] at uniform step dt [s]; periods [s] >= 0 (T = 0: rigid, S_a = PGA);
    dampings: ratios of critical in [0, 1). free_vibration: include the free vibration after the
    record end (default; see the module docstring). min_steps_per_period: sub-stepping of short
    periods. Peaks are exact between samples (analytic turning points). method: "auto" (the
    loops of upliftcli.runtime.backend, the default), "compiled" (C) or "numpy" (the vectorised twin).
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    acc = np.ascontiguousarray(acceleration, dtype=float)
    periods = np.atleast_1d(np.asarray(periods, dtype=float))
    dampings = np.atleast_1d(np.asarray(dampings, dtype=float))
    _check_record(acc, dt)
    _check_oscillators(periods, dampings, min_steps_per_period)
    grid_t, grid_xi = np.meshgrid(periods, dampings)
    flat_t = grid_t.ravel()
    flat_xi = grid_xi.ravel()
    positive = flat_t > 0.0
    omegas = np.where(positive, TWO_PI / np.where(positive, flat_t, 1.0), 0.0)
    peak_u = np.zeros(flat_t.size)
    peak_at = np.full(flat_t.size, float(np.max(np.abs(acc))))  # T = 0: rigid, follows the ground
    index = np.flatnonzero(positive)
    if index.size:
        counts = substeps(dt, flat_t[index], min_steps_per_period)
        with backend.use(backend.choice() if method == "auto" else method):
            peak_u[index], peak_at[index] = _peaks(acc, float(dt), omegas[index], flat_xi[index], counts,
                                                   bool(free_vibration))
    shape = grid_t.shape
    displacement = peak_u.reshape(shape)
    omega = omegas.reshape(shape)
    pseudo_acceleration = np.where(grid_t > 0.0, omega ** 2 * displacement, peak_at.reshape(shape))
    return Spectrum(periods=periods, dampings=dampings, displacement=displacement,
                    pseudo_velocity=omega * displacement, pseudo_acceleration=pseudo_acceleration,
                    absolute_acceleration=peak_at.reshape(shape))


def _check_record(acc: np.ndarray, dt: float) -> None:
    """ValueError unless the acceleration is 1-D of at least two samples at a finite dt > 0 [s]."""
    if acc.ndim != 1 or acc.size < 2:
        raise ValueError("acceleration must be a 1-D array of at least two samples")
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"dt must be > 0 s, got {dt}")


def _check_oscillators(periods: np.ndarray, dampings: np.ndarray, min_steps_per_period: int) -> None:
    """ValueError unless the periods are 1-D, finite and >= 0 [s], each damping in [0, 1) and
    min_steps_per_period >= 3."""
    if periods.ndim != 1 or not np.all(np.isfinite(periods)) or np.any(periods < 0.0):
        raise ValueError("periods must be finite and >= 0 s")
    for damping in dampings:
        _check_damping(damping)
    if int(min_steps_per_period) < 3:
        raise ValueError("min_steps_per_period must be >= 3 (w h < pi keeps at most two turning points per step)")


def _peaks(acc, dt, omegas, xis, counts, free_vibration) -> tuple[np.ndarray, np.ndarray]:
    """Peaks |u|, |a_t| by spectra_kernels.spectrum_kernel: chunks of equal sub-step count, costliest first."""
    from .spectra_kernels import spectrum_kernel

    order = np.argsort(-counts, kind="stable")
    chunk_starts = [0]
    for position in range(1, order.size + 1):
        if position == order.size or counts[order[position]] != counts[order[position - 1]] \
                or position - chunk_starts[-1] == CHUNK:
            chunk_starts.append(position)
    sorted_u = np.empty(order.size)
    sorted_at = np.empty(order.size)
    spectrum_kernel(acc, dt, np.ascontiguousarray(omegas[order]), np.ascontiguousarray(xis[order]),
                    np.ascontiguousarray(counts[order]), np.asarray(chunk_starts, dtype=np.int64),
                    free_vibration, sorted_u, sorted_at)
    out_u = np.empty(order.size)
    out_at = np.empty(order.size)
    out_u[order] = sorted_u
    out_at[order] = sorted_at
    return out_u, out_at


#: the most S_a values a RecordSpectrum keeps (about 140 bytes each: 7 MB)
MAX_CACHED = 50_000


@dataclass
class RecordSpectrum:
    """Pseudo-acceleration spectrum of a record at any damping, computed exactly on demand and cached.

    Used by the simplified engine in place of a design spectrum (same `.sa`, `.name`, `.period_range`).
    It asks a few periods at a time; the oscillators of the loops do not share any arithmetic: a
    value does not depend on which periods were asked together.
    """

    record: object  # records.Record
    free_vibration: bool = True
    _cache: dict = field(default_factory=dict, repr=False)

    @property
    def name(self) -> str:
        return f"record {self.record.name}"

    @property
    def period_range(self) -> tuple[float, float]:
        """Valid periods [s]: every T >= 0."""
        return (0.0, math.inf)

    def sa(self, periods, damping: float) -> np.ndarray:
        """Pseudo-acceleration S_a(T, xi) [m/s^2] for periods [s] (scalar or array) and damping ratio [-]."""
        source = getattr(self.record, "source", "") or self.name
        periods_array = np.asarray(periods, dtype=float)
        flat = np.atleast_1d(periods_array).ravel()
        damping = _checked_request(flat, damping, source)
        self._compute_missing(flat, damping)
        result = np.array([self._cache[(float(t), damping)] for t in flat])
        return result.reshape(periods_array.shape) if periods_array.ndim else result[0] * np.ones(())

    def _compute_missing(self, periods: np.ndarray, damping: float) -> None:
        """Compute and cache S_a at the periods [s] not in the cache yet (one spectrum for all of
        them); a cache that would hold more than MAX_CACHED values is emptied first (a sweep asks
        ~40 new periods a case: 10^5 cases kept 0.5 GiB; a value does not depend on what was asked
        with it, so the values are the same)."""
        missing = self._missing(periods, damping)
        if len(self._cache) + len(missing) > MAX_CACHED:
            self._cache.clear()
            missing = self._missing(periods, damping)
        if not missing:
            return
        spectrum = response_spectrum(self.record.acceleration, self.record.dt, missing, [damping],
                                     free_vibration=self.free_vibration)
        for t, value in zip(missing, spectrum.pseudo_acceleration[0], strict=False):
            self._cache[(t, damping)] = float(value)

    def _missing(self, periods: np.ndarray, damping: float) -> list[float]:
        """The periods [s] (sorted, each once) whose S_a at `damping` is not in the cache."""
        return sorted({float(t) for t in periods if (float(t), damping) not in self._cache})


def _checked_request(periods: np.ndarray, damping: float, source: str) -> float:
    """The damping ratio as a float; InputError naming the first period that is not finite and
    >= 0 [s], or a damping ratio outside [0, 1)."""
    if not np.all(np.isfinite(periods)) or np.any(periods < 0.0):
        first = periods[~(np.isfinite(periods) & (periods >= 0))][0]
        raise InputError(source, "period", f"periods >= 0 s, got {first:g}")
    damping = float(damping)
    if not (0.0 <= damping < 1.0):
        raise InputError(source, "damping", f"a damping ratio in [0, 1), got {damping:g}")
    return damping
