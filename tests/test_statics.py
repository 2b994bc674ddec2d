"""engines/statics.py: story maps and the reactions of a rigid mat, against hand statics."""

from __future__ import annotations

import numpy as np
import pytest

from upliftcli.engines.statics import largest_compression, static_reactions, story_maps
from upliftcli.model.building import shear_building


def test_story_maps_by_hand():
    building = shear_building([1.0, 1.0, 1.0], [4.0, 3.0, 3.0], [1.0, 1.0, 1.0])
    maps = story_maps(building)
    forces = np.array([1.0, 2.0, 3.0])
    np.testing.assert_allclose(maps.shear @ forces, [6.0, 5.0, 3.0])
    # about the bottom of story 1 (z = 0), 2 (z = 4) and 3 (z = 7); floors at 4, 7, 10 m
    np.testing.assert_allclose(maps.moment @ forces, [1 * 4 + 2 * 7 + 3 * 10, 2 * 3 + 3 * 6, 3 * 3])
    np.testing.assert_allclose(maps.drift @ np.array([0.1, 0.25, 0.3]), [0.1, 0.15, 0.05])


def test_two_elements_bonded_uplift_and_tipping():
    x, k, weight, b = np.array([-2.0, 2.0]), np.array([5.0, 5.0]), 100.0, 2.0
    np.testing.assert_allclose(static_reactions(x, k, weight, 0.0, tension=True), [50.0, 50.0])
    np.testing.assert_allclose(static_reactions(x, k, weight, 80.0, tension=True), [30.0, 70.0])
    # M = W b: the left edge just unloads; beyond, a bonded mat pulls, an uplifting one tips
    np.testing.assert_allclose(static_reactions(x, k, weight, weight * b, tension=False), [0.0, 100.0], atol=1e-12)
    np.testing.assert_allclose(static_reactions(x, k, weight, 300.0, tension=True), [-25.0, 125.0])
    np.testing.assert_allclose(static_reactions(x, k, weight, 300.0, tension=False), [0.0, 100.0])
    np.testing.assert_allclose(largest_compression(x, k, weight, 80.0, tension=True), [70.0, 70.0])


def test_winkler_strip_partly_lifted_gives_the_triangular_pressure():
    """Uniform springs under W at eccentricity e = M/W > b/3: contact over 3 (b - e) from the
    pressed edge, triangular pressure peaking at 2 W / (3 (b - e)) [N/m]."""
    n, b, weight = 4000, 1.0, 1.0
    dx = 2 * b / n
    x = -b + dx * (np.arange(n) + 0.5)
    e = 0.5
    reactions = static_reactions(x, np.ones(n), weight, weight * e, tension=False)
    assert reactions.sum() == pytest.approx(weight, rel=1e-12)
    assert (reactions * x).sum() == pytest.approx(weight * e, rel=1e-12)
    contact = x[reactions > 0]
    assert contact.min() == pytest.approx(b - 3 * (b - e), abs=2 * dx)
    assert reactions.max() / dx == pytest.approx(2 * weight / (3 * (b - e)), rel=2e-3)
    # e < b/3 (inside the kern): all in contact, trapezoid W/(2b) (1 +- 3 e / b)
    reactions = static_reactions(x, np.ones(n), weight, weight * 0.2, tension=False)
    assert np.all(reactions > 0)
    assert reactions.max() / dx == pytest.approx(weight / (2 * b) * (1 + 3 * 0.2), rel=2e-3)


def test_elements_with_a_capacity_carry_at_most_it_and_keep_equilibrium():
    """Two elements, W = 100, Q_y = 70: M below M_c = (2 Q_y - W) b = 80 is elastic, at 80 the
    right element is at capacity; beyond there is no static solution and each carries at most Q_y.
    A strip: the reactions carry W and M, none above Q_y, the elastic ones on one straight line."""
    x, k, weight = np.array([-2.0, 2.0]), np.array([5.0, 5.0]), 100.0
    cap = np.array([70.0, 70.0])
    np.testing.assert_allclose(static_reactions(x, k, weight, 60.0, False, cap), [35.0, 65.0])
    np.testing.assert_allclose(static_reactions(x, k, weight, 80.0, False, cap), [30.0, 70.0])
    assert np.all(static_reactions(x, k, weight, 150.0, False, cap) <= cap)
    n, b = 200, 1.0
    dx = 2 * b / n
    xs = -b + dx * (np.arange(n) + 0.5)
    q_y = np.full(n, 1.5 * weight / n)  # FS_v = 1.5: M_c = W b (1 - 1/1.5) = W b / 3
    reactions = static_reactions(xs, np.ones(n), weight, 0.3 * weight * b, False, q_y)
    assert reactions.sum() == pytest.approx(weight, rel=1e-12)
    assert (reactions * xs).sum() == pytest.approx(0.3 * weight * b, rel=1e-12)
    assert reactions.max() == pytest.approx(q_y[0], rel=1e-12) and np.any(reactions == q_y)
    elastic = (reactions > 0) & (reactions < q_y)
    slope = np.polyfit(xs[elastic], reactions[elastic], 1)
    np.testing.assert_allclose(np.polyval(slope, xs[elastic]), reactions[elastic], rtol=1e-9)
    # a capacity never reached changes nothing, bit for bit
    plain = static_reactions(xs, np.ones(n), weight, 0.3 * weight * b, False)
    assert np.array_equal(static_reactions(xs, np.ones(n), weight, 0.3 * weight * b, False, np.full(n, 1e30)), plain)
