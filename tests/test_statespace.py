"""engines/exact/statespace.py: the contact-state matrices against the physical equations [1a-1c]."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from paper_example import paper_system
from scipy.linalg import eig

from upliftcli.engines.exact.modal import modal_model
from upliftcli.engines.exact.patterns import contact_states
from upliftcli.engines.exact.statespace import state_space


def physical_matrices(system, lifted=(False, False)):
    """M, C, K of [1a-1c] in physical coordinates (u_1..u_N, theta, v), elements in contact
    where not lifted: rows of [3a, 3b] with v_i = v - x_i theta."""
    b = system.building
    n = b.n_stories
    modes = system.modes
    mass_phi = b.masses[:, None] * modes.shapes
    c_struct = mass_phi @ np.diag(2 * modes.damping * modes.omega) @ mass_phi.T
    elements = system.foundation.contact_elements(system.half_width, float(modes.omega[0]))
    size = n + 2
    mass, damp, stiff = np.zeros((size, size)), np.zeros((size, size)), np.zeros((size, size))
    mass[:n, :n] = np.diag(b.masses)
    mass[:n, n] = mass[n, :n] = b.masses * b.heights
    mass[n, n] = np.sum(b.masses * b.heights**2) + system.mat_rotary_inertia
    mass[n + 1, n + 1] = system.total_mass
    stiff[:n, :n], damp[:n, :n] = b.stiffness, c_struct
    for x, k, c, off in zip(elements.positions, elements.stiffness, elements.damping, lifted, strict=True):
        if off:
            continue
        e = np.zeros(size)
        e[n], e[n + 1] = -x, 1.0
        stiff += k * np.outer(e, e)
        damp += c * np.outer(e, e)
    return mass, damp, stiff


def finite_eigenvalues(mass, damp, stiff):
    """Roots of det(s^2 M + s C + K) = 0 (M may be singular: the finite ones only)."""
    size = mass.shape[0]
    zero, one = np.zeros((size, size)), np.eye(size)
    values = eig(np.block([[zero, one], [-stiff, -damp]]), np.block([[one, zero], [zero, mass]]), right=False)
    return np.sort_complex(values[np.isfinite(values) & (np.abs(values) < 1e9)])


def state_eigenvalues(system, support, lifted):
    space = state_space(modal_model(system, support, system.building.n_stories))
    (state,) = contact_states([space], np.array([lifted]), "reaction")
    n_x = space.layout.n_x
    values = np.linalg.eigvals(state.matrix[:n_x, :n_x])
    z = np.zeros(n_x, dtype=bool)
    z[space.layout.z_indices] = True
    # the relaxing tops of lifted elements (k z + c z' = 0) are modes of their own
    relax = -space.element_stiffness[np.array(lifted)] / space.element_damping[np.array(lifted)]
    keep = np.ones(values.size, dtype=bool)
    for rate in relax:
        keep[np.argmin(np.abs(values - rate) + ~keep * 1e300)] = False
    return np.sort_complex(values[keep & (np.abs(values) > 1e-9)]), relax


@pytest.mark.parametrize("mat_inertia", [0.0, 2.0e7])
@pytest.mark.parametrize("lifted", [(False, False), (True, False), (False, True)])
def test_contact_state_matrix_has_the_physical_eigenvalues(mat_inertia, lifted):
    """All modes coupled: in every contact pattern the state matrix (W coordinates, a massless
    mat as a first-order constraint) has the eigenvalues of the physical system [1a-1c]; the
    lifted elements add their relaxation rates -k/c."""
    system = replace(paper_system(0.5), mat_rotary_inertia=mat_inertia)
    expected = finite_eigenvalues(*physical_matrices(system, lifted))
    got, relax = state_eigenvalues(system, "uplift", list(lifted))
    # one edge lifted: the structure may pivot rigidly about the other (a double zero root,
    # which the singular pencil gives only to ~1e-7): compare the others
    scale = np.abs(expected).max()
    expected, got = expected[np.abs(expected) > 1e-6 * scale], got[np.abs(got) > 1e-6 * scale]
    assert got.size == expected.size == 2 * 12 - 2 * any(lifted) - (mat_inertia == 0.0)
    for value in got:  # each eigenvalue has its physical counterpart (the pencil's accuracy: ~1e-6)
        assert np.min(np.abs(expected - value)) < 1e-5 * abs(value), value
    for value in expected:
        assert np.min(np.abs(got - value)) < 1e-5 * abs(value), value
    assert len(relax) == sum(lifted)


def test_bonded_static_state_is_the_settlement_under_gravity():
    """At rest under gravity: v = -m_t g / (2 k_f), theta = 0, and A X = 0 (no motion)."""
    system = paper_system(0.5)
    space = state_space(modal_model(system, "bonded", 10))
    (state,) = contact_states([space], np.zeros((1, 2), dtype=bool), "reaction")
    v = space.position[-1] @ space.rest
    assert v == pytest.approx(-system.weight / (2 * system.foundation.stiffness), rel=1e-12)
    assert np.abs(state.matrix @ space.rest).max() < 1e-9 * np.abs(state.matrix).max()


def test_event_rows_are_the_scaled_element_forces():
    """In contact, reaction criterion: g_i = (k v_i + c v_i') / (m_t g) > 0 means tension [4a]."""
    system = paper_system(0.5)
    space = state_space(modal_model(system, "uplift", 10))
    (state,) = contact_states([space], np.zeros((1, 2), dtype=bool), "reaction")
    rng = np.random.default_rng(2)
    x = rng.normal(size=space.layout.n_aug)
    # v_i = v - x_i theta [3b], built from the coordinates p = (Y*_1..Y*_N, theta, v) and the
    # element positions of the foundation (-b, +b): theta > 0 raises the left edge
    n = space.model.n_modes
    positions = system.foundation.contact_elements(system.half_width).positions
    p, p_dot = space.position @ x, state.velocity @ x  # X -> p, X -> p'
    v = p[n + 1] - positions * p[n]
    v_dot = p_dot[n + 1] - positions * p_dot[n]
    np.testing.assert_allclose(space.displacement_rows @ x, v, rtol=1e-12)
    force = space.element_stiffness * v + space.element_damping * v_dot
    np.testing.assert_allclose(state.events @ x, force / system.weight, rtol=1e-12)
    lift = np.zeros(space.layout.n_p)
    lift[n] = 1e-3  # theta > 0 alone
    assert (space.directions @ lift)[0] > 0 > (space.directions @ lift)[1]


def test_the_bonded_vertical_period_has_one_home():
    """modal.vertical_period, 2 pi sqrt(m_t / sum k_i), is the period of the vertical mode of the bonded
    mat, and the sampling resolves it (governing_period)."""
    from upliftcli.engines.exact.modal import governing_period, vertical_period

    system = paper_system(frequency_ratio=3.0)
    model = modal_model(system, "bonded", system.building.n_stories)
    period = vertical_period(model)
    assert period == 2.0 * np.pi * np.sqrt(system.total_mass / model.elements.stiffness.sum())
    assert governing_period(model) <= period
    eigenvalues = finite_eigenvalues(*physical_matrices(system))
    undamped = np.abs(eigenvalues)
    assert np.min(np.abs(undamped - 2.0 * np.pi / period)) < 0.1 * 2.0 * np.pi / period  # a root near w_v


@pytest.mark.parametrize("lifted", [(False, False), (True, False), (False, True)])
def test_a_capacity_that_does_not_yield_assembles_the_elastic_state(lifted):
    """patterns.contact_states is one assembly for both foundations: with a bearing capacity and no
    element yielding, A, the velocity map and the lift-off/recontact rows on the state without the
    settlements s_i are those of the elastic foundation."""
    system = paper_system()
    capacity = 3.0 * system.weight
    yielding_system = replace(system, foundation=replace(system.foundation, capacity=capacity))
    n = system.building.n_stories
    elastic = state_space(modal_model(system, "uplift", n))
    plastic = state_space(modal_model(yielding_system, "uplift", n))
    (a,) = contact_states([elastic], np.array([lifted]), "reaction")
    (b,) = contact_states([plastic], np.array([lifted]), "reaction", np.zeros((1, 2), dtype=bool))
    keep = np.setdiff1d(np.arange(plastic.layout.n_aug), plastic.layout.settlement_indices)
    assert b.yielding is not None and not b.yielding.any() and a.yielding is None
    np.testing.assert_allclose(b.matrix[np.ix_(keep, keep)], a.matrix, rtol=1e-12, atol=1e-12 * np.abs(a.matrix).max())
    np.testing.assert_allclose(b.velocity[:, keep], a.velocity, rtol=1e-12, atol=1e-12 * np.abs(a.velocity).max())
    np.testing.assert_allclose(b.events[:2, keep], a.events, rtol=1e-12, atol=1e-12)
