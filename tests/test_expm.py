"""The matrix exponential of the step operators (engines/exact/expm.py) against closed forms and
an independent implementation (scipy.linalg.expm)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm as scipy_expm

from upliftcli.engines.exact.expm import THETA_13, expm


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
