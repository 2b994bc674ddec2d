"""The paper's worked example (docs/theory.md section 6) built directly, not through a deck."""

from __future__ import annotations

from upliftcli.model.building import modal_analysis, uniform_building
from upliftcli.model.foundations import two_element_from_ratios
from upliftcli.model.system import System


def paper_system(period: float = 0.5, slenderness: float = 10.0, frequency_ratio: float = 8.0,
                 damping_ratio: float = 0.4, mat_mass: float = 0.0, stories: int = 10) -> System:
    """Uniform shear building (350 t floors, 3.5 m stories, 5 % damping) with fundamental period
    T_1 [s], h_1*/b = slenderness, two-element foundation with w_v/w_1 and xi_v, mat mass [kg]."""
    building = uniform_building(stories, 350e3, 3.5, period=period, damping=0.05)
    modes = modal_analysis(building)
    total = building.masses.sum() + mat_mass
    foundation = two_element_from_ratios(total, modes.omega[0], frequency_ratio, damping_ratio)
    return System(building, foundation, modes.effective_height[0] / slenderness, mat_mass)
