"""An R-mu-T estimate of the ductility of a yielding building from its elastic demand (issue 35,
docs/theory.md 15.6). Pure numpy; knows nothing of decks, files or the engines.

    R = elastic demand / strength        (per story: the elastic story shear over the story strength)
    mu = ductility(R, T, T_c, relation)  (the peak |drift| over the yield drift the relation predicts)

Two published R-mu-T relations of a single-degree-of-freedom bilinear oscillator:

- "vidic1994": Vidic, Fajfar & Fischinger (1994), "Consistent inelastic design spectra: strength
  and displacement", Earthquake Engng Struct. Dyn. 23(5) 507-521, eqs. for R_mu:

      R = c_1 (mu - 1)^c_R T / T_0 + 1    (T <= T_0)
      R = c_1 (mu - 1)^c_R + 1            (T > T_0),     T_0 = c_2 mu^c_T T_c

  with their Table II row for the bilinear model with damping proportional to the instantaneous
  stiffness: c_1 = 1.10, c_R = 0.95, c_2 = 0.75, c_T = 0.20. mu from R by bisection (R grows with mu).
- "fajfar2000": the simplified form of the N2 method, Fajfar (2000), "A nonlinear analysis method for
  performance-based seismic design", Earthquake Spectra 16(3) 573-592 (EN 1998-1:2004 Annex B, B.5):

      mu = (R - 1) T_c / T + 1   (T < T_c),   mu = R   (T >= T_c: equal displacements)

For R <= 1 the oscillator stays elastic and its peak over the yield displacement is R itself (the
exact engine's story ductility, peak |drift| / yield drift, is R for an elastic story): both
relations return mu = R there. T_c, the corner between the constant-acceleration and
constant-velocity ranges of the spectrum: from a design spectrum, its own (ASCE 7-22: T_s =
S_D1/S_DS); from a record, characteristic_period (the corner of a smoothed spectrum 2.5 PGA, 2.0 PGV).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: amplifications of the smoothed spectrum whose corner is a record's characteristic period
ACCELERATION_AMPLIFICATION = 2.5
VELOCITY_AMPLIFICATION = 2.0
#: bisection of vidic1994: the largest ductility searched and the number of halvings
MAX_DUCTILITY = 1e4
HALVINGS = 80


@dataclass(frozen=True)
class VidicCoefficients:
    """One row of Table II of Vidic, Fajfar & Fischinger (1994)."""

    c1: float
    c_r: float
    c2: float
    c_t: float


#: bilinear hysteresis, damping proportional to the instantaneous stiffness (Table II, 4th row)
BILINEAR = VidicCoefficients(1.10, 0.95, 0.75, 0.20)


def characteristic_period(pga: float, pgv: float) -> float:
    """T_c [s] of a record: 2 pi (2.0 PGV) / (2.5 PGA), the corner of the smoothed spectrum whose
    constant-acceleration plateau is 2.5 PGA and constant-velocity plateau 2.0 PGV [m/s^2, m/s]."""
    if not (pga > 0.0 and pgv > 0.0):
        raise ValueError(f"a characteristic period needs PGA and PGV > 0 (got {pga}, {pgv})")
    return 2.0 * math.pi * VELOCITY_AMPLIFICATION * pgv / (ACCELERATION_AMPLIFICATION * pga)


def _check(value: float, period: float, corner: float) -> None:
    """R or mu >= 0, T > 0 and T_c > 0, or a ValueError naming the one that is not."""
    if not value >= 0.0:
        raise ValueError(f"the strength ratio or ductility must be >= 0 (got {value})")
    if not (period > 0.0 and corner > 0.0):
        raise ValueError(f"the periods T and T_c must be > 0 (got {period}, {corner})")


def vidic_strength_ratio(mu: float, period: float, corner: float, row: VidicCoefficients = BILINEAR) -> float:
    """R_mu of Vidic et al. (1994) for ductility mu >= 1 at period T [s] with corner T_c [s] (mu < 1: R = mu)."""
    _check(mu, period, corner)
    if mu <= 1.0:
        return float(mu)
    t0 = row.c2 * mu ** row.c_t * corner
    return 1.0 + row.c1 * (mu - 1.0) ** row.c_r * min(period / t0, 1.0)


def vidic_ductility(ratio: float, period: float, corner: float, row: VidicCoefficients = BILINEAR) -> float:
    """The ductility whose R_mu (vidic_strength_ratio) is `ratio`, by bisection (R <= 1: mu = R)."""
    _check(ratio, period, corner)
    if ratio <= 1.0:
        return float(ratio)
    low, high = 1.0, MAX_DUCTILITY
    for _ in range(HALVINGS):
        middle = 0.5 * (low + high)
        if vidic_strength_ratio(middle, period, corner, row) < ratio:
            low = middle
        else:
            high = middle
    return 0.5 * (low + high)


def fajfar_ductility(ratio: float, period: float, corner: float) -> float:
    """mu of the N2 method (Fajfar 2000; EN 1998-1 B.5): (R - 1) T_c / T + 1 below T_c, R from T_c on
    (R <= 1: mu = R)."""
    _check(ratio, period, corner)
    if ratio <= 1.0 or period >= corner:
        return float(ratio)
    return (ratio - 1.0) * corner / period + 1.0


#: relation name -> mu(R, T, T_c)
RELATIONS = {"vidic1994": vidic_ductility, "fajfar2000": fajfar_ductility}


def ductility(ratio: float, period: float, corner: float, relation: str = "vidic1994") -> float:
    """The ductility the named R-mu-T relation (RELATIONS) gives for R at T with corner T_c."""
    if relation not in RELATIONS:
        raise ValueError(f"unknown R-mu-T relation {relation!r}: one of {', '.join(RELATIONS)}")
    return RELATIONS[relation](ratio, period, corner)


def strength_ratios(elastic_shears, strengths) -> np.ndarray:
    """R_j = |elastic story shear| / story strength [-] per story (0 where the strength is infinite)."""
    shears = np.abs(np.asarray(elastic_shears, dtype=float))
    strengths = np.asarray(strengths, dtype=float)
    if shears.shape != strengths.shape or np.any(strengths <= 0.0):
        raise ValueError("one story strength > 0 per elastic story shear is needed")
    return shears / strengths


def story_ductilities(elastic_shears, strengths, period: float, corner: float,
                      relation: str = "vidic1994") -> np.ndarray:
    """The estimated ductility of every story: the relation applied to each story's R_j with the
    building's period T (each story taken as the oscillator of the whole building)."""
    return np.array([ductility(r, period, corner, relation) for r in strength_ratios(elastic_shears, strengths)])


def roof_ductility(roof_inelastic: float, roof_elastic: float, ratio: float) -> float:
    """The system (roof) ductility of a yielding run: its peak roof displacement over the roof yield
    displacement u_r,el / R_b (the elastic roof displacement scaled down to the base-shear strength,
    R_b = elastic base shear / base-shear strength)."""
    if not (roof_elastic > 0.0 and ratio > 0.0):
        raise ValueError("a roof ductility needs an elastic roof displacement and a strength ratio > 0")
    return roof_inelastic * ratio / roof_elastic
