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
from collections.abc import Callable, Sequence
from dataclasses import replace

from ..errors import InputError
from .executors import WORKER_ENVIRONMENT, OnRow, sigint_ignored
from .plan import Chunk
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
    host = host.strip("[]") or "127.0.0.1"
    try:
        port_number = int(port.split("/")[0])
    except ValueError:
        raise InputError("--scheduler", address, "an address tcp://host:port, e.g. tcp://10.0.0.5:8786") from None
    try:
        with socket.create_connection((host, port_number), timeout=timeout):
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
        import logging

        with contextlib.ExitStack() as stack:
            if self.address is None:
                with sigint_ignored():  # the worker processes inherit it: Ctrl-C is ours to handle
                    cluster = stack.enter_context(distributed.LocalCluster(
                        n_workers=self.workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                        dashboard_address=":0", silence_logs=logging.ERROR, env=dict(WORKER_ENVIRONMENT)))
                address = cluster.scheduler_address
            else:
                address = self.address
            try:
                client = stack.enter_context(distributed.Client(address, timeout=self.connect_timeout))
            except (OSError, TimeoutError) as error:
                raise InputError("--scheduler", address, f"a reachable Dask scheduler ({error})") from None
            info = client.scheduler_info()
            self.workers = max(1, len(info.get("workers", {})) or self.workers)
            yield client

    def run(self, chunks: Sequence[Chunk], on_row: OnRow) -> None:
        distributed = import_distributed()
        with self.client() as client:
            queue = distributed.Queue(client=client)  # rows stream through it case by case
            finished: set[str] = set()
            started: set[str] = set()
            resubmits: dict[str, int] = {}

            def deliver(row: dict) -> None:
                if row["key"] not in finished:
                    finished.add(row["key"])
                    on_row(row)

            inbox: deque = deque()  # messages taken from the queue and not handled yet (kept over Ctrl-C)

            def drain() -> None:
                inbox.extend(message for messages in queue.get(batch=True) for message in messages)
                while inbox:
                    kind, value = inbox.popleft()
                    if kind == "start":
                        started.update(value)
                    else:
                        deliver(json.loads(value))

            def submit(chunk: Chunk) -> None:
                futures[client.submit(_dask_run_chunk, chunk, queue.name, self.runner, pure=False)] = chunk

            futures: dict = {}
            for chunk in chunks:
                submit(chunk)
            try:
                while futures:
                    try:
                        done, _ = distributed.wait(list(futures), timeout=self.poll_seconds,
                                                   return_when="FIRST_COMPLETED")
                    except TimeoutError:  # none finished within poll_seconds: collect the streamed rows
                        done = []
                    drain()
                    for future in done:
                        chunk = futures.pop(future)
                        try:
                            rows = future.result()
                        except Exception as error:
                            drain()
                            for again in self._after_failure(chunk, error, finished, started, deliver, resubmits):
                                submit(again)
                            continue
                        for row in rows:
                            deliver(row)
                drain()
            except BaseException:
                try:
                    drain()  # keep what the workers finished before Ctrl-C
                except Exception:
                    pass
                finally:
                    client.cancel(list(futures))
                raise
            finally:
                with contextlib.suppress(Exception):
                    queue.close()

    @staticmethod
    def _after_failure(chunk: Chunk, error: Exception, finished: set, started: set, deliver,
                       resubmits: dict[str, int], max_resubmits: int = 3) -> list[Chunk]:
        """A chunk's task failed after the scheduler's retries (distributed.scheduler.allowed-failures).

        Tasks queued on a dying worker fail with it although they never started, so only a
        case that had started is charged: alone in its task, it is reported 'crashed'; in a
        larger chunk (a batch runs together) each started case runs again alone, so the
        killer is known for sure. Cases that had not started run again (together), at most
        `max_resubmits` times each. Returns the chunks to submit."""
        rest = [case for case in chunk.cases if case.key not in finished]
        message = f"{type(error).__name__}: {error}"
        again: list[Chunk] = []
        waiting = []
        for case in rest:
            if case.key in started and len(chunk.cases) == 1:
                deliver(failed_row(case, "crashed", message))
                continue
            resubmits[case.key] = resubmits.get(case.key, 0) + 1
            if resubmits[case.key] > max_resubmits:
                deliver(failed_row(case, "crashed", f"{message} (submitted {max_resubmits + 1} times)"))
            elif case.key in started:
                again.append(replace(chunk, cases=[case]))
            else:
                waiting.append(case)
            started.discard(case.key)  # from now on: whether it started in its new task
        if waiting:
            again.append(replace(chunk, cases=waiting))
        return again


def _dask_run_chunk(chunk: Chunk, queue_name: str, runner: Callable = run_chunk) -> list[dict]:
    """Dask task: the chunk runner (sweep.run_chunk), sending each case's start and row to the
    client's queue as they happen (rows as JSON text: the queue carries msgpack-able data only)."""
    from distributed import Queue

    from ..output import to_jsonable

    queue = Queue(queue_name)  # by name: a Queue object among the task's arguments is unpickled by the scheduler
    waiting: list[list] = []

    def emit(message: tuple) -> None:
        kind, value = message
        waiting.append([kind, value if kind == "start" else json.dumps(to_jsonable(value), allow_nan=False)])
        if kind == "start":  # before its cases run, with the rows finished since: one put per batch
            queue.put(list(waiting))
            waiting.clear()

    try:
        return runner(chunk, emit)
    finally:
        if waiting:
            queue.put(waiting)
