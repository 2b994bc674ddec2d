"""Foundation idealisations under the rigid mat (docs/theory.md section 1) and their contact elements.

Each foundation gives
- its rocking stiffness K_theta [N m/rad] and damping C_theta [N m s/rad] for the
  simplified engine (paper Eqs. 22, 25 and their Winkler/half-space counterparts);
- its vertical stiffness [N/m] and damping [N s/m];
- the unilateral spring-damper elements (positions x_i [m], k_i [N/m], c_i [N s/m])
  that the exact engine integrates (docs/theory.md sections 2 and 4);
- two elements and Winkler: an optional bearing capacity, each element's spring then
  elastic-perfectly-plastic in compression with capacity Q_y [N] (docs/theory.md section 14),
  and the moment capacity M_c of the static backbone (model/rocking_capacity.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..deck.fields import Field
from . import rocking_capacity
from .bearing import CAPACITY_FIELDS, bearing_capacity, check_static_capacity
from .deck_context import DeckContext


@dataclass(frozen=True)
class ContactElements:
    """Unilateral spring-dampers under the mat: positions [m], stiffnesses [N/m], dampings [N s/m];
    capacity: the bearing capacity Q_y [N] of each element's spring (docs/theory.md section 14),
    None for elastic elements (no capacity given)."""

    positions: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    capacity: np.ndarray | None = None

    @property
    def count(self) -> int:
        return int(self.positions.size)


@dataclass(frozen=True)
class TwoElement:
    """Two spring-dampers at the mat edges x = -b and x = +b (the paper's model).

    stiffness: k_f of each element [N/m]; damping: c_f of each element [N s/m]; capacity:
    bearing capacity Q_y of each element [N] (None: elastic; docs/theory.md section 14).
    """

    stiffness: float
    damping: float
    capacity: float | None = None
    kind: ClassVar[str] = "two-element"
    #: fraction of W b at which contact is first lost under a static overturning moment
    contact_loss_moment_ratio: ClassVar[float] = 1.0
    #: its fields in the deck's [foundation] table, and the groups of them that replace each other
    deck_fields: ClassVar[dict[str, Field]] = {
        "k_f": Field("number", "N/m", "two-element: stiffness of each edge element", "positive",
                     plausible=(1e5, 1e13)),
        "c_f": Field("number", "N s/m", "two-element: damping of each edge element", "nonnegative", 0.0),
        "frequency_ratio": Field("number", "-", "two-element: w_v/w_1 with w_v = sqrt(2 k_f / m_t) "
                                 "(instead of k_f)", "positive", plausible=(0.5, 100.0)),
        "damping_ratio": Field("number", "-", "two-element: xi_v = c_f / (m_t w_v) (instead of c_f)",
                               "nonnegative"),
        "element_capacity": Field("number", "N", "two-element: bearing capacity Q_y of each edge element "
                                  "(instead of bearing_pressure or safety_factor)", "positive"),
        **CAPACITY_FIELDS,
    }
    deck_alternatives: ClassVar[list[list[set[str]]]] = [
        [{"k_f"}, {"frequency_ratio"}], [{"c_f"}, {"damping_ratio"}],
        [{"element_capacity"}, {"bearing_pressure"}, {"safety_factor"}]]

    @classmethod
    def from_deck(cls, fields: dict[str, Any], context: DeckContext) -> TwoElement:
        """k_f [N/m] or w_v/w_1, c_f [N s/m] or xi_v (THEORY notes: w_v = sqrt(2 k_f / m_t))."""
        if "k_f" in fields:
            k_f = fields["k_f"]
        elif "frequency_ratio" in fields:
            k_f = two_element_from_ratios(context.total_mass, context.omega_1, fields["frequency_ratio"], 0.0).stiffness
        else:
            context.missing("k_f", "the element stiffness k_f > 0 [N/m] (missing; or give "
                            "foundation.frequency_ratio = w_v/w_1)")
        omega_v = float(np.sqrt(2.0 * k_f / context.total_mass))
        c_f = fields["c_f"] if "c_f" in fields else fields.get("damping_ratio", 0.0) * context.total_mass * omega_v
        # each edge element stands for half the mat: a strip of width b
        capacity = bearing_capacity(fields, context, "element_capacity", context.half_width)
        if capacity is not None:
            check_static_capacity(2.0 * capacity, context, fields, "element_capacity")
        return cls(float(k_f), float(c_f), capacity)

    def moment_capacity(self, b: float, weight: float) -> float:
        """M_c [N m]: W b without a capacity [16b], else W b min(1, FS_v - 1) (docs/theory.md 14.4)."""
        if self.capacity is None:
            return weight * b
        return rocking_capacity.two_element_moment_capacity(b, self.capacity, weight)

    def total_capacity(self, b: float) -> float | None:
        """Sum of the elements' capacities [N] (None: elastic)."""
        return None if self.capacity is None else 2.0 * self.capacity

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
        capacity = None if self.capacity is None else np.full(2, float(self.capacity))
        return ContactElements(
            np.array([-b, b]), np.full(2, float(self.stiffness)), np.full(2, float(self.damping)), capacity
        )


@dataclass(frozen=True)
class Winkler:
    """Spring-dampers distributed over the mat width, per unit length along the width.

    stiffness: k_w [N/m per m of width = N/m^2]; damping: c_w [N s/m^2];
    elements: number n of discrete elements the exact engine uses (midpoint rule,
    k_i = k_w dx, c_i = c_w dx, dx = 2b/n); capacity: bearing capacity q_w per unit length
    along the width [N/m] = q_c L (None: elastic), each element Q_y = q_w dx
    (docs/theory.md section 14).
    """

    stiffness: float
    damping: float
    elements: int = 20
    capacity: float | None = None
    kind: ClassVar[str] = "winkler"
    #: contact loss starts at the kern, M = W b / 3 (docs/theory.md section 7, item 6)
    contact_loss_moment_ratio: ClassVar[float] = 1.0 / 3.0
    deck_fields: ClassVar[dict[str, Field]] = {
        "k_w": Field("number", "N/m^2", "winkler: stiffness per unit length along the width", "positive",
                     plausible=(1e5, 1e13)),
        "c_w": Field("number", "N s/m^2", "winkler: damping per unit length along the width",
                     "nonnegative", 0.0),
        "elements": Field("integer", "-", "winkler: number of discrete elements for the exact engine "
                          "(limits.MAX_CONTACT_ELEMENTS: one bit each of its contact pattern)", "contact-elements", 20),
        "line_capacity": Field("number", "N/m", "winkler: bearing capacity per unit length along the width, q_c L "
                               "(instead of bearing_pressure or safety_factor)", "positive",
                               quantity="force per length"),
        **CAPACITY_FIELDS,
    }
    deck_alternatives: ClassVar[list[list[set[str]]]] = [[{"line_capacity"}, {"bearing_pressure"},
                                                          {"safety_factor"}]]

    @classmethod
    def from_deck(cls, fields: dict[str, Any], context: DeckContext) -> Winkler:
        """k_w [N/m^2], c_w [N s/m^2], elements."""
        if "k_w" not in fields:
            context.missing("k_w", "the Winkler stiffness k_w > 0 [N/m^2] (missing)")
        capacity = bearing_capacity(fields, context, "line_capacity", 1.0)
        if capacity is not None:
            check_static_capacity(2.0 * context.half_width * capacity, context, fields, "line_capacity")
        return cls(fields["k_w"], fields.get("c_w", cls.deck_fields["c_w"].default),
                   fields.get("elements", cls.deck_fields["elements"].default), capacity)

    def moment_capacity(self, b: float, weight: float) -> float:
        """M_c [N m]: W b without a capacity, else the strip's W b (1 - W/(2 b q_w)) =
        (P B/2)(1 - q/q_c) (docs/theory.md 14.4; the n elements tend to it as n grows)."""
        if self.capacity is None:
            return weight * b
        return rocking_capacity.winkler_moment_capacity(b, self.capacity, weight)

    def total_capacity(self, b: float) -> float | None:
        """2 b q_w [N] (None: elastic)."""
        return None if self.capacity is None else 2.0 * b * self.capacity

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
        capacity = None if self.capacity is None else np.full(n, self.capacity * dx)
        return ContactElements(positions, np.full(n, self.stiffness * dx), np.full(n, self.damping * dx), capacity)


def two_element_from_ratios(
    total_mass: float, omega_1: float, frequency_ratio: float, damping_ratio: float
) -> TwoElement:
    """The paper's nondimensional foundation: w_v/w_1 and xi_v (docs/theory.md section 6).

    w_v = sqrt(2 k_f / m_t) and xi_v = c_f / (m_t w_v), so k_f = m_t w_v^2 / 2 [N/m]
    and c_f = xi_v m_t w_v [N s/m].
    """
    omega_v = frequency_ratio * omega_1
    return TwoElement(0.5 * total_mass * omega_v**2, damping_ratio * total_mass * omega_v)


@dataclass(frozen=True)
class HalfSpace:
    """Rigid rectangular surface mat on a viscoelastic (elastic, radiating) half-space.

    shear_modulus: G [Pa]; poisson_ratio: nu [-] (0 <= nu < 0.5); density: rho [kg/m^3];
    half_length: half-dimension of the mat normal to the plane of motion [m] (the in-plane
    half-width b is the system's); impedance_frequency: "flexible-base" (default: every engine
    evaluates K_theta, C_theta at the flexible-base fundamental frequency, model/interaction.py)
    or "fixed-base" (at the fixed-base w_1). Rocking stiffness K_theta(omega) and dashpot C_theta(omega)
    follow Pais & Kausel (1988) as tabulated in NIST GCR 12-917-21 (2012), "Soil-Structure
    Interaction for Building Structures": Table 2-2a (static surface stiffness) and Table 2-3a
    (dynamic modifiers alpha and radiation damping beta, a_0 = omega B / V_s); the dashpot is
    C = 2 beta K(omega) / omega (NIST GCR 12-917-21 Eq. 2-9). With omega = None the static
    stiffness and zero radiation damping are returned (rocking radiation damping vanishes as
    a_0 -> 0). The exact engine represents the half-space by two equivalent edge elements
    k = K_theta / (2 b^2), c = C_theta / (2 b^2) (docs/theory.md section 1, item 3).
    """

    shear_modulus: float
    poisson_ratio: float
    density: float
    half_length: float
    impedance_frequency: str = "flexible-base"
    kind: ClassVar[str] = "halfspace"
    #: represented by two edge elements: contact is lost at M = W b, as for two elements
    contact_loss_moment_ratio: ClassVar[float] = 1.0
    deck_fields: ClassVar[dict[str, Field]] = {
        "shear_modulus": Field("number", "Pa", "halfspace: shear modulus G", "positive", plausible=(1e6, 1e11)),
        "shear_wave_velocity": Field("number", "m/s", "halfspace: V_s (instead of G; G = rho V_s^2)",
                                     "positive", plausible=(50.0, 3500.0)),
        "poisson_ratio": Field("number", "-", "halfspace: Poisson's ratio nu", "poisson", 1.0 / 3.0),
        "density": Field("number", "kg/m^3", "halfspace: mass density rho", "positive", plausible=(1000.0, 3000.0)),
        "half_length": Field("number", "m", "halfspace: half-dimension of the mat normal to the plane of "
                             "motion (default: b, a square mat)", "positive", plausible=(0.5, 300.0)),
        "impedance_frequency": Field("string", "-", "halfspace: frequency at which every engine evaluates "
                                     "K_theta, C_theta: the flexible-base w1bar (fixed point) or the fixed-base "
                                     "w_1", "", "flexible-base", ("flexible-base", "fixed-base")),
    }
    deck_alternatives: ClassVar[list[list[set[str]]]] = [[{"shear_modulus"}, {"shear_wave_velocity"}]]

    @classmethod
    def from_deck(cls, fields: dict[str, Any], context: DeckContext) -> HalfSpace:
        """G [Pa] or V_s [m/s], nu, rho [kg/m^3], the half-length [m] (default b)."""
        if "density" not in fields:
            context.missing("density", "the soil density rho > 0 [kg/m^3] (missing)")
        rho = fields["density"]
        if "shear_modulus" in fields:
            modulus = fields["shear_modulus"]
        elif "shear_wave_velocity" in fields:
            modulus = rho * fields["shear_wave_velocity"] ** 2
        else:
            context.missing("shear_modulus", "the soil shear modulus G > 0 [Pa] (missing; or give "
                            "foundation.shear_wave_velocity [m/s])")
        return cls(modulus, fields.get("poisson_ratio", cls.deck_fields["poisson_ratio"].default), rho,
                   fields.get("half_length", context.half_width),
                   fields.get("impedance_frequency", cls.deck_fields["impedance_frequency"].default))

    @property
    def shear_wave_velocity(self) -> float:
        """V_s = sqrt(G / rho) [m/s]."""
        return float(np.sqrt(self.shear_modulus / self.density))

    @property
    def _psi(self) -> float:
        """psi = sqrt(2 (1 - nu) / (1 - 2 nu)) <= 2.5 (NIST GCR 12-917-21 Table 2-3a)."""
        nu = self.poisson_ratio
        return float(min(np.sqrt(2.0 * (1.0 - nu) / (1.0 - 2.0 * nu)), 2.5))

    def _dimensions(self, b: float) -> tuple[float, float, bool]:
        """(B, L, across): B <= L the half-dimensions; across=True when the mat rocks across
        its short side (rotation about the long axis, NIST's xx), False for NIST's yy."""
        if b <= self.half_length:
            return float(b), float(self.half_length), True
        return float(self.half_length), float(b), False

    def _a0(self, b: float, omega: float | None) -> float:
        small, _, _ = self._dimensions(b)
        return 0.0 if not omega else float(omega) * small / self.shear_wave_velocity

    def static_rocking_stiffness(self, b: float) -> float:
        """K_theta,sur [N m/rad], NIST GCR 12-917-21 Table 2-2a (Pais & Kausel 1988):
        across: G B^3/(1-nu) (3.2 L/B + 0.8); along: G B^3/(1-nu) (3.73 (L/B)^2.4 + 0.27)."""
        small, large, across = self._dimensions(b)
        ratio = large / small
        shape = 3.2 * ratio + 0.8 if across else 3.73 * ratio**2.4 + 0.27
        return self.shear_modulus * small**3 / (1.0 - self.poisson_ratio) * shape

    def _rocking_modifiers(self, b: float, omega: float | None) -> tuple[float, float]:
        """(alpha, beta) of rocking, NIST GCR 12-917-21 Table 2-3a."""
        a0 = self._a0(b, omega)
        if a0 == 0.0:
            return 1.0, 0.0
        small, large, across = self._dimensions(b)
        ratio = large / small
        static = self.static_rocking_stiffness(b) / (self.shear_modulus * small**3)
        if across:
            alpha = 1.0 - (0.55 + 0.01 * np.sqrt(ratio - 1.0)) * a0**2 / (2.4 - 0.4 / ratio**3 + a0**2)
            beta = 4.0 * self._psi / 3.0 * ratio * a0**2 / (static * (2.2 - 0.4 / ratio**3 + a0**2))
        else:
            alpha = 1.0 - 0.55 * a0**2 / (0.6 + 1.4 / ratio**3 + a0**2)
            beta = 4.0 * self._psi / 3.0 * ratio**3 * a0**2 / (static * (1.8 / (1.0 + 1.75 * (ratio - 1.0)) + a0**2))
        return float(alpha), float(beta * a0 / (2.0 * alpha))

    def rocking_stiffness(self, b: float, omega: float | None = None) -> float:
        """K_theta(omega) = alpha K_theta,sur [N m/rad] (Table 2-3a)."""
        alpha, _ = self._rocking_modifiers(b, omega)
        return alpha * self.static_rocking_stiffness(b)

    def rocking_damping(self, b: float, omega: float | None = None) -> float:
        """C_theta(omega) = 2 beta K_theta(omega) / omega [N m s/rad] (Eq. 2-9); 0 when omega is None."""
        if not omega:
            return 0.0
        alpha, beta = self._rocking_modifiers(b, omega)
        return 2.0 * beta * alpha * self.static_rocking_stiffness(b) / float(omega)

    def _vertical_modifiers(self, b: float, omega: float | None) -> tuple[float, float]:
        a0 = self._a0(b, omega)
        if a0 == 0.0:
            return 1.0, 0.0
        small, large, _ = self._dimensions(b)
        ratio = large / small
        alpha = 1.0 - (0.4 + 0.2 / ratio) * a0**2 / (10.0 / (1.0 + 3.0 * (ratio - 1.0)) + a0**2)
        static = self.static_vertical_stiffness(b) / (self.shear_modulus * small)
        beta = 4.0 * self._psi * ratio / static * a0 / (2.0 * alpha)
        return float(alpha), float(beta)

    def static_vertical_stiffness(self, b: float) -> float:
        """K_z,sur = G B/(1-nu) (3.1 (L/B)^0.75 + 1.6) [N/m] (Table 2-2a)."""
        small, large, _ = self._dimensions(b)
        return self.shear_modulus * small / (1.0 - self.poisson_ratio) * (3.1 * (large / small) ** 0.75 + 1.6)

    def vertical_stiffness(self, b: float, omega: float | None = None) -> float:
        """K_z(omega) = alpha_z K_z,sur [N/m] (Table 2-3a)."""
        alpha, _ = self._vertical_modifiers(b, omega)
        return alpha * self.static_vertical_stiffness(b)

    def vertical_damping(self, b: float, omega: float | None = None) -> float:
        """C_z = 2 beta_z K_z(omega) / omega [N s/m]; 0 when omega is None."""
        if not omega:
            return 0.0
        alpha, beta = self._vertical_modifiers(b, omega)
        return 2.0 * beta * alpha * self.static_vertical_stiffness(b) / float(omega)

    def contact_elements(self, b: float, omega: float | None = None) -> ContactElements:
        """Two edge elements with the half-space's rocking stiffness and damping:
        k = K_theta / (2 b^2) [N/m], c = C_theta / (2 b^2) [N s/m]."""
        k = self.rocking_stiffness(b, omega) / (2.0 * b**2)
        c = self.rocking_damping(b, omega) / (2.0 * b**2)
        return ContactElements(np.array([-b, b]), np.full(2, k), np.full(2, c))


#: the foundation types by their deck name (foundation.type)
FOUNDATIONS: dict[str, type[TwoElement] | type[Winkler] | type[HalfSpace]] = {
    cls.kind: cls for cls in (TwoElement, Winkler, HalfSpace)
}
Foundation = TwoElement | Winkler | HalfSpace
