"""Running a sweep: the driver that feeds an executor the unfinished cases, appends every
row to the store as it arrives and handles Ctrl-C.

Resume rule: `--resume` keeps the 'ok' rows of the cases still in the sweep and the 'failed'
rows too (an analysis that raised fails again: it is reported, not retried) unless
`retry_failed`; 'crashed' rows (the worker died) are run again. A row computed from other
inputs than the plan's (a record file whose SHA-256 changed, another tool version: its
fingerprint differs, plan.run_fingerprint) is refused with a message, or run again with
`rerun_stale`.

Memory: the driver keeps the keys of the cases with a row, not the rows (keep_rows=False; the
API keeps them): the rows are read back from the store when they are needed (stored_rows), one
at a time.

Signals (sweep/signals.py): SIGTERM and SIGHUP stop a sweep like Ctrl-C (the rows written
are kept; the outcome names the signal); once one has arrived, further ones are ignored
until the executor has stopped its workers, so a second Ctrl-C cannot cut the clean-up short.
"""

from __future__ import annotations

import signal
from dataclasses import dataclass, field

from ..errors import InputError
from .chunks import chunk_size, stream_chunks
from .plan import SweepPlan
from .signals import Interrupted, ignore_stop_signals, stop_signals_interrupt  # noqa: F401 - interface
from .store import Entry, RowStore, StoredRows


@dataclass
class SweepOutcome:
    """rows: one per finished case, in case order (keep_rows; else none: stored_rows reads them);
    reused: rows kept from a previous run; signal: the stop signal of an interrupted run
    (signal.SIGINT for Ctrl-C); keys: the cases with a row (kept, arrived, or written before an
    interruption); finished: how many."""

    rows: list[dict]
    total: int
    reused: int
    interrupted: bool
    signal: int = 0
    keys: set[str] = field(default_factory=set)

    @property
    def finished(self) -> int:
        return len(self.keys)


class NoProgress:
    def start(self, total: int, done: int) -> None: ...
    def advance(self, row: dict) -> None: ...
    def stop(self) -> None: ...


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


def _kept(plan: SweepPlan, entry: Entry, retry_failed: bool) -> bool:
    """Whether --resume keeps a row: of the plan's inputs, and 'ok', or 'failed' unless retry_failed."""
    if not _of_plan(plan, entry):
        return False
    return entry.status == "ok" or (entry.status == "failed" and not retry_failed)


def _plan_entries(plan: SweepPlan, store: RowStore) -> dict[str, Entry]:
    """The last rows of `store` whose case is in the plan (where they are, status, fingerprint)."""
    keys = {case.key for case in plan.cases}
    return {key: entry for key, entry in store.scan().items() if key in keys}


def _of_plan(plan: SweepPlan, entry: Entry) -> bool:
    """Whether a stored row was computed from the plan's inputs (its fingerprint)."""
    return entry.fingerprint == plan.fingerprint


def resumable_keys(plan: SweepPlan, store: RowStore, retry_failed: bool, rerun_stale: bool) -> set[str]:
    """The cases whose rows in `store` --resume keeps (see the module docstring); InputError naming
    --resume if some of the plan's cases were computed from other inputs, unless rerun_stale."""
    entries = _plan_entries(plan, store)
    if not rerun_stale:
        _refuse_stale(plan, store, entries)
    return {key for key, entry in entries.items() if _kept(plan, entry, retry_failed)}


def _refuse_stale(plan: SweepPlan, store: RowStore, entries: dict[str, Entry]) -> None:
    """InputError naming --resume if some rows were computed from other inputs, and why (_stale_reason)."""
    stale = [entry for entry in entries.values() if not _of_plan(plan, entry)]
    if not stale:
        return
    reason = _stale_reason(plan, store.runs().get(str(stale[0].fingerprint)))
    raise InputError("--resume", str(store.path), f"rows computed from the inputs of this run; {len(stale)} "
                     f"rows were computed {reason}: pass --rerun-stale to run them again or --overwrite to "
                     "start over")


