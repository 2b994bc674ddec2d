"""Benchmark: the numpy twins of the compiled loops against the loops (issue 26; upliftcli.runtime.backend),
as the ratio of wall times numpy / compiled of the same command in fresh processes, run
interleaved in the same run (the machine is shared: medians and ranges). Targets: the README's
analysis with its exact check within 2x, the Fig. 3 spectrum within 8x; one exact analysis of the
README deck and a spectrum of El Centro at 500 periods are shown without a target.

    python benchmarks/bench_backends.py [--repeats 3] [--only readme,fig3,...]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
README_DECK = str(ROOT / "inputs" / "ten_story_elcentro.toml")
RECORD = str(ROOT / "records" / "elcentro_1940_ns_chopra.txt")

#: name -> (arguments of uplift, largest ratio numpy / compiled or None)
TARGETS = {
    "readme": (["analyze", README_DECK], 2.0),
    "exact": (["analyze", README_DECK, "--engine", "exact"], None),
    "record-spectrum": (["record", "spectrum", RECORD, "--periods", "0.02:10:500"], None),
    "fig3": (["spectra", README_DECK, "--periods", "0.05:5:100", "--engine", "exact", "--quiet", "--overwrite"], 8.0),
}


def run(arguments: list[str], backend: str, folder: str) -> float:
    """Wall time [s] of `uplift arguments` in a fresh process on `backend`."""
    environment = dict(os.environ, UPLIFT_BACKEND=backend)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", "from upliftcli.cli import console; console()", *arguments],
                          cwd=folder, env=environment, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if done.returncode not in (0, 3):
        raise SystemExit(f"uplift {' '.join(arguments)} failed on {backend}:\n{done.stderr}")
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--only", default=",".join(TARGETS))
    options = parser.parse_args()
    print(f"{'command':16} {'compiled [s]':>14} {'numpy [s]':>14} {'ratio':>16} {'target':>7}")
    with tempfile.TemporaryDirectory() as folder:
        for name in options.only.split(","):
            arguments, target = TARGETS[name]
            times = {"compiled": [], "numpy": []}
            for backend in times:  # one untimed run each: the bytecode is written
                run(arguments, backend, folder)
            for _ in range(options.repeats):
                for backend in times:
                    times[backend].append(run(arguments, backend, folder))
            compiled, numpy = (statistics.median(times[b]) for b in ("compiled", "numpy"))
            ratios = [n / c for c, n in zip(times["compiled"], times["numpy"], strict=True)]
            verdict = "" if target is None else (f"{target:.0f}x " + ("ok" if numpy / compiled <= target else "MISSED"))
            print(f"{name:16} {compiled:14.3f} {numpy:14.3f} {numpy / compiled:6.2f} "
                  f"({min(ratios):.2f}-{max(ratios):.2f}) {verdict:>7}")


if __name__ == "__main__":
    main()
