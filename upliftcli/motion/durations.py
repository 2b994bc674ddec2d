"""Significant durations of a scenario: the model of Afshari & Stewart (2016), "Physically
parameterized prediction equations for significant duration in active crustal regions",
Earthquake Spectra 32(4), 2057-2081, for D5-75, D5-95 and D20-80 [s] (all mechanisms):

    ln D = ln(F_E + F_P) + F_S                                                 (Eq. 3)
    F_E = b_0 for M <= M_1, else 1/f_0 (source duration)                       (Eq. 4)
    f_0 = 4.9e6 beta (dsigma / M_0)^(1/3), M_0 = 10^(1.5 M + 16.05) dyne-cm,
      beta = 3.2 km/s                                                          (Eq. 5)
    dsigma = exp(b_1 + b_2 (min(M, M_2) - M*) + b_3 max(M - M_2, 0)) [bar]     (Eq. 6)
    F_P = c_1 min(R, R_1) + c_2 (min(R, R_2) - R_1)^+ + c_3 (R - R_2)^+        (Eq. 7)
    F_S = c_4 ln(min(Vs30, V_1) / V_ref) (the basin-depth term, c_5 dz_1, is 0: no depth given)  (Eq. 8)

with R the rupture distance [km] and the coefficients of the paper's Table 3; the aleatory
variability is lognormal with the between-event tau and within-event phi of Table 3, tau going
linearly from tau_1 at M 6.5 to tau_2 at M 7, phi from phi_1 at M 5.5 to phi_2 at M 5.75 (Eq. 9).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: the measures, in the order of the coefficient tuples below
MEASURES = ("D5-75", "D5-95", "D20-80")
M1 = (5.35, 5.2, 5.2)
M2 = (7.15, 7.4, 7.4)
M_STAR = 6.0
#: (b_0, b_1) of each mechanism ("" unspecified, strike-slip, normal, reverse)
SOURCE = {"": ((1.280, 2.182, 0.8822), (5.576, 3.628, 6.182)),
          "SS": ((1.279, 2.302, 0.8804), (5.578, 3.467, 6.188)),
          "NS": ((1.555, 2.541, 1.409), (4.992, 3.170, 4.778)),
          "RS": ((0.7806, 1.612, 0.7729), (7.061, 4.536, 6.188))}
B2 = (0.9011, 0.9443, 0.7414)
B3 = (-1.684, -3.911, -3.164)
C1 = (0.1159, 0.3165, 0.0646)
C2 = (0.1065, 0.2539, 0.0865)
C3 = (0.0682, 0.0932, 0.0373)
C4 = (-0.2246, -0.3183, -0.4237)
R1, R2 = 10.0, 50.0  # km
V1 = 600.0  # m/s
V_REF = (368.2, 369.9, 369.6)  # m/s
TAU = ((0.28, 0.25), (0.25, 0.19), (0.30, 0.19))  # (tau_1, tau_2)
PHI = ((0.54, 0.41), (0.43, 0.35), (0.56, 0.45))  # (phi_1, phi_2)
SHEAR_WAVE_VELOCITY = 3.2  # km/s, beta of Eq. 5
#: the ranges over which the model was fitted (magnitude, rupture distance [km], Vs30 [m/s])
RANGES = {"magnitude": (3.0, 7.9), "distance": (0.0, 200.0), "vs30": (150.0, 1500.0)}


@dataclass(frozen=True)
class Scenario:
    """An earthquake scenario: moment magnitude, rupture distance [km], Vs30 [m/s] and mechanism
    ("" unspecified, "SS", "NS" or "RS")."""

    magnitude: float
    distance: float
    vs30: float
    mechanism: str = ""


def _index(measure: str) -> int:
    return MEASURES.index(measure)


def source_duration(magnitude: float, k: int, mechanism: str = "") -> float:
    """F_E [s] of measure k (Eqs. 4-6)."""
    b0, b1 = SOURCE[mechanism]
    if magnitude <= M1[k]:
        return b0[k]
    stress_drop = math.exp(b1[k] + B2[k] * (min(magnitude, M2[k]) - M_STAR) + B3[k] * max(magnitude - M2[k], 0.0))
    moment = 10.0 ** (1.5 * magnitude + 16.05)
    corner = 4.9e6 * SHEAR_WAVE_VELOCITY * (stress_drop / moment) ** (1.0 / 3.0)
    return 1.0 / corner


def path_duration(distance: float, k: int) -> float:
    """F_P [s] of measure k (Eq. 7)."""
    return (C1[k] * min(distance, R1) + C2[k] * max(min(distance, R2) - R1, 0.0)
            + C3[k] * max(distance - R2, 0.0))


def median_duration(scenario: Scenario, measure: str = "D5-95") -> float:
    """The median duration [s] of the scenario (Eq. 3)."""
    k = _index(measure)
    site = C4[k] * math.log(min(scenario.vs30, V1) / V_REF[k])
    source = source_duration(scenario.magnitude, k, scenario.mechanism)
    return math.exp(math.log(source + path_duration(scenario.distance, k)) + site)


def _between(magnitude: float, low: float, high: float, pair: tuple[float, float]) -> float:
    """pair[0] below `low`, pair[1] above `high`, linear in between."""
    share = (min(max(magnitude, low), high) - low) / (high - low)
    return pair[0] + (pair[1] - pair[0]) * share


def sigmas(magnitude: float, measure: str = "D5-95") -> tuple[float, float]:
    """(tau, phi): the between- and within-event standard deviations of ln D [-] (Eq. 9)."""
    k = _index(measure)
    return _between(magnitude, 6.5, 7.0, TAU[k]), _between(magnitude, 5.5, 5.75, PHI[k])


def draw_duration(rng: np.random.Generator, scenario: Scenario, measure: str = "D5-95") -> float:
    """A duration [s] drawn from the model's lognormal distribution, total sigma = sqrt(tau^2 + phi^2)."""
    tau, phi = sigmas(scenario.magnitude, measure)
    return median_duration(scenario, measure) * math.exp(math.hypot(tau, phi) * rng.standard_normal())
