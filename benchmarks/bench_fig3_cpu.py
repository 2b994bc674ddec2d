"""Benchmark: the CPU time of the Fig. 3 spectrum end to end at one commit against another, both
measured in one run (issue 34: no more CPU than at the turn-3 commit 36da920).

The command is `uplift spectra inputs/ten_story_elcentro.toml --periods 0.05:5:100 --engine exact
--workers 1` (300 exact analyses, the CSV and JSON tables and three PNGs): one process does all
the work, so its CPU time (user + system, of the process and what it waited for) is the whole cost.
Each commit is checked out into a temporary worktree and its compiled loops built in place with
this interpreter (`setup.py build_ext --inplace`: the same compiler, flags and libraries for both);
each runs from its own tree (PYTHONPATH) under this interpreter, after one untimed run (the .pyc
files written); the build needs setuptools >= 77 in this interpreter, as pyproject.toml's build does
(`pip install 'setuptools>=77'`). The runs alternate, the order swapped every repeat (the machine is shared: the
ratio of each pair, then their median and range). On a loaded machine CPU time drifts by 10 % and
more; --instructions counts the instructions of one run of each instead (valgrind's callgrind: the
same count whatever else the machine does; about 50x slower), the run held to one CPU so that its
figures are drawn in its own process (a forked copy's count would repeat its parent's up to the fork).

    python benchmarks/bench_fig3_cpu.py [--base 36da920] [--head HEAD] [--repeats 7] [--instructions]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
FIG3 = ["spectra", str(ROOT / "inputs" / "ten_story_elcentro.toml"), "--periods", "0.05:5:100", "--engine", "exact",
        "--workers", "1", "--quiet", "--overwrite"]


def checkout(revision: str, where: Path) -> Path:
    """A worktree of `revision` at `where` with its compiled loops built in place."""
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-f", str(where), revision], check=True,
                   capture_output=True)
    built = subprocess.run([sys.executable, "setup.py", "-q", "build_ext", "--inplace"], cwd=where,
                           capture_output=True, text=True)
    if built.returncode != 0:
        raise SystemExit(f"building {revision} failed (setuptools >= 77?): {built.stderr.strip()[-400:]}")
    return where


def cpu_seconds(tree: Path, out: Path) -> float:
    """User + system seconds of one run of the Fig. 3 command from `tree`."""
    env = dict(os.environ, PYTHONPATH=str(tree), UPLIFT_BACKEND="compiled")
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run([sys.executable, "-c", "from upliftcli.cli import main; main()", *FIG3, "--out", str(out)],
                          cwd=out, env=env, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"{tree}: exit {done.returncode}: {done.stderr.strip()[-400:]}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def _one_cpu() -> None:
    """In the child: run on one CPU (figures/draw.py then draws every figure in this process)."""
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})


def instructions(tree: Path, out: Path) -> int:
    """Instructions executed by one run of the Fig. 3 command from `tree` on one CPU (valgrind
    --tool=callgrind)."""
    env = dict(os.environ, PYTHONPATH=str(tree), UPLIFT_BACKEND="compiled")
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    command = [sys.executable, "-c", "from upliftcli.cli import main; main()", *FIG3, "--out", str(out)]
    done = subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}/callgrind.%p", *command],
                          cwd=out, env=env, capture_output=True, text=True, preexec_fn=_one_cpu)
    if done.returncode != 0:
        raise SystemExit(f"{tree}: exit {done.returncode}: {done.stderr.strip()[-400:]}")
    return sum(int(line.split()[-1]) for line in done.stderr.splitlines() if "Collected :" in line)


def compare_instructions(trees: dict, scratch: Path, revisions: dict) -> None:
    """One run of each under callgrind: the instructions and their ratio."""
    counts = {label: instructions(tree, Path(tempfile.mkdtemp(dir=scratch))) for label, tree in trees.items()}
    for label, count in counts.items():
        print(f"{label} {revisions[label]:>10s}: {count / 1e9:.3f} G instructions")
    ratio = counts["head"] / counts["base"]
    print(f"head / base: {ratio:.4f} (target <= 1: {'met' if ratio <= 1.0 else 'NOT met'})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", default="36da920")
    parser.add_argument("--head", default="HEAD")
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--instructions", action="store_true", help="count instructions (callgrind) instead")
    args = parser.parse_args()
    scratch = Path(tempfile.mkdtemp(prefix="bench_fig3_"))
    trees = {}
    try:
        for label, revision in (("base", args.base), ("head", args.head)):
            trees[label] = checkout(revision, scratch / label)
            cpu_seconds(trees[label], Path(tempfile.mkdtemp(dir=scratch)))  # untimed: the .pyc files
        if args.instructions:
            compare_instructions(trees, scratch, {"base": args.base, "head": args.head})
            return
        times = {"base": [], "head": []}
        for repeat in range(args.repeats):
            for label in (("base", "head") if repeat % 2 == 0 else ("head", "base")):
                times[label].append(cpu_seconds(trees[label], Path(tempfile.mkdtemp(dir=scratch))))
        ratios = [h / b for h, b in zip(times["head"], times["base"], strict=True)]
        print(f"load average {os.getloadavg()[0]:.2f}; {args.repeats} pairs; CPU seconds (user + system)")
        for label, revision in (("base", args.base), ("head", args.head)):
            values = times[label]
            print(f"{label} {revision:>10s}: median {statistics.median(values):.3f} s "
                  f"[{min(values):.3f}-{max(values):.3f}]")
        print(f"head / base: median {statistics.median(ratios):.3f} [{min(ratios):.3f}-{max(ratios):.3f}] "
              f"(target <= 1: {'met' if statistics.median(ratios) <= 1.0 else 'NOT met'})")
    finally:
        for tree in trees.values():
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)], capture_output=True)
        subprocess.run(["rm", "-rf", str(scratch)])


if __name__ == "__main__":
    main()
