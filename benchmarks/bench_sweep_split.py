"""Benchmark (issue 35, item 6): where the yielding sweep's CPU goes, the exact engine against the rest.

The sweep of bench_yielding_stories.py (`uplift sweep` of the README example under El Centro x2, `-e exact
--vary building.period=0.4:0.8:100 --workers 1`: 300 analyses), elastic and yielding (building.
strength_coefficient = 0.4, hardening_ratio = 0.05), each in a fresh process, interleaved. In the child the
exact engine's work is timed (time.process_time): every step of engines.exact.iter_batch (the 300 analyses)
and the state-space models built before it (engine.model_for, called by the size check of analysis/run.py;
the engine takes them from its cache). The rest is the command's CPU time (user + system) less the engine's:
start-up, the plan, the decks, the checks, the rows, the tables.

It prints, per tree, the medians and the ratios (yielding / elastic) of the whole command, of the engine and
of the rest, then the sweep ratio the command would have with the engine at --engine-ratio times the elastic
engine (the rest as measured), and the engine ratio at which the sweep reaches the target 3.

    python benchmarks/bench_sweep_split.py [--repeats 3] [--tree PATH ...] [--engine-ratio 3]

--tree: the checkouts to measure (default: this one), interleaved run by run on a shared machine. Bytecode:
where PYTHONDONTWRITEBYTECODE is set, each tree gets a PYTHONPYCACHEPREFIX of its own under the temporary
folder, so that the .pyc files are written and kept, as for an installed tool.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import hashlib
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ELASTIC = ("analysis.engine=exact", "ground_motion.scale=2")
YIELDING = (*ELASTIC, "building.strength_coefficient=0.4", "building.hardening_ratio=0.05")
VARY = "building.period=0.4:0.8:100"
TARGET = 3.0

_ENGINE = {"cpu": 0.0, "inside": False}


def _timed_batch(batch):
    """engines.exact.iter_batch with the CPU time of each of its steps added to _ENGINE."""

    def timed(*args, **kwargs):
        steps = batch(*args, **kwargs)
        while True:
            start, _ENGINE["inside"] = time.process_time(), True
            try:
                item = next(steps)
            except StopIteration:
                return
            finally:
                _ENGINE["cpu"] += time.process_time() - start
                _ENGINE["inside"] = False
            yield item

    return timed


def _timed_models(build):
    """engine.model_for with its CPU time added to _ENGINE when called outside iter_batch (the size check)."""

    def timed(*args, **kwargs):
        if _ENGINE["inside"]:
            return build(*args, **kwargs)
        start = time.process_time()
        try:
            return build(*args, **kwargs)
        finally:
            _ENGINE["cpu"] += time.process_time() - start

    return timed


def child(out: str, arguments: list[str]) -> None:
    """Run `uplift ARGUMENTS` in this process with the exact engine timed; at exit write {"total", "engine"}
    [s of CPU] to `out` (the command ends the process with os._exit after the atexit handlers)."""
    import atexit

    import upliftcli.engines.exact as exact
    from upliftcli.engines.exact import engine

    exact.iter_batch = _timed_batch(exact.iter_batch)
    engine.model_for = _timed_models(engine.model_for)

    def write() -> None:
        times = os.times()
        Path(out).write_text(json.dumps({"total": times.user + times.system, "engine": _ENGINE["cpu"]}))

    atexit.register(write)
    sys.argv = ["uplift", *arguments]
    from upliftcli.__main__ import console

    console()


def _sweep(tree: Path, overrides: tuple[str, ...], out: Path, name: str) -> list[str]:
    deck = tree / "inputs" / "ten_story_elcentro.toml"
    sets = [item for value in overrides for item in ("--set", value)]
    return ["sweep", str(deck), *sets, "-e", "exact", "--vary", VARY, "--workers", "1", "-q", "--table", "csv",
            "--overwrite", "-o", str(out), "--name", name]


def _environment(tree: Path, scratch: Path) -> dict[str, str]:
    """The child's environment: the tree first on the path, its own bytecode folder where none is written."""
    env = {**os.environ, "PYTHONPATH": str(tree)}
    if env.pop("PYTHONDONTWRITEBYTECODE", None):
        env["PYTHONPYCACHEPREFIX"] = str(scratch / "pyc" / hashlib.sha256(str(tree).encode()).hexdigest()[:12])
    return env


def measure(tree: Path, overrides: tuple[str, ...], scratch: Path) -> dict[str, float]:
    """{"total", "engine", "rest"} [s of CPU] of one sweep in a fresh process."""
    name = "yielding" if overrides == YIELDING else "elastic"
    out = scratch / "split.json"
    command = [sys.executable, str(Path(__file__).resolve()), "--child", str(out), "--",
               *_sweep(tree, overrides, scratch / "tables", name)]
    done = subprocess.run(command, capture_output=True, text=True, env=_environment(tree, scratch), check=False,
                          cwd=scratch)
    if done.returncode not in (0, 3):
        raise SystemExit(f"the {name} sweep of {tree} failed ({done.returncode}): {done.stderr.strip()[-400:]}")
    times = json.loads(out.read_text())
    return {**times, "rest": times["total"] - times["engine"]}


def _report(tree: Path, samples: dict[str, list[dict[str, float]]], engine_ratio: float) -> None:
    """The medians and ratios of one tree, and the sweep ratio with the engine at engine_ratio."""
    median = {kind: {part: statistics.median(s[part] for s in runs) for part in ("total", "engine", "rest")}
              for kind, runs in samples.items()}
    elastic, yielding = median["elastic"], median["yielding"]
    print(f"{tree}")
    for part in ("total", "engine", "rest"):
        print(f"  {part:7} elastic {elastic[part]:6.3f} s  yielding {yielding[part]:6.3f} s  "
              f"ratio {yielding[part] / elastic[part]:5.2f}")
    projected = (engine_ratio * elastic["engine"] + yielding["rest"]) / elastic["total"]
    needed = (TARGET * elastic["total"] - yielding["rest"]) / elastic["engine"]
    print(f"  with the engine at {engine_ratio:g}x: sweep {projected:.2f}x; the sweep is {TARGET:g}x with the "
          f"engine at {needed:.2f}x")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="sweeps of each kind per tree")
    parser.add_argument("--tree", type=Path, action="append", help="a checkout to measure (repeatable)")
    parser.add_argument("--engine-ratio", type=float, default=3.0, help="the engine ratio to project the sweep at")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    options, rest = parser.parse_known_args()
    if options.child:
        child(options.child, rest[1:] if rest[:1] == ["--"] else rest)
        return
    trees = [tree.resolve() for tree in options.tree or [ROOT]]
    samples = {tree: {"elastic": [], "yielding": []} for tree in trees}
    with tempfile.TemporaryDirectory() as scratch:
        for tree in trees:  # untimed: the .pyc files, the record's cache
            measure(tree, ELASTIC, Path(scratch)), measure(tree, YIELDING, Path(scratch))
        for _ in range(options.repeats):
            for tree in trees:
                samples[tree]["elastic"].append(measure(tree, ELASTIC, Path(scratch)))
                samples[tree]["yielding"].append(measure(tree, YIELDING, Path(scratch)))
    for tree in trees:
        _report(tree, samples[tree], options.engine_ratio)
    print(f"load average {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
