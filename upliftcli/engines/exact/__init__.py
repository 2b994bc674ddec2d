"""The exact engine: nonlinear response history with contact transitions inside the step."""

from ..options import ExactOptions
from .engine import analyze, analyze_batch, iter_batch

__all__ = ["ExactOptions", "analyze", "analyze_batch", "iter_batch"]
