"""Simplified engine: response spectrum analysis with interaction and uplift in mode 1.

docs/theory.md section 7 (paper Eqs. 21-35). Pure functions of a System and a spectrum
object with .sa(periods [s], damping [-]) -> S_a [m/s^2]:

- rigid: standard modal response spectrum analysis on a fixed base [31-35];
- bonded: mode 1 with the effective period and damping of the flexibly supported
  system T1bar, xi1bar [21-25]; higher modes fixed-base;
- uplift: as bonded, and if V_1 = m_1* S_a(T1bar, xi1bar) exceeds V_c [16a] the
  uplift base shear [26-29]; higher modes fixed-base.

Every intermediate an engineer checks by hand is returned in result.intermediates
(names and units: engines/quantities.INTERMEDIATES).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import asdict, replace

import numpy as np

from ..errors import AnalysisError, InputError
from ..model.interaction import effective_properties, frequency_warning
from ..model.system import System
from .options import SimplifiedOptions
from .registry import check_support
from .result import AnalysisResult
from .statics import largest_compression, story_maps


def srss(modal_peaks: np.ndarray) -> np.ndarray:
    """Square root of the sum of squares over the first axis (modes) [35]."""
    peaks = np.asarray(modal_peaks, dtype=float)
    return np.sqrt(np.sum(peaks**2, axis=0))


def cqc_correlation(omega: np.ndarray, damping: np.ndarray) -> np.ndarray:
    """Der Kiureghian's CQC correlation coefficients rho_ij for frequencies [rad/s] and damping [-]."""
    w = np.asarray(omega, dtype=float)
    xi = np.broadcast_to(np.asarray(damping, dtype=float), w.shape)
    r = w[None, :] / w[:, None]
    xi_i, xi_j = xi[:, None], xi[None, :]
    numerator = 8.0 * np.sqrt(xi_i * xi_j) * (xi_i + r * xi_j) * r**1.5
    denominator = (1.0 - r**2) ** 2 + 4.0 * xi_i * xi_j * r * (1.0 + r**2) + 4.0 * (xi_i**2 + xi_j**2) * r**2
    with np.errstate(invalid="ignore", divide="ignore"):
        rho = np.where(denominator > 0.0, numerator / denominator, 1.0)
    np.fill_diagonal(rho, 1.0)
    return rho


def cqc(modal_peaks: np.ndarray, omega: np.ndarray, damping: np.ndarray) -> np.ndarray:
    """Complete quadratic combination over the first axis (modes), signed modal peaks."""
    peaks = np.asarray(modal_peaks, dtype=float)
    rho = cqc_correlation(omega, damping)
    flat = peaks.reshape(peaks.shape[0], -1)
    total = np.einsum("ik,ij,jk->k", flat, rho, flat)
    return np.sqrt(np.maximum(total, 0.0)).reshape(peaks.shape[1:])


def spectral_acceleration(spectrum, period: float, damping: float) -> float:
    """S_a(T, xi) [m/s^2] of one period."""
    value = np.asarray(spectrum.sa(np.array([float(period)]), float(damping)), dtype=float).ravel()[0]
    if not math.isfinite(value):
        raise AnalysisError(f"the spectrum gives no finite S_a at T = {period:.4g} s, xi = {damping:.4g}")
    return float(value)


def uplift_base_shear(critical_shear: float, slenderness: float, x_value: float, zeta: float,
                      formula: str = "full") -> tuple[float, float]:
    """(V_1,max [N], phi [rad]) with uplift, Eq. 28a/28b ("full") or Eq. 29 ("slender").

    slenderness: h_1*/b; x_value: X (> 1); zeta: damping while uplifted [27]."""
    b_over_r2 = 1.0 / (1.0 + slenderness**2)  # b^2/r^2
    excess = max(x_value - 1.0, 0.0)
    if formula == "slender":
        phi = math.pi / 2
        return critical_shear * (1.0 + math.sqrt(b_over_r2) * math.exp(-zeta * phi) * math.sqrt(excess)), phi
    phi = math.atan(math.sqrt(excess / b_over_r2))
    amplitude = math.sqrt(b_over_r2**2 + b_over_r2 * excess)
    return critical_shear * ((1.0 - b_over_r2) + math.exp(-zeta * phi) * amplitude), phi


