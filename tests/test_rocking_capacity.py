"""Closed-form backbones and moment capacities of model/rocking_capacity.py against an independent
numerical equilibrium solve of the elements with their plastic memory, the elastic backbone
already in the code (engines/improved.uplift_capacity) and the limits of docs/theory.md 14.4."""

import itertools
import math

import numpy as np
import pytest

from upliftcli.engines.improved import uplift_capacity
from upliftcli.model import rocking_capacity as rc

W, B, K = 1.0e6, 2.0, 1.0e9  # weight [N], half-width [m], stiffness [N/m or N/m^2]


def equilibrium_push(positions, stiffness, capacities, weight, thetas):
    """M(theta) [N m] of a rigid mat pushed through the rotations `thetas` (increasing) on
    elastic-perfectly-plastic compression-only springs: at each rotation the centre's level v is
    found by bisection so that the reactions carry the weight, then each yielded element keeps
    its plastic settlement s_i (<= 0) for the next rotation."""
    x, k, q = (np.asarray(a, dtype=float) for a in (positions, stiffness, capacities))
    settled = np.zeros_like(x)

    def reactions(v, theta):
        return np.clip(k * (settled - (v - x * theta)), 0.0, q)

    moments = []
    for theta in thetas:
        low, high = -10.0, 10.0  # the centre's level [m]: reactions fall as v rises
        for _ in range(200):
            mid = 0.5 * (low + high)
            if reactions(mid, theta).sum() > weight:
                low = mid
            else:
                high = mid
        v = 0.5 * (low + high)
        force = reactions(v, theta)
        moments.append(float(np.sum(x * force)))
        settled = np.minimum(settled, v - x * theta + q / k)
    return np.array(moments)


def strip(n, line_capacity):
    dx = 2.0 * B / n
    positions = -B + dx * (np.arange(n) + 0.5)
    return positions, np.full(n, K * dx), np.full(n, line_capacity * dx)


@pytest.mark.parametrize("fs", [1.2, 1.5, 1.9, 2.0, 2.5, 4.0])
def test_two_element_backbone_is_the_equilibrium_of_the_elements(fs):
    capacity = fs * W / 2.0
    thetas = np.linspace(0.0, 5.0 * W / (K * B), 60)
    expected = equilibrium_push([-B, B], [K, K], [capacity, capacity], W, thetas)
    closed = rc.two_element_backbone(thetas, B, K, capacity, W)
    assert np.allclose(closed, expected, rtol=1e-9, atol=1e-9 * W * B)
    assert math.isclose(closed[-1], rc.two_element_moment_capacity(B, capacity, W), rel_tol=1e-12)


def test_two_element_moment_capacity_limits():
    assert rc.two_element_moment_capacity(B, W / 2.0 * (1.0 + 1e-9), W) == pytest.approx(0.0, abs=1e-6 * W * B)
    assert rc.two_element_moment_capacity(B, W, W) == pytest.approx(W * B)  # FS_v = 2
    assert rc.two_element_moment_capacity(B, 5.0 * W, W) == W * B  # tipping, as without a capacity
    # infinite capacity: the elastic uplift backbone min(K_theta theta, W b)
    thetas = np.linspace(0.0, 3.0 * W / (K * B), 7)
    assert np.array_equal(rc.two_element_backbone(thetas, B, K, math.inf, W),
                          np.minimum(2.0 * K * B**2 * thetas, W * B))


@pytest.mark.parametrize("fs", [1.3, 1.8, 2.6, 5.0])
def test_winkler_backbone_is_the_equilibrium_of_a_fine_strip(fs):
    """Both orders of the stages (yield first below FS_v = 2, uplift first above) against 400
    midpoint elements pushed with their plastic memory (which also checks that no element
    unloads after it yielded, the backbone's assumption)."""
    line_capacity = fs * W / (2.0 * B)
    scale = line_capacity**2 / (K * W)  # the rotations of the stage ends
    thetas = np.linspace(0.0, 8.0 * scale, 80)[1:]
    expected = equilibrium_push(*strip(400, line_capacity), W, thetas)
    closed = rc.winkler_backbone(thetas, B, K, line_capacity, W)
    assert np.max(np.abs(closed - expected)) < 1e-5 * W * B  # 1e-6 to 5e-6 measured: O(1/n^2)
    assert np.all(np.diff(closed) > 0.0)
    assert closed[-1] < rc.winkler_moment_capacity(B, line_capacity, W)


