"""The story strengths of [building] (docs/theory.md section 15): story_strengths, or strength_coefficient
distributed over the height as ASCE 7-22 12.8.3 distributes the lateral force, and hardening_ratio.
Without either strength the building is returned as it is (elastic: every result unchanged).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..model.building import Building, modal_analysis
from . import schema

#: ASCE 7-22 12.8.3: the exponent k is 1 for T <= 0.5 s, 2 for T >= 2.5 s, linear between
SHORT_PERIOD, LONG_PERIOD = 0.5, 2.5


def distribution_exponent(period: float) -> float:
    """k of ASCE 7-22 12.8.3 at the fundamental period T_1 [s]."""
    return 1.0 + float(np.clip((period - SHORT_PERIOD) / (LONG_PERIOD - SHORT_PERIOD), 0.0, 1.0))


def vertical_distribution(weights: np.ndarray, heights: np.ndarray, period: float) -> np.ndarray:
    """C_vx = w_x h_x^k / sum w_i h_i^k of each floor (ASCE 7-22 Eq. 12.8-12), weights w_x [N] and
    heights h_x above the base [m], k from T_1 [s]."""
    share = weights * heights ** distribution_exponent(period)
    return share / share.sum()


def coefficient_strengths(building: Building, coefficient: float, gravity: float) -> np.ndarray:
    """Story strengths [N]: the story shears of the base shear coefficient x W (W = sum m_j g, the
    building's weight) distributed as ASCE 7-22 12.8.3 with T_1 of the fixed-base building."""
    weights = building.masses * gravity
    period = float(modal_analysis(building).periods[0])
    forces = coefficient * weights.sum() * vertical_distribution(weights, building.heights, period)
    return np.cumsum(forces[::-1])[::-1]


def strengths_from_fields(building: Building, fields: dict, analysis: dict, error) -> Building:
    """The building with its story strengths and hardening ratio (fields: [building], analysis: [analysis]
    for gravity); unchanged without a strength. Every mistake is one error(field, expected)."""
    name = schema.exactly_one(fields, ["story_strengths", "strength_coefficient"], "building", error)
    if name is None:
        if "hardening_ratio" in fields:
            raise error("building.hardening_ratio", "a story strength with it (building.story_strengths or "
                        "building.strength_coefficient)")
        return building
    if building.story_stiffness is None:
        raise error(f"building.{name}", "story stiffnesses (a shear building): yielding stories need "
                    "building.story_stiffness(es), not building.stiffness_matrix")
    if name == "story_strengths":
        strength = np.asarray(fields[name], dtype=float)
    else:
        gravity = float(analysis.get("gravity", schema.default("analysis", "gravity")))
        strength = coefficient_strengths(building, float(fields[name]), gravity)
    return replace(building, story_strength=strength, hardening_ratio=float(fields.get("hardening_ratio", 0.0)))
