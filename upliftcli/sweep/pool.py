"""The parent's side of running cases on workers: each case's first row handed on once
(Delivered), the messages of a pool of local workers (Messages: cases started, heartbeats,
rows), and what is left of a chunk after its worker died (after_death). Used by
sweep/executors.py (local processes) and sweep/dask_executor.py (Delivered).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from concurrent.futures.process import BrokenProcessPool
from typing import Any

from .chunks import Chunk
from .plan import Case
from .signals import deferred

#: called with each finished row
OnRow = Callable[[dict], None]


class Delivered:
    """The rows handed on so far, each case's first only (a retried case may report twice), and
    the attempts charged to each case (its worker died while it ran alone)."""

    def __init__(self, on_row: OnRow):
        self.on_row = on_row
        self.done: set[str] = set()
        self.attempts: dict[str, int] = {}

    def deliver(self, row: dict) -> None:
        if row["key"] not in self.done:
            self.done.add(row["key"])
            self.on_row(row)

    def charge(self, key: str) -> int:
        """Charge a case one attempt; the attempts so far."""
        self.attempts[key] = self.attempts.get(key, 0) + 1
        return self.attempts[key]


def after_death(chunk: Chunk, started: set[str], done: set[str]) -> tuple[list[Case], list[Case]]:
    """The cases of a chunk lost to a dead worker, still without a row: (suspects, the ones that
    were running, or all if none had started; the others)."""
    rest = chunk.unfinished(done)
    suspects = [case for case in rest if case.key in started or not started]
    return suspects, [case for case in rest if case not in suspects]


class Messages:
    """The messages of a pool's workers: cases started, heartbeats (worker pid -> time of its last
    heartbeat, or of its first sight) and rows."""

    def __init__(self, queue, started: set[str], deliver: OnRow):
        self.queue = queue
        self.started = started
        self.deliver = deliver
        self.beats: dict[int, float] = {}

    def drain(self) -> None:
        """Handle every message waiting in the queue."""
        while True:
            with deferred():  # a stop signal never cuts a message read from the pipe in half
                if self.queue.empty():
                    return
                self._handle(*self.queue.get())

    def _handle(self, kind: str, value) -> None:
        if kind == "start":
            self.started.update(value)
        elif kind == "beat":
            self.beats[value] = time.monotonic()
        else:
            self.deliver(value)


def processes(pool) -> list[tuple[int, Any]]:
    """(pid, process) of the pool's worker processes."""
    return list(getattr(pool, "_processes", {}).items())


def deliver_result(future, deliver: OnRow) -> bool:
    """Deliver the rows of a finished chunk; False if its pool broke (a worker died)."""
    try:
        rows = future.result()
    except BrokenProcessPool:
        return False
    with deferred():
        for row in rows:
            deliver(row)
    return True


def stop_pool(pool, messages: Messages) -> None:
    """Keep what arrived and stop the workers now (SIGKILL: they ignore SIGINT/SIGHUP, and a worker
    blocked writing dies too); draining may fail again (the disk is still full): the workers are
    stopped all the same."""
    try:
        messages.drain()
    finally:
        for _, process in processes(pool):
            process.kill()
        pool.shutdown(wait=False, cancel_futures=True)