def test_winkler_backbone_without_capacity_is_the_elastic_one_in_the_code():
    """q_w -> inf: (2/3) k_w b^3 theta to the kern, then W (b - c/3), which engines/improved.py's
    uplift_capacity gives at theta = x W b / K_theta (kern 1/3)."""
    k_theta = 2.0 / 3.0 * K * B**3
    x = np.array([0.1, 0.2, 1.0 / 3.0, 0.5, 1.0, 2.0, 10.0])
    moment = rc.winkler_backbone(x * W * B / k_theta, B, K, math.inf, W)
    expected = [xi * W * B if xi <= 1.0 / 3.0 else uplift_capacity(xi, 1.0 / 3.0) * W * B for xi in x]
    assert np.allclose(moment, expected, rtol=1e-12)
    big = rc.winkler_backbone(x * W * B / k_theta, B, K, 1e6 * W / B, W)  # a capacity never reached
    assert np.allclose(big, expected, rtol=1e-12)


def test_winkler_moment_capacity_is_asce41_and_vanishes_at_fs_1():
    for fs in (1.0 + 1e-9, 1.5, 2.0, 3.0, 10.0):
        line_capacity = fs * W / (2.0 * B)
        assert rc.winkler_moment_capacity(B, line_capacity, W) == pytest.approx(
            rc.asce41_moment_capacity(W, 2.0 * B, 1.0 / fs), rel=1e-12, abs=1e-12 * W * B)
    assert rc.winkler_moment_capacity(B, W / (2.0 * B) * (1.0 + 1e-9), W) < 1e-8 * W * B
    # the backbone tends to M_c at large rotations
    line_capacity = 1.5 * W / (2.0 * B)
    far = rc.winkler_backbone(1e6 * line_capacity**2 / (K * W), B, K, line_capacity, W)[0]
    assert far == pytest.approx(rc.winkler_moment_capacity(B, line_capacity, W), rel=1e-5)


def test_winkler_backbone_refuses_a_capacity_below_the_weight():
    with pytest.raises(ValueError, match="FS_v > 1"):
        rc.winkler_backbone(1e-3, B, K, 0.9 * W / (2.0 * B), W)


@pytest.mark.parametrize("fs", [1.25, 2.0, 3.0])
def test_midpoint_capacity_of_the_elements_tends_to_the_strip(fs):
    """The exact engine's n midpoint elements: their M_c tends to (P B/2)(1 - q/q_c) as n grows,
    the difference shrinking as 1/n^2 (or zero where the elements tile the plastic length), and
    equals the large-rotation equilibrium."""
    line_capacity = fs * W / (2.0 * B)
    strip_capacity = rc.winkler_moment_capacity(B, line_capacity, W)
    errors = []
    for n in (10, 20, 40, 80, 160):
        positions, _, capacities = strip(n, line_capacity)
        errors.append(abs(rc.midpoint_moment_capacity(positions, capacities, W) - strip_capacity))
    assert errors[-1] < 1e-3 * W * B
    assert all(later <= 0.55 * earlier + 1e-12 * W * B for earlier, later in itertools.pairwise(errors))
    positions, stiffness, capacities = strip(20, line_capacity)
    pushed = equilibrium_push(positions, stiffness, capacities, W, np.geomspace(1e-6, 0.05, 120))[-1]
    assert pushed == pytest.approx(rc.midpoint_moment_capacity(positions, capacities, W), rel=1e-6)


def test_factor_of_safety():
    assert rc.factor_of_safety(3.0e6, 1.0e6) == 3.0
