"""The matrix exponential of the step operators (engines/exact/expm.py) against closed forms and
an independent implementation (scipy.linalg.expm)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm as scipy_expm

from upliftcli.engines.exact.expm import THETA_13, expm, squared_levels


@pytest.mark.parametrize("angle", [1e-6, 0.3, 2.0, 40.0])
def test_rotation_generator_gives_the_rotation(angle):
    """exp([[0, -t], [t, 0]]) = [[cos t, -sin t], [sin t, cos t]] (with squarings for large t)."""
    out = expm(np.array([[0.0, -angle], [angle, 0.0]]))
    c, s = np.cos(angle), np.sin(angle)
    np.testing.assert_allclose(out, [[c, -s], [s, c]], rtol=0, atol=2e-15 * max(1.0, angle))


def test_damped_oscillator_matches_its_closed_form():
    """x'' + 2 xi w x' + w^2 x = 0: the state transition matrix over t in closed form."""
    w, xi, t = 7.0, 0.05, 0.9
    wd, sigma = w * np.sqrt(1 - xi**2), xi * w
    e, c, s = np.exp(-sigma * t), np.cos(wd * t), np.sin(wd * t)
    exact = e * np.array([[c + sigma / wd * s, s / wd], [-w**2 / wd * s, c - sigma / wd * s]])
    out = expm(np.array([[0.0, 1.0], [-w**2, -2 * xi * w]]) * t)
    np.testing.assert_allclose(out, exact, rtol=0, atol=1e-14 * np.abs(exact).max())


def test_nilpotent_and_diagonal():
    nilpotent = np.array([[0.0, 1.0, 2.0], [0.0, 0.0, 3.0], [0.0, 0.0, 0.0]])
    np.testing.assert_allclose(expm(nilpotent), np.eye(3) + nilpotent + nilpotent @ nilpotent / 2, rtol=1e-15,
                               atol=1e-15)
    # normwise: the error is round-off of the largest entry (squarings), not of each one
    np.testing.assert_allclose(expm(np.diag([-30.0, 0.0, 1.5])), np.diag(np.exp([-30.0, 0.0, 1.5])), rtol=0,
                               atol=1e-14 * np.exp(1.5))
    np.testing.assert_array_equal(expm(np.zeros((0, 4, 4))).shape, (0, 4, 4))


@pytest.mark.parametrize("norm", [1e-5, 0.1, THETA_13, 60.0])
def test_stack_equals_scipy_to_round_off(norm):
    """Each matrix of a stack, each with its own scaling, as scipy.linalg.expm computes it alone."""
    rng = np.random.default_rng(3)
    stack = rng.normal(size=(4, 26, 26))
    stack *= norm / np.abs(stack).sum(axis=-2).max(axis=-1)[:, None, None] * np.array([1.0, 0.5, 0.1, 2.0])[:, None,
                                                                                                               None]
    out = expm(stack)
    for a, e in zip(stack, out, strict=True):
        reference = scipy_expm(a)
        assert np.abs(e - reference).max() <= 1e-13 * np.abs(reference).max()


@pytest.mark.parametrize("support", ["rigid", "bonded", "uplift"])
def test_squared_levels_are_the_exponentials_of_yielding_states(support):
    """squared_levels (the Taylor polynomial at the finest level, squarings for the others) gives
    exp(A h / 2^j) at every level j = 0..12 of the states where stories yield, against scipy.linalg.expm
    of each, to 1e-12 of the largest entry (measured 1.4e-12 at level 0, the most squared, on the bonded
    README deck; the exponential of the finest and of the coarsest level, as elastic states are built, is
    off by as much: 2.3e-12), in states with one to all ten stories yielding, and a stack of states gives
    each the bits it gets alone."""
    from pathlib import Path

    from upliftcli.deck.load import load_deck
    from upliftcli.engines.exact.patterns import contact_states
    from upliftcli.engines.exact.statespace import exact_model
    from upliftcli.engines.options import ExactOptions

    deck = Path(__file__).resolve().parent.parent / "inputs" / "ten_story_elcentro.toml"
    space = exact_model(load_deck(deck, ["building.strength_coefficient=0.3"]).system, support, ExactOptions())
    lay = space.layout
    rng = np.random.default_rng(35)
    signs = rng.integers(-1, 2, (6, lay.n_plastic)).astype(np.int8)
    signs[0], signs[1] = 1, 0
    signs[1, 4] = -1
    lifted = np.zeros((len(signs), lay.n_elements), dtype=bool)
    states = contact_states([space] * len(signs), lifted, "reaction", None, signs)
    h = 0.01
    stack = squared_levels(np.stack([state.matrix * h for state in states]), 12)
    for r, state in enumerate(states):
        alone = squared_levels(state.matrix[None] * h, 12)[0]
        assert np.array_equal(alone, stack[r])
        for j in range(13):
            reference = scipy_expm(state.matrix * (h / 2.0**j))
            assert np.abs(stack[r, j] - reference).max() <= 1e-12 * np.abs(reference).max(), (r, j)


def test_squared_levels_halve_a_matrix_whose_powers_grow():
    """A stiff matrix with eta = max(|A^2|^(1/2), |A^3|^(1/3)) above THETA_TAYLOR at the finest level (an
    oscillator of w h = 1000 to 2000, not a few large forcing columns) is halved before its Taylor polynomial:
    every level to 1e-11 of scipy's, and closer than the exponential of the finest and of the coarsest level
    with squarings between (measured 9e-12 against 2e-9 at level 3)."""
    from upliftcli.engines.exact.operators import _stacked_operators

    for w in (1.0e5, 2.0e5):
        a = np.array([[0.0, 1.0, 0.0], [-w**2, -0.1 * w, 1.0e3], [0.0, 0.0, 0.0]])
        levels = squared_levels(a[None] * 0.01, 12)[0]
        pade = _stacked_operators(a.T[None], np.array([[[0.01]]]))[0].transpose(0, 2, 1)
        for j in range(13):
            reference = scipy_expm(a * (0.01 / 2.0**j))
            scale = max(1.0, np.abs(reference).max())
            error = np.abs(levels[j] - reference).max() / scale
            assert error <= 1e-11 and error <= np.abs(pade[j] - reference).max() / scale, (w, j)
