"""Running a planned sweep for `uplift sweep` and `uplift spectra`: the executor --workers,
--scheduler and --dask ask for (or the plan's size decides), the local workers started early,
the progress display, the --out checks (earlier rows need --resume or --overwrite) and the exit
on an interruption (128 + the signal, the finished rows kept)."""

from __future__ import annotations

import signal
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from ..errors import InputError
from ..runtime.atomic import refuse_existing, refuse_inputs
from ..sweep.signals import ignore_stop_signals
from . import stdout
from .options import check_out_directory, not_writable
from .sweep_options import check_workers

if TYPE_CHECKING:
    from ..sweep.plan import SweepPlan

#: rough cost of one case [s], to decide whether worker processes pay for their start-up (about 1 s of one
#: core for the warm server, sweep/warm.py, and their chunks' transfer)
CASE_SECONDS = {"simplified": 0.002, "approximate": 0.04, "exact": 0.04}


def choose_executor(plan: SweepPlan, workers: int | None, scheduler: str | None, dask: str | None):
    """The executor --dask, --scheduler or --workers ask for; without them the plan's size decides."""
    if dask not in (None, "local"):
        raise InputError("--dask", dask, "'local' (or give --scheduler tcp://host:port)")
    if scheduler is not None or dask is not None:
        return _dask_executor(scheduler, workers)
    if workers is not None:
        return _local_executor(workers)
    return _executor_for_size(plan)


def _dask_executor(scheduler: str | None, workers: int | None):
    """A Dask cluster: the one at --scheduler (reachable at once, before any file is written), or a
    local one of --workers processes (default: the cores, at most 4)."""
    from ..runtime.process import available_cores
    from ..sweep.dask_executor import DaskExecutor, check_reachable, import_distributed

    import_distributed()  # the extra is installed, before anything runs
    address = None if scheduler in (None, "local") else scheduler
    if address is not None:
        check_reachable(address)
    return DaskExecutor(address, workers or min(available_cores(), 4))


def _local_executor(workers: int):
    """--workers N: this process for N = 1, else N local worker processes."""
    from ..sweep.executors import ProcessExecutor, SerialExecutor

    check_workers(workers)
    return SerialExecutor() if workers == 1 else ProcessExecutor(workers)


def _executor_for_size(plan: SweepPlan):
    """Local worker processes on all cores when the sweep is long enough to gain from them, else this process."""
    from ..runtime.process import available_cores
    from ..sweep.executors import ProcessExecutor, SerialExecutor

    cores = available_cores()
    return ProcessExecutor(cores) if cores > 1 and _estimated_seconds(plan) > 4.0 else SerialExecutor()


def _estimated_seconds(plan: SweepPlan) -> float:
    """The rough cost of the plan in this process [s] (CASE_SECONDS; a suite case runs every record)."""
    seconds = len(plan.cases) * max(CASE_SECONDS.get(engine, 0.04) for engine in plan.engines)
    return seconds * max(1, plan.suite_records)


def progress_for(quiet: bool, label: str):
    from ..sweep.run import NoProgress
    from . import render
    from .sweep_render import PlainProgress, RichProgress, use_rich_progress

    if quiet:
        return NoProgress()
    console = render.console(stderr=True)
    return RichProgress(console, label) if use_rich_progress(console) else PlainProgress(label)


def _prepare_out(plan: SweepPlan, out: Path, rows_path: Path, resume: bool, overwrite: bool) -> None:
    """--out a directory; the rows of an earlier run of this sweep need --resume or --overwrite;
    those of another sweep (another deck, other varied fields: the same --name) are refused, even
    with --resume (which would replace that sweep's tables with this one's)."""
    check_out_directory(out)
    if overwrite or not rows_path.exists() or rows_path.stat().st_size == 0:
        return
    from ..sweep.store import RowStore

    store = RowStore(rows_path)
    cases, other = len(store.scan()), _other_sweep(plan, store)
    if other:
        raise InputError("--out", str(rows_path), f"holds the rows of another sweep ({cases} cases {other}), "
                         "not of this one: give this sweep its own --name, or another --out folder")
    if not resume:
        raise InputError("--out", str(rows_path), f"holds the rows of an earlier run of this sweep ({cases} "
                         "cases): pass --resume to continue that run, or --overwrite to discard them and start "
                         "again")


def _other_sweep(plan: SweepPlan, store) -> str:
    """How the sweep whose rows the store holds differs from the plan ('varying foundation.k_f;
    this one varies building.period'), or '' when it is this sweep: a deck of the same file name
    (given from another folder or not) and the same varied fields (the same values or not:
    --resume then runs the cases it lacks)."""
    decks = _earlier_decks(store)
    varied, mine = _earlier_varied(store), sorted(v.path for v in plan.varies)
    if decks and Path(plan.source).name not in {Path(deck).name for deck in decks}:  # run from elsewhere: the same
        return f"of {', '.join(decks)}; this sweep is of {plan.source}"
    return f"varying {_fields(varied)}; this one varies {_fields(mine)}" if varied != mine else ""


def _earlier_decks(store) -> list[str]:
    """The decks of the runs whose headers the rows file holds."""
    return sorted({str(run.get("deck")) for run in store.runs().values()})


def _earlier_varied(store) -> list[str]:
    """The varied fields of the rows file's rows: their dotted keys (no output column has a dot)."""
    return sorted(store.fields())


def _refuse_other_table(plan: SweepPlan, table: Path) -> None:
    """A table of another sweep under this stem (its rows file gone: --resume would replace it) refused,
    as its rows would be (_prepare_out)."""
    varied, mine = _table_varied(table), sorted(v.path for v in plan.varies)
    if varied is not None and varied != mine:
        raise InputError("--out", str(table), f"holds the table of another sweep (varying {_fields(varied)}; this "
                         f"one varies {_fields(mine)}), not of this one: give this sweep its own --name, or another "
                         "--out folder")