def _uplift(system: System, props: dict, v1_bonded: float, sa1bar: float, options: SimplifiedOptions) -> dict:
    """Steps 4-5 of docs/theory.md section 7: zeta, X, phi and V_1 with uplift."""
    b, h1 = system.half_width, system.effective_height
    v_c = system.critical_base_shear
    r = math.hypot(h1, b)
    base_damping = props["xi1bar"] if options.uplift_damping == "xi1bar" else props["xi1"]
    zeta = base_damping * r / b
    x0 = (system.total_mass * sa1bar / v_c) ** 2 if options.uplift_x == "spectral" else (v1_bonded / v_c) ** 2
    xi1bar = props["xi1bar"]
    if options.uplift_x_factor == "exponential":
        factor = math.exp(xi1bar * math.pi)
    elif options.uplift_x_factor == "phase":
        factor = math.exp(2.0 * xi1bar * (math.pi / 2 - math.asin(min(1.0, 1.0 / math.sqrt(x0)))))
    else:
        factor = 1.0
    x_value = x0 * factor
    v1, phi = uplift_base_shear(v_c, h1 / b, x_value, zeta, options.uplift_formula)
    return {"r": r, "zeta": zeta, "X0": x0, "X_factor": factor, "X": x_value, "phi": phi, "V1_uplift": v1}


def capacity_intermediates(system: System) -> dict[str, float]:
    """With a bearing capacity (docs/theory.md section 14.6): the elastic tipping moment M_tip =
    m_t g b [N m] (M_c is the capacity's), each element's capacity Q_y [N] and FS_v [-]; else {}."""
    foundation = system.foundation
    if getattr(foundation, "capacity", None) is None:
        return {}
    capacity = foundation.contact_elements(system.half_width).capacity
    return {"M_tip": system.tipping_moment, "Q_y": float(capacity[0]),
            "FS_v": foundation.total_capacity(system.half_width) / system.weight}


def modal_static_response(system: System, modal_base_shears: np.ndarray, n_modes: int) -> dict[str, np.ndarray]:
    """Per-mode peaks (modes x floors) from modal base shears: equivalent lateral forces [32],
    story shears and overturning moments by statics (engines/statics.py), floor displacements
    [33], drifts [34], drift ratios and absolute floor accelerations f_jn / m_j."""
    building, modes = system.building, system.modes
    phi = modes.shapes[:, :n_modes]
    shares = building.masses[:, None] * phi / modes.participation_h[:n_modes]  # m_j phi_jn / L_n
    forces = (modal_base_shears[None, :] * shares).T  # (modes, floors) [N]
    displacement = forces / (modes.omega[:n_modes, None] ** 2 * building.masses[None, :])  # [33]
    maps = story_maps(building)
    drift = displacement @ maps.drift.T  # [34]
    return {"forces": forces, "displacement": displacement, "drift": drift,
            "drift_ratio": drift / building.story_heights, "shear": forces @ maps.shear.T,
            "moment": forces @ maps.moment.T, "floor_acceleration": forces / building.masses[None, :]}


def analyze(system: System, spectrum, support: str, options: SimplifiedOptions = SimplifiedOptions()) -> AnalysisResult:
    """Peak response by the simplified procedure (options.procedure: "improved", engines/improved.py,
    or "paper") for support "rigid", "bonded" or "uplift", with the warnings of
    engines/plausibility.py in result.details["warnings"]."""
    from . import improved, plausibility

    check_support(support)
    if support == "uplift" and options.procedure == "improved":
        result = improved.analyze_uplift(system, spectrum, options)
    else:
        result = paper_analyze(system, spectrum, support, options)
    found = plausibility.warnings(system, spectrum, support, options, result)
    return replace(result, details={**result.details, "warnings": [*result.details["warnings"], *found]})


