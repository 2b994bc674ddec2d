"""Approximate engine (paper Figs. 6 and 8): the fundamental mode coupled with the foundation
through the one-mode equations [17a-17c] with I_b ~ m_1* h_1*^2 and L_0 ~ m_1* h_1* [20],
the higher modes fixed-base (no interaction, no uplift), combined instant by instant.

It is the exact engine's model with only mode 1 coupled to the mat rotation: the higher
modes are independent fixed-base oscillators integrated on the same time grid.
"""

from __future__ import annotations

from ..results import AnalysisResult
from ..system import System
from . import single_threaded_blas
from .exact import ExactOptions, modal_model, resolve_modes, run_history, summarize


@single_threaded_blas
def analyze(system: System, record, support: str, options: ExactOptions | None = None) -> AnalysisResult:
    """Approximate peak response: first mode with interaction and uplift, higher modes fixed-base."""
    options = options or ExactOptions()
    n_modes = resolve_modes(system, options.n_modes)
    model = modal_model(system, support, n_modes, coupled_modes=1, approximate=True)
    history = run_history(system, model, record.acceleration, record.dt, support, options)
    return summarize(system, history, support, "approximate", options, system.modes.shapes_star[:, :n_modes])
