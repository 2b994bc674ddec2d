"""Benchmark (issue 35, item 6): the exact engine on a building whose stories yield against the same
building elastic, as ratios measured in one run. Targets: exact-engine CPU at most 3x, the whole
command at most 1.5x, a 100-case exact sweep at most 3x.

The deck: the README example (inputs/ten_story_elcentro.toml) under El Centro x2
(ground_motion.scale = 2) with the exact engine on its three supports; the yielding run adds
building.strength_coefficient = 0.4 and hardening_ratio = 0.05, which give largest story ductilities
of 2.9 (uplift), 3.9 (bonded) and 4.7 (rigid).

- engine: CPU time (time.process_time, one BLAS thread, the allocator as the command sets it) of
  exact.analyze on each support, the elastic and the yielding run interleaved in this process (medians of
  --repeats calls each, three rounds, the median of the rounds' ratios), with the contact states each run
  builds and its transitions, and the rest ratio: the yielding run's CPU time outside building its states
  (operators.add_states: its stepping and post-processing, as if its operators were free) over the elastic
  run, which bounds what faster state building could reach (a rigid or bonded yielding run's states, which
  the compiled loop builds itself, docs/theory.md 15.9, go through add_states for this measure);
- command: `uplift analyze` of the deck in a fresh process each time, the elastic and the yielding
  command interleaved: wall time and CPU time (the child's user + system time), medians;
- sweep: `uplift sweep -e exact --vary building.period=0.4:0.8:100 --workers 1` in a fresh process
  (300 analyses: 100 cases on three supports), interleaved, wall and CPU time, medians.

No timed assertion anywhere: the machine is shared, the ratios are printed with the load average.

    python benchmarks/bench_yielding_stories.py [--repeats 7] [--command-repeats 5] [--sweep-repeats 1]
        [--only engine,command,sweep]
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DECK = ROOT / "inputs" / "ten_story_elcentro.toml"
ELASTIC = ("analysis.engine=exact", "ground_motion.scale=2")
YIELDING = (*ELASTIC, "building.strength_coefficient=0.4", "building.hardening_ratio=0.05")
SUPPORTS = ("rigid", "bonded", "uplift")
SWEEP_VARY = "building.period=0.4:0.8:100"
TARGETS = {"engine": 3.0, "command": 1.5, "sweep": 3.0}


def _load(overrides: tuple[str, ...]):
    from upliftcli.deck.load import load_deck

    return load_deck(DECK, list(overrides))


def _cpu(deck, support: str, repeats: int) -> float:
    """Median CPU time [s] of `repeats` exact analyses of the deck on one support."""
    from upliftcli.engines.exact import engine as exact

    times = []
    for _ in range(repeats):
        start = time.process_time()
        exact.analyze(deck.system, deck.ground_motion, support, deck.analysis.exact)
        times.append(time.process_time() - start)
    return statistics.median(times)


def _outside_building(deck, support: str, repeats: int) -> float:
    """Median CPU time [s] of an analysis outside operators.add_states (its stepping and post-processing, as if
    its states' operators were free): bench_yielding.time_outside_building on the deck."""
    from bench_yielding import time_outside_building

    return time_outside_building(deck.system, deck.ground_motion, repeats, support, deck.analysis.exact)


def _states(deck, support: str) -> tuple[int, int, float]:
    """(contact states built, transitions, largest story ductility) of one analysis (untimed): the states its
    runs hold at the end (those add_states built and those the compiled loop built itself)."""
    from upliftcli.engines.exact import engine as exact
    from upliftcli.engines.exact import stepping

    runs = {}
    advance = stepping.Run.advance

    def kept(run):
        runs[id(run.operators)] = run.operators
        return advance(run)

    stepping.Run.advance = kept
    try:
        result = exact.analyze(deck.system, deck.ground_motion, support, deck.analysis.exact)
    finally:
        stepping.Run.advance = advance
    ductility = max((story.get("ductility", 0.0) for story in _stories(result)), default=0.0)
    return sum(len(operators.contact) for operators in runs.values()), int(result.intermediates["transitions"]), \
        ductility


def _stories(result) -> list[dict]:
    from upliftcli.output import result_to_dict

    return result_to_dict(result).get("stories", [])


def engine_ratios(repeats: int) -> float:
    """Print the engine's CPU ratio per support and for the three together; return the latter. The
    allocator is set as the uplift command sets it (runtime/process.py: without it, freed operator
    arrays move glibc's mmap threshold and the post-processing's time with it)."""
    from upliftcli.runtime.process import keep_freed_memory

    keep_freed_memory()
    elastic, yielding = _load(ELASTIC), _load(YIELDING)
    print(f"{'engine (CPU)':14} {'elastic [ms]':>13} {'yielding [ms]':>14} {'ratio':>6} {'rest ratio':>11} "
          f"{'states':>9} {'transitions':>12} {'ductility':>10}")
    totals = [0.0, 0.0]
    for support in SUPPORTS:
        _cpu(elastic, support, 1), _cpu(yielding, support, 1)  # untimed: imports, caches
        rounds = []
        for _ in range(3):  # interleaved: each pair of medians sees the same load
            base, run = _cpu(elastic, support, repeats), _cpu(yielding, support, repeats)
            rounds.append((base, run))
        base = statistics.median(b for b, _ in rounds)
        run = statistics.median(r for _, r in rounds)
        ratio = statistics.median(r / b for b, r in rounds)
        totals[0], totals[1] = totals[0] + base, totals[1] + run
        rest = _outside_building(yielding, support, repeats) / base
        states_e, transitions_e, _ = _states(elastic, support)
        states_y, transitions_y, ductility = _states(yielding, support)
        print(f"{support:14} {1e3 * base:13.2f} {1e3 * run:14.2f} {ratio:6.2f} {rest:11.2f} "
              f"{f'{states_y}/{states_e}':>9} {f'{transitions_y}/{transitions_e}':>12} {ductility:10.2f}")
    ratio = totals[1] / totals[0]
    print(f"{'all three':14} {1e3 * totals[0]:13.2f} {1e3 * totals[1]:14.2f} {ratio:6.2f}   (target "
          f"{TARGETS['engine']:g})")
    return ratio


def _timed_command(arguments: list[str]) -> tuple[float, float]:
    """(wall, CPU) time [s] of `uplift ARGUMENTS` in a fresh process (CPU: the child's user + system)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "upliftcli", *arguments], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(ROOT)}, check=False)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode not in (0, 3):  # 3: a criterion exceeded (the deck's drift limit), still a full run
        raise SystemExit(f"uplift {' '.join(arguments)} failed ({done.returncode}): {done.stderr.strip()[-400:]}")
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def _sets(overrides: tuple[str, ...]) -> list[str]:
    return [item for value in overrides for item in ("--set", value)]


def _interleaved(make, repeats: int, label: str) -> tuple[float, float]:
    """Median wall and CPU ratios (yielding / elastic) of commands made by make(overrides), interleaved;
    prints their medians."""
    samples = {"elastic": [], "yielding": []}
    make(ELASTIC), make(YIELDING)  # untimed: the .pyc files, the record's cache
    for _ in range(repeats):
        samples["elastic"].append(_timed_command(make(ELASTIC)))
        samples["yielding"].append(_timed_command(make(YIELDING)))
    wall = {k: statistics.median(w for w, _ in v) for k, v in samples.items()}
    cpu = {k: statistics.median(c for _, c in v) for k, v in samples.items()}
    wall_ratio, cpu_ratio = wall["yielding"] / wall["elastic"], cpu["yielding"] / cpu["elastic"]
    print(f"{label:14} wall {wall['elastic']:.3f} s -> {wall['yielding']:.3f} s ({wall_ratio:.2f}x), CPU "
          f"{cpu['elastic']:.3f} s -> {cpu['yielding']:.3f} s ({cpu_ratio:.2f}x)   (target "
          f"{TARGETS[label.split()[0]]:g})")
    return wall_ratio, cpu_ratio


def _analyze_command(overrides: tuple[str, ...]) -> list[str]:
    return ["analyze", str(DECK), *_sets(overrides), "--format", "json"]


def _sweep_command(out: Path):
    def make(overrides: tuple[str, ...]) -> list[str]:
        name = "yielding" if overrides == YIELDING else "elastic"
        return ["sweep", str(DECK), *_sets(overrides), "-e", "exact", "--vary", SWEEP_VARY, "--workers", "1", "-q",
                "--table", "csv", "--overwrite", "-o", str(out), "--name", name]

    return make


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7, help="calls per median of the engine's CPU time")
    parser.add_argument("--command-repeats", type=int, default=5)
    parser.add_argument("--sweep-repeats", type=int, default=1)
    parser.add_argument("--only", default="engine,command,sweep")
    options = parser.parse_args()
    parts = set(options.only.split(","))
    if "engine" in parts:
        engine_ratios(options.repeats)
    if "command" in parts:
        _interleaved(_analyze_command, options.command_repeats, "command")
    if "sweep" in parts:
        with tempfile.TemporaryDirectory() as out:
            _interleaved(_sweep_command(Path(out)), options.sweep_repeats, "sweep (100)")
    print(f"load average {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
