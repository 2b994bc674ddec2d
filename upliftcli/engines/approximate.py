"""Approximate engine (paper Figs. 6 and 8): the fundamental mode coupled with the foundation
through the one-mode equations [17a-17c] with I_b ~ m_1* h_1*^2 and L_0 ~ m_1* h_1* [20],
the higher modes fixed-base (no interaction, no uplift), combined instant by instant.

It is a choice of model, not of method: the exact engine integrates it (exact/engine.py),
with only mode 1 coupled to the mat rotation; the higher modes are independent fixed-base
oscillators integrated on the same time grid.
"""

from __future__ import annotations

from collections.abc import Iterator

from ..errors import AnalysisError, InputError
from ..model.system import System
from .exact import engine as exact
from .exact.modal import modal_model, resolve_modes
from .exact.statespace import StateSpace, state_space
from .options import ExactOptions
from .result import AnalysisResult


def approximate_model(system: System, support: str, options: ExactOptions) -> StateSpace:
    """The model with mode 1 alone coupled with the mat [17-20] (no residual inertia). A building whose
    stories yield is refused (InputError; docs/theory.md 15.6), for a caller that passes the registry by."""
    if system.building.yields:
        raise InputError("building", "story_strengths", "the approximate engine does not model yielding stories "
                         "(docs/theory.md 15.6): use the exact engine, or remove the story strengths")
    n_modes = resolve_modes(system, options.n_modes)
    return state_space(modal_model(system, support, n_modes, coupled_modes=1, approximate=True))


def iter_batch(systems: list[System], record, support: str, options: ExactOptions | None = None
               ) -> Iterator[tuple[int, AnalysisResult | AnalysisError | InputError]]:
    """Approximate peak responses (exact.iter_batch with the approximate model)."""
    return exact.iter_batch(systems, record, support, options, model=approximate_model, name="approximate")


def analyze_batch(systems: list[System], record, support: str, options: ExactOptions | None = None) -> list:
    """iter_batch as a list in the order of `systems`."""
    return exact.analyze_batch(systems, record, support, options, model=approximate_model, name="approximate")


def analyze(system: System, record, support: str, options: ExactOptions | None = None) -> AnalysisResult:
    """Approximate peak response: first mode with interaction and uplift, higher modes fixed-base."""
    return exact.analyze(system, record, support, options, model=approximate_model, name="approximate")
