"""Motion of the lifting mat by the improved simplified procedure: mat rotation, edge uplift and
the floor accelerations of the impacts at recontact (docs/accuracy.md, "the improved procedure";
docs/theory.md section 7). Array functions over cases (the engine passes one case, the
calibration many), from the paper's equivalent system of mode 1 (Fig. 2: m_1* at h_1* on the
mat, total mass m_t):

1. rocking displacement: the equivalent system's peak displacement relative to the ground is
   C D, D the spectral displacement S_a (T/2 pi)^2 averaged (geometrically) over the periods the
   lifting system sweeps, [T1bar, x_u T1bar] (its secant period at the peak: a system whose
   strength is exceeded x_u times reaches a ductility of about x_u^2 at short periods, equal
   energy, and the secant period grows as its square root; at most 3 T1bar, the tabulated range),
   C = 1 + (x_u - 1) (T_d / T1bar)^2 the short-period amplification of such a system (the form of
   FEMA 440 eq. 5-1 for C_1; T_d fitted); the structure takes V_1,max / k_1* of it, the rest is
   rocking: theta = (C D - V_1,max/k_1*) / h_1*;
2. edge uplift: 2 b (theta - theta_c), theta_c = V_c h_1* / K_theta the rotation at which the mat
   lifts (K_theta = k_1* h_1*^2 / ((T1bar/T_1)^2 - 1) [21]);
3. impact: lifted by theta - theta_c about its edge, the mat falls back under the moment
   M_c = m_t g b with inertia m_1* h_1*^2 + m_t b^2 about the edge, so it recontacts with
   theta' = sqrt(2 M_c (theta - theta_c) / (m_1* h_1*^2 + m_t b^2)); stopping it is a pulse of
   h_n* theta'' on mode n [11a] whose duration is set by the rocking frequency w_theta of the
   structure on its foundation (1/w1bar^2 = 1/w_1^2 + 1/w_theta^2 [21]): the modal
   pseudo-acceleration is h_n* min(w_n, w_theta) theta' (an impulse for the modes slower than
   the pulse, its peak for the faster ones); floor j gets impact x sqrt(sum_n (Gamma_n phi_jn
   A_n)^2) of it, combined with the modal floor acceleration by SRSS (impact fitted).
"""

from __future__ import annotations

import math

import numpy as np


def spectral_band(x_long, stretch, span) -> np.ndarray:
    """x_u: V_1/V_c from the geometric mean of S_a over [T1bar, span T1bar] (x_long: V_1/V_c at
    stretch x T1bar, cases x stretch)."""
    band = stretch <= float(span) + 1e-9
    return np.exp(np.mean(np.log(np.maximum(np.asarray(x_long, dtype=float)[:, band], 1e-300)), axis=1))


def rotation(data: dict, x_u, v1_max, stretch, displacement_period) -> dict[str, np.ndarray]:
    """Mat rotation theta [rad], rotation at lift-off theta_c [rad] and edge uplift [m] of each case
    (items 1-2 of the module docstring); data: the terms of improved.uplift_terms, stacked."""
    t1bar, t1 = np.asarray(data["T1bar"], dtype=float), np.asarray(data["T1"], dtype=float)
    x_u = np.asarray(x_u, dtype=float)
    band = stretch[None, :] <= np.clip(x_u, 1.0, stretch[-1])[:, None] + 1e-9
    m1 = data["m1"]
    k1 = m1 * data["omega1"] ** 2
    h1 = data["slenderness"] * data["b"]
    sa = np.asarray(data["x_long"], dtype=float) * (data["V_c"] / m1)[:, None]
    sd = np.log(np.maximum(sa * (stretch[None, :] * t1bar[:, None] / (2.0 * math.pi)) ** 2, 1e-300))
    spectral = np.exp(np.sum(np.where(band, sd, 0.0), axis=1) / np.sum(band, axis=1))
    amplification = 1.0 + np.maximum(x_u - 1.0, 0.0) * (displacement_period / t1bar) ** 2
    theta = np.maximum(amplification * spectral - v1_max / k1, 0.0) / h1
    theta_c = data["V_c"] * np.maximum((t1bar / t1) ** 2 - 1.0, 0.0) / (k1 * h1)
    return {"theta": theta, "theta_c": theta_c, "uplift": 2.0 * data["b"] * np.maximum(theta - theta_c, 0.0)}


def impact_acceleration(data: dict, lifted_rotation) -> np.ndarray:
    """Floor accelerations of the recontact impact (cases x floors) [m/s^2], before the factor
    `impact` (item 3 of the module docstring); lifted_rotation: theta - theta_c [rad]."""
    m1, m_t, b = data["m1"], data["m_t"], data["b"]
    h1 = data["slenderness"] * b
    rate = np.sqrt(2.0 * m_t * data["g"] * b * np.maximum(lifted_rotation, 0.0) / (m1 * h1**2 + m_t * b**2))
    omega_bar = 2.0 * math.pi / np.asarray(data["T1bar"], dtype=float)
    flexibility = np.maximum(1.0 / omega_bar**2 - 1.0 / data["omega1"] ** 2, 1e-300)
    omega_theta = 1.0 / np.sqrt(flexibility)
    pseudo = data["unit_base_moment"] * np.minimum(data["fixed_omega"], omega_theta[:, None]) * rate[:, None]
    modal = data["unit_floor_acceleration"] * (data["effective_mass"] * pseudo)[:, :, None]  # cases, modes, floors
    return np.sqrt(np.sum(modal**2, axis=1))
