"""Timing helper shared by the benchmarks (run as scripts: `python benchmarks/<name>.py`, so this
folder is on sys.path)."""

from __future__ import annotations

import statistics
import time


def timed(function, repeats: int) -> tuple[float, float]:
    """(best, median) wall time [ms] of function() over `repeats` calls."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(1e3 * (time.perf_counter() - start))
    return min(times), statistics.median(times)
