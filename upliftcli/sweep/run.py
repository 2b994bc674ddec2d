"""Running a sweep: the driver that feeds an executor the unfinished cases, appends every
row to the store as it arrives and handles Ctrl-C.

Resume rule: `--resume` keeps the 'ok' rows of the cases still in the sweep and the 'failed'
rows too (an analysis that raised fails again: it is reported, not retried) unless
`retry_failed`; 'crashed' rows (the worker died) are run again.
"""

from __future__ import annotations

from dataclasses import dataclass

from .plan import SweepPlan, chunk_size, make_chunks
from .store import RowStore


@dataclass
class SweepOutcome:
    """rows: one per finished case, in case order; reused: rows kept from a previous run."""

    rows: list[dict]
    total: int
    reused: int
    interrupted: bool


class NoProgress:
    def start(self, total: int, done: int) -> None: ...
    def advance(self, row: dict) -> None: ...
    def stop(self) -> None: ...


def run_sweep(plan: SweepPlan, executor, store: RowStore, *, resume: bool = False, retry_failed: bool = False,
              progress=None, size: int | None = None) -> SweepOutcome:
    """Run the cases not finished yet, appending each row to `store` as it arrives.

    resume: keep the rows of `store` whose case is in the plan: 'ok' rows always, 'failed'
    rows unless retry_failed; 'crashed' rows are run again. Ctrl-C (KeyboardInterrupt) stops
    the executor and returns what was kept (interrupted=True)."""
    progress = progress or NoProgress()
    keys = {case.key for case in plan.cases}
    kept = {}
    if resume:
        for key, row in store.read().items():
            if key in keys and (row["status"] == "ok" or (row["status"] == "failed" and not retry_failed)):
                kept[key] = row
    todo = [case for case in plan.cases if case.key not in kept]
    rows = dict(kept)
    delivered: set[str] = set()

    def on_row(row: dict) -> None:
        if row["key"] in delivered:
            return
        delivered.add(row["key"])
        store.append(row)
        rows[row["key"]] = row
        progress.advance(row)

    store.open(fresh=not resume)
    progress.start(len(plan.cases), len(kept))
    interrupted = False
    try:
        executor.run(make_chunks(plan, todo, size or chunk_size(len(todo), getattr(executor, "workers", 1))), on_row)
    except KeyboardInterrupt:
        interrupted = True
    finally:
        store.close()
        progress.stop()
    if interrupted:  # Ctrl-C may land between writing a row and recording it: the file is the truth
        rows.update({key: row for key, row in store.read().items() if key in keys and key not in rows})
    ordered = [rows[case.key] for case in plan.cases if case.key in rows]
    return SweepOutcome(ordered, len(plan.cases), len(kept), interrupted)
