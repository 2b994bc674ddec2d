"""Foundation idealisations under the rigid mat (THEORY.md section 1) and their contact elements.

Each foundation gives
- its rocking stiffness K_theta [N m/rad] and damping C_theta [N m s/rad] for the
  simplified engine (paper Eqs. 22, 25 and their Winkler/half-space counterparts);
- its vertical stiffness [N/m] and damping [N s/m];
- the unilateral spring-damper elements (positions x_i [m], k_i [N/m], c_i [N s/m])
  that the exact engine integrates (THEORY.md sections 2 and 4).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np


@dataclass(frozen=True)
class ContactElements:
    """Unilateral spring-dampers under the mat: positions [m], stiffnesses [N/m], dampings [N s/m]."""

    positions: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray

    @property
    def count(self) -> int:
        return int(self.positions.size)


@dataclass(frozen=True)
class TwoElement:
    """Two spring-dampers at the mat edges x = -b and x = +b (the paper's model).

    stiffness: k_f of each element [N/m]; damping: c_f of each element [N s/m].
    """

    stiffness: float
    damping: float
    kind: ClassVar[str] = "two-element"
    #: fraction of W b at which contact is first lost under a static overturning moment
    contact_loss_moment_ratio: ClassVar[float] = 1.0

    def rocking_stiffness(self, b: float, omega: float | None = None) -> float:
        """K_theta = 2 k_f b^2 [N m/rad] [22]."""
        return 2.0 * self.stiffness * b**2

    def rocking_damping(self, b: float, omega: float | None = None) -> float:
        """C_theta = 2 c_f b^2 [N m s/rad] [25]."""
        return 2.0 * self.damping * b**2

    def vertical_stiffness(self, b: float, omega: float | None = None) -> float:
        """2 k_f [N/m]."""
        return 2.0 * self.stiffness

    def vertical_damping(self, b: float, omega: float | None = None) -> float:
        """2 c_f [N s/m]."""
        return 2.0 * self.damping

    def contact_elements(self, b: float, omega: float | None = None) -> ContactElements:
        return ContactElements(
            np.array([-b, b]), np.full(2, float(self.stiffness)), np.full(2, float(self.damping))
        )


@dataclass(frozen=True)
class Winkler:
    """Spring-dampers distributed over the mat width, per unit length along the width.

    stiffness: k_w [N/m per m of width = N/m^2]; damping: c_w [N s/m^2];
    elements: number n of discrete elements the exact engine uses (midpoint rule,
    k_i = k_w dx, c_i = c_w dx, dx = 2b/n).
    """

    stiffness: float
    damping: float
    elements: int = 20
    kind: ClassVar[str] = "winkler"
    #: contact loss starts at the kern, M = W b / 3 (THEORY.md section 7, item 6)
    contact_loss_moment_ratio: ClassVar[float] = 1.0 / 3.0

    def rocking_stiffness(self, b: float, omega: float | None = None) -> float:
        """K_theta = (2/3) k_w b^3 [N m/rad]."""
        return 2.0 / 3.0 * self.stiffness * b**3

    def rocking_damping(self, b: float, omega: float | None = None) -> float:
        """C_theta = (2/3) c_w b^3 [N m s/rad]."""
        return 2.0 / 3.0 * self.damping * b**3

    def vertical_stiffness(self, b: float, omega: float | None = None) -> float:
        """2 k_w b [N/m]."""
        return 2.0 * self.stiffness * b

    def vertical_damping(self, b: float, omega: float | None = None) -> float:
        """2 c_w b [N s/m]."""
        return 2.0 * self.damping * b

    def contact_elements(self, b: float, omega: float | None = None) -> ContactElements:
        n = int(self.elements)
        dx = 2.0 * b / n
        positions = -b + dx * (np.arange(n) + 0.5)
        return ContactElements(positions, np.full(n, self.stiffness * dx), np.full(n, self.damping * dx))


def two_element_from_ratios(
    total_mass: float, omega_1: float, frequency_ratio: float, damping_ratio: float
) -> TwoElement:
    """The paper's nondimensional foundation: w_v/w_1 and xi_v (THEORY.md section 6).

    w_v = sqrt(2 k_f / m_t) and xi_v = c_f / (m_t w_v), so k_f = m_t w_v^2 / 2 [N/m]
    and c_f = xi_v m_t w_v [N s/m].
    """
    omega_v = frequency_ratio * omega_1
    return TwoElement(0.5 * total_mass * omega_v**2, damping_ratio * total_mass * omega_v)
