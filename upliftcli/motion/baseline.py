"""Baseline correction of modified or artificial accelerograms.

The correction subtracts from the acceleration a low-order polynomial p(t) chosen so that the
corrected record ends at rest, v(t_end) = 0 and d(t_end) = 0, and the drift of its displacement
is least: p minimises sum d_c(t_i)^2 under those two constraints (a least-squares fit of the
displacement with the end conditions imposed, the classic polynomial baseline correction with
exact end conditions). The polynomial vanishes at both ends, p = s (1 - s) q(s) with s = t/t_end
and q of degree `order` (Legendre basis), so the first and last samples are kept: a record that
starts and ends quietly does not get an offset there (issue 24: the degree-4 polynomial without
that factor left the first and last samples at up to 8 % of the PGA). Velocities and
displacements are the exact integrals of the piecewise-linear record
(records.ground_velocity / ground_displacement), so the end conditions hold to rounding.
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial import legendre

from .records import ground_displacement, ground_velocity

#: degree of q: the correcting polynomial s (1 - s) q(s) has degree ORDER + 2 (5 terms)
ORDER = 4


def correction_basis(n: int, dt: float, order: int = ORDER) -> np.ndarray:
    """(n, order + 1): s (1 - s) P_k(2 s - 1) at the samples, s = t / t_end, P_k Legendre."""
    t = np.arange(n) * dt
    s = t / t[-1]
    return (s * (1.0 - s))[:, None] * legendre.legvander(2.0 * s - 1.0, order)


def baseline_correct(acceleration, dt: float, order: int = ORDER) -> np.ndarray:
    """The acceleration [m/s^2] minus the polynomial (vanishing at both ends) that brings the
    record to rest at its end (v = d = 0) with the least displacement drift (module docstring)."""
    a = np.asarray(acceleration, dtype=float)
    n = a.size
    if n < order + 5:
        return a.copy()
    duration = (n - 1) * dt
    basis = correction_basis(n, dt, order)
    columns = np.column_stack((a, basis))
    velocity, displacement = ground_velocity(columns, dt), ground_displacement(columns, dt)
    scale = duration**2  # displacement of a unit acceleration over the record, for conditioning
    d_record, d_basis = displacement[:, 0] / scale, displacement[:, 1:] / scale
    constraints = np.vstack((velocity[-1, 1:] / duration, d_basis[-1]))
    ends = np.array([velocity[-1, 0] / duration, d_record[-1]])
    k = order + 1
    system = np.zeros((k + 2, k + 2))
    system[:k, :k] = d_basis.T @ d_basis
    system[:k, k:] = constraints.T
    system[k:, :k] = constraints
    rhs = np.concatenate((d_basis.T @ d_record, ends))
    coefficients = np.linalg.lstsq(system, rhs, rcond=None)[0][:k]
    return a - basis @ coefficients
