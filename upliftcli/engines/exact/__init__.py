"""The exact engine: nonlinear response history with contact transitions inside the step."""

from .engine import ExactOptions, analyze, analyze_batch, iter_batch

__all__ = ["ExactOptions", "analyze", "analyze_batch", "iter_batch"]
