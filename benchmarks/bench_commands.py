"""Benchmark: what a user waits for at the command line (issue 14), each target as a ratio to a
baseline measured in the same run: the interpreter start with numpy, `python -c "import numpy"`.

Every command runs in a fresh process, `--repeats` times, interleaved with the baseline (the
machine is shared: medians and ranges). Warm: one untimed run first (the .pyc files exist). First
run (cold): no bytecode (PYTHONPYCACHEPREFIX set to a new directory, a worse case than after an
install, where pip has written the .pyc files; the compiled loops are C extensions built at
install, so nothing else is compiled at run time); with --venv DIR, the commands of that virtual
environment instead (make one with `python3 -m venv DIR && DIR/bin/pip install .`; its first
runs are then the real first runs, --repeats 1).
The Fig. 3 spectrum: end to end with its three PNGs, and its analysis part
(run_sweep in a fresh process after what `uplift spectra` does before it: the allocator set as the
command sets it (process.py); with 2 local workers their warm server started and ready, after an
untimed two-case run on either; the command also imports matplotlib in a thread while the workers
run, left out here) on 1 and 2 workers, overall and between the first and the last row.

    python benchmarks/bench_commands.py [--repeats 5] [--only help,modes,...] [--venv DIR]
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
DESIGN_DECK = str(ROOT / "inputs" / "ten_story_asce7.toml")
FIG3 = ["spectra", README_DECK, "--periods", "0.05:5:100", "--engine", "exact", "--quiet", "--overwrite"]

#: name -> (arguments of uplift, first run (no bytecode)?, target: ("ratio", r) or ("seconds", s))
TARGETS = {
    "help": (["--help"], False, ("ratio", 2.5)),
    "modes": (["modes", README_DECK], False, ("seconds", 0.5)),
    "readme": (["analyze", README_DECK], False, ("seconds", 0.5)),  # with the exact engine's check (a record)
    "readme-no-check": (["analyze", README_DECK, "--no-check"], False, ("seconds", 0.5)),  # the simplified engine
    "exact": (["analyze", README_DECK, "--engine", "exact"], False, None),
    "first-design-spectrum": (["analyze", DESIGN_DECK], True, ("seconds", 3.0)),
    "first-readme": (["analyze", README_DECK], True, ("seconds", 5.0)),
    "first-readme-no-check": (["analyze", README_DECK, "--no-check"], True, ("seconds", 3.0)),
    "first-exact": (["analyze", README_DECK, "--engine", "exact"], True, ("seconds", 5.0)),
    "fig3": (FIG3, False, ("seconds", 1.5)),
}

ANALYSIS_PART = """
import sys, tempfile, time
from pathlib import Path
from upliftcli.sweep.executors import ProcessExecutor, SerialExecutor
from upliftcli.sweep.figures import period_vary
from upliftcli.sweep.plan import plan_sweep
from upliftcli.sweep.run import NoProgress, run_sweep
from upliftcli.sweep.store import RowStore

class Stamps(NoProgress):
    times = []
    def advance(self, row):
        self.times.append(time.perf_counter())

