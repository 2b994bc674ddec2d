"""Running a sweep: the driver that feeds an executor the unfinished cases, appends every
row to the store as it arrives and handles Ctrl-C.

Resume rule: `--resume` keeps the 'ok' rows of the cases still in the sweep and the 'failed'
rows too (an analysis that raised fails again: it is reported, not retried) unless
`retry_failed`; 'crashed' rows (the worker died) are run again. A row computed from other
inputs than the plan's (a record file whose SHA-256 changed, another tool version: its
fingerprint differs, plan.run_fingerprint) is refused with a message, or run again with
`rerun_stale`.

Signals (sweep/signals.py): SIGTERM and SIGHUP stop a sweep like Ctrl-C (the rows written
are kept; the outcome names the signal); once one has arrived, further ones are ignored
until the executor has stopped its workers, so a second Ctrl-C cannot cut the clean-up short.
"""

from __future__ import annotations

import signal
from dataclasses import dataclass

from ..errors import InputError
from .chunks import chunk_size, stream_chunks
from .plan import SweepPlan
from .signals import Interrupted, ignore_stop_signals, stop_signals_interrupt  # noqa: F401 - interface
from .store import RowStore


@dataclass
class SweepOutcome:
    """rows: one per finished case, in case order; reused: rows kept from a previous run;
    signal: the stop signal of an interrupted run (signal.SIGINT for Ctrl-C)."""

    rows: list[dict]
    total: int
    reused: int
    interrupted: bool
    signal: int = 0


class NoProgress:
    def start(self, total: int, done: int) -> None: ...
    def advance(self, row: dict) -> None: ...
    def stop(self) -> None: ...


def _without_fingerprint(row: dict) -> dict:
    return {name: value for name, value in row.items() if name != "fingerprint"}


def _stale_reason(plan: SweepPlan, header: dict | None) -> str:
    """Why rows with another fingerprint differ from the plan's, in words."""
    if header is None:
        return "by a run that recorded no fingerprint of its inputs (an older version of uplift)"
    changed = _changed_records(plan, header)
    if changed:
        return f"from another content of the record {changed[0]} (its SHA-256 changed)"
    if header.get("version") != plan.version:
        return f"by uplift {header.get('version')} (this is {plan.version})"
    return "from other inputs (another record file or deck)"


def _changed_records(plan: SweepPlan, header: dict) -> list[str]:
    """The plan's record files that a run's header gives another SHA-256."""
    recorded = header.get("records", {})
    return [path for path, digest in plan.records.items() if recorded.get(path) not in (None, digest)]


def _kept(plan: SweepPlan, row: dict, retry_failed: bool) -> bool:
    """Whether --resume keeps a row: of the plan's inputs, and 'ok', or 'failed' unless retry_failed."""
    if not _of_plan(plan, row):
        return False
    return row["status"] == "ok" or (row["status"] == "failed" and not retry_failed)


def _plan_rows(plan: SweepPlan, store: RowStore) -> dict[str, dict]:
    """The rows of `store` whose case is in the plan."""
    keys = {case.key for case in plan.cases}
    return {key: row for key, row in store.read().items() if key in keys}


def _of_plan(plan: SweepPlan, row: dict) -> bool:
    """Whether a stored row was computed from the plan's inputs (its fingerprint)."""
    return row.get("fingerprint") == plan.fingerprint


def resumable_rows(plan: SweepPlan, store: RowStore, retry_failed: bool, rerun_stale: bool) -> dict[str, dict]:
    """The rows of `store` that --resume keeps (see the module docstring); InputError naming
    --resume if some of the plan's cases were computed from other inputs, unless rerun_stale."""
    rows = _plan_rows(plan, store)
    if not rerun_stale:
        _refuse_stale(plan, store, rows)
    return {key: _without_fingerprint(row) for key, row in rows.items() if _kept(plan, row, retry_failed)}