def _table_varied(table: Path) -> list[str] | None:
    """The varied fields of a sweep's CSV table (its dotted columns), None without one."""
    try:
        with open(table, encoding="utf-8") as handle:
            header = next((line for line in handle if not line.startswith("#")), "")
    except (OSError, UnicodeDecodeError):
        return None
    return sorted(name for name in header.strip().split(",") if "." in name)


def _fields(paths: list[str]) -> str:
    """The varied fields as a list in words ('no field' for none)."""
    return ", ".join(paths) if paths else "no field"


def output_paths(out: Path, stem: str, extra=()) -> list[Path]:
    """The files a sweep writes under --out (rows, tables and any figures)."""
    return [out / f"{stem}{suffix}" for suffix in (".rows.jsonl", ".csv", ".json", ".parquet")] + list(extra)


def warm_workers_early(workers: int | None, scheduler: str | None, dask: str | None) -> None:
    """Start the warm server of local worker processes now, before the deck is read and the cases
    planned, when they are likely (more than one core, neither --workers 1 nor Dask; `uplift
    sweep` asks only with --workers N): it imports the engines on another core meanwhile. A sweep
    that then runs in this process leaves it unused (it ends with this process)."""
    if not _workers_likely(workers, scheduler, dask):
        return
    from ..sweep.executors import ProcessExecutor

    ProcessExecutor(workers or 2).prestart()


def _workers_likely(workers: int | None, scheduler: str | None, dask: str | None) -> bool:
    """Local worker processes are likely to run: no Dask, and --workers N > 1 or (not given) more than one core."""
    if scheduler is not None or dask is not None:
        return False
    if workers is not None:
        return workers > 1
    from ..runtime.process import available_cores

    return available_cores() >= 2


def head_start(executor, figures: bool) -> None:
    """Local worker processes: start their warm server (it imports and loads the engines, about
    0.25 s of one core) if warm_workers_early did not, and import matplotlib in a thread of this
    process when figures follow the run (this process only waits on the workers meanwhile).
    Measured on the Fig. 3 spectrum with warm_workers_early, 10 runs of each on 2 cores: 2.07 ->
    1.94 s end to end (median)."""
    prestart = getattr(executor, "prestart", None)
    if prestart is None:
        return
    prestart()
    if figures:
        from ..figures import draw as plots

        plots.preload(background=True)


def execute(plan: SweepPlan, out: Path, stem: str, *, workers, scheduler, dask, resume, retry_failed,
            overwrite, quiet, label, rerun_stale=False, figures_written=(), tables=()):
    """Run the plan with progress (the caller holds stem_lock); exit 128 + the signal (130 for
    Ctrl-C, 143 for SIGTERM, 129 for SIGHUP) keeping the rows when interrupted; the outcome keeps
    the cases' keys, not their rows (stored_rows reads them back). figures_written:
    the figures that follow the run (their paths); tables: the tables it writes (both refused if
    they exist, unless overwrite or resume)."""
    from ..sweep.run import run_sweep
    from ..sweep.store import RowStore

    rows_path = out / f"{stem}.rows.jsonl"
    _refuse_outputs(plan, out, stem, rows_path, resume, overwrite, figures_written, tables)
    executor = choose_executor(plan, workers, scheduler, dask)
    head_start(executor, bool(figures_written))
    try:
        outcome = run_sweep(plan, executor, RowStore(rows_path), resume=resume, retry_failed=retry_failed,
                            rerun_stale=rerun_stale, progress=progress_for(quiet, label), exit_on_stop=True,
                            keep_rows=False)
    except OSError as error:  # a full disk: the rows written so far are kept
        kept = len(RowStore(rows_path).scan())
        raise not_writable("--out", out, error, more=f"; {kept} finished rows are kept in {rows_path}: run the "
                           "same command with --resume once there is room") from None
    if outcome.interrupted:
        _exit_interrupted(outcome, rows_path)
    return outcome


def stored_rows(plan: SweepPlan, out: Path, stem: str, outcome):
    """The rows of a finished run in case order, read back from its rows file one at a time each time they are
    iterated (run_sweep keeps their keys only: a sweep's rows are never all in memory)."""
    from ..sweep.run import stored_rows as read_back
    from ..sweep.store import RowStore

    return read_back(plan, RowStore(out / f"{stem}.rows.jsonl"), outcome)


def _refuse_outputs(plan: SweepPlan, out: Path, stem: str, rows_path: Path, resume: bool, overwrite: bool,
                    figures_written, tables) -> None:
    """No output may be an input of the plan; earlier rows, tables and figures need --resume or --overwrite."""
    refuse_inputs(output_paths(out, stem, figures_written), plan.input_files, "--out")
    _prepare_out(plan, out, rows_path, resume, overwrite)
    if not overwrite:
        _refuse_other_table(plan, out / f"{stem}.csv")
    if not resume:  # --resume finishes an earlier run: its tables and figures are written again
        refuse_existing([*tables, *figures_written], "--out", overwrite, ": written by an earlier run; --resume "
                        "continues that run")


def _exit_interrupted(outcome, rows_path: Path) -> None:
    """An interrupted run: the rows kept named on stderr, exit 128 + the signal."""
    ignore_stop_signals()  # a second Ctrl-C while exiting changes nothing
    name = signal.Signals(outcome.signal).name if outcome.signal else "SIGINT"
    stdout.echo(f"interrupted ({name}): {outcome.finished} of {outcome.total} cases are kept in {rows_path}; "
               "run the same command with --resume to finish", err=True)
    raise typer.Exit(128 + (outcome.signal or signal.SIGINT))