def paper_analyze(system: System, spectrum, support: str, options: SimplifiedOptions = SimplifiedOptions()
                  ) -> AnalysisResult:
    """Peak response by the paper's procedure [21-35] (docs/theory.md), no plausibility checks."""
    check_support(support)
    modes = system.modes
    n = int(options.n_modes or modes.n_modes)
    periods = modes.periods[:n]
    xi = modes.damping[:n]
    sa = np.array([spectral_acceleration(spectrum, t, d) for t, d in zip(periods, xi, strict=True)])
    base_shears = modes.effective_mass[:n] * sa  # [31]
    m_t = system.total_mass
    inter: dict = {"T_n": periods.tolist(), "Sa_n": sa.tolist(),
                   "m_n*/m_t": (modes.effective_mass[:n] / m_t).tolist(),
                   "h_n*": modes.effective_height[:n].tolist(),
                   "V_c": system.critical_base_shear, "M_c": system.critical_base_moment}
    inter.update(capacity_intermediates(system))
    warnings: list[str] = []
    omega_corr, damping_corr = modes.omega[:n].copy(), xi.copy()
    uplift = False
    if support != "rigid":
        props = effective_properties(system, options.effective_properties)
        if not props.pop("frequency_converged"):
            warnings.append(frequency_warning(props))
        sa1bar = spectral_acceleration(spectrum, props["T1bar"], props["xi1bar"])
        v1_bonded = float(modes.effective_mass[0]) * sa1bar  # [26]
        inter.update(props)
        inter["xi1bar/xi1"] = props["xi1bar"] / props["xi1"]
        inter.update({"Sa1bar": sa1bar, "V1_bonded": v1_bonded,
                      "V1_bonded/V_c": v1_bonded / system.critical_base_shear})
        base_shears[0] = v1_bonded
        omega_corr[0], damping_corr[0] = 2 * math.pi / props["T1bar"], props["xi1bar"]
        ratio = system.foundation.contact_loss_moment_ratio
        if support == "uplift" and v1_bonded > system.critical_base_shear:
            uplift = True
            values = _uplift(system, props, v1_bonded, sa1bar, options)
            inter.update(values)
            base_shears[0] = values["V1_uplift"]
        tipping_shear = system.tipping_moment / system.effective_height  # V_c without a capacity
        tipping, over = ("V_c", "V_1/V_c") if "M_tip" not in inter else ("W b/h_1*", "V_1/(W b/h_1*)")
        if support == "uplift" and ratio < 1.0 and v1_bonded > ratio * tipping_shear:
            warnings.append(
                f"{system.foundation.kind} foundation: contact is lost at the kern (M = {ratio:.3g} W b, "
                f"V = {ratio:.3g} {tipping}) before tipping at {tipping}; for {over} = {v1_bonded / tipping_shear:.3g} "
                "the mat is partly uplifted, which the simplified procedure does not model")
    inter["V_n"] = base_shears.tolist()
    per_mode = modal_static_response(system, base_shears, n)
    def combine(peaks):
        return cqc(peaks, omega_corr, damping_corr) if options.combination == "cqc" else srss(peaks)

    peaks = {name: combine(values) for name, values in per_mode.items() if name != "forces"}
    if n >= 2:
        two = base_shears[:2]
        inter["V_1+2"] = float(srss(two) if options.combination == "srss"
                               else cqc(two, omega_corr[:2], damping_corr[:2]))
    elements = None if support == "rigid" else system.foundation.contact_elements(system.half_width)
    # quasi-static reactions under W and the peak M_b either way (no vertical inertia: impacts
    # are the history engines'); the uplifting mat's elements cannot pull
    peaks["reaction"] = np.zeros(0) if elements is None else largest_compression(
        elements.positions, elements.stiffness, system.weight, float(peaks["moment"][0]), support == "bonded",
        elements.capacity if support == "uplift" else None)
    return AnalysisResult.of(system, "simplified", support, peaks, uplift=uplift, periods=periods,
                             elements=elements, intermediates=inter,
                             details={"options": asdict(options), "warnings": warnings,
                                      "modal_forces": per_mode["forces"].tolist()})


def iter_batch(systems: list[System], spectrum, support: str, options: SimplifiedOptions = SimplifiedOptions()
               ) -> Iterator[tuple[int, AnalysisResult | AnalysisError | InputError]]:
    """analyze for each system (engines/registry.py: the engines' common interface)."""
    for k, system in enumerate(systems):
        try:
            yield k, analyze(system, spectrum, support, options)
        except (AnalysisError, InputError) as error:
            yield k, error
