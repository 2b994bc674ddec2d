"""Chunks of a sweep as tasks on a Dask cluster (a scheduler's address or a LocalCluster), with
the same rows as the local executors (sweep/executors.py).

On Dask, workers stream the start of each batch of cases and each case's row to the client
through a distributed.Queue, so finished cases are kept whatever happens to their chunk later. The
scheduler re-runs the task of a dead worker (distributed.scheduler.allowed-failures) and then
raises KilledWorker, also for tasks that were only queued on that worker: the cases that had
started are submitted again one per task (the one that kills its worker alone is marked
'crashed') and the cases not started yet are submitted again together.
"""

from __future__ import annotations

import contextlib
import json
import socket
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import replace

from ..errors import InputError
from .chunks import Chunk
from .executors import WORKER_ENVIRONMENT, OnRow, sigint_ignored
from .plan import Case
from .pool import Delivered
from .worker import failed_row, run_chunk


def check_reachable(address: str, timeout: float = 3.0) -> None:
    """InputError naming --scheduler at once if a tcp:// scheduler address does not accept
    connections (before any file is written; the Dask client would wait 20 s)."""
    scheme, sep, rest = address.partition("://")
    if not sep:
        scheme, rest = "tcp", address
    if scheme != "tcp":
        return  # tls://, ucx://, inproc://: left to the Dask client
    host, _, port = rest.rpartition(":")
    _connect(host.strip("[]") or "127.0.0.1", _port_number(port, address), timeout, address)


def _port_number(port: str, address: str) -> int:
    """The port of a tcp:// address (before any path); InputError naming --scheduler if not a number."""
    try:
        return int(port.split("/")[0])
    except ValueError:
        raise InputError("--scheduler", address, "an address tcp://host:port, e.g. tcp://10.0.0.5:8786") from None


def _connect(host: str, port: int, timeout: float, address: str) -> None:
    """Open and close a connection to the scheduler; InputError naming --scheduler if refused."""
    try:
        with socket.create_connection((host, port), timeout=timeout):
            pass
    except OSError as error:
        reason = error.strerror or str(error) or type(error).__name__
        raise InputError("--scheduler", address, f"a reachable Dask scheduler ({reason})") from None


def import_distributed():
    """dask.distributed, or an InputError naming the extra to install."""
    try:
        import distributed
    except ImportError:
        raise InputError("--scheduler", "dask", "the Dask extra installed: pip install 'upliftcli[dask]'") from None
    return distributed


class DaskExecutor:
    """Chunks as tasks on a Dask cluster: `address` (tcp://host:8786) or a LocalCluster of
    `workers` processes on loopback (address None)."""

    def __init__(self, address: str | None = None, workers: int = 2, connect_timeout: str = "20s",
                 poll_seconds: float = 0.1, runner: Callable = run_chunk):
        self.address = address
        self.runner = runner
        self.poll_seconds = poll_seconds
        self.workers = max(1, int(workers))
        self.connect_timeout = connect_timeout

    @contextlib.contextmanager
    def client(self):
        distributed = import_distributed()
        with contextlib.ExitStack() as stack:
            address = self.address if self.address is not None else self._local_cluster(stack, distributed)
            try:
                client = stack.enter_context(distributed.Client(address, timeout=self.connect_timeout))
            except (OSError, TimeoutError) as error:
                raise InputError("--scheduler", address, f"a reachable Dask scheduler ({error})") from None
            info = client.scheduler_info()
            self.workers = max(1, len(info.get("workers", {})) or self.workers)
            yield client

    def _local_cluster(self, stack: contextlib.ExitStack, distributed) -> str:
        """Start a LocalCluster of `workers` processes on loopback (closed with the stack); its address."""
        import logging

        with sigint_ignored():  # the worker processes inherit it: Ctrl-C is ours to handle
            cluster = stack.enter_context(distributed.LocalCluster(
                n_workers=self.workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                dashboard_address=":0", silence_logs=logging.ERROR, env=dict(WORKER_ENVIRONMENT)))
        return cluster.scheduler_address

    def run(self, chunks: Iterable[Chunk], on_row: OnRow) -> None:
        distributed = import_distributed()
        with self.client() as client:
            queue = distributed.Queue(client=client)  # rows stream through it case by case
            tasks = _Tasks(client, queue, self.runner, on_row)
            for chunk in chunks:
                tasks.submit(chunk)
            try:
                self._collect(distributed, tasks)
            except BaseException:
                tasks.stop()
                raise
            finally:
                with contextlib.suppress(Exception):
                    queue.close()

    def _collect(self, distributed, tasks: _Tasks) -> None:
        """Wait for the tasks, handing on the streamed rows every poll_seconds and each task's
        rows (or its failure) as it ends."""
        while tasks.futures:
            try:
                done, _ = distributed.wait(list(tasks.futures), timeout=self.poll_seconds,
                                           return_when="FIRST_COMPLETED")
            except TimeoutError:  # none finished within poll_seconds: collect the streamed rows
                done = []
            tasks.drain()
            for future in done:
                tasks.finish(future)
        tasks.drain()

    @staticmethod
    def _after_failure(chunk: Chunk, error: Exception, finished: set, started: set, deliver,
                       resubmits: dict[str, int], max_resubmits: int = 3) -> list[Chunk]:
        """A chunk's task failed after the scheduler's retries (distributed.scheduler.allowed-failures).

        Tasks queued on a dying worker fail with it although they never started, so only a
        case that had started is charged: alone in its task, it is reported 'crashed'; in a
        larger chunk (a batch runs together) each started case runs again alone, so the
        killer is known for sure. Cases that had not started run again (together), at most
        `max_resubmits` times each. Returns the chunks to submit."""
        message = f"{type(error).__name__}: {error}"
        rest = chunk.unfinished(finished)
        if _killed_alone(chunk, rest, started):
            deliver(failed_row(rest[0], "crashed", message))
            return []
        alone, waiting = _resubmissions(rest, started, message, resubmits, max_resubmits, deliver)
        again = [replace(chunk, cases=[case]) for case in alone]
        return [*again, replace(chunk, cases=waiting)] if waiting else again


