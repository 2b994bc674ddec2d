"""Approximate engine (paper Figs. 6 and 8): the fundamental mode coupled with the foundation
through the one-mode equations [17a-17c] with I_b ~ m_1* h_1*^2 and L_0 ~ m_1* h_1* [20],
the higher modes fixed-base (no interaction, no uplift), combined instant by instant.

It is the exact engine's model with only mode 1 coupled to the mat rotation: the higher
modes are independent fixed-base oscillators integrated on the same time grid.
"""

from __future__ import annotations

from ..model.system import System
from .exact import engine as exact
from .exact.engine import ExactOptions
from .result import AnalysisResult


def analyze(system: System, record, support: str, options: ExactOptions | None = None) -> AnalysisResult:
    """Approximate peak response: first mode with interaction and uplift, higher modes fixed-base."""
    return exact.analyze(system, record, support, options, engine="approximate")


def analyze_batch(systems: list[System], record, support: str, options: ExactOptions | None = None) -> list:
    """analyze for several systems (exact.analyze_batch with the approximate model)."""
    return exact.analyze_batch(systems, record, support, options, engine="approximate")
