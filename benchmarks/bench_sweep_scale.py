"""Benchmark: how a large simplified sweep scales (issue 38, item 5: the first row within 10 s of
the start, memory flat, at most 300 MB at 10^5 cases).

Runs `uplift sweep inputs/ten_story_elcentro.toml -e simplified --support uplift` over
building.period x foundation.slenderness in a child process, for a baseline of 100 cases and
then 10^3 and 10^4 cases (10^5 with --large), and prints for each:

- the time from the start of the child to its first row (the rows file is read as it grows: its
  first line is the run's header, the second the first row);
- the peak resident memory of the command (os.wait4's ru_maxrss: the largest of the command and
  the worker processes it waited for) and of the command's own process (VmHWM of /proc);
- rows per second from the first row to the last;

each also as a ratio to the baseline measured in the same run (the machine is shared: compare
ratios between runs, not seconds), and at 10^5 cases against the goals (GOALS: the first row
within 10 s, peak memory at most 300 MB). A case exceeding the deck's [criteria] (exit code 3)
is a finished sweep.

    python benchmarks/bench_sweep_scale.py [--large] [--workers 1] [--table json|csv|parquet]
    python benchmarks/bench_sweep_scale.py --sizes 100000 --table json   # the goals alone

Measured at 99,856 cases, --workers 1, on this project's shared 2-core machine (2026-12-06):
before the rows were read back from the rows file (3d18d71) the peak was 1,114 MB with --table
json (every row a dict, and the whole JSON document built and dumped at once) and 318 MB with
--table csv; since then 91 MB with json or csv and 225 MB with parquet (131 MB of it pyarrow's,
at 100 cases). First row 0.6-1.0 s on a quiet machine (0.66 s before), 3-7 s with other sweeps running;
total 258 s with csv (262 s before).
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DECK = ROOT / "inputs" / "ten_story_elcentro.toml"
POLL_SECONDS = 0.02
#: the stem of the outputs (--name)
STEM = "bench"
#: exit codes of a finished sweep: 0, or 3 (a case exceeds a limit of the deck's [criteria])
FINISHED = (0, 3)
#: issue 38 item 5, at GOAL_CASES cases: the first row within FIRST_ROW_GOAL_S, peak memory at most PEAK_GOAL_MB
GOAL_CASES = 100_000
FIRST_ROW_GOAL_S = 10.0
PEAK_GOAL_MB = 300.0


@dataclass(frozen=True)
class Figures:
    cases: int
    first_row_s: float
    peak_rss_mb: float
    main_hwm_mb: float
    rows_per_s: float
    total_s: float


def command(cases: int, out: Path, workers: int, table: str = "json") -> list[str]:
    """The sweep of about `cases` cases: periods x slenderness ratios, one engine, one support."""
    periods = max(1, round(math.sqrt(cases)))
    ratios = max(1, round(cases / periods))
    return [sys.executable, "-m", "upliftcli", "sweep", str(DECK), "--vary", f"building.period=0.2:3:{periods}",
            "--vary", f"foundation.slenderness=2:8:{ratios}", "-e", "simplified", "--support", "uplift",
            "--out", str(out), "--name", STEM, "--quiet", "--table", table, "--workers", str(workers)]


def _lines(path: Path) -> int:
    try:
        with open(path, "rb") as handle:
            return sum(chunk.count(b"\n") for chunk in iter(lambda: handle.read(1 << 20), b""))
    except FileNotFoundError:
        return 0


def _hwm_mb(pid: int) -> float:
    """VmHWM (the peak resident memory) of a running process [MB], 0 where /proc has none."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return 0.0


def measure(cases: int, workers: int, table: str = "json") -> Figures:
    """Run one sweep in a child process and read its rows file as it grows."""
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "out"
        rows = out / f"{STEM}.rows.jsonl"
        environment = {**os.environ, "PYTHONPATH": str(ROOT)}
        errors = Path(folder) / "stderr.txt"  # a file, not a pipe: many lines (violations) never block the sweep
        with open(errors, "wb") as stderr:
            start = time.perf_counter()
            child = subprocess.Popen(command(cases, out, workers, table), env=environment, stdout=subprocess.DEVNULL,
                                     stderr=stderr)
            first, hwm = _wait_first_row(child, rows, start)
            _, status, usage = os.wait4(child.pid, 0)
        child.returncode = os.waitstatus_to_exitcode(status)
        total = time.perf_counter() - start
        if child.returncode not in FINISHED:
            raise SystemExit(f"the sweep of {cases} cases failed ({child.returncode}): "
                             f"{errors.read_text(errors='replace')[-2000:]}")
        finished = _lines(rows) - 1  # the header line
    rate = (finished - 1) / max(total - first, 1e-9) if finished > 1 else float("nan")
    return Figures(finished, first, usage.ru_maxrss / 1024, hwm, rate, total)


def _wait_first_row(child: subprocess.Popen, rows: Path, start: float) -> tuple[float, float]:
    """(seconds to the first row, the command's peak memory seen while it ran [MB])."""
    first, hwm = float("nan"), 0.0
    while os.waitid(os.P_PID, child.pid, os.WEXITED | os.WNOHANG | os.WNOWAIT) is None:
        hwm = max(hwm, _hwm_mb(child.pid))
        if first != first and _lines(rows) >= 2:
            first = time.perf_counter() - start
        time.sleep(POLL_SECONDS if first != first else 0.25)
    if first != first and _lines(rows) >= 2:  # it ended between two looks
        first = time.perf_counter() - start
    return first, hwm


def report(figures: Figures, baseline: Figures) -> str:
    return (f"{figures.cases:>7,} cases: first row {figures.first_row_s:7.2f} s "
            f"(x{figures.first_row_s / baseline.first_row_s:5.2f}), peak RSS {figures.peak_rss_mb:6.0f} MB "
            f"(x{figures.peak_rss_mb / baseline.peak_rss_mb:4.2f}; the command's own {figures.main_hwm_mb:5.0f} MB), "
            f"{figures.rows_per_s:7.1f} rows/s (x{figures.rows_per_s / baseline.rows_per_s:4.2f}), "
            f"total {figures.total_s:7.1f} s")


def against_goals(figures: Figures) -> str:
    """The first row and the peak memory against the goals (issue 38 item 5), met or not."""
    first = "met" if figures.first_row_s <= FIRST_ROW_GOAL_S else "NOT met"
    peak = "met" if figures.peak_rss_mb <= PEAK_GOAL_MB else "NOT met"
    return (f"{figures.cases:>7,} cases against the goals: first row {figures.first_row_s:.2f} s <= "
            f"{FIRST_ROW_GOAL_S:g} s {first}; peak RSS {figures.peak_rss_mb:.0f} MB <= {PEAK_GOAL_MB:g} MB {peak}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--large", action="store_true", help="also 10^5 cases (minutes)")
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--sizes", type=int, nargs="*", default=None, help="case counts (default 1000 10000)")
    parser.add_argument("--table", default="json", choices=("json", "csv", "parquet"),
                        help="the sweep's --table (default json, the sweep's default)")
    args = parser.parse_args()
    sizes = args.sizes or [1_000, 10_000, *([GOAL_CASES] if args.large else [])]
    print(f"uplift sweep ... --table {args.table} --workers {args.workers}", flush=True)
    baseline = measure(100, args.workers, args.table)
    print(report(baseline, baseline), flush=True)
    for cases in sizes:
        figures = measure(cases, args.workers, args.table)
        print(report(figures, baseline), flush=True)
        if cases >= GOAL_CASES:
            print(against_goals(figures), flush=True)


if __name__ == "__main__":
    main()
