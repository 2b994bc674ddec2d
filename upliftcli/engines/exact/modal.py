"""The data of the modal equations [11a-11c] of a system on its foundation (ModalModel), from which
statespace.py builds the linear system of each contact state (docs/theory.md sections 3-5, 9).

Modes kept (resolve_modes), which of them are coupled with the mat rotation, the inertia of the
rotation coordinate I_theta (with the residual rotary inertia of truncated modes if asked for),
the contact elements and the impedance they were built with, and the shortest period the
sampling must resolve (governing_period).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ...model.building import Modes
from ...model.foundations import ContactElements
from ...model.interaction import impedance
from ...model.system import System
from .stories import StoryYield, story_yield


@dataclass(frozen=True)
class ModalModel:
    """Data of the modal equations [11a-11c] (SI units).

    omega [rad/s], damping [-], effective_mass m_n* [kg], effective_height h_n* [m]: per mode.
    coupled: which modes interact with the mat rotation (bool per mode).
    theta_inertia: I_theta [kg m^2], inertia of the rotation coordinate in the W coordinates.
    first_moment_residual: L_0 - sum_coupled m_n* h_n* [kg m], the part of the rocking
        excitation not carried by the coupled modes.
    total_mass: m_t [kg] (vertical equation). gravity: g [m/s^2].
    elements: the foundation's contact elements; None for a rigid (fixed) base.
    impedance: the foundation model the elements were built with (interaction.impedance:
        K_theta, C_theta at omega_impedance, k and c of the edge elements); None for a rigid base.
    """

    omega: np.ndarray
    damping: np.ndarray
    effective_mass: np.ndarray
    effective_height: np.ndarray
    coupled: np.ndarray
    theta_inertia: float
    first_moment_residual: float
    total_mass: float
    gravity: float
    elements: ContactElements | None
    impedance: dict[str, float] | None = None
    stories: StoryYield | None = None  # the stories that yield (docs/theory.md 15), None: elastic

    @property
    def n_modes(self) -> int:
        return int(self.omega.size)

    @property
    def flexible(self) -> bool:
        return self.elements is not None


def modal_model(system: System, support: str, n_modes: int, coupled_modes: int | None = None,
                residual_inertia: str = "neglect", approximate: bool = False) -> ModalModel:
    """ModalModel of the N + 2 equations [11] (or of the paper's approximation [17-20])."""
    modes = system.modes.truncated(n_modes)
    flexible = support != "rigid"
    coupled = np.zeros(n_modes, dtype=bool)
    if flexible:
        coupled[: (n_modes if coupled_modes is None else coupled_modes)] = True
    residual = flexible and not approximate and residual_inertia == "include"
    theta_inertia, first_moment_residual = _rotation_inertia(system, modes, residual)
    # the impedance at the flexible-base frequency, as in every engine (model/interaction.py)
    foundation = impedance(system) if flexible else None
    stories = None if approximate else story_yield(system.building, modes.shapes_star, modes.omega)
    return ModalModel(modes.omega, modes.damping, modes.effective_mass, modes.effective_height, coupled,
                      theta_inertia, first_moment_residual, system.total_mass, system.gravity,
                      _contact_elements(system, support, foundation), foundation, stories)


def _rotation_inertia(system: System, modes: Modes, residual: bool) -> tuple[float, float]:
    """(I_theta [kg m^2], L_0 - sum m_n* h_n* [kg m]) of the rotation coordinate: the mat's rotary inertia
    I_0, plus with `residual` the rotary inertia of the truncated modes and their share of the
    excitation; each 0 when below 1e-12 of the structure's (docs/theory.md section 9)."""
    mh = modes.effective_mass * modes.effective_height
    b = system.building
    structure_inertia = float(np.sum(b.masses * b.heights**2))
    theta_inertia = system.mat_rotary_inertia
    first_moment_residual = 0.0
    if residual:
        theta_inertia += max(structure_inertia - float(np.sum(mh * modes.effective_height)), 0.0)
        first_moment_residual = system.first_moment - float(np.sum(mh))
    if theta_inertia < 1e-12 * structure_inertia:
        theta_inertia = 0.0
    if abs(first_moment_residual) < 1e-12 * system.first_moment:
        first_moment_residual = 0.0
    return theta_inertia, first_moment_residual


def _contact_elements(system: System, support: str, foundation: dict[str, float] | None) -> ContactElements | None:
    """The foundation's contact elements built with the impedance `foundation` (None: a rigid base, no
    elements); the bonded support's without a capacity: the linear reference, its elements neither
    lift nor yield (theory 14)."""
    if foundation is None:
        return None
    elements = system.foundation.contact_elements(system.half_width, foundation["omega_impedance"])
    if support == "bonded" and elements.capacity is not None:
        elements = replace(elements, capacity=None)
    return elements


def governing_period(model: ModalModel) -> float:
    """Shortest period the sampling must resolve [s]: T_1, the bonded vertical period, and
    every mode with at least 1 % of the total mass."""
    periods = [2.0 * math.pi / model.omega[0]]
    heavy = model.effective_mass >= 0.01 * model.total_mass
    periods.extend((2.0 * math.pi / model.omega[heavy]).tolist())
    if model.flexible:
        periods.append(vertical_period(model))
        if model.theta_inertia > 0.0:
            rocking = float(np.sum(model.elements.stiffness * model.elements.positions**2))
            periods.append(2.0 * math.pi * math.sqrt(model.theta_inertia / rocking))
    return min(periods)


def vertical_period(model: ModalModel) -> float:
    """The bonded vertical period T_v = 2 pi sqrt(m_t / sum k_i) [s] of a flexible base: every element in
    contact, elastic."""
    return 2.0 * math.pi * math.sqrt(model.total_mass / model.elements.stiffness.sum())


def resolve_modes(system: System, n_modes: int | None) -> int:
    n = system.building.n_stories
    if n_modes is None:
        return n
    if not 1 <= int(n_modes) <= n:
        raise ValueError(f"n_modes must be an integer from 1 to {n}, got {n_modes!r}")
    return int(n_modes)
