"""Benchmark: generating 11 artificial records and matching 11 records to the ASCE 7-22 multi-period
spectrum of inputs/ten_story_asce7_suite.toml (period range 0.2-2.43 s, 347 control periods), and
the exact engine on that deck's 11-record suite for 3 supports.

Targets (issue 12): generating and matching each at most 2 s; the exact engine on the suite, 3
supports, at most 1 s in process. Printed as wall time and as a ratio to a baseline measured in
the same run: for generating and matching, one exact response spectrum (spectra.response_spectrum)
of one generated record at the 347 control periods, the unit of work of one iteration; for the
engines, one exact analysis of one record of the suite with uplift (33 of them if nothing were
shared; the rigid base shares nothing across records either). The 11 seeds
to match are El Centro and ten records made from it (time-reversed, and cut at 2 s steps and
wrapped around), so that the suite needs no downloads. With --reqpy, the same El Centro match
by reqpy-m (if installed) is timed and checked against the same tolerance.

    python benchmarks/bench_suites.py [--repeats 3] [--reqpy] [--part all|generate|match|engines]
"""

from __future__ import annotations

import argparse
import resource
import statistics
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from upliftcli.analysis import run as analysis
from upliftcli.deck.load import load_deck
from upliftcli.deck.suite import plan_from_deck
from upliftcli.engines.registry import ENGINES
from upliftcli.motion.generate import generate_suite
from upliftcli.motion.matching import control_periods, settings_for
from upliftcli.motion.records import ground_velocity, read_record
from upliftcli.motion.spectra import response_spectrum
from upliftcli.motion.suites import build_suite
from upliftcli.units import STANDARD_GRAVITY

ROOT = Path(__file__).resolve().parent.parent
DECK = ROOT / "inputs" / "ten_story_asce7_suite.toml"
RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"


def timed(function, repeats: int) -> tuple[float, float, object]:
    """(best, median) wall time [s] of function() over `repeats` calls, and its last result."""
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return min(times), statistics.median(times), result


def seeds() -> list:
    """El Centro and ten variants of it (reversed; rotated by 2-10 s; both)."""
    record = read_record(RECORD)
    a = record.acceleration
    shifts = [round(s / record.dt) for s in (2, 4, 6, 8, 10)]
    variants = [a, a[::-1]] + [np.roll(a, k) for k in shifts] + [np.roll(a[::-1], k) for k in shifts[:4]]
    return [replace(record, acceleration=np.ascontiguousarray(v), name=f"elcentro variant {k}",
                    source=f"{RECORD} variant {k}") for k, v in enumerate(variants)]


def reqpy_check(plan, settings) -> None:
    try:
        import reqpy_M
    except ImportError:
        print("reqpy-m is not installed: pip install reqpy-m (in a separate environment)")
        return
    record = read_record(RECORD)
    periods = np.geomspace(0.01, 10.0, 200)
    target = settings.reference * plan.target.sa(periods, 0.05) / STANDARD_GRAVITY
    low, high = plan.period_range
    start = time.perf_counter()
    out = reqpy_M.generate_single_component_compatible_record(record.acceleration / STANDARD_GRAVITY, 1 / record.dt,
                                                              periods, target, T1PSA=low, T2PSA=high, zi=0.05)
    elapsed = time.perf_counter() - start
    matched = out["sc"] * STANDARD_GRAVITY
    check = control_periods(plan.period_range)
    ratios = response_spectrum(matched, record.dt, check, [0.05]).pseudo_acceleration[0] / (
        settings.reference * plan.target.sa(check, 0.05))
    velocity = ground_velocity(matched, record.dt)
    print(f"reqpy-m on El Centro: {elapsed:.2f} s, S_a/matching target {ratios.min():.3f}-{ratios.max():.3f} "
          f"(spread {ratios.max() / ratios.min():.3f}), final velocity {velocity[-1]:.3f} m/s, "
          f"peak RSS {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")


