"""Result type shared by every engine, and the modal combination rules [35].

All quantities SI: m, N, N m, s. Story j joins floor j-1 and floor j (floor 0 is the mat).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass
class AnalysisResult:
    """Peak response of one analysis (one engine, one support condition).

    heights: floor heights above the mat [m], (N,).
    displacement: peak floor displacement relative to the mat [m], (N,).
    drift: peak story drift u_j - u_{j-1} [m], (N,).
    drift_ratio: peak drift / story height [-], (N,).
    shear: peak story shear [N], (N,) (shear[0] is the base shear).
    moment: peak overturning moment at the bottom of story j [N m], (N,).
    base_shear, base_moment: peaks at the base [N], [N m].
    critical_base_shear, critical_base_moment: V_c, M_c [N], [N m] [16a, 16b].
    weight: m_t g [N]; effective_height: h_1* [m].
    uplift: whether the mat lifts off (always False for rigid and bonded).
    periods: fixed-base periods T_n [s] of the modes used.
    intermediates: named scalar or list values an engineer checks by hand
        (T1bar, xi1bar, V_c, zeta, ... for the simplified engine).
    details: engine-specific extras (times of peaks, uplift summary, energy balance ...).
    """

    engine: str
    support: str
    heights: np.ndarray
    displacement: np.ndarray
    drift: np.ndarray
    drift_ratio: np.ndarray
    shear: np.ndarray
    moment: np.ndarray
    base_shear: float
    base_moment: float
    critical_base_shear: float
    critical_base_moment: float
    weight: float
    effective_height: float
    uplift: bool
    periods: np.ndarray
    intermediates: dict[str, Any] = field(default_factory=dict)
    details: dict[str, Any] = field(default_factory=dict)

    @property
    def base_shear_coefficient(self) -> float:
        """V_b / (m_t g) [-]."""
        return self.base_shear / self.weight

    @property
    def base_moment_coefficient(self) -> float:
        """M_b / (m_t g h_1*) [-]."""
        return self.base_moment / (self.weight * self.effective_height)

    @property
    def critical_coefficient(self) -> float:
        """b / h_1* [-], the critical value of both coefficients."""
        return self.critical_base_shear / self.weight


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
