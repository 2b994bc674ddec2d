"""Benchmark (issue 35, the residuals' stability check): what the perturbed twin of a yielding run costs
(analysis/residuals.py), as ratios measured in one run: the whole command `uplift analyze` (the README
deck with the exact engine on its three supports, El Centro x2) with yielding stories and the check
("auto", the default), the same with `analysis.exact.residual_check = "off"`, and the elastic run.
Issue 35's target: the whole yielding command at most 1.5 times the elastic one.

Each command runs in a fresh process, interleaved, --repeats times; shown: the medians of the wall time
and of the CPU time of the process and its children (resource.RUSAGE_CHILDREN; the machine is shared:
the CPU time is the steadier of the two), and their ratios.

    python benchmarks/bench_residual_check.py [--repeats 5] [--strength 0.5]
"""

from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DECK = str(ROOT / "inputs" / "ten_story_elcentro.toml")
BASE = ["analyze", DECK, "--engine", "exact", "--set", "ground_motion.scale=2", "--format", "json"]
TARGET = 1.5


def commands(strength: float) -> dict[str, list[str]]:
    """name -> arguments of uplift."""
    yielding = [*BASE, "--set", f"building.strength_coefficient={strength}", "--set", "building.hardening_ratio=0.05"]
    return {"elastic": BASE, "yielding, check off": [*yielding, "--set", "analysis.exact.residual_check=off"],
            "yielding, check (auto)": yielding}


def timed(arguments: list[str]) -> tuple[float, float]:
    """(wall, CPU of the children) [s] of one `uplift` command in a fresh process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "upliftcli", *arguments], stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode not in (0, 3):
        raise SystemExit(f"uplift {' '.join(arguments)} failed ({done.returncode}): {done.stderr[-400:]}")
    return wall, (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--strength", type=float, default=0.5, help="building.strength_coefficient")
    args = parser.parse_args()
    runs = commands(args.strength)
    for arguments in runs.values():
        timed(arguments)  # warm: the .pyc files, the page cache
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in runs}
    for _ in range(args.repeats):
        for name, arguments in runs.items():
            times[name].append(timed(arguments))
    wall = {name: statistics.median(t[0] for t in values) for name, values in times.items()}
    cpu = {name: statistics.median(t[1] for t in values) for name, values in times.items()}
    for name in runs:
        print(f"{name:24s} wall {wall[name]:6.2f} s  CPU {cpu[name]:6.2f} s  "
              f"CPU / elastic {cpu[name] / cpu['elastic']:5.2f}  wall / elastic {wall[name] / wall['elastic']:5.2f}")
    twin = cpu["yielding, check (auto)"] / cpu["yielding, check off"]
    print(f"the twin: CPU x {twin:.2f} of the yielding command without it; target (whole command / elastic) "
          f"{TARGET}: {'met' if cpu['yielding, check (auto)'] / cpu['elastic'] <= TARGET else 'not met'}")


if __name__ == "__main__":
    main()