def engines_on_the_suite(repeats: int) -> None:
    """The exact engine on the deck's 11 records x 3 supports through analysis.run (one batch per
    record, the statistics and the simplified engine beside it), against one exact analysis."""
    load_deck(DECK)  # JIT warm-up of the spectra
    load, _, deck = timed(lambda: load_deck(DECK), repeats)
    suite = deck.ground_motion
    print(f"reading the deck and its suite (11 records read, their spectra for the code's mean check): {load:.3f} s")
    exact = ENGINES["exact"]
    first = suite.motions()[0]
    exact.analyze(deck.system, first, "uplift", deck.analysis.exact)  # JIT warm-up
    base_best, base_median, _ = timed(lambda: exact.analyze(deck.system, first, "uplift", deck.analysis.exact),
                                      5 * repeats)
    print(f"baseline: one exact analysis, uplift, one record ({first.npts} samples) {1e3 * base_best:.1f} ms best, "
          f"{1e3 * base_median:.1f} ms median")
    supports = ("rigid", "bonded", "uplift")
    best, median, results = timed(lambda: analysis.run(deck, "exact", supports), repeats)
    print(f"exact engine on the suite, {suite.count} records x {len(supports)} supports: {best:.3f} s best, "
          f"{median:.3f} s median = {best / base_best:.1f} baselines; target <= 1 s: "
          f"{'met' if best <= 1.0 else 'NOT met'}")
    for support in supports:
        one, _, _ = timed(lambda support=support: [exact.analyze(deck.system, m, support, deck.analysis.exact)
                                                   for m in suite.motions()], repeats)
        print(f"  {support}: the {suite.count} records one by one {one:.3f} s = {one / base_best:.1f} baselines")
    simplified, _, _ = timed(lambda: [ENGINES["simplified"].analyze(deck.system, deck.spectrum, s,
                                                                     deck.analysis.simplified) for s in supports],
                             repeats)
    print(f"  the simplified engine beside it, 3 supports: {1e3 * simplified:.1f} ms; design values: "
          + ", ".join(f"{r.support} V_b/(m_t g) {r.base_shear_coefficient:.3f}" for r in results))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--reqpy", action="store_true", help="also time reqpy-m on El Centro")
    parser.add_argument("--part", choices=("all", "generate", "match", "engines"), default="all")
    args = parser.parse_args()
    if args.part in ("all", "engines"):
        engines_on_the_suite(args.repeats)
    if args.part == "engines":
        return
    plan = plan_from_deck(load_deck(DECK, load_ground_motion=False))
    settings = settings_for(plan.rule)
    periods = control_periods(plan.period_range)
    print(f"target {plan.target.name}; period range {plan.period_range[0]:.3g}-{plan.period_range[1]:.3g} s, "
          f"{periods.size} control periods")

    generate_suite(plan.target, plan.period_range, plan.rule, 1, 99)  # JIT warm-up
    suite, items = generate_suite(plan.target, plan.period_range, plan.rule, 1, 2024)
    one = suite.records[0]
    base_best, base_median, _ = timed(lambda: response_spectrum(one.acceleration, one.dt, periods, [0.05]),
                                      10 * args.repeats)
    print(f"baseline: one response spectrum ({one.npts} samples, {periods.size} periods) "
          f"{1e3 * base_best:.2f} ms best, {1e3 * base_median:.2f} ms median")

    if args.part in ("all", "generate"):
        best, median, (suite, items) = timed(
            lambda: generate_suite(plan.target, plan.period_range, plan.rule, 11, 2024), args.repeats)
        draws = sum(item.attempt for item in items)
        print(f"generate 11: {best:.2f} s best, {median:.2f} s median = {best / base_best:.0f} baselines "
              f"({draws} redrawn); mean S_a/target min {suite.mean_ratio().min():.3f}; "
              f"target <= 2 s: {'met' if best <= 2.0 else 'NOT met'}")
    if args.part == "generate":
        return

    records = seeds()
    best, median, suite = timed(lambda: build_suite(records, plan.target, plan.period_range, plan.rule, "match"),
                                args.repeats)
    print(f"match 11: {best:.2f} s best, {median:.2f} s median = {best / base_best:.0f} baselines; "
          f"mean S_a/target min {suite.mean_ratio().min():.3f}; target <= 2 s: {'met' if best <= 2.0 else 'NOT met'}")
    for warning in suite.warnings:
        print(f"  warning: {warning}")
    if args.reqpy:
        reqpy_check(plan, settings)


if __name__ == "__main__":
    main()
