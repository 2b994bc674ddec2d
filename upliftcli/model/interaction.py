"""Soil-structure interaction of the bonded fundamental-mode system (paper Fig. 2): the one
definition of the effective period and damping [21-25] and of the frequency at which a
frequency-dependent foundation (half-space) is evaluated, shared by every engine.

The rocking impedance K_theta(w), C_theta(w) of a half-space depends on the frequency. All
engines evaluate it at the flexible-base fundamental frequency w1bar = 2 pi / T1bar, the
fixed point of w -> 2 pi / T1bar(K_theta(w)) (docs/theory.md, simplified procedure), unless
the foundation says otherwise (HalfSpace.impedance_frequency = "fixed-base": at the
fixed-base w_1). The equivalent edge elements k = K_theta / (2 b^2), c = C_theta / (2 b^2)
reported here are the exact engine's elements for a two-element foundation and a half-space;
a Winkler strip keeps its distributed elements (foundations.Winkler.contact_elements), and
for it they are the two-element equivalent of its rocking stiffness and damping.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import AnalysisError
from .system import System

#: fixed-point iterations tried before the bracketed search, and the relative tolerance on T1bar
ITERATIONS = 200
TOLERANCE = 1e-12


def _mode1(system: System) -> tuple[float, float, float, float]:
    modes = system.modes
    return (float(modes.effective_mass[0]), float(modes.effective_height[0]), float(modes.omega[0]),
            float(modes.damping[0]))


def _rocking(system: System, omega: float | None) -> tuple[float, float]:
    b = system.half_width
    return system.foundation.rocking_stiffness(b, omega), system.foundation.rocking_damping(b, omega)


def effective_properties_formula(system: System, omega: float | None = None) -> dict[str, float]:
    """T1bar [21] and xi1bar [23, 24] for rocking stiffness/damping evaluated at omega [rad/s]."""
    m1, h1, w1, xi1 = _mode1(system)
    k_theta, c_theta = _rocking(system, omega)
    ratio = math.sqrt(1.0 + w1**2 * m1 * h1**2 / k_theta)
    xi_f = c_theta / (2.0 * m1 * w1 * h1**2) * (ratio**2 - 1.0) ** 2 / ratio**3
    return {"K_theta": k_theta, "C_theta": c_theta, "T1": 2 * math.pi / w1, "T1bar": 2 * math.pi / w1 * ratio,
            "T1bar/T1": ratio, "xi1": xi1, "xi_f": xi_f, "xi1bar": xi_f + xi1 / ratio**3}


def effective_properties_eigenvalue(system: System, omega: float | None = None) -> dict[str, float]:
    """T1bar, xi1bar from the complex eigenvalue of the bonded one-mode system (paper Fig. 2,
    massless mat, L_0 ~ m_1* h_1*, I_b ~ m_1* h_1*^2 [20]): T1bar = 2 pi/|lambda|,
    xi1bar = -Re(lambda)/|lambda|. xi_f is reported as xi1bar - xi_1 (T_1/T1bar)^3.

    The massless mat makes the mass matrix singular: a generalized eigenproblem (scipy.linalg.eig,
    imported here so that the default "formula" method never loads scipy.linalg)."""
    from scipy.linalg import eig

    m1, h1, w1, xi1 = _mode1(system)
    k_theta, c_theta = _rocking(system, omega)
    mass = m1 * np.array([[1.0, h1], [h1, h1**2]])
    damping = np.diag([2.0 * xi1 * w1 * m1, c_theta])
    stiffness = np.diag([w1**2 * m1, k_theta])
    zero, one = np.zeros((2, 2)), np.eye(2)
    lhs = np.block([[one, zero], [zero, mass]])
    rhs = np.block([[zero, one], [-stiffness, -damping]])
    values = eig(rhs, lhs, right=False)
    finite = values[np.isfinite(values) & (np.abs(values) < 1e12 * w1)]
    oscillatory = finite[finite.imag > 1e-9 * w1]
    if oscillatory.size == 0:
        raise AnalysisError("the bonded one-mode system has no oscillatory mode (overdamped)")
    value = oscillatory[np.argmin(np.abs(oscillatory))]
    omega_bar = abs(value)
    ratio = w1 / omega_bar
    xi1bar = -value.real / omega_bar
    return {"K_theta": k_theta, "C_theta": c_theta, "T1": 2 * math.pi / w1, "T1bar": 2 * math.pi / omega_bar,
            "T1bar/T1": ratio, "xi1": xi1, "xi_f": xi1bar - xi1 / ratio**3, "xi1bar": xi1bar}


METHODS = {"formula": effective_properties_formula, "eigenvalue": effective_properties_eigenvalue}


def _with_frequency(props: dict, system: System, omega: float, converged: bool) -> dict:
    b = system.half_width
    return {**props, "omega_impedance": omega, "k_element": props["K_theta"] / (2.0 * b**2),
            "c_element": props["C_theta"] / (2.0 * b**2), "frequency_converged": converged}


def effective_properties(system: System, method: str = "formula") -> dict:
    """T1bar, xi1bar and K_theta, C_theta evaluated at the flexible-base frequency
    w1bar = 2 pi/T1bar (fixed point; at w_1 if the foundation's impedance_frequency is
    "fixed-base"), with omega_impedance [rad/s], the equivalent edge element k_element [N/m],
    c_element [N s/m], and frequency_converged (False: no fixed point was found; the values are
    the last reached, and the caller warns)."""
    function = METHODS[method]
    w1 = float(system.modes.omega[0])
    if getattr(system.foundation, "impedance_frequency", "flexible-base") == "fixed-base":
        return _with_frequency(function(system, w1), system, w1, True)
    props = function(system, w1)
    omega = w1
    for _ in range(ITERATIONS):
        omega = 2 * math.pi / props["T1bar"]
        new = function(system, omega)
        if abs(new["T1bar"] - props["T1bar"]) <= TOLERANCE * props["T1bar"]:
            return _with_frequency(new, system, omega, True)
        props = new
    return _bracketed(system, function, props, omega)


def _bracketed(system: System, function, props: dict, omega: float) -> dict:
    """The fixed point by a bracketed search on g(w) = w - 2 pi/T1bar(w) over (0, w_1] when
    the plain iteration oscillates; the last iterate, not converged, if there is none."""
    from scipy.optimize import brentq  # here: the plain iteration converges for every example deck

    w1 = float(system.modes.omega[0])

    def gap(w: float) -> float:
        return w - 2 * math.pi / function(system, w)["T1bar"]

    low = w1 * 1e-3
    try:
        if gap(low) < 0.0 <= gap(w1):
            root = brentq(gap, low, w1, xtol=1e-14 * w1, rtol=4 * np.finfo(float).eps)
            new = function(system, root)
            if abs(gap(root)) <= 1e-9 * root:
                return _with_frequency(new, system, root, True)
    except (ValueError, ArithmeticError):
        pass
    return _with_frequency(props, system, omega, False)


#: the foundation model every engine reports among its intermediates (units and meanings:
#: engines/quantities.INTERMEDIATES)
IMPEDANCE_NAMES = ("K_theta", "C_theta", "omega_impedance", "k_element", "c_element")


def impedance(system: System) -> dict[str, float]:
    """The foundation model of every engine: K_theta, C_theta at omega_impedance and the
    equivalent edge elements (IMPEDANCE_NAMES), by the formula [21] fixed point."""
    props = effective_properties(system, "formula")
    return {name: float(props[name]) for name in IMPEDANCE_NAMES}


def frequency_warning(props: dict) -> str:
    """The line the engines print when the impedance frequency has no fixed point."""
    return (f"the effective-period iteration did not converge: K_theta(w) has no fixed point w = 2 pi/T1bar; "
            f"values reached: T1bar = {props['T1bar']:.4g} s, xi1bar = {props['xi1bar']:.4g}, "
            f"w = {props['omega_impedance']:.4g} rad/s, K_theta = {props['K_theta']:.4g} N m/rad; try "
            "foundation.impedance_frequency = \"fixed-base\" or check the soil properties")
