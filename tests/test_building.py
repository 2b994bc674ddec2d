"""Modal analysis of the paper's ten-story example (docs/theory.md section 6) and modal identities."""

import numpy as np
import pytest

from upliftcli.model.building import (
    eigh_diagonal_mass,
    modal_analysis,
    modes_for_mass_target,
    shear_building,
    uniform_building,
)

# The paper's table (docs/theory.md section 6): w_n/w_1, m_n*/m_t, h_n*/b with h_1*/b = 10
PAPER_FREQUENCY_RATIOS = [1.0, 2.98, 4.89, 6.69, 8.34]
PAPER_MASS_RATIOS = [0.844, 0.091, 0.031, 0.014, 0.007]
PAPER_SLENDERNESS = [10.0, -3.4, 2.0, -1.5, 1.2]


@pytest.fixture(scope="module")
def ten_story():
    building = uniform_building(10, 350e3, 3.5, period=0.5, damping=0.05)
    return building, modal_analysis(building)


def test_paper_modal_table(ten_story):
    building, modes = ten_story
    m_t = building.masses.sum()
    b = modes.effective_height[0] / 10.0  # h_1*/b = 10
    np.testing.assert_allclose(modes.omega[:5] / modes.omega[0], PAPER_FREQUENCY_RATIOS, atol=0.01)
    np.testing.assert_allclose(modes.effective_mass[:5] / m_t, PAPER_MASS_RATIOS, atol=0.005)
    np.testing.assert_allclose(modes.effective_height[:5] / b, PAPER_SLENDERNESS, atol=0.05)
    assert modes.periods[0] == pytest.approx(0.5, rel=1e-12)


def test_uniform_shear_building_closed_form_frequencies(ten_story):
    """Uniform shear building, fixed base, free top: w_n = 2 sqrt(k/m) sin((2n-1) pi / (2(2N+1)))."""
    building, modes = ten_story
    k, m, n = building.story_stiffness[0], building.masses[0], 10
    exact = 2 * np.sqrt(k / m) * np.sin((2 * np.arange(1, n + 1) - 1) * np.pi / (2 * (2 * n + 1)))
    np.testing.assert_allclose(modes.omega, exact, rtol=1e-10)


def test_modal_identities_irregular_building():
    """Sums over all modes: m_n* -> sum m_j, m_n* h_n* -> sum m_j h_j, m_n* h_n*^2 -> sum m_j h_j^2 (section 5)."""
    masses = np.array([3.0, 2.5, 2.0, 1.0]) * 1e5
    building = shear_building(masses, [4.0, 3.0, 3.0, 3.5], np.array([9.0, 7.0, 5.0, 3.0]) * 1e8)
    modes = modal_analysis(building)
    h = building.heights
    assert modes.effective_mass.sum() == pytest.approx(masses.sum(), rel=1e-10)
    assert np.sum(modes.effective_mass * modes.effective_height) == pytest.approx(np.sum(masses * h), rel=1e-10)
    assert np.sum(modes.effective_mass * modes.effective_height**2) == pytest.approx(np.sum(masses * h**2), rel=1e-10)


def test_mass_target_count(ten_story):
    building, modes = ten_story
    m_t = building.masses.sum()
    assert modes_for_mass_target(modes, m_t, 0.80) == 1
    assert modes_for_mass_target(modes, m_t, 0.90) == 2
    assert modes_for_mass_target(modes, m_t, 0.99) == 5
    assert modes_for_mass_target(modes, 2 * m_t, 0.99) == 10  # never reached: every mode


def test_modes_are_shared_between_equal_buildings():
    """A sweep over foundation fields meets one building many times: its modes are solved once,
    and the shared arrays cannot be changed by one user under another."""
    first = modal_analysis(uniform_building(4, 1e5, 3.0, period=0.4, damping=0.05))
    again = modal_analysis(uniform_building(4, 1e5, 3.0, period=0.4, damping=0.05))
    other = modal_analysis(uniform_building(4, 1e5, 3.0, period=0.5, damping=0.05))
    assert again is first and other is not first
    assert other.omega[0] == pytest.approx(2 * np.pi / 0.5, rel=1e-12)
    with pytest.raises(ValueError, match="read-only"):
        first.omega[0] = 1.0


@pytest.mark.parametrize("stories", [1, 3, 10, 40])
def test_diagonal_mass_eigensolver_matches_generalized_solver(stories):
    """numpy's standard symmetric solver on M^-1/2 K M^-1/2 against scipy's generalized K phi = w^2 M phi,
    on shear buildings with random masses and stiffnesses: eigenvalues and mass-normalised shapes."""
    from scipy.linalg import eigh

    rng = np.random.default_rng(stories)
    building = shear_building(rng.uniform(1e5, 1e6, stories), np.full(stories, 3.5), rng.uniform(1e8, 1e9, stories))
    eigenvalues, shapes = eigh_diagonal_mass(building.stiffness, building.masses)
    reference, reference_shapes = eigh(building.stiffness, np.diag(building.masses))
    np.testing.assert_allclose(eigenvalues, reference, rtol=1e-12)
    signs = np.sign(np.sum(shapes * reference_shapes, axis=0))
    np.testing.assert_allclose(shapes * signs, reference_shapes, rtol=0, atol=1e-12 * np.max(np.abs(reference_shapes)))
    np.testing.assert_allclose(shapes.T @ np.diag(building.masses) @ shapes, np.eye(stories), atol=1e-12)
    np.testing.assert_allclose(eigh_diagonal_mass(building.stiffness, building.masses, eigvals_only=True), reference,
                               rtol=1e-12)