def _refuse_stale(plan: SweepPlan, store: RowStore, rows: dict[str, dict]) -> None:
    """InputError naming --resume if some rows were computed from other inputs, and why (_stale_reason)."""
    stale = [row for row in rows.values() if not _of_plan(plan, row)]
    if not stale:
        return
    reason = _stale_reason(plan, store.runs().get(str(stale[0].get("fingerprint"))))
    raise InputError("--resume", str(store.path), f"rows computed from the inputs of this run; {len(stale)} "
                     f"rows were computed {reason}: pass --rerun-stale to run them again or --overwrite to "
                     "start over")


class _Arrivals:
    """The rows of a run: those kept, then each arriving case's first row, appended to the store
    (with the plan's fingerprint) and counted by the progress."""

    def __init__(self, plan: SweepPlan, store: RowStore, progress, kept: dict[str, dict]):
        self.plan = plan
        self.store = store
        self.progress = progress
        self.rows = dict(kept)
        self.delivered: set[str] = set()

    def on_row(self, row: dict) -> None:
        if row["key"] in self.delivered:
            return
        self.delivered.add(row["key"])
        self.store.append(row, self.plan.fingerprint)
        self.rows[row["key"]] = row
        self.progress.advance(row)

    def add_written(self) -> None:
        """Add the rows of the plan's inputs the store holds and the run has not recorded (Ctrl-C may
        land between writing a row and recording it: the file is the truth)."""
        written = _plan_rows(self.plan, self.store)
        self.rows.update({key: _without_fingerprint(row) for key, row in written.items()
                          if key not in self.rows and _of_plan(self.plan, row)})


def _run_header(plan: SweepPlan) -> dict:
    """The header line of a run in the store: what its rows were computed from."""
    return {"fingerprint": plan.fingerprint, "deck": plan.source, "records": plan.records, "version": plan.version}


def _execute(plan: SweepPlan, executor, kept: dict, size: int | None, exit_on_stop: bool, on_row) -> int | None:
    """Run the cases not kept on the executor in chunks made as they are needed (stream_chunks);
    the stop signal that interrupted it (None: finished)."""
    todo = len(plan.cases) - len(kept)  # the kept rows are the plan's (_plan_rows)
    try:
        with stop_signals_interrupt(stay_ignored=exit_on_stop):
            chunks = stream_chunks(plan, kept, size or chunk_size(todo, getattr(executor, "workers", 1)))
            executor.run(chunks, on_row)
    except KeyboardInterrupt as error:
        return getattr(error, "signum", int(signal.SIGINT))
    return None


def _in_case_order(plan: SweepPlan, rows: dict[str, dict]) -> list[dict]:
    """The rows of the plan's cases (key -> row), in case order."""
    return [rows[case.key] for case in plan.cases if case.key in rows]


def run_sweep(plan: SweepPlan, executor, store: RowStore, *, resume: bool = False, retry_failed: bool = False,
              rerun_stale: bool = False, progress=None, size: int | None = None,
              exit_on_stop: bool = False) -> SweepOutcome:
    """Run the cases not finished yet, appending each row to `store` as it arrives.

    resume: keep the rows of `store` whose case is in the plan: 'ok' rows always, 'failed'
    rows unless retry_failed; 'crashed' rows are run again; rows of other inputs are refused
    unless rerun_stale (resumable_rows). Ctrl-C, SIGTERM or SIGHUP stops the executor and
    returns what was kept (interrupted=True); exit_on_stop: the caller exits then, so the stop
    signals stay ignored (signals.stop_signals_interrupt). An OSError of the store (a full disk) stops the
    executor and is raised; the rows written before it are kept."""
    progress = progress or NoProgress()
    kept = resumable_rows(plan, store, retry_failed, rerun_stale) if resume else {}
    arrivals = _Arrivals(plan, store, progress, kept)
    store.open(fresh=not resume, header=_run_header(plan))
    progress.start(len(plan.cases), len(kept))
    stop_signal, finished = None, False
    try:
        stop_signal = _execute(plan, executor, kept, size, exit_on_stop, arrivals.on_row)
        finished = stop_signal is None
    finally:
        store.close(discard_if_empty=not finished)
        progress.stop()
    if not finished:
        arrivals.add_written()
    return SweepOutcome(_in_case_order(plan, arrivals.rows), len(plan.cases), len(kept), not finished,
                        stop_signal or 0)
