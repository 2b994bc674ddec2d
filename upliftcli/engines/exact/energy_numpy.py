"""The numpy twin of the energy balance's compiled loop (_energy.c): the work integrals over the
intervals between samples, as whole arrays (upliftcli.runtime.backend chooses between the two)."""

from __future__ import annotations

import numpy as np

#: 6-point Gauss-Legendre on [0, 1] (exact to degree 11: the product of two quintics)
_X, _W = np.polynomial.legendre.leggauss(6)
NODES, WEIGHTS = 0.5 * (_X + 1.0), 0.5 * _W


def quintic_basis(s: float) -> np.ndarray:
    """The weights of p0, d0, c0, p1, d1, c1 in the quintic Hermite interpolant on [0, 1] at s (the
    loop's expressions)."""
    return np.array([1 - 10 * s**3 + 15 * s**4 - 6 * s**5, s - 6 * s**3 + 8 * s**4 - 3 * s**5,
                     0.5 * s**2 - 1.5 * s**3 + 1.5 * s**4 - 0.5 * s**5, 10 * s**3 - 15 * s**4 + 6 * s**5,
                     -4 * s**3 + 7 * s**4 - 3 * s**5, 0.5 * s**3 - s**4 + 0.5 * s**5])


def _ends(values, slopes, switch, end_values, end_slopes, n: int, k: int):
    """Values and slopes at the right end of every interval: the next sample, or the left limits where
    it ends at a transition."""
    v1, s1 = values[1:n + 1].copy(), slopes[1:n + 1, :k].copy()
    fixed = switch[:n] >= 0
    v1[fixed], s1[fixed] = end_values[switch[:n][fixed]], end_slopes[switch[:n][fixed], :k]
    return v1, s1


def work_integrals(values, slopes, curvatures, end_curvatures, switch, end_values, end_slopes, lengths, lifted,
                   n_interpolated, row_a, row_input, row_ydot, n_modes, row_vel, row_z, n_elements, modal_damping,
                   element_stiffness, element_damping) -> tuple[float, float, float]:
    """Input work, structural and foundation damping energy [J] (energy.work): 6-point Gauss quadrature of
    the quintic Hermite interpolants in every interval, the ground acceleration linear, the dashpots of
    lifted elements exactly."""
    n, k, k_c = lengths.size, n_interpolated, curvatures.shape[1]
    v1, s1 = _ends(values, slopes, switch, end_values, end_slopes, n, k)
    length = lengths[:, None]
    # the signals with curvatures (the first k_c): those the integrands read
    data = (values[:n, :k_c], slopes[:n, :k_c] * length, curvatures[:n] * length**2, v1[:, :k_c],
            s1[:, :k_c] * length, end_curvatures[:n] * length**2)
    lifted = lifted[:n]
    c_el, k_el = element_damping[:n_elements], element_stiffness[:n_elements]
    damped = ~lifted & (c_el > 0)
    total_in = total_struct = total_found = 0.0
    for s, w in zip(NODES, WEIGHTS, strict=True):
        g = sum(b * d for b, d in zip(quintic_basis(s), data, strict=True))
        a = values[:n, row_a] + slopes[:n, row_a] * lengths * s  # a_g is linear inside each interval
        total_in += np.sum(w * lengths * a * g[:, row_input])
        total_struct += np.sum(w * lengths * (g[:, row_ydot:row_ydot + n_modes] ** 2 @ modal_damping[:n_modes]))
        vel = g[:, row_vel:row_vel + n_elements]
        total_found += np.sum(w * lengths * np.where(damped, c_el * vel**2, 0.0).sum(axis=1))
    z0, z1 = values[:n, row_z:row_z + n_elements], v1[:, row_z:row_z + n_elements]
    # lifted: k z + c z' = 0, its dashpot dissipates exactly the spring energy released
    total_found += np.sum(np.where(lifted & (c_el > 0), 0.5 * k_el * (z0**2 - z1**2), 0.0))
    return float(total_in), float(total_struct), float(total_found)