from upliftcli.process import keep_freed_memory
keep_freed_memory()  # as the uplift command does
workers = int(sys.argv[1])
plan = plan_sweep(sys.argv[2], (), (), ["exact"], (), varies=[period_vary("0.05:5:100")])
executor = SerialExecutor() if workers == 1 else ProcessExecutor(workers)
from upliftcli.cli.sweep import head_start
# as uplift spectra: the warm server started (and ready: a two-case run first, untimed, as the
# command's start-up and planning give it time to be); the matplotlib import that the command
# runs in a thread while the workers run is left out: this times the analysis alone
head_start(executor, figures=False)
warm_up = plan_sweep(sys.argv[2], (), (), ["exact"], ["rigid"], varies=[period_vary("1:2:2")])
run_sweep(warm_up, executor, RowStore(Path(tempfile.mkdtemp()) / "rows.jsonl"))
Stamps.times.clear()
start = time.perf_counter()
outcome = run_sweep(plan, executor, RowStore(Path(tempfile.mkdtemp()) / "rows.jsonl"), progress=Stamps())
seconds = time.perf_counter() - start
assert len(outcome.rows) == 300 and all(row["status"] == "ok" for row in outcome.rows)
print(seconds, (len(Stamps.times) - 1) / (Stamps.times[-1] - Stamps.times[0]))
"""


def uplift_command(python: str) -> list[str]:
    """The console script next to the interpreter (as a user runs it), else the same through -c."""
    script = Path(python).parent / "uplift"
    return [str(script)] if script.exists() else [python, "-c", "from upliftcli.cli import main; main()"]


def user_environment() -> dict:
    """This process's environment as a user's shell has it: PYTHONDONTWRITEBYTECODE removed (set
    on this project's machine, it makes every command compile its Python source again, about
    1 s for an exact analysis; pip writes the .pyc files of an installation, an editable one
    writes them at its first run)."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def timed(command: list[str], env: dict | None = None, cwd: str | None = None) -> float:
    start = time.perf_counter()
    done = subprocess.run(command, env=env, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed ({done.returncode}): {done.stderr.strip()[-500:]}")
    return seconds


def summary(values: list[float]) -> str:
    return f"{statistics.median(values):6.2f} s [{min(values):.2f}-{max(values):.2f}]"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--only", default=",".join([*TARGETS, "fig3-analysis"]),
                        help="comma list of: " + ", ".join([*TARGETS, "fig3-analysis"]))
    parser.add_argument("--venv", type=Path, default=None, help="run the commands of this virtual environment")
    args = parser.parse_args()
    chosen = [name.strip() for name in args.only.split(",") if name.strip()]
    python = str(Path(args.venv) / "bin" / "python") if args.venv else sys.executable
    uplift = uplift_command(python)
    baseline: list[float] = []
    out = tempfile.mkdtemp(prefix="bench_commands_")
    print(f"{python}; {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}; {args.repeats} repeats")
    print(f"{'':26s} {'median [range]':>22s}  {'/ baseline':>10s}  target")
    for name in chosen:
        if name == "fig3-analysis":
            continue
        argv, cold, target = TARGETS[name]
        argv = [*argv, "--out", out] if argv[0] == "spectra" else argv
        if not cold and args.venv is None:
            timed(uplift + argv, env=user_environment(), cwd=out)  # warm: the .pyc files exist
        times, paired = [], []
        for _ in range(1 if (cold and args.venv) else args.repeats):
            paired.append(timed([python, "-c", "import numpy"], env=user_environment()))
            env = user_environment()
            if cold and args.venv is None:
                env["PYTHONPYCACHEPREFIX"] = tempfile.mkdtemp(prefix="pycache_cold_")
            times.append(timed(uplift + argv, env=env, cwd=out))
        baseline += paired
        ratio = statistics.median(times) / statistics.median(paired)
        verdict = ""
        if target is not None:
            kind, limit = target
            value = ratio if kind == "ratio" else statistics.median(times)
            verdict = f"{'<=':s} {limit:g}{'x' if kind == 'ratio' else ' s'}: {'met' if value <= limit else 'NOT met'}"
        print(f"{name:26s} {summary(times):>22s}  {ratio:9.2f}x  {verdict}")
    if "fig3-analysis" in chosen:
        parts, rates = {}, {}
        for workers in (1, 2):
            values, steady = [], []
            for _ in range(args.repeats):
                done = subprocess.run([python, "-c", ANALYSIS_PART, str(workers), README_DECK], capture_output=True,
                                      text=True, check=True, env=user_environment())
                seconds, rate = (float(x) for x in done.stdout.split())
                values.append(seconds)
                steady.append(rate)
            parts[workers], rates[workers] = values, steady
            print(f"{f'fig3 analysis, {workers} worker(s)':26s} {summary(values):>22s}  "
                  f"({statistics.median(steady):.0f} cases/s between the first and the last row)")
        speedup = statistics.median(parts[1]) / statistics.median(parts[2])
        steady = statistics.median(rates[2]) / statistics.median(rates[1])
        print(f"{'fig3 analysis speed-up':26s} {speedup:8.2f}x overall (start-up included), {steady:.2f}x once "
              f"running (1 -> 2 workers)  >= 1.7x: {'met' if speedup >= 1.7 else 'NOT met'} overall, "
              f"{'met' if steady >= 1.7 else 'NOT met'} once running")
    if baseline:
        print(f"{'baseline (import numpy)':26s} {summary(baseline):>22s}  (all {len(baseline)} runs)")


if __name__ == "__main__":
    main()