class _Arrivals:
    """The cases of a run with a row: those kept, then each arriving case's first row, appended to
    the store (with the plan's fingerprint) and counted by the progress; keep_rows: the arriving
    rows kept too (else only their keys)."""

    def __init__(self, plan: SweepPlan, store: RowStore, progress, kept: set[str], keep_rows: bool):
        self.plan = plan
        self.store = store
        self.progress = progress
        self.keys = set(kept)
        self.delivered: set[str] = set()
        self.rows: dict[str, dict] | None = {} if keep_rows else None

    def on_row(self, row: dict) -> None:
        if row["key"] in self.delivered:
            return
        self.delivered.add(row["key"])
        self.store.append(row, self.plan.fingerprint)
        self.keys.add(row["key"])
        if self.rows is not None:
            self.rows[row["key"]] = row
        self.progress.advance(row)

    def add_written(self) -> None:
        """Add the cases of the plan's inputs the store holds and the run has not recorded (Ctrl-C may
        land between writing a row and recording it: the file is the truth)."""
        self.keys.update(key for key, entry in _plan_entries(self.plan, self.store).items()
                         if _of_plan(self.plan, entry))

    def in_case_order(self) -> list[dict]:
        """The rows of the cases with one, in case order: those that arrived as they came, the others read
        back from the store (keep_rows; else none)."""
        if self.rows is None:
            return []
        stored = {row["key"]: row for row in self.store.rows_of(key for key in self.keys if key not in self.rows)}
        return [self.rows.get(case.key) or stored[case.key] for case in self.plan.cases if case.key in self.keys]


def _run_header(plan: SweepPlan) -> dict:
    """The header line of a run in the store: what its rows were computed from."""
    return {"fingerprint": plan.fingerprint, "deck": plan.source, "records": plan.records, "version": plan.version}


def _execute(plan: SweepPlan, executor, kept: dict, size: int | None, exit_on_stop: bool, on_row) -> int | None:
    """Run the cases not kept on the executor in chunks made as they are needed (stream_chunks);
    the stop signal that interrupted it (None: finished)."""
    todo = len(plan.cases) - len(kept)  # the kept rows are the plan's (_plan_entries)
    try:
        with stop_signals_interrupt(stay_ignored=exit_on_stop):
            chunks = stream_chunks(plan, kept, size or chunk_size(todo, getattr(executor, "workers", 1)))
            executor.run(chunks, on_row)
    except KeyboardInterrupt as error:
        return getattr(error, "signum", int(signal.SIGINT))
    return None


def stored_rows(plan: SweepPlan, store: RowStore, outcome: SweepOutcome) -> StoredRows:
    """The rows of the outcome's cases in case order, read back from `store` one at a time each time
    they are iterated (the rows of a run that kept only their keys)."""
    return store.rows_of(case.key for case in plan.cases if case.key in outcome.keys)


def run_sweep(plan: SweepPlan, executor, store: RowStore, *, resume: bool = False, retry_failed: bool = False,
              rerun_stale: bool = False, progress=None, size: int | None = None,
              exit_on_stop: bool = False, keep_rows: bool = True) -> SweepOutcome:
    """Run the cases not finished yet, appending each row to `store` as it arrives.

    resume: keep the rows of `store` whose case is in the plan: 'ok' rows always, 'failed'
    rows unless retry_failed; 'crashed' rows are run again; rows of other inputs are refused
    unless rerun_stale (resumable_keys). Ctrl-C, SIGTERM or SIGHUP stops the executor and
    returns what was kept (interrupted=True); exit_on_stop: the caller exits then, so the stop
    signals stay ignored (signals.stop_signals_interrupt). An OSError of the store (a full disk) stops the
    executor and is raised; the rows written before it are kept. keep_rows: the outcome holds the
    rows (else only their cases' keys: stored_rows reads them back)."""
    progress = progress or NoProgress()
    kept = resumable_keys(plan, store, retry_failed, rerun_stale) if resume else set()
    arrivals = _Arrivals(plan, store, progress, kept, keep_rows)
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
    return SweepOutcome(arrivals.in_case_order(), len(plan.cases), len(kept), not finished, stop_signal or 0,
                        arrivals.keys)
