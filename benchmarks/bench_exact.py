"""Exact engine speed: the paper's ten-story example under El Centro (all modes).

Prints the time of one analysis (uplift, T_1 = 0.5 s and 1 s) and of a 100-period x
3-support spectrum (T_1 from 0.05 to 5 s, log-spaced), serial and on 2 processes.
Targets (issue 4): one analysis under 20 ms; the 300 analyses under 3 s on 2 cores.
Run: python benchmarks/bench_exact.py
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import statistics
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from upliftcli.engines.exact import engine as exact
from upliftcli.model.building import modal_analysis, uniform_building
from upliftcli.model.foundations import two_element_from_ratios
from upliftcli.model.system import System
from upliftcli.motion.records import read_record

RECORD = Path(__file__).resolve().parents[1] / "records" / "elcentro_1940_ns_chopra.txt"
SUPPORTS = ("rigid", "bonded", "uplift")


def paper_system(period: float) -> System:
    building = uniform_building(10, 350e3, 3.5, period=period)
    modes = modal_analysis(building)
    foundation = two_element_from_ratios(building.masses.sum(), modes.omega[0], 8.0, 0.4)
    return System(building, foundation, modes.effective_height[0] / 10.0)


def run_periods(periods: list[float]) -> list[tuple[float, str, float]]:
    record = read_record(RECORD)
    out = []
    for period in periods:
        system = paper_system(period)
        for support in SUPPORTS:
            out.append((period, support, exact.analyze(system, record, support).base_shear_coefficient))
    return out


def main() -> None:
    record = read_record(RECORD)
    exact.analyze(paper_system(0.5), record, "uplift")  # first call: every module and path loaded
    for period in (0.5, 1.0):
        system = paper_system(period)
        times = []
        for _ in range(15):
            start = time.perf_counter()
            exact.analyze(system, record, "uplift")
            times.append(time.perf_counter() - start)
        print(f"one analysis, uplift, T_1 = {period} s: median {statistics.median(times) * 1e3:.1f} ms, "
              f"best {min(times) * 1e3:.1f} ms (target < 20 ms)")
    periods = np.geomspace(0.05, 5.0, 100).tolist()
    start = time.perf_counter()
    serial = run_periods(periods)
    serial_time = time.perf_counter() - start
    print(f"spectrum 100 periods x 3 supports, 1 process: {serial_time:.2f} s")
    start = time.perf_counter()
    with ProcessPoolExecutor(2) as pool:
        chunks = [periods[0::2], periods[1::2]]
        parallel = [row for rows in pool.map(run_periods, chunks) for row in rows]
    parallel_time = time.perf_counter() - start
    print(f"spectrum 100 periods x 3 supports, 2 processes: {parallel_time:.2f} s (target < 3 s)")
    assert sorted(parallel) == sorted(serial), "parallel and serial spectra differ"
    sys.stdout.flush()


if __name__ == "__main__":
    main()
