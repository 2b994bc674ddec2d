"""Improved simplified procedure for the uplift support (analysis.procedure = "improved").

The paper's procedure (engines/simplified.py, docs/theory.md) with these changes; the
coefficients (COEFFICIENTS) are calibrated against the exact engine on the FEMA P695
far-field records only (benchmarks/calibrate.py; data, fit and residuals in docs/accuracy.md):

0. a mat on a Winkler strip lifts progressively from the kern (M = W b/3): the critical shear
   is V_c times the capacity 1 - (2/3) sqrt((1/3)/x) (uplift_capacity, derived, not fitted);
1. mass-consistent X [28a]: X = x^2 e^(2 xi1bar (pi/2 - asin(1/x))), x = V_1/V_c with
   V_1 = m_1* S_a(T1bar, xi1bar) [26], not (S_a/g)^2 (h_1*/b)^2, which assumes m_1* = m_t:
   the bonded amplitude the uplift crossing interrupts is that of m_1*, and the decay is taken
   over the phase travelled from the crossing to the bonded peak (continuous at V_1 = V_c);
2. mode 1 while uplifted: x is read from the spectrum at the lengthened period
   T_u = T1bar (1 + lengthening s) (the lifting system softens), and V_1,max is raised by
   1 + short_gain s / (1 + (T1bar/short_period)^sharpness) for the impacts that govern short
   periods; s = (1 - 1/x)^onset is the uplift severity, 0 at the onset of uplift;
3. higher modes raised by uplift: V_n = m_n* S_a(T_n, xi_n) (1 + s (gain_n + short_modes /
   (1 + (T1bar/short_period)^sharpness))), gain2 for mode 2, gain3 for modes 3 and up: the
   rocking (impacts above all) excites them through the h_n* theta'' term of [11a];
4. combination: the signed modal peaks with correlation rho_1n = correlation s between mode 1
   and each higher mode (the impacts that set the higher-mode peaks come with the mode-1 peak),
   the others by the deck's rule (SRSS [35] or CQC);
5. no response quantity above the bonded or the rigid-base value of the same procedure.
Below the onset of uplift (x <= 1) the result is the paper's (the bonded one).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..model.system import System
from .options import SimplifiedOptions
from .result import AnalysisResult
from .statics import largest_compression

#: version of the per-case terms (benchmarks/calibrate.py caches them)
TERMS_VERSION = 2


@dataclass(frozen=True)
class Coefficients:
    """Coefficients of the improved procedure (module docstring; docs/accuracy.md): all
    dimensionless [-] but short_period [s], the period below which impacts govern."""

    lengthening: float = 0.0
    short_gain: float = 0.0
    short_period: float = 0.1
    gain2: float = 0.0
    gain3: float = 0.0
    short_modes: float = 0.0
    correlation: float = 0.0
    onset: float = 1.0
    sharpness: float = 2.0

    def short(self, t1bar):
        """1 / (1 + (T1bar/short_period)^sharpness): 1 for the shortest periods, 0 for long ones."""
        return 1.0 / (1.0 + (np.asarray(t1bar, dtype=float) / self.short_period) ** self.sharpness)


#: the range each coefficient is fitted in (benchmarks/calibrate.py)
BOUNDS = {"lengthening": (0.0, 2.0), "short_gain": (0.0, 10.0), "short_period": (0.01, 1.0), "gain2": (0.0, 3.0),
          "gain3": (0.0, 3.0), "short_modes": (0.0, 6.0), "correlation": (0.0, 1.0), "onset": (0.1, 2.0),
          "sharpness": (1.0, 8.0)}


#: the calibrated values (benchmarks/calibrate.py on the FEMA P695 far-field set)
COEFFICIENTS = Coefficients(lengthening=0.0627, short_gain=3.915, short_period=0.1727, gain2=0.7171, gain3=0.0404,
                            short_modes=0.6746, correlation=0.3501, onset=0.2788, sharpness=3.553)
#: the coefficients benchmarks/calibrate.py fits
FITTED = ("lengthening", "short_gain", "short_period", "gain2", "gain3", "short_modes", "correlation", "onset",
          "sharpness")
#: period multipliers at which S_a(c T1bar, xi1bar) is tabulated for the lengthened period
STRETCH = np.round(np.arange(1.0, 3.0001, 0.05), 10)


@dataclass(frozen=True)
class UpliftTerms:
    """The quantities of one system and spectrum that the improved procedure combines.

    x: V_1/V_c at T1bar; x_long: V_1/V_c at STRETCH x T1bar (array); slenderness h_1*/b;
    zeta: damping while uplifted xi1bar r/b [27]; xi1bar, t1bar [s]; v_c [N];
    modal_shears: fixed-base m_n* S_a(T_n, xi_n) [N] (mode 1: its bonded value);
    unit_drift (modes, stories), unit_roof (modes,) [1/N and m/N], unit_moment (modes,) [m]:
    signed drift ratios, roof displacement and base moment per unit modal base shear;
    omega, damping: of the modes for the correlation (mode 1: 2 pi/T1bar, xi1bar);
    bonded, rigid: the paper procedure's results for the caps; capacity: M_c,eff/M_c of a mat that
    lifts progressively (uplift_capacity), v_c and x are taken with it."""

    x: float
    x_long: np.ndarray
    slenderness: float
    zeta: float
    xi1bar: float
    t1bar: float
    v_c: float
    modal_shears: np.ndarray
    unit_drift: np.ndarray
    unit_roof: np.ndarray
    unit_moment: np.ndarray
    omega: np.ndarray
    damping: np.ndarray
    bonded: AnalysisResult
    rigid: AnalysisResult
    capacity: float = 1.0


def uplift_terms(system: System, spectrum, options: SimplifiedOptions) -> UpliftTerms:
    """The terms of one case from the paper procedure's bonded and rigid results."""
    from .simplified import modal_static_response, paper_analyze

    paper = replace(options, procedure="paper")
    bonded = paper_analyze(system, spectrum, "bonded", paper)
    rigid = paper_analyze(system, spectrum, "rigid", paper)
    inter = bonded.intermediates
    n = len(inter["V_n"])
    modes = system.modes
    m1 = float(modes.effective_mass[0])
    capacity = backbone_capacity(system, float(inter["V1_bonded"]))
    v_c = capacity * system.critical_base_shear
    t1bar, xi1bar = float(inter["T1bar"]), float(inter["xi1bar"])
    sa = np.asarray(spectrum.sa(STRETCH * t1bar, xi1bar), dtype=float)
    unit = modal_static_response(system, np.ones(n), n)
    b, h1 = system.half_width, system.effective_height
    omega, damping = modes.omega[:n].copy(), modes.damping[:n].copy()
    omega[0], damping[0] = 2.0 * math.pi / t1bar, xi1bar
    return UpliftTerms(
        x=float(inter["V1_bonded"]) / v_c, x_long=m1 * sa / v_c, slenderness=h1 / b,
        zeta=xi1bar * math.hypot(h1, b) / b, xi1bar=xi1bar, t1bar=t1bar, v_c=v_c,
        modal_shears=np.asarray(inter["V_n"], dtype=float), unit_drift=unit["drift_ratio"],
        unit_roof=unit["displacement"][:, -1], unit_moment=unit["moment"][:, 0],
        omega=omega, damping=damping, bonded=bonded, rigid=rigid, capacity=capacity)


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


