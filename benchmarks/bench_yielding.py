"""Benchmark (issue 28, item 6): an exact analysis on soil that yields against the same analysis on
elastic soil, as the ratio of their CPU times (time.process_time, one BLAS thread: the wall time
of a machine shared with other work counts the time spent waiting for a core) measured
interleaved in the same run (medians of --repeats calls each, and of enough calls to last 0.2 s of
the elastic run: a two-element run takes 3 ms). Target: every ratio at most 1.5.

Each distinct contact state met needs its step operators (docs/theory.md 14.3), and a yielding
Winkler mat meets many more than an elastic one: the states of both runs, their ratio and the
time ratio per state ratio (the cost of a yielding state against an elastic one) are shown too.

Cases: the paper's ten-story example (w_v/w_1 = 8, xi_v = 0.4, h_1*/b = 10) under El Centro 1940
N-S with T_1 = 0.5 s and 1 s on two elements, and T_1 = 0.5 s on a 20-element Winkler mat of the
same vertical stiffness and damping; each with FS_v = 1.5, 2 and 3 (Q_i = FS_v W tributary / 2b)
against no capacity. The yielding run's transitions and plastic work are shown beside its ratio.

The floor of the method: the CPU time of the exponentials alone of the states the yielding run
meets, at the smallest size that gives them exactly (yielding.coupled_blocks: 28 x 28 on the mat) in one
stacked call, with the squarings for the bisection levels (floor_time), as a ratio to the whole
elastic run measured beside it. The yielding run also steps the same record and post-processes
it, as the elastic run does, so its time ratio cannot come much below 1 + that floor ratio. The
rest ratio: the yielding run's CPU time outside building its states (its stepping and
post-processing, as if its operators were free) over the elastic run (time_outside_building).

    python benchmarks/bench_yielding.py [--repeats 7]
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import statistics
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from upliftcli.engines.exact import engine as exact
from upliftcli.engines.exact import stepping
from upliftcli.engines.exact.expm import expm
from upliftcli.engines.exact.operators import LEVELS
from upliftcli.engines.exact.statespace import ContactState, StateSpace
from upliftcli.engines.exact.yielding import coupled_blocks
from upliftcli.model.building import modal_analysis, uniform_building
from upliftcli.model.foundations import Winkler, two_element_from_ratios
from upliftcli.model.system import System
from upliftcli.motion.records import read_record

RECORD = Path(__file__).resolve().parents[1] / "records" / "elcentro_1940_ns_chopra.txt"
FACTORS = (1.5, 2.0, 3.0)
TARGET = 1.5


def paper_system(period: float, foundation: str) -> System:
    """The paper's ten-story example on two elements, or on a 20-element Winkler mat with the
    same total vertical stiffness and damping."""
    building = uniform_building(10, 350e3, 3.5, period=period)
    modes = modal_analysis(building)
    two = two_element_from_ratios(building.masses.sum(), modes.omega[0], 8.0, 0.4)
    half_width = modes.effective_height[0] / 10.0
    if foundation == "winkler":
        width = 2.0 * half_width
        return System(building, Winkler(2.0 * two.stiffness / width, 2.0 * two.damping / width, 20), half_width)
    return System(building, two, half_width)


def with_capacity(system: System, factor: float) -> System:
    """The system with Q_i = FS_v W tributary / (2b): Q per edge element, q_w per unit length."""
    weight, half_width = system.weight, system.half_width
    per_length = factor * weight / (2.0 * half_width)
    capacity = per_length if isinstance(system.foundation, Winkler) else factor * weight / 2.0
    return replace(system, foundation=replace(system.foundation, capacity=capacity))


def median_time(system: System, record, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.process_time()
        exact.analyze(system, record, "uplift")
        times.append(time.process_time() - start)
    return statistics.median(times)


def time_outside_building(system: System, record, repeats: int, support: str = "uplift", options=None) -> float:
    """Median CPU time [s] of an analysis outside operators.add_states: the stepping and the
    post-processing of the run with its states' operators as if they were free (also
    bench_yielding_stories.py's, on the deck's support and exact-engine options). The states the compiled
    loop would build itself (a rigid or bonded run's yielding stories: story_requests.loop_builds) go
    through add_states here, the same arrays bit for bit, so that their building is left out too."""
    spent = [0.0]
    build, builds = stepping.add_states, stepping.loop_builds

    def timed(requests):
        start = time.process_time()
        indices = build(requests)
        spent[0] += time.process_time() - start
        return indices

    stepping.add_states, stepping.loop_builds = timed, lambda operators: None
    times = []
    try:
        for _ in range(repeats):
            spent[0] = 0.0
            start = time.process_time()
            exact.analyze(system, record, support, options)
            times.append(time.process_time() - start - spent[0])
    finally:
        stepping.add_states, stepping.loop_builds = build, builds
    return statistics.median(times)


def built_states(system: System, record) -> list[tuple[StateSpace, ContactState, float]]:
    """The contact states an analysis builds, (model, state, step h [s]) each (caught at
    operators.add_states, untimed)."""
    built = []
    build = stepping.add_states

    def caught(requests):
        indices = build(requests)
        built.extend((ops.space, ops.contact[index], ops.h)
                     for (ops, _, _), index in zip(requests, indices, strict=True) if not isinstance(index, Exception))
        return indices

    stepping.add_states = caught
    try:
        exact.analyze(system, record, "uplift")
    finally:
        stepping.add_states = build
    return built


def floor_time(states: list[tuple[StateSpace, ContactState, float]], repeats: int) -> tuple[float, int]:
    """CPU time [s] of the exponentials a run that meets these states cannot avoid: every state's
    block of the smallest size that gives its operators exactly (yielding.coupled_blocks: the
    motion and the forcing entries, and two columns for the settlements of the elements in
    contact, which load the mat only through its vertical force and moment; docs/theory.md 14.3)
    exponentiated at the finest bisection step h / 2^L in one stacked call, then squared L times
    for the coarser levels down to the step itself (the fewest products that give the L + 1
    operators); and the size of the block."""
    blocks = np.stack([coupled_blocks(space, [state])[0][0] * (h / 2.0**LEVELS) for space, state, h in states])
    times = []
    for _ in range(repeats):
        start = time.process_time()
        operators = expm(blocks)
        for _ in range(LEVELS):
            operators = operators @ operators
        times.append(time.process_time() - start)
    return statistics.median(times), blocks.shape[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    options = parser.parse_args()
    record = read_record(RECORD, units="g")
    print(f"{'case':28} {'elastic [ms]':>13} {'yielding [ms]':>14} {'ratio':>6} {'target':>7} "
          f"{'transitions':>12} {'states':>8} {'per state':>10} {'W_p/input':>10} {'floor [ms]':>11} "
          f"{'floor ratio':>12} {'rest ratio':>11}")
    worst = worst_per_state = worst_floor = 0.0
    for period, foundation in ((0.5, "two-element"), (1.0, "two-element"), (0.5, "winkler")):
        elastic = paper_system(period, foundation)
        exact.analyze(elastic, record, "uplift")  # untimed: imports, caches
        elastic_states = len(built_states(elastic, record))
        elastic_transitions = exact.analyze(elastic, record, "uplift").intermediates["transitions"]
        repeats = max(options.repeats, int(0.2 / median_time(elastic, record, 3)))
        for factor in FACTORS:
            yielding = with_capacity(elastic, factor)
            result = exact.analyze(yielding, record, "uplift")
            base = run = 0.0
            samples = []
            for _ in range(3):  # interleaved: each pair of medians sees the same load
                base = median_time(elastic, record, repeats)
                run = median_time(yielding, record, repeats)
                samples.append(run / base)
            ratio = statistics.median(samples)
            met = built_states(yielding, record)
            states = len(met)
            floor, size = floor_time(met, repeats=5)
            floor_ratio = floor / base
            rest_ratio = time_outside_building(yielding, record, repeats) / base
            worst_floor = max(worst_floor, floor_ratio)
            per_state = ratio / max(1.0, states / elastic_states)
            worst, worst_per_state = max(worst, ratio), max(worst_per_state, per_state)
            energy = result.details["energy"]
            transitions = f"{result.intermediates['transitions']}/{elastic_transitions}"
            print(f"{foundation + f' T1={period:g} s FS_v={factor:g}':28} {1e3 * base:13.2f} {1e3 * run:14.2f} "
                  f"{ratio:6.2f} {TARGET:7.1f} {transitions:>12} {f'{states}/{elastic_states}':>8} "
                  f"{per_state:10.2f} {energy['plastic_work'] / energy['input']:10.3f} {1e3 * floor:11.2f} "
                  f"{floor_ratio:12.2f} {rest_ratio:11.2f}")
    verdict = lambda value: "met" if value <= TARGET else "NOT met"  # noqa: E731
    print(f"largest ratio {worst:.2f} (target {TARGET}): {verdict(worst)}; largest time ratio per states ratio "
          f"(over max(1, states ratio)) {worst_per_state:.2f}: {verdict(worst_per_state)}; "
          f"load average {os.getloadavg()[0]:.1f}")
    print(f"floor: the exponentials alone of every state a yielding run meets (coupled_blocks, {size} x {size} on the "
          f"mat), one stacked expm and {LEVELS} squarings, as a ratio to the whole elastic run; the largest "
          f"{worst_floor:.2f}: the yielding run costs at least the elastic run's stepping and post-processing plus "
          f"this, so a time ratio much below 1 + {worst_floor:.2f} is out of reach of the method "
          f"(1 + floor: {verdict(1.0 + worst_floor)})")
    print("rest ratio: the yielding run's CPU time outside building its states (stepping, post-processing: its "
          "states' operators as if free) over the whole elastic run; floor + rest ratio bounds what building the "
          "states faster could reach")


if __name__ == "__main__":
    main()
