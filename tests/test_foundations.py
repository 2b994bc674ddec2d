"""Foundation idealisations: rocking stiffness and damping against closed forms and limits."""

import math

import numpy as np
import pytest

from upliftcli.model.foundations import HalfSpace, TwoElement, Winkler, two_element_from_ratios


def test_two_element_rocking_and_elements():
    f = TwoElement(stiffness=2.0e8, damping=3.0e6)
    b = 4.0
    assert f.rocking_stiffness(b) == pytest.approx(2 * 2.0e8 * b**2)
    assert f.rocking_damping(b) == pytest.approx(2 * 3.0e6 * b**2)
    e = f.contact_elements(b)
    assert np.sum(e.stiffness * e.positions**2) == pytest.approx(f.rocking_stiffness(b))


def test_two_element_from_ratios_definitions():
    m_t, w1 = 3.5e6, 2 * math.pi / 0.5
    f = two_element_from_ratios(m_t, w1, 8.0, 0.4)
    w_v = math.sqrt(2 * f.stiffness / m_t)
    assert w_v / w1 == pytest.approx(8.0)
    assert f.damping / (m_t * w_v) == pytest.approx(0.4)


def test_winkler_rocking_equals_integral_of_elements():
    """K_theta = integral k_w x^2 dx over [-b, b] = (2/3) k_w b^3; the midpoint elements converge to it."""
    f = Winkler(stiffness=5.0e7, damping=1.0e6, elements=2000)
    b = 3.0
    e = f.contact_elements(b)
    assert np.sum(e.stiffness * e.positions**2) == pytest.approx(f.rocking_stiffness(b), rel=1e-6)
    assert np.sum(e.damping * e.positions**2) == pytest.approx(f.rocking_damping(b), rel=1e-6)
    assert e.stiffness.sum() == pytest.approx(f.vertical_stiffness(b))


SOIL = dict(shear_modulus=8.0e7, poisson_ratio=0.3, density=1900.0)


def test_halfspace_square_static_stiffness_near_equivalent_disk():
    """Square mat 2B x 2B: Pais-Kausel 4.0 G B^3/(1-nu) vs rigid disk of equal moment of inertia,
    8 G R^3 / (3 (1-nu)) with pi R^4/4 = (2B)^4/12: within 3 %."""
    b = 5.0
    f = HalfSpace(half_length=b, **SOIL)
    G, nu = SOIL["shear_modulus"], SOIL["poisson_ratio"]
    assert f.rocking_stiffness(b) == pytest.approx(4.0 * G * b**3 / (1 - nu))
    radius = ((2 * b) ** 4 / 12 * 4 / math.pi) ** 0.25
    assert f.rocking_stiffness(b) == pytest.approx(8 * G * radius**3 / (3 * (1 - nu)), rel=0.03)
    radius_area = math.sqrt(4 * b * b / math.pi)  # vertical: disk of equal area, 4 G R / (1 - nu)
    assert f.vertical_stiffness(b) == pytest.approx(4 * G * radius_area / (1 - nu), rel=0.05)


def test_halfspace_long_mat_rocking_tends_to_strip():
    """Mat rocking across a long side: per unit length the strip value pi G B^2 / (2 (1 - nu)) (Gazetas)."""
    b, length = 2.0, 200.0
    f = HalfSpace(half_length=length, **SOIL)
    G, nu = SOIL["shear_modulus"], SOIL["poisson_ratio"]
    per_length = f.rocking_stiffness(b) / (2 * length)
    assert per_length == pytest.approx(math.pi * G * b**2 / (2 * (1 - nu)), rel=0.03)


def test_halfspace_orientation_is_continuous_at_square():
    """Across (b < L) and along (b > L) formulas of Tables 2-2a/2-3a agree for a square mat."""
    for omega in (None, 5.0, 40.0):
        below = HalfSpace(half_length=5.0, **SOIL)
        k_across = below.rocking_stiffness(5.0 * (1 - 1e-9), omega)
        k_along = below.rocking_stiffness(5.0 * (1 + 1e-9), omega)
        assert k_across == pytest.approx(k_along, rel=1e-6)
        c_across = below.rocking_damping(5.0 * (1 - 1e-9), omega)
        c_along = below.rocking_damping(5.0 * (1 + 1e-9), omega)
        assert c_across == pytest.approx(c_along, rel=1e-6)


@pytest.mark.parametrize("b, length", [(3.0, 8.0), (8.0, 3.0), (4.0, 4.0)])
def test_halfspace_damping_limits(b, length):
    """omega -> 0: static stiffness, no radiation damping. omega -> infinity: the rocking dashpot tends to
    rho V_p I_theta (plane P waves, V_p = psi V_s), the vertical one to rho V_p A."""
    f = HalfSpace(half_length=length, **SOIL)
    assert f.rocking_damping(b, 1e-6) == pytest.approx(0.0, abs=1e-6 * f.rocking_stiffness(b))
    assert f.rocking_stiffness(b, 1e-6) == pytest.approx(f.rocking_stiffness(b), rel=1e-9)
    nu = SOIL["poisson_ratio"]
    v_p = min(math.sqrt(2 * (1 - nu) / (1 - 2 * nu)), 2.5) * f.shear_wave_velocity
    inertia = (2 * length) * (2 * b) ** 3 / 12  # rocking in the plane of b
    omega = 1e4 * f.shear_wave_velocity / min(b, length)
    assert f.rocking_damping(b, omega) == pytest.approx(SOIL["density"] * v_p * inertia, rel=1e-3)
    assert f.vertical_damping(b, omega) == pytest.approx(SOIL["density"] * v_p * 4 * b * length, rel=1e-3)


def test_halfspace_dynamic_stiffness_decreases_and_elements_match():
    f = HalfSpace(half_length=6.0, **SOIL)
    b = 4.0
    omega = 0.8 * f.shear_wave_velocity / b  # a_0 = 0.8
    assert f.rocking_stiffness(b, omega) < f.rocking_stiffness(b)
    e = f.contact_elements(b, omega)
    assert list(e.positions) == [-b, b]
    assert np.sum(e.stiffness * e.positions**2) == pytest.approx(f.rocking_stiffness(b, omega))
    assert np.sum(e.damping * e.positions**2) == pytest.approx(f.rocking_damping(b, omega))


def test_winkler_elements_are_limited_before_anything_is_allocated():
    """foundation.elements = 100000 allocated a 74.5 GiB state matrix before the exact engine's own
    62-element check: the deck field is refused at the limit (limits.MAX_CONTACT_ELEMENTS)."""
    from pathlib import Path

    from upliftcli.deck.load import load_deck
    from upliftcli.errors import InputError
    from upliftcli.runtime.limits import MAX_CONTACT_ELEMENTS

    deck = Path(__file__).resolve().parents[1] / "inputs" / "ten_story_winkler.toml"
    with pytest.raises(InputError, match=r"^--set: foundation.elements: an integer from 2 to 62, got 100000$"):
        load_deck(deck, ["foundation.elements=100000"])
    assert load_deck(deck, [f"foundation.elements={MAX_CONTACT_ELEMENTS}"]).system.foundation.elements == 62