def as_arrays(terms: UpliftTerms, size: int) -> dict[str, np.ndarray | float]:
    """One case's terms as combine_arrays takes them, modes and stories padded with zeros to size."""

    def padded(value: np.ndarray) -> np.ndarray:
        out = np.zeros((size,) * np.ndim(value))
        out[tuple(slice(0, n) for n in np.shape(value))] = value
        return out

    out: dict = {"x": terms.x, "x_long": terms.x_long, "slenderness": terms.slenderness, "zeta": terms.zeta,
                 "xi1bar": terms.xi1bar, "T1bar": terms.t1bar, "V_c": terms.v_c,
                 "modal_shears": padded(terms.modal_shears), "unit_drift": padded(terms.unit_drift),
                 "unit_roof": padded(terms.unit_roof), "unit_moment": padded(terms.unit_moment)}
    for support, result in (("bonded", terms.bonded), ("rigid", terms.rigid)):
        out[f"{support}_drift"] = padded(np.abs(result.drift_ratio))
        out[f"{support}_V"], out[f"{support}_M"] = result.base_shear, result.base_moment
        out[f"{support}_roof"] = abs(float(result.displacement[-1]))
    return out


def mode1_terms(x, x_long, slenderness, zeta, xi1bar, t1bar, c: Coefficients) -> dict[str, np.ndarray]:
    """V_1,max / V_c with uplift ("ratio") and its X, phi [28a, 28b] and amplitude ratio (arrays over
    cases): the mass-consistent X, the lengthened period and the short-period factor (module
    docstring, items 1-2)."""
    stretch = np.clip(1.0 + c.lengthening * severity(x, c), STRETCH[0], STRETCH[-1])
    x_long = np.asarray(x_long, dtype=float)
    position = np.interp(stretch, STRETCH, np.arange(STRETCH.size))
    low = np.clip(np.floor(position).astype(int), 0, STRETCH.size - 2)
    weight = position - low
    rows = np.arange(x_long.shape[0])
    amplitude = np.maximum((1 - weight) * x_long[rows, low] + weight * x_long[rows, low + 1], 1.0)
    big_x = amplitude**2 * np.exp(2.0 * xi1bar * (math.pi / 2 - np.arcsin(1.0 / amplitude)))
    b_over_r2 = 1.0 / (1.0 + slenderness**2)
    excess = np.maximum(big_x - 1.0, 0.0)
    phi = np.arctan(np.sqrt(excess / b_over_r2))
    ratio = (1.0 - b_over_r2) + np.exp(-zeta * phi) * np.sqrt(b_over_r2**2 + b_over_r2 * excess)
    ratio = ratio * (1.0 + c.short_gain * severity(x, c) * c.short(t1bar))
    return {"ratio": ratio, "X": big_x, "phi": phi, "amplitude": amplitude, "T_u": stretch * t1bar}


