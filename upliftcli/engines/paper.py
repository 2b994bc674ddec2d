"""The paper's simplified procedure: response spectrum analysis with interaction and uplift in mode 1.

docs/theory.md section 7 (paper Eqs. 21-35). Pure functions of a System and a spectrum
object with .sa(periods [s], damping [-]) -> S_a [m/s^2]:

- rigid: standard modal response spectrum analysis on a fixed base [31-35];
- bonded: mode 1 with the effective period and damping of the flexibly supported
  system T1bar, xi1bar [21-25]; higher modes fixed-base;
- uplift: as bonded, and if V_1 = m_1* S_a(T1bar, xi1bar) exceeds V_c [16a] the
  uplift base shear [26-29]; higher modes fixed-base.

Every intermediate an engineer checks by hand is returned in result.intermediates
(names and units: engines/quantities.INTERMEDIATES). The improved procedure
(engines/improved.py) and the plausibility warnings (engines/plausibility.py) build on this
module; engines/simplified.py, the engine, chooses between the procedures.
"""

from __future__ import annotations

import math
from dataclasses import asdict

import numpy as np

from ..errors import AnalysisError
from ..model.foundations import ContactElements
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
    inter = _fixed_base_intermediates(system, periods, sa, n)
    warnings: list[str] = []
    omega_corr, damping_corr = modes.omega[:n].copy(), xi.copy()
    uplift = False
    if support != "rigid":
        uplift = _flexible_mode1(system, spectrum, support, options, inter, warnings)
        base_shears[0] = inter["V1_uplift"] if uplift else inter["V1_bonded"]
        omega_corr[0], damping_corr[0] = 2 * math.pi / inter["T1bar"], inter["xi1bar"]
    inter["V_n"] = base_shears.tolist()
    per_mode = modal_static_response(system, base_shears, n)
    peaks = {name: _combine(values, options.combination, omega_corr, damping_corr)
             for name, values in per_mode.items() if name != "forces"}
    if n >= 2:
        inter["V_1+2"] = float(_combine(base_shears[:2], options.combination, omega_corr[:2], damping_corr[:2]))
    elements = None if support == "rigid" else system.foundation.contact_elements(system.half_width)
    peaks["reaction"] = _reactions(system, support, elements, float(peaks["moment"][0]))
    return AnalysisResult.of(system, "simplified", support, peaks, uplift=uplift, periods=periods,
                             elements=elements, intermediates=inter,
                             details={"options": asdict(options), "warnings": warnings,
                                      "modal_forces": per_mode["forces"].tolist()})


def _fixed_base_intermediates(system: System, periods: np.ndarray, sa: np.ndarray, n: int) -> dict:
    """The intermediates of every support: T_n, S_a,n, m_n*/m_t, h_n*, V_c, M_c (and the capacity's)."""
    modes = system.modes
    inter: dict = {"T_n": periods.tolist(), "Sa_n": sa.tolist(),
                   "m_n*/m_t": (modes.effective_mass[:n] / system.total_mass).tolist(),
                   "h_n*": modes.effective_height[:n].tolist(),
                   "V_c": system.critical_base_shear, "M_c": system.critical_base_moment}
    inter.update(capacity_intermediates(system))
    return inter


def _flexible_mode1(system: System, spectrum, support: str, options: SimplifiedOptions, inter: dict,
                    warnings: list[str]) -> bool:
    """Mode 1 on a flexible support into inter: T1bar, xi1bar [21-25], the bonded V_1 [26] and, where
    uplift is permitted and V_1 > V_c, V_1 with uplift [27-29] (warnings: the effective frequency's,
    the kern's); whether the mat lifts."""
    props = effective_properties(system, options.effective_properties)
    if not props.pop("frequency_converged"):
        warnings.append(frequency_warning(props))
    sa1bar = spectral_acceleration(spectrum, props["T1bar"], props["xi1bar"])
    v1_bonded = float(system.modes.effective_mass[0]) * sa1bar  # [26]
    inter.update(props)
    inter["xi1bar/xi1"] = props["xi1bar"] / props["xi1"]
    inter.update({"Sa1bar": sa1bar, "V1_bonded": v1_bonded, "V1_bonded/V_c": v1_bonded / system.critical_base_shear})
    if support != "uplift":
        return False
    uplift = bool(v1_bonded > system.critical_base_shear)
    if uplift:
        inter.update(_uplift(system, props, v1_bonded, sa1bar, options))
    if (message := _kern_warning(system, inter, v1_bonded)) is not None:
        warnings.append(message)
    return uplift


def _kern_warning(system: System, inter: dict, v1_bonded: float) -> str | None:
    """The warning that the mat is partly uplifted (contact lost at the kern before tipping, which
    the simplified procedure does not model) at the bonded V_1 [N]; None if it is not."""
    ratio = system.foundation.contact_loss_moment_ratio
    tipping_shear = system.tipping_moment / system.effective_height  # V_c without a capacity
    if not (ratio < 1.0 and v1_bonded > ratio * tipping_shear):
        return None
    tipping, over = ("V_c", "V_1/V_c") if "M_tip" not in inter else ("W b/h_1*", "V_1/(W b/h_1*)")
    return (f"{system.foundation.kind} foundation: contact is lost at the kern (M = {ratio:.3g} W b, "
            f"V = {ratio:.3g} {tipping}) before tipping at {tipping}; for {over} = {v1_bonded / tipping_shear:.3g} "
            "the mat is partly uplifted, which the simplified procedure does not model")


def _combine(modal_peaks: np.ndarray, combination: str, omega: np.ndarray, damping: np.ndarray) -> np.ndarray:
    """Modal peaks combined by the deck's rule: CQC with omega [rad/s] and damping [-], or SRSS [35]."""
    return cqc(modal_peaks, omega, damping) if combination == "cqc" else srss(modal_peaks)


def _reactions(system: System, support: str, elements: ContactElements | None, moment: float) -> np.ndarray:
    """Quasi-static reactions [N] under W and the peak M_b [N m] either way (no vertical inertia: impacts
    are the history engines'); the uplifting mat's elements cannot pull; none on a rigid base."""
    if elements is None:
        return np.zeros(0)
    return largest_compression(elements.positions, elements.stiffness, system.weight, moment, support == "bonded",
                               elements.capacity if support == "uplift" else None)
