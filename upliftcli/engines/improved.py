"""Improved simplified procedure for the uplift support (analysis.procedure = "improved").

The paper's procedure (engines/paper.py, docs/theory.md) with these changes; the fitted
coefficients (COEFFICIENTS, FITTED) are calibrated against the exact engine on the FEMA P695
far-field records only and validated on other records (benchmarks/calibrate.py,
benchmarks/accuracy.py; data, fit and both tables in docs/accuracy.md):

0. a mat on a Winkler strip lifts progressively from the kern (M = W b/3): the critical shear
   is V_c times the capacity 1 - (2/3) sqrt((1/3)/x) (uplift_capacity, derived, not fitted);
1. mass-consistent X [28a]: X = x_u^2 e^(2 xi1bar (pi/2 - asin(1/x_u))) with x_u = m_1* S_a / V_c,
   not (S_a/g)^2 (h_1*/b)^2, which assumes m_1* = m_t (derived);
2. the amplitude x_u is read from the geometric mean of S_a(T, xi1bar) over [T1bar, T_u],
   T_u = span T1bar: a lifting system's period grows with its rotation, from T1bar in contact to
   much longer while uplifted, so its peak follows the spectrum over a band, not at one
   period (a single record's spectrum is jagged; the band average halves the scatter of the
   peaks at 0.2-0.5 s); x = V_1/V_c at T1bar still decides whether the mat lifts;
3. impacts: V_1,max times 1 + short_gain s short(T1bar) and the higher modes times
   1 + s (gain2 [mode 2 only] + short_modes short(T1bar)), short(T) = 1/(1 + (T/short_period)^4),
   s = (1 - 1/x)^onset the uplift severity (0 at the onset of uplift): recontact excites every
   mode through the h_n* theta'' term of [11a], most at short periods;
4. combination: signed modal peaks with rho_1n = correlation s between mode 1 and each higher
   mode (the impacts that set the higher-mode peaks come with the mode-1 peak), the others by the
   deck's rule (SRSS [35] or CQC);
5. no caps: uplift can raise a response above the bonded or rigid-base one (floor accelerations
   above all: impacts), so none is capped;
6. mat rotation, edge uplift and the impact floor accelerations (engines/rocking.py).
Below the onset of uplift (x <= 1) the result is the paper's (the bonded one) with the elastic
mat rotation and no uplift.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..model.system import System
from . import rocking
from .options import SimplifiedOptions
from .paper import cqc_correlation, modal_static_response, paper_analyze
from .result import AnalysisResult
from .statics import largest_compression

#: version of the per-case terms (benchmarks/calibrate.py caches them)
TERMS_VERSION = 3
#: exponent of short(T) = 1/(1 + (T/short_period)^SHARPNESS) (fixed, not fitted)
SHARPNESS = 4.0
#: the peak quantities combined mode by mode (engines/paper.modal_static_response)
COMBINED = ("displacement", "drift", "drift_ratio", "shear", "moment", "floor_acceleration")


@dataclass(frozen=True)
class Coefficients:
    """Coefficients of the improved procedure (module docstring; docs/accuracy.md): dimensionless
    [-] but short_period and displacement_period [s]. The defaults are neutral (no band, no
    impact terms, no correlation)."""

    span: float = 1.0
    short_gain: float = 0.0
    short_period: float = 0.1
    gain2: float = 0.0
    short_modes: float = 0.0
    correlation: float = 0.0
    onset: float = 1.0
    displacement_period: float = 0.0
    impact: float = 0.0

    def short(self, t1bar):
        """1 / (1 + (T1bar/short_period)^SHARPNESS): 1 for the shortest periods, 0 for long ones."""
        return 1.0 / (1.0 + (np.asarray(t1bar, dtype=float) / self.short_period) ** SHARPNESS)


#: the range each coefficient is fitted in (benchmarks/calibrate.py)
BOUNDS = {"span": (1.0, 3.0), "short_gain": (0.0, 10.0), "short_period": (0.02, 1.0), "gain2": (0.0, 3.0),
          "short_modes": (0.0, 6.0), "correlation": (0.0, 1.0), "onset": (0.1, 2.0),
          "displacement_period": (0.0, 2.0), "impact": (0.0, 3.0)}
#: the calibrated values (benchmarks/calibrate.py on the FEMA P695 far-field set)
COEFFICIENTS = Coefficients(span=1.4446, short_gain=1.3372, short_period=0.1608, gain2=1.0483, short_modes=0.3086,
                            correlation=0.1942, onset=0.3631, displacement_period=0.153, impact=0.3618)
#: the coefficients benchmarks/calibrate.py fits: those of the forces, then those of the motion
FITTED = ("span", "short_gain", "short_period", "gain2", "short_modes", "correlation", "onset")
FITTED_MOTION = ("displacement_period", "impact")
#: period multipliers at which S_a(c T1bar, xi1bar) is tabulated for the band of item 2
STRETCH = np.round(np.arange(1.0, 3.0001, 0.05), 10)


def uplift_capacity(x: float, kern: float) -> float:
    """M_c,eff / M_c: the overturning moment a mat carries while lifting, as a fraction of W b.

    1 for two edge elements (and the half-space, represented so). A Winkler strip (kern = 1/3:
    contact is first lost at M = W b/3) lifts progressively: with contact over a length a from
    the compressed edge, vertical equilibrium k_w theta a^2/2 = W and the moment about the centre
    M = W (b - a/3) (docs/theory.md). Taking the rotation equal to the bonded one at the bonded
    moment x W b (x = V_1/V_c; theta = x W b / K_theta, K_theta = 2 k_w b^3/3) gives
    a/b = sqrt(4/(3x)) and M_c,eff/M_c = 1 - sqrt(4/(3x))/3 = 1 - (1 - kern) sqrt(kern/x), from
    1/3 at x = 1/3 (full contact, so continuous with the bonded branch) towards 1."""
    if kern >= 1.0:
        return 1.0
    return 1.0 - (1.0 - kern) * math.sqrt(kern / max(x, kern))


def backbone_capacity(system: System, v1_bonded: float) -> float:
    """M_c,eff / M_c of the mat at the bonded mode-1 base shear V_1 [N]: uplift_capacity, or with a
    bearing capacity of a Winkler strip the strip's static backbone (model/rocking_capacity.py,
    docs/theory.md 14.4) at the bonded rotation V_1 h_1* / K_theta over the capacity's M_c (two
    elements: 1 past V_c, as without a capacity)."""
    foundation = system.foundation
    if getattr(foundation, "capacity", None) is None or foundation.kind != "winkler":
        return uplift_capacity(v1_bonded / system.critical_base_shear, foundation.contact_loss_moment_ratio)
    from ..model.rocking_capacity import winkler_backbone

    b = system.half_width
    theta = v1_bonded * system.effective_height / foundation.rocking_stiffness(b)
    moment = float(winkler_backbone(theta, b, foundation.stiffness, foundation.capacity, system.weight)[0])
    return moment / system.critical_base_moment


def uplift_terms(system: System, spectrum, options: SimplifiedOptions, size: int | None = None) -> dict:
    """The terms of one case as arrays (modes and floors padded with zeros to `size`, default the
    larger of the two counts): what combine_arrays takes (stack the dicts of many cases for the
    calibration)."""
    bonded = paper_analyze(system, spectrum, "bonded", replace(options, procedure="paper"))
    inter = bonded.intermediates
    n = len(inter["V_n"])
    size = size or max(n, system.building.n_stories)
    modes = system.modes
    m1 = float(modes.effective_mass[0])
    capacity = backbone_capacity(system, float(inter["V1_bonded"]))
    v_c = capacity * system.critical_base_shear
    t1bar, xi1bar = float(inter["T1bar"]), float(inter["xi1bar"])
    unit = modal_static_response(system, np.ones(n), n)
    b, h1 = system.half_width, system.effective_height
    omega, damping = modes.omega[:n].copy(), modes.damping[:n].copy()
    omega[0], damping[0] = 2.0 * math.pi / t1bar, xi1bar

    def padded(value) -> np.ndarray:
        value = np.asarray(value, dtype=float)
        out = np.zeros((size,) * value.ndim)
        out[tuple(slice(0, k) for k in value.shape)] = value
        return out

    return {"x": float(inter["V1_bonded"]) / v_c, "x_long": m1 * np.asarray(spectrum.sa(STRETCH * t1bar, xi1bar),
                                                                           dtype=float) / v_c,
            "slenderness": h1 / b, "zeta": xi1bar * math.hypot(h1, b) / b, "xi1bar": xi1bar, "T1bar": t1bar,
            "T1": float(modes.periods[0]), "V_c": v_c, "capacity": capacity, "m1": m1, "m_t": system.total_mass,
            "omega1": float(modes.omega[0]), "b": b, "g": system.gravity, "n_modes": n,
            "n_floors": system.building.n_stories,
            "modal_shears": padded(inter["V_n"]), "effective_mass": padded(modes.effective_mass[:n]),
            "fixed_omega": padded(modes.omega[:n]), "omega": padded(omega), "damping": padded(damping),
            "unit_base_moment": padded(unit["moment"][:, 0]),
            **{f"unit_{name}": padded(unit[name]) for name in COMBINED}}


def stacked(cases: list[dict]) -> dict[str, np.ndarray]:
    """The terms of many cases (uplift_terms of each, same size) as arrays over the cases."""
    return {name: np.asarray([case[name] for case in cases]) for name in cases[0]}


def severity(x, c: Coefficients):
    """(1 - 1/x)^onset: 0 at the onset of uplift (V_1 = V_c), tending to 1 as V_1/V_c grows."""
    return np.maximum(1.0 - 1.0 / np.maximum(np.asarray(x, dtype=float), 1.0), 0.0) ** c.onset


def mode1_terms(data: dict, c: Coefficients) -> dict[str, np.ndarray]:
    """V_1,max / V_c with uplift ("ratio"), its X and phi [28a, 28b], the band amplitude x_u and
    T_u (items 1-3 of the module docstring), arrays over the cases."""
    amplitude = np.maximum(rocking.spectral_band(data["x_long"], STRETCH, c.span), 1.0)
    xi1bar = np.asarray(data["xi1bar"], dtype=float)
    big_x = amplitude**2 * np.exp(2.0 * xi1bar * (math.pi / 2 - np.arcsin(1.0 / amplitude)))
    b_over_r2 = 1.0 / (1.0 + np.asarray(data["slenderness"], dtype=float) ** 2)
    excess = np.maximum(big_x - 1.0, 0.0)
    phi = np.arctan(np.sqrt(excess / b_over_r2))
    ratio = (1.0 - b_over_r2) + np.exp(-data["zeta"] * phi) * np.sqrt(b_over_r2**2 + b_over_r2 * excess)
    ratio = ratio * (1.0 + c.short_gain * severity(data["x"], c) * c.short(data["T1bar"]))
    return {"ratio": ratio, "X": big_x, "phi": phi, "x_u": amplitude, "T_u": c.span * np.asarray(data["T1bar"])}


def modal_factors(x, t1bar, n_modes: int, c: Coefficients) -> np.ndarray:
    """Factors on the modal base shears (cases, modes): 1 + s (gain2 + short_modes short(T1bar))
    for mode 2, 1 + s short_modes short(T1bar) for modes 3 and up, 1 for mode 1."""
    gains = np.zeros(n_modes)
    if n_modes > 1:
        gains[1] = c.gain2
    raised = gains[None, :] + c.short_modes * c.short(t1bar)[:, None]
    raised[:, 0] = 0.0
    return 1.0 + raised * severity(x, c)[:, None]


def combine_peaks(peaks: np.ndarray, rho: np.ndarray) -> np.ndarray:
    """sqrt(sum_ij rho_ij r_i r_j) over modes (axis -2), rho (cases, modes, modes); peaks
    (cases, modes, k). Negative sums (possible with rho_1n > 0 and opposite signs) give 0."""
    total = np.sum(peaks * (rho @ peaks), axis=1)
    return np.sqrt(np.maximum(total, 0.0))


def correlations(x, base: np.ndarray, c: Coefficients) -> np.ndarray:
    """rho (cases, modes, modes): the deck's rule (base, identity for SRSS) with
    rho_1n = max(base_1n, correlation s) for n >= 2, s = severity(x)."""
    rho = np.array(base, dtype=float, copy=True)
    coupled = np.maximum(rho[:, 0, 1:], (c.correlation * severity(x, c))[:, None])
    rho[:, 0, 1:] = coupled
    rho[:, 1:, 0] = coupled
    return rho


def combine_arrays(data: dict, c: Coefficients, base_rho: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """The improved uplift peaks of many cases at once (stacked uplift_terms, all lifting: x > 1):
    modal base shears "V_n" and correlation "rho", every COMBINED quantity (cases, floors or
    stories; floor accelerations with the impact term), "theta", "theta_c", "uplift" [m],
    "impact_acceleration" [m/s^2] and the mode-1 terms. base_rho: the deck's correlation
    (cases, modes, modes; default SRSS)."""
    x = np.asarray(data["x"], dtype=float)
    shears = np.array(data["modal_shears"], dtype=float)
    n_modes = shears.shape[1]
    mode1 = mode1_terms(data, c)
    shears[:, 0] = data["V_c"] * mode1["ratio"]
    shears *= modal_factors(x, data["T1bar"], n_modes, c)
    base = np.broadcast_to(np.eye(n_modes), (x.size, n_modes, n_modes)) if base_rho is None else base_rho
    rho = correlations(x, base, c)
    out = {name: combine_peaks(shears[:, :, None] * data[f"unit_{name}"], rho) for name in COMBINED}
    motion = rocking.rotation(data, mode1["x_u"], shears[:, 0], STRETCH, c.displacement_period)
    impact = c.impact * rocking.impact_acceleration(data, motion["theta"] - motion["theta_c"])
    out["floor_acceleration"] = np.hypot(out["floor_acceleration"], impact)
    return {**out, **mode1, **motion, "V_n": shears, "rho": rho, "impact_acceleration": impact.max(axis=1)}


def analyze_uplift(system: System, spectrum, options: SimplifiedOptions,
                   coefficients: Coefficients = COEFFICIENTS) -> AnalysisResult:
    """The improved procedure's uplift result (module docstring): intermediates as the paper's
    plus V1_uplift, the band T_u and x_u, the modal factors, the correlation used, the mat rotation
    max_rotation [rad], the edge uplift max_uplift [m] and the impact floor acceleration."""
    paper = paper_analyze(system, spectrum, "uplift", replace(options, procedure="paper"))
    details = {**paper.details, "warnings": list(paper.details["warnings"]),
               "options": {**paper.details["options"], "procedure": "improved"}}
    terms = uplift_terms(system, spectrum, options)
    if terms["x"] <= 1.0:  # no uplift: the bonded result and its elastic mat rotation
        inter = {**paper.intermediates, "max_rotation": paper.base_moment / paper.intermediates["K_theta"],
                 "max_uplift": 0.0}
        return replace(paper, intermediates=inter, details=details)
    if terms["capacity"] < 1.0:  # partial uplift is modelled by the capacity: the paper's caveat does not apply
        details["warnings"] = [w for w in details["warnings"] if "kern" not in w]
    n, floors = terms["n_modes"], system.building.n_stories
    out = combine_arrays(stacked([terms]), coefficients, _deck_correlation(terms, options.combination)[None])
    peaks = {name: out[name][0, :floors] for name in COMBINED}
    elements = system.foundation.contact_elements(system.half_width)
    peaks["reaction"] = largest_compression(elements.positions, elements.stiffness, system.weight,
                                            float(peaks["moment"][0]), False, elements.capacity)
    inter = _uplift_intermediates(system, paper.intermediates, terms, out, coefficients)
    details["modal_forces"] = modal_static_response(system, out["V_n"][0, :n], n)["forces"].tolist()
    return AnalysisResult.of(system, "simplified", "uplift", peaks, uplift=True, periods=paper.periods,
                             elements=elements, intermediates=inter, details=details)


def _deck_correlation(terms: dict, combination: str) -> np.ndarray:
    """The deck's modal correlation of one case (uplift_terms; padded size): CQC with T1bar, xi1bar in
    mode 1, or the identity (SRSS)."""
    n = terms["n_modes"]
    base = np.eye(terms["modal_shears"].size)
    if combination == "cqc":
        base[:n, :n] = cqc_correlation(terms["omega"][:n], terms["damping"][:n])
    return base


def _uplift_intermediates(system: System, paper: dict, terms: dict, out: dict, coefficients: Coefficients) -> dict:
    """The paper's intermediates (paper; without X0 and X_factor, which the improved X does not use)
    updated with the improved procedure's of one case (terms: uplift_terms, out: combine_arrays)."""
    n = terms["n_modes"]
    shears, rho = out["V_n"][0, :n], out["rho"][0, :n, :n]
    inter = {k: v for k, v in paper.items() if k not in ("X0", "X_factor")}
    inter.update({"capacity": terms["capacity"], "zeta": terms["zeta"],
                  "r": math.hypot(system.effective_height, system.half_width), "X": float(out["X"][0]),
                  "phi": float(out["phi"][0]), "T_u": float(out["T_u"][0]), "x_u": float(out["x_u"][0]),
                  "V1_uplift": float(shears[0]), "V_n": shears.tolist(),
                  "modal_factors": modal_factors(np.array([terms["x"]]), np.array([terms["T1bar"]]), n,
                                                 coefficients)[0].tolist(),
                  "rho_1n": float(rho[0, 1]) if n > 1 else 0.0,
                  "max_rotation": float(out["theta"][0]), "max_uplift": float(out["uplift"][0]),
                  "impact_acceleration": float(out["impact_acceleration"][0])})
    if n >= 2:
        inter["V_1+2"] = float(combine_peaks(shears[None, :2, None], rho[None, :2, :2])[0, 0])
    return inter