def severity(x, c: Coefficients):
    """(1 - 1/x)^onset: 0 at the onset of uplift (V_1 = V_c), tending to 1 as V_1/V_c grows."""
    return np.maximum(1.0 - 1.0 / np.maximum(np.asarray(x, dtype=float), 1.0), 0.0) ** c.onset


def modal_factors(x, t1bar, n_modes: int, c: Coefficients) -> np.ndarray:
    """Factors on the modal base shears (cases, modes): 1 + s (gain_n + short_modes short(T1bar))
    for modes 2.. (gain2 for mode 2, gain3 above), s = severity(x) and short as in
    Coefficients.short; 1 for mode 1."""
    gains = np.full(n_modes, c.gain3)
    gains[0] = 0.0
    if n_modes > 1:
        gains[1] = c.gain2
    raised = gains[None, :] + c.short_modes * c.short(t1bar)[:, None]
    raised[:, 0] = 0.0
    return 1.0 + raised * severity(x, c)[:, None]


def combine_peaks(peaks: np.ndarray, rho: np.ndarray) -> np.ndarray:
    """sqrt(sum_ij rho_ij r_i r_j) over modes (axis -2), rho (cases, modes, modes); peaks
    (cases, modes, k). Negative sums (possible with rho_1n > 0 and opposite signs) give 0."""
    total = np.einsum("cik,cij,cjk->ck", peaks, rho, peaks)
    return np.sqrt(np.maximum(total, 0.0))


def correlations(x, base: np.ndarray, c: Coefficients) -> np.ndarray:
    """rho (cases, modes, modes): the deck's rule (base, identity for SRSS) with
    rho_1n = max(base_1n, correlation s) for n >= 2, s = severity(x)."""
    rho = np.array(base, dtype=float, copy=True)
    coupled = np.maximum(rho[:, 0, 1:], (c.correlation * severity(x, c))[:, None])
    rho[:, 0, 1:] = coupled
    rho[:, 1:, 0] = coupled
    return rho


