"""Static moment-rotation backbones of a rigid mat on elastic-perfectly-plastic contact elements,
and their moment capacities M_c (docs/theory.md section 14.4; ASCE 41-17 section 8.4).

A slow monotonic push: the mat carries its weight W [N] and turns by theta >= 0 [rad] (lifting the
left edge, x = -b); M [N m] is the overturning moment the foundation resists about the mat centre,
M = -sum x_i F_i. Each element's spring is elastic-perfectly-plastic in compression (capacity Q
[N], or q_w [N/m] per unit length of a Winkler strip) and cannot pull. FS_v = q_c/q: the factor
of safety against vertical bearing failure under W. Pure functions of arrays.
"""

from __future__ import annotations

import numpy as np


def factor_of_safety(total_capacity: float, weight: float) -> float:
    """FS_v = q_c/q = (sum of the element capacities) / W [-]."""
    return float(total_capacity) / float(weight)


def asce41_moment_capacity(weight: float, width: float, load_ratio: float) -> float:
    """M_c = (P B / 2)(1 - q/q_c) [N m] (ASCE 41-17 section 8.4): P = W [N], B the width in the
    plane of rocking [m] (2b), load_ratio q/q_c = A_c/A = 1/FS_v [-]."""
    return 0.5 * weight * width * (1.0 - load_ratio)


def two_element_moment_capacity(half_width: float, capacity: float, weight: float) -> float:
    """M_c = W b min(1, FS_v - 1) [N m] of two elements of capacity Q [N] each at x = -b, +b,
    FS_v = 2Q/W (> 1): the right element carries W at the lever b once the left one lifts
    (FS_v >= 2), or Q against the left one's W - Q once it yields (FS_v < 2)."""
    return float(weight * half_width * min(1.0, 2.0 * capacity / weight - 1.0))


def two_element_backbone(theta, half_width: float, stiffness: float, capacity: float, weight: float) -> np.ndarray:
    """M(theta) [N m] of two elements (k [N/m], Q [N] each at x = -b, +b): 2 k b^2 theta up to
    the first of lift-off (M = W b) and yield, then constant at M_c (two_element_moment_capacity).
    capacity = inf: the elastic uplift backbone min(2 k b^2 theta, W b)."""
    theta = np.asarray(theta, dtype=float)
    cap = weight * half_width if np.isinf(capacity) else two_element_moment_capacity(half_width, capacity, weight)
    return np.minimum(2.0 * stiffness * half_width**2 * theta, cap)


def winkler_moment_capacity(half_width: float, line_capacity: float, weight: float) -> float:
    """M_c = W b (1 - W/(2 b q_w)) [N m] of a Winkler strip of capacity q_w [N/m] per unit length,
    = (P B / 2)(1 - q/q_c) with B = 2b and q/q_c = W/(2 b q_w) (asce41_moment_capacity)."""
    return float(weight * half_width * (1.0 - weight / (2.0 * half_width * line_capacity)))


def winkler_backbone(theta, half_width: float, stiffness: float, line_capacity: float, weight: float) -> np.ndarray:
    """M(theta) [N m] of a rigid mat of half-width b on a Winkler strip, k_w [N/m^2], capacity
    q_w [N/m] per unit length (inf: elastic), under W [N] (docs/theory.md 14.4):

    1. full contact, elastic: (2/3) k_w b^3 theta;
    2. FS_v > 2: uplift, elastic contact length c = sqrt(2 W / (k_w theta)), M = W (b - c/3), up to
       toe yield at theta = q_w^2 / (2 W k_w); FS_v < 2: toe yield in full contact, elastic length
       l = sqrt(2 (2 b q_w - W) / (k_w theta)), M = k_w theta l^2 (3 b - l) / 6, up to the heel's
       uplift at theta = q_w^2 / (2 k_w (2 b q_w - W));
    3. uplift and toe yield: elastic length l = q_w / (k_w theta), plastic length
       p = W/q_w - l/2, contact from x_0 = b - p - l,
       M = (q_w l / 2)(x_0 + 2 l / 3) + q_w p (b - p / 2), tending to winkler_moment_capacity."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    b, k, q, w = float(half_width), float(stiffness), float(line_capacity), float(weight)
    if 2.0 * b * q <= w:
        raise ValueError("the strip's capacity 2 b q_w must exceed the weight W (FS_v > 1)")
    moment = np.empty_like(theta)
    with np.errstate(divide="ignore", invalid="ignore"):
        elastic = 2.0 / 3.0 * k * b**3 * theta
        if 2.0 * b * q >= 2.0 * w:  # FS_v >= 2: uplift first
            lift, toe = w / (2.0 * k * b**2), q**2 / (2.0 * w * k)
            contact = np.sqrt(2.0 * w / (k * theta))
            second = w * (b - contact / 3.0)
        else:  # toe yield first
            lift = (q - w / (2.0 * b)) / (k * b)  # here: the onset of yield (the first stage's end)
            toe = q**2 / (2.0 * k * (2.0 * b * q - w))  # here: the heel lifts
            length = np.sqrt(2.0 * (2.0 * b * q - w) / (k * theta))
            second = k * theta * length**2 * (3.0 * b - length) / 6.0
        elastic_length = q / (k * theta)
        plastic = w / q - elastic_length / 2.0
        start = b - plastic - elastic_length
        third = q * elastic_length / 2.0 * (start + 2.0 * elastic_length / 3.0) + q * plastic * (b - plastic / 2.0)
    moment[:] = np.where(theta <= lift, elastic, np.where(theta <= toe, second, third))
    return moment


def midpoint_moment_capacity(positions, capacities, weight: float) -> float:
    """M_c [N m] of discrete elements (positions x_i [m] in increasing order, capacities Q_i [N])
    under a large rotation: the elements from the right edge carry their capacity until their sum
    reaches W, the last one the remainder (the others lifted). The strip's
    winkler_moment_capacity is its limit as the elements get finer."""
    x = np.asarray(positions, dtype=float)[::-1]
    q = np.asarray(capacities, dtype=float)[::-1]
    carried = np.minimum(q, np.maximum(weight - (np.cumsum(q) - q), 0.0))
    return float(np.sum(x * carried))
