"""Baseline correction of modified or artificial accelerograms.

The correction subtracts from the acceleration a low-order polynomial p(t) (Legendre basis over
the record) chosen so that the corrected record ends at rest, v(t_end) = 0 and d(t_end) = 0,
and the drift of its displacement is least: p minimises sum d_c(t_i)^2 under those two
constraints (a least-squares fit of the displacement with the end conditions imposed, the
classic polynomial baseline correction with exact end conditions). Velocities and displacements
are the exact integrals of the piecewise-linear record (records.ground_velocity / ground_displacement),
so the end conditions hold to rounding for the sampled record.
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial import legendre

from .records import ground_displacement, ground_velocity

#: degree of the correcting polynomial in the acceleration (5 terms)
ORDER = 4


def baseline_correct(acceleration, dt: float, order: int = ORDER) -> np.ndarray:
    """The acceleration [m/s^2] minus the polynomial of degree `order` that brings the record to rest
    at its end (v = d = 0) with the least displacement drift (module docstring)."""
    a = np.asarray(acceleration, dtype=float)
    n = a.size
    if n < order + 3:
        return a.copy()
    t = np.arange(n) * dt
    basis = legendre.legvander(2.0 * t / t[-1] - 1.0, order)  # (n, order + 1)
    columns = np.column_stack((a, basis))
    velocity, displacement = ground_velocity(columns, dt), ground_displacement(columns, dt)
    scale = t[-1] ** 2  # displacement of a unit acceleration over the record, for conditioning
    d_record, d_basis = displacement[:, 0] / scale, displacement[:, 1:] / scale
    constraints = np.vstack((velocity[-1, 1:] / t[-1], d_basis[-1]))
    ends = np.array([velocity[-1, 0] / t[-1], d_record[-1]])
    k = order + 1
    system = np.zeros((k + 2, k + 2))
    system[:k, :k] = d_basis.T @ d_basis
    system[:k, k:] = constraints.T
    system[k:, :k] = constraints
    rhs = np.concatenate((d_basis.T @ d_record, ends))
    coefficients = np.linalg.lstsq(system, rhs, rcond=None)[0][:k]
    return a - basis @ coefficients