def combine_arrays(data: dict, c: Coefficients) -> dict[str, np.ndarray]:
    """V_b, M_b, largest drift ratio and roof displacement of many cases at once (the
    calibration's form of analyze_uplift; same functions, padded arrays)."""
    x = data["x"]
    shears = data["modal_shears"].copy()
    n_modes = shears.shape[1]
    lifting = x > 1.0
    v1 = data["V_c"] * mode1_terms(x, data["x_long"], data["slenderness"], data["zeta"], data["xi1bar"],
                                   data["T1bar"], c)["ratio"]
    shears[:, 0] = np.where(lifting, v1, shears[:, 0])
    shears *= np.where(lifting[:, None], modal_factors(x, data["T1bar"], n_modes, c), 1.0)
    base = np.broadcast_to(np.eye(n_modes), (x.size, n_modes, n_modes))
    rho = np.where(lifting[:, None, None], correlations(x, base, c), base)
    drift = combine_peaks(shears[:, :, None] * data["unit_drift"], rho)
    roof = combine_peaks((shears * data["unit_roof"])[:, :, None], rho)[:, 0]
    moment = combine_peaks((shears * data["unit_moment"])[:, :, None], rho)[:, 0]
    shear = combine_peaks(shears[:, :, None], rho)[:, 0]
    drift = np.minimum(drift, np.minimum(data["bonded_drift"], data["rigid_drift"]))
    return {"V": np.minimum(shear, np.minimum(data["bonded_V"], data["rigid_V"])),
            "M": np.minimum(moment, np.minimum(data["bonded_M"], data["rigid_M"])),
            "drift": drift.max(axis=1),
            "roof": np.minimum(roof, np.minimum(data["bonded_roof"], data["rigid_roof"]))}


def analyze_uplift(system: System, spectrum, options: SimplifiedOptions,
                   coefficients: Coefficients = COEFFICIENTS) -> AnalysisResult:
    """The improved procedure's uplift result (module docstring); intermediates as the paper's
    plus V1_uplift, the modal factors and the correlation used."""
    from .simplified import cqc_correlation, modal_static_response, paper_analyze

    terms = uplift_terms(system, spectrum, options)
    paper = paper_analyze(system, spectrum, "uplift", replace(options, procedure="paper"))
    details = {**paper.details, "warnings": list(paper.details["warnings"]),
               "options": {**paper.details["options"], "procedure": "improved"}}
    if terms.x <= 1.0:
        return replace(paper, details=details)
    inter = {k: v for k, v in paper.intermediates.items() if k not in ("X0", "X_factor")}
    if terms.capacity < 1.0:  # partial uplift is modelled by the capacity: the paper's caveat does not apply
        details["warnings"] = [w for w in details["warnings"] if "kern" not in w]
    inter["capacity"] = terms.capacity
    n = terms.modal_shears.size
    x = np.array([terms.x])
    mode1 = {k: float(v[0]) for k, v in mode1_terms(x, terms.x_long[None, :], terms.slenderness, terms.zeta,
                                                    terms.xi1bar, terms.t1bar, coefficients).items()}
    factors = modal_factors(x, np.array([terms.t1bar]), n, coefficients)[0]
    shears = terms.modal_shears * factors
    shears[0] = mode1["ratio"] * terms.v_c
    base = cqc_correlation(terms.omega, terms.damping) if options.combination == "cqc" else np.eye(n)
    rho = correlations(x, base[None], coefficients)[0]
    per_mode = modal_static_response(system, shears, n)
    combined = {name: combine_peaks(values[None], rho[None])[0] for name, values in per_mode.items()
                if name != "forces"}
    peaks = {name: np.minimum(value, np.minimum(terms.bonded.peaks[name], terms.rigid.peaks[name]))
             for name, value in combined.items()}
    # the modal base shears as they enter V_b: scaled by the cap on V_b when it binds
    scale = float(peaks["shear"][0] / combined["shear"][0]) if combined["shear"][0] > 0 else 1.0
    elements = system.foundation.contact_elements(system.half_width)
    peaks["reaction"] = largest_compression(elements.positions, elements.stiffness, system.weight,
                                            float(peaks["moment"][0]), False, elements.capacity)
    inter.update({"zeta": terms.zeta, "r": math.hypot(system.effective_height, system.half_width),  # as used
                  "X": mode1["X"], "phi": mode1["phi"], "T_u": mode1["T_u"], "x_u": mode1["amplitude"],
                  "V1_uplift": float(shears[0]), "V_n": (scale * shears).tolist(), "modal_factors": factors.tolist(),
                  "rho_1n": float(rho[0, 1]) if n > 1 else 0.0, "cap": scale})
    if n >= 2:
        inter["V_1+2"] = scale * float(combine_peaks(shears[None, :2, None], rho[None, :2, :2])[0, 0])
    details["modal_forces"] = per_mode["forces"].tolist()
    return AnalysisResult.of(system, "simplified", "uplift", peaks, uplift=True, periods=paper.periods,
                             elements=elements, intermediates=inter, details=details)
