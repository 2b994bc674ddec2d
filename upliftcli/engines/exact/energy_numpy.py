"""The numpy twin of the energy balance's compiled loop (_energy.c): the work integrals over the
intervals between samples, as whole arrays (upliftcli.runtime.backend chooses between the two)."""

from __future__ import annotations

import functools

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


@functools.cache
def basis_integrals() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The quintic Hermite basis b_j on [0, 1]: its Gram matrix int b_j b_k (6, 6) and moments int b_j,
    int s b_j (6,) each, by the Gauss rule (exact: degree 10 at most)."""
    basis = np.array([quintic_basis(s) for s in NODES])  # (node, j)
    return (basis.T * WEIGHTS) @ basis, WEIGHTS @ basis, (WEIGHTS * NODES) @ basis


def _ends(values, slopes, switch, end_values, end_slopes, n: int):
    """Values and slopes at the right end of every interval: the next sample, or the left limits where
    it ends at a transition."""
    v1, s1 = values[1:n + 1].copy(), slopes[1:n + 1].copy()
    fixed = switch[:n] >= 0
    v1[fixed], s1[fixed] = end_values[switch[:n][fixed]], end_slopes[switch[:n][fixed]]
    return v1, s1


def _coefficients(ends: tuple, first: int, count: int, curvature: int) -> np.ndarray:
    """(n, count, 6): p0, d0, c0, p1, d1, c1 of the quintic Hermite interpolants of signals first..first +
    count in every interval, their curvatures in slope columns curvature.. (ends: values, slopes at the
    starts, at the right ends, the right ends' curvature corrections, the lengths (n, 1))."""
    v0, s0, v1, s1, jumps, length = ends
    q, c = slice(first, first + count), slice(curvature, curvature + count)
    return np.stack((v0[:, q], s0[:, q] * length, s0[:, c] * length**2, v1[:, q], s1[:, q] * length,
                     (s1[:, c] + jumps[:, q]) * length**2), axis=-1)


def _squared(u: np.ndarray) -> np.ndarray:
    """int_0^1 p^2 of the quintic Hermite interpolants with coefficients u (n, m, 6): (n, m), through the
    whole Gram matrix (the loop splits it into its even and odd blocks: the same integrals to rounding)."""
    return np.einsum("imj,jk,imk->im", u, basis_integrals()[0], u)


def work_integrals(values, slopes, end_values, end_slopes, switch, ids, slope_rows, lengths, lifted, row_a,
                   row_input, row_ydot, n_modes, row_vel, row_z, n_elements, curvature_ydot, curvature_input,
                   curvature_vel, modal_damping, element_stiffness, element_damping) -> tuple[float, float, float]:
    """Input work, structural and foundation damping energy [J] (energy.work): the integrals of the quintic
    Hermite interpolants in every interval exactly (the basis' Gram matrix and moments), the ground
    acceleration linear, the dashpots of lifted elements exactly. The right ends' curvatures are read with
    the next sample's ground slope: slope_rows[ids] times the jump to the interval's own is added."""
    n = lengths.size
    v1, s1 = _ends(values, slopes, switch, end_values, end_slopes, n)
    jumps = slope_rows[ids[:n]] * (slopes[:n, row_a] - slopes[1:n + 1, row_a])[:, None]
    ends = (values[:n], slopes[:n], v1, s1, jumps, lengths[:, None])
    _, mean, first = basis_integrals()
    u = _coefficients(ends, row_input, 1, curvature_input)[:, 0]
    a0, a1 = values[:n, row_a], slopes[:n, row_a] * lengths  # a_g is linear inside each interval
    total_in = np.sum(lengths * (a0 * (u @ mean) + a1 * (u @ first)))
    power = _squared(_coefficients(ends, row_ydot, n_modes, curvature_ydot)) @ modal_damping[:n_modes]
    total_struct = np.sum(lengths * power)
    c_el, k_el = element_damping[:n_elements], element_stiffness[:n_elements]
    power = c_el * _squared(_coefficients(ends, row_vel, n_elements, curvature_vel))
    total_found = np.sum(lengths[:, None] * np.where(~lifted[:n] & (c_el > 0), power, 0.0))
    z0, z1 = values[:n, row_z:row_z + n_elements], v1[:, row_z:row_z + n_elements]
    # lifted: k z + c z' = 0, its dashpot dissipates exactly the spring energy released
    total_found += np.sum(np.where(lifted[:n] & (c_el > 0), 0.5 * k_el * (z0**2 - z1**2), 0.0))
    return float(total_in), float(total_struct), float(total_found)
