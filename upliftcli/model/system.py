"""The whole system of docs/theory.md section 1: building, rigid mat and foundation.

Totals m_t, L_0 and the critical base shear and moment [16a, 16b] (with a bearing capacity,
those of the capacity: docs/theory.md section 14.4).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..units import STANDARD_GRAVITY
from .building import Building, Modes, modal_analysis
from .foundations import Foundation


@dataclass(frozen=True)
class System:
    """Building on a rigid mat of half-width b [m] resting on a flexible foundation.

    mat_mass: m_0 [kg]; mat_rotary_inertia: I_0 [kg m^2] about the mat centre;
    gravity: g [m/s^2].
    """

    building: Building
    foundation: Foundation
    half_width: float
    mat_mass: float = 0.0
    mat_rotary_inertia: float = 0.0
    gravity: float = STANDARD_GRAVITY

    @cached_property
    def modes(self) -> Modes:
        """All N fixed-base modes."""
        return modal_analysis(self.building)

    @property
    def total_mass(self) -> float:
        """m_t = sum m_j + m_0 [kg]."""
        return float(self.building.masses.sum() + self.mat_mass)

    @property
    def first_moment(self) -> float:
        """L_0 = sum m_j h_j [kg m]."""
        b = self.building
        return float(np.sum(b.masses * b.heights))

    @property
    def effective_height(self) -> float:
        """h_1* [m], first-mode effective height [9]."""
        return float(self.modes.effective_height[0])

    @property
    def tipping_moment(self) -> float:
        """m_t g b [N m]: the moment at which a rigid mat on elastic elements tips [16b]."""
        return self.total_mass * self.gravity * self.half_width

    @property
    def critical_base_moment(self) -> float:
        """M_c [N m]: m_t g b [16b]; with a bearing capacity, the maximum of the foundation's
        static backbone (docs/theory.md section 14.4: two elements W b min(1, FS_v - 1), Winkler
        (P B/2)(1 - q/q_c) of ASCE 41-17 section 8.4)."""
        if getattr(self.foundation, "capacity", None) is None:
            return self.tipping_moment
        return self.foundation.moment_capacity(self.half_width, self.weight)

    @property
    def critical_base_shear(self) -> float:
        """V_c = M_c / h_1* [N] [16a] (m_t g b / h_1*, or with the capacity's M_c)."""
        return self.critical_base_moment / self.effective_height

    @property
    def weight(self) -> float:
        """m_t g [N]."""
        return self.total_mass * self.gravity


#: the columns of fixed_base_mode_rows and their units
MODE_ROW_UNITS = {"mode": "-", "period": "s", "frequency_ratio": "-", "effective_mass_ratio": "-",
                     "cumulative_mass_ratio": "-", "effective_height": "m", "effective_height_over_b": "-",
                     "damping": "-"}


def fixed_base_mode_rows(system: System) -> list[dict[str, float]]:
    """One row per fixed-base mode: T_n [s], w_n/w_1, m_n*/m_t and its running sum, h_n* [m],
    h_n*/b [9, 10] and the modal damping ratio xi_n [-] (m_t includes the mat mass, so with a
    mat the m_n*/m_t add up to less than 1)."""
    modes = system.modes
    ratio = modes.effective_mass / system.total_mass
    cumulative = np.cumsum(ratio)
    return [{"mode": n + 1, "period": float(modes.periods[n]),
             "frequency_ratio": float(modes.omega[n] / modes.omega[0]),
             "effective_mass_ratio": float(ratio[n]), "cumulative_mass_ratio": float(cumulative[n]),
             "effective_height": float(modes.effective_height[n]),
             "effective_height_over_b": float(modes.effective_height[n] / system.half_width),
             "damping": float(modes.damping[n])}
            for n in range(modes.n_modes)]
