"""Benchmark: throughput of a 500-case exact sweep (the paper's ten-story building under El Centro
1940 N-S, uplift support, 25 foundation stiffnesses x 20 periods) on 1 and 2 local workers.

Prints cases per second for the serial executor (1 worker, in this process), the same without
batching the cases that share a structure (one case per chunk), for 2 local worker processes
(start-up included: spawning, imports) and the
speed-up, and checks that both give the same rows. Optionally the same on a Dask LocalCluster.

    python benchmarks/bench_sweep.py [--cases 500] [--dask]
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path

from upliftcli.runtime.process import available_cores, keep_freed_memory
from upliftcli.sweep.dask_executor import DaskExecutor
from upliftcli.sweep.executors import ProcessExecutor, SerialExecutor
from upliftcli.sweep.plan import plan_sweep
from upliftcli.sweep.run import run_sweep
from upliftcli.sweep.store import RowStore

DECK = Path(__file__).resolve().parent.parent / "inputs" / "ten_story_elcentro.toml"


def plan_for(cases: int, supports=("uplift",)):
    periods = max(1, round(cases / 25 / len(supports)))
    plan = plan_sweep(DECK, [], ["foundation.frequency_ratio=2:20:25:log", f"building.period=0.2:3:{periods}"],
                      ["exact"], list(supports))
    plan.cases = plan.cases[:cases]
    return plan


class Stamps:
    """Progress hook recording when each row arrives."""

    def __init__(self):
        self.times = []

    def start(self, total, done):
        pass

    def advance(self, row):
        self.times.append(time.perf_counter())

    def stop(self):
        pass

    def steady_rate(self) -> float:
        """Rows per second between the first and the last row (start-up excluded)."""
        return (len(self.times) - 1) / (self.times[-1] - self.times[0])


def timed_run(plan, executor, directory: Path, name: str, size: int | None = None):
    stamps = Stamps()
    start = time.perf_counter()
    outcome = run_sweep(plan, executor, RowStore(directory / f"{name}.jsonl"), progress=stamps, size=size)
    seconds = time.perf_counter() - start
    failed = sum(row["status"] != "ok" for row in outcome.rows)
    return outcome.rows, seconds, failed, stamps.steady_rate()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=500)
    parser.add_argument("--dask", action="store_true", help="also on a Dask LocalCluster of 2 workers")
    parser.add_argument("--supports", default="uplift", help="support conditions, e.g. rigid,bonded,uplift")
    args = parser.parse_args()
    keep_freed_memory()  # as `uplift sweep` does (its local workers do it themselves)
    plan = plan_for(args.cases, args.supports.split(","))
    n = len(plan.cases)
    print(f"{n} exact cases ({args.supports} support, {DECK.name}), {available_cores()} cores available")
    warm = plan_for(2)
    run_sweep(warm, SerialExecutor(), RowStore(Path(tempfile.mkdtemp()) / "warm.jsonl"))  # JIT cache, record
    with tempfile.TemporaryDirectory() as tmp:
        directory = Path(tmp)
        serial, serial_s, failed, serial_rate = timed_run(plan, SerialExecutor(), directory, "serial")
        print(f"1 worker  (serial)     : {serial_s:7.2f} s  {n / serial_s:7.1f} cases/s  ({failed} failed)")
        alone, alone_s, failed, _ = timed_run(plan, SerialExecutor(), directory, "alone", size=1)
        print(f"1 worker, no batches   : {alone_s:7.2f} s  {n / alone_s:7.1f} cases/s  ({failed} failed; one case "
              f"per chunk: batching by structure gains {alone_s / serial_s:.2f} x, identical rows: {alone == serial})")
        parallel, parallel_s, failed, parallel_rate = timed_run(plan, ProcessExecutor(2), directory, "processes")
        print(f"2 workers (processes)  : {parallel_s:7.2f} s  {n / parallel_s:7.1f} cases/s  ({failed} failed)")
        print(f"speed-up over 1 worker : {serial_s / parallel_s:7.2f} x overall (start-up of the 2 processes "
              f"included), {parallel_rate / serial_rate:.2f} x once running "
              f"({serial_rate:.1f} -> {parallel_rate:.1f} cases/s)")
        print(f"identical rows         : {parallel == serial}")
        if args.dask:
            rows, dask_s, failed, dask_rate = timed_run(plan, DaskExecutor(None, 2), directory, "dask")
            print(f"2 workers (Dask local) : {dask_s:7.2f} s  {n / dask_s:7.1f} cases/s overall, {dask_rate:.1f} "
                  f"once running ({failed} failed), identical rows: {rows == serial}")
    per_case = 1e3 * serial_s / n
    print(f"per case (serial)      : {per_case:7.1f} ms; ideal 2-worker time {serial_s / 2:.2f} s "
          f"(+ ~{max(0.0, parallel_s - serial_s / 2):.1f} s start-up and overhead)")
    assert math.isfinite(per_case)


if __name__ == "__main__":
    main()