def _killed_alone(chunk: Chunk, rest: list[Case], started: set[str]) -> bool:
    """Whether a chunk of one case failed while that case ran (so the case killed its worker)."""
    return len(chunk.cases) == 1 and bool(rest) and rest[0].key in started


def _resubmissions(rest: list[Case], started: set[str], message: str, resubmits: dict[str, int],
                   max_resubmits: int, deliver) -> tuple[list[Case], list[Case]]:
    """The cases to submit again: (those that had started, each alone; those that had not,
    together); a case past max_resubmits is delivered 'crashed' instead."""
    alone, waiting = [], []
    for case in rest:
        if _resubmitted(case, message, resubmits, max_resubmits, deliver):
            (alone if case.key in started else waiting).append(case)
        started.discard(case.key)  # from now on: whether it started in its new task
    return alone, waiting


def _resubmitted(case: Case, message: str, resubmits: dict[str, int], max_resubmits: int, deliver) -> bool:
    """Charge a case one more submission: True if it may run again, else it is delivered 'crashed'."""
    resubmits[case.key] = resubmits.get(case.key, 0) + 1
    if resubmits[case.key] <= max_resubmits:
        return True
    deliver(failed_row(case, "crashed", f"{message} (submitted {max_resubmits + 1} times)"))
    return False


class _Tasks:
    """The chunks' tasks on the cluster (future -> chunk), the rows handed on (Delivered), the
    cases started, the resubmissions of each case, and the messages taken from the queue and
    not handled yet (kept over Ctrl-C)."""

    def __init__(self, client, queue, runner: Callable, on_row: OnRow):
        self.client = client
        self.queue = queue
        self.runner = runner
        self.delivered = Delivered(on_row)
        self.started: set[str] = set()
        self.resubmits: dict[str, int] = {}
        self.inbox: deque = deque()
        self.futures: dict = {}

    def submit(self, chunk: Chunk) -> None:
        self.futures[self.client.submit(_dask_run_chunk, chunk, self.queue.name, self.runner, pure=False)] = chunk

    def drain(self) -> None:
        """Handle every message the workers streamed: cases started, rows."""
        self.inbox.extend(message for messages in self.queue.get(batch=True) for message in messages)
        while self.inbox:
            kind, value = self.inbox.popleft()
            if kind == "start":
                self.started.update(value)
            else:
                self.delivered.deliver(json.loads(value))

    def finish(self, future) -> None:
        """Hand on the rows of an ended task; after a failure, submit its unfinished cases again."""
        chunk = self.futures.pop(future)
        try:
            rows = future.result()
        except Exception as error:
            self.drain()
            for again in DaskExecutor._after_failure(chunk, error, self.delivered.done, self.started,
                                                     self.delivered.deliver, self.resubmits):
                self.submit(again)
            return
        for row in rows:
            self.delivered.deliver(row)

    def stop(self) -> None:
        """Keep what the workers finished before Ctrl-C, then cancel the tasks."""
        try:
            self.drain()
        except Exception:
            pass
        finally:
            self.client.cancel(list(self.futures))


class _Streamer:
    """A Dask task's emit: each case's start and row to the client's queue (rows as JSON text:
    the queue carries msgpack-able data only), one put per batch of cases."""

    def __init__(self, queue):
        self.queue = queue
        self.waiting: list[list] = []

    def emit(self, message: tuple) -> None:
        kind, value = message
        self.waiting.append([kind, value if kind == "start" else _json_row(value)])
        if kind == "start":  # before its cases run, with the rows finished since: one put per batch
            self.flush()

    def flush(self) -> None:
        """Put the waiting messages, if any."""
        if self.waiting:
            self.queue.put(list(self.waiting))
            self.waiting.clear()


def _json_row(row: dict) -> str:
    from ..output import to_jsonable

    return json.dumps(to_jsonable(row), allow_nan=False)


def _dask_run_chunk(chunk: Chunk, queue_name: str, runner: Callable = run_chunk) -> list[dict]:
    """Dask task: the chunk runner (sweep.run_chunk), sending each case's start and row to the
    client's queue as they happen (_Streamer)."""
    from distributed import Queue

    streamer = _Streamer(Queue(queue_name))  # by name: a Queue among the task's arguments is unpickled by the scheduler
    try:
        return runner(chunk, streamer.emit)
    finally:
        streamer.flush()
