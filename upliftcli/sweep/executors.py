"""Where the chunks of a sweep run: in this process, in local worker processes, or on Dask.

Every executor has `workers` and `run(chunks, on_row)`: it calls `on_row(row)` once per case
of the chunks (status ok, failed or crashed), as soon as the row is known, and lets
KeyboardInterrupt through after stopping its workers. All give the same rows: a case's row
depends only on the case (sweep.run_chunk), never on which worker ran it.

Local workers are forked from a server process that imported the engines and loaded their
compiled code once (multiprocessing's forkserver preloading sweep/warm.py), so each starts in
milliseconds with everything in memory; where there is no forkserver (Windows), they are spawned
and each imports the engines itself (docs/platforms.md).

Parent death: a local worker process exits when the sweep's process dies (SIGKILL included): a
thread of every worker waits on the sweep's process sentinel (_exit_when_ready). A forked
worker's parent is the warm server, which lives on while a worker holds its liveness pipe, so
the kernel's PR_SET_PDEATHSIG (Linux) and the parent-pid watchdog (exit_with_parent) only add
to it where the parent is the sweep's process. Workers ignore SIGINT and SIGHUP (the parent
stops them).

Worker deaths: local processes report the cases as they start and as each finishes. After a worker
dies, the cases that were running (started, not finished) are run again one at a time on a
single worker, so a case that kills its worker is known for sure; it is charged an attempt
and marked 'crashed' after `max_attempts`. The other cases go on in parallel.

Stalled workers: a thread of every local worker sends a heartbeat every HEARTBEAT_SECONDS (the
compiled loops release the interpreter's lock, so it beats while they run); a worker silent
for `stall_seconds` (STALL_SECONDS: stopped by SIGSTOP, or hung) is killed, and its cases are
retried as after a death (a stopped worker blocked the sweep for ever).
The Dask executor: sweep/dask_executor.py; the rows and messages of a pool: sweep/pool.py.
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import multiprocessing
import multiprocessing.connection
import os
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import replace

from ..runtime.process import keep_freed_memory
from .chunks import Chunk
from .plan import Case
from .pool import Delivered, Messages, OnRow, after_death, deliver_result, processes, stop_pool
from .signals import deferred
from .worker import failed_row, run_chunk

#: environment of worker processes, set before they import numpy: one thread per worker
WORKER_ENVIRONMENT = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}

#: imported by the forkserver before it forks the local workers (the engines, warm)
WARM_MODULE = f"{__package__}.warm"
#: a local worker's heartbeat period [s], and the silence after which it is taken as stalled [s]
HEARTBEAT_SECONDS = 1.0
STALL_SECONDS = 60.0


@contextlib.contextmanager
def worker_environment() -> Iterator[None]:
    """Set WORKER_ENVIRONMENT while worker processes are started; restore it afterwards."""
    saved = {name: os.environ.get(name) for name in WORKER_ENVIRONMENT}
    os.environ.update(WORKER_ENVIRONMENT)
    try:
        yield
    finally:
        _restore_environment(saved)


def _restore_environment(saved: dict[str, str | None]) -> None:
    """Put back the variables as saved (None: the variable was not set)."""
    for name, value in saved.items():
        if value is None:
            os.environ.pop(name, None)
        else:
            os.environ[name] = value


def _emit_row(on_row: OnRow, message: tuple) -> None:
    """A chunk runner's emit that passes on the rows (and drops the starts)."""
    if message[0] == "row":
        on_row(message[1])


class SerialExecutor:
    """Every chunk in this process, in order."""

    workers = 1

    def run(self, chunks: Iterable[Chunk], on_row: OnRow) -> None:
        emit = functools.partial(_emit_row, on_row)
        for chunk in chunks:
            run_chunk(chunk, emit)


# ----------------------------------------------------------------------------- local processes

_QUEUE = None  # per worker process: the queue to the parent
_RUNNER = run_chunk  # per worker process: the chunk runner


PR_SET_PDEATHSIG = 1  # linux/prctl.h
#: whether the kernel can kill a process when its parent dies (Linux's prctl; elsewhere a watchdog)
PARENT_DEATH_SIGNAL = sys.platform.startswith("linux")


def exit_with_parent(parent_pid: int, poll_seconds: float = 1.0) -> None:
    """Make this process end when `parent_pid` (its parent) dies: SIGKILL from the kernel
    on Linux (prctl PR_SET_PDEATHSIG, PARENT_DEATH_SIGNAL), else a daemon thread polling os.getppid()."""
    if PARENT_DEATH_SIGNAL and _kernel_kills_with_parent(parent_pid):
        return
    threading.Thread(target=_watch_parent, args=(parent_pid, poll_seconds), name="exit-with-parent",
                     daemon=True).start()


def _kernel_kills_with_parent(parent_pid: int) -> bool:
    """Ask the kernel for SIGKILL when the parent dies (prctl); whether it took the request
    (exit now if the parent died before it took effect)."""
    with contextlib.suppress(OSError, AttributeError):
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0:
            _exit_unless_parent(parent_pid)
            return True
    return False


def _exit_unless_parent(parent_pid: int) -> None:
    """Exit at once if this process's parent is no longer `parent_pid` (it died)."""
    if os.getppid() != parent_pid:
        os._exit(1)


def _watch_parent(parent_pid: int, poll_seconds: float) -> None:
    """Poll the parent's pid; exit when it changes (the parent died)."""
    while os.getppid() == parent_pid:
        time.sleep(poll_seconds)
    os._exit(1)


def _init_worker(queue, runner, parent_pid: int | None = None, environment=None, directory=None) -> None:
    global _QUEUE, _RUNNER
    _QUEUE, _RUNNER = queue, runner
    _take_parent_state(environment, directory)
    keep_freed_memory()
    warnings.simplefilter("ignore", RuntimeWarning)  # as in the uplift process: numpy's never reach the terminal
    _ignore_terminal_signals()
    _exit_with_the_sweep(parent_pid)
    threading.Thread(target=_beat, args=(queue,), name="heartbeat", daemon=True).start()


def _take_parent_state(environment: dict | None, directory: str | None) -> None:
    """The parent's environment now (not the warm server's when it started) and its folder (relative
    deck and record paths as in the parent), where given."""
    if environment is not None:
        os.environ.clear()
        os.environ.update(environment)
    if directory is not None:
        os.chdir(directory)


def _ignore_terminal_signals() -> None:
    """Ctrl-C, and a hang-up of the terminal (POSIX), are the parent's to handle."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "SIGHUP"):
        signal.signal(signal.SIGHUP, signal.SIG_IGN)


def _exit_with_the_sweep(parent_pid: int | None) -> None:
    """End this worker with its parent (exit_with_parent) and with the sweep's process, also when
    the warm server forked it (_exit_when_ready)."""
    if parent_pid is not None:
        exit_with_parent(parent_pid)
    sweep = multiprocessing.parent_process()
    if sweep is not None and sweep.sentinel is not None:
        threading.Thread(target=_exit_when_ready, args=(sweep.sentinel,), name="exit-with-sweep", daemon=True).start()


def _beat(queue) -> None:
    """Tell the sweep every HEARTBEAT_SECONDS that this worker runs (ProcessExecutor kills one
    that stays silent for its stall_seconds)."""
    pid = os.getpid()
    try:
        while True:
            queue.put(("beat", pid))
            time.sleep(HEARTBEAT_SECONDS)
    except (OSError, ValueError, EOFError):  # the sweep is gone
        return


def _exit_when_ready(sentinel) -> None:
    """Exit as soon as the sweep's process is gone (its end of our start-up pipe closes). A forked
    worker's parent is the warm server, which lives on while any worker holds its liveness pipe."""
    multiprocessing.connection.wait([sentinel])
    os._exit(1)


def _worker_run_chunk(chunk: Chunk) -> list[dict]:
    return _RUNNER(chunk, _QUEUE.put)


def _context(start_method: str):
    context = multiprocessing.get_context(start_method)
    if start_method == "forkserver":
        context.set_forkserver_preload([WARM_MODULE])
    return context


class ProcessExecutor:
    """Chunks on `workers` local processes, forked from a fresh warm server (forkserver) or
    spawned (where there is no forkserver: Windows): either is safe whatever threads the parent has.

    runner: the chunk runner, a module-level function like sweep.run_chunk(chunk, emit);
    start_method: "forkserver" (default where available) or "spawn"; stall_seconds: a worker
    without a heartbeat for this long is killed and its cases retried (module docstring)."""

    def __init__(self, workers: int, max_attempts: int = 3, poll_seconds: float = 0.1,
                 runner: Callable = run_chunk, start_method: str | None = None, stall_seconds: float = STALL_SECONDS):
        self.runner = runner
        self.workers = max(1, int(workers))
        self.max_attempts = max_attempts
        self.poll_seconds = poll_seconds
        self.stall_seconds = stall_seconds
        methods = multiprocessing.get_all_start_methods()
        self.start_method = start_method or ("forkserver" if "forkserver" in methods else "spawn")

    def _parent_pid(self) -> int | None:
        """The pid a worker's parent has: this process, or the warm server that forks it."""
        if self.start_method != "forkserver":
            return os.getpid()
        self.prestart()
        import multiprocessing.forkserver  # POSIX's: imported where it is used

        return getattr(getattr(multiprocessing.forkserver, "_forkserver", None), "_forkserver_pid", None)

    def prestart(self) -> None:
        """Start the warm server now: it imports and loads the engines while the caller goes on."""
        if self.start_method == "forkserver":
            _context(self.start_method)
            import multiprocessing.forkserver

            with worker_environment(), sigint_ignored():
                multiprocessing.forkserver.ensure_running()

    def run(self, chunks: Iterable[Chunk], on_row: OnRow) -> None:
        delivered = Delivered(on_row)
        pending, isolate = list(chunks), []  # isolate: one-case chunks of suspects, run on a single worker
        context = _context(self.start_method)
        with worker_environment():
            while pending or isolate:
                isolated = bool(isolate)
                batch, workers = (isolate, 1) if isolated else (pending, self.workers)
                pending, isolate = (pending, []) if isolated else ([], isolate)
                again, rest = self._run_round(batch, workers, context, isolated, delivered)
                isolate += again
                pending += rest

    def _run_round(self, batch: list[Chunk], workers: int, context, isolated: bool,
                   delivered: Delivered) -> tuple[list[Chunk], list[Chunk]]:
        """Run chunks on a fresh pool; of the chunks lost to a dead worker: (the suspects, one per
        chunk, to run alone; the chunks of the other cases, to run in parallel)."""
        queue = context.SimpleQueue()  # a new one per pool: a killed writer may hold the old one's lock
        started: set[str] = set()
        isolate, pending = [], []
        for chunk in self._run_pool(batch, workers, context, queue, started, delivered.deliver):
            suspects, others = after_death(chunk, started, delivered.done)
            isolate += [replace(chunk, cases=[case]) for case in suspects
                        if not self._crashed(case, started, isolated, delivered)]
            if others:
                pending.append(replace(chunk, cases=others))
        return isolate, pending

    def _crashed(self, case: Case, started: set[str], isolated: bool, delivered: Delivered) -> bool:
        """Whether a suspect of a dead worker is done with: it ran alone on its worker (so it killed
        it) for the max_attempts-th time, and is delivered as 'crashed'."""
        if not (isolated and case.key in started):
            return False
        attempts = delivered.charge(case.key)
        if attempts < self.max_attempts:
            return False
        delivered.deliver(failed_row(case, "crashed", "the worker process died while running this "
                                     f"case ({attempts} attempts)"))
        return True

    def _run_pool(self, chunks, workers: int, context, queue, started: set, deliver) -> list[Chunk]:
        """Run the chunks on a fresh pool; return the chunks of a broken pool (a worker died)."""
        pool = ProcessPoolExecutor(workers, mp_context=context, initializer=_init_worker,
                                   initargs=(queue, self.runner, self._parent_pid(), dict(os.environ), os.getcwd()))
        with sigint_ignored(), deferred():  # processes are started by submit; they ignore Ctrl-C from birth
            futures = {pool.submit(_worker_run_chunk, chunk): chunk for chunk in chunks}
        messages = Messages(queue, started, deliver)
        try:
            leftovers = self._collect(pool, futures, messages)
        except BaseException:  # Ctrl-C, a full disk ...: keep what arrived, stop the workers now
            stop_pool(pool, messages)
            raise
        pool.shutdown(wait=True)
        return leftovers

    def _collect(self, pool, futures: dict, messages: Messages) -> list[Chunk]:
        """Deliver the rows of the pool's chunks as they arrive; the chunks of a broken pool."""
        leftovers = []
        while futures:
            with deferred():  # a signal inside wait() could leave futures' locks held: the pool would hang
                finished, _ = wait(futures, timeout=self.poll_seconds, return_when=FIRST_COMPLETED)
            messages.drain()
            self._kill_stalled(pool, messages.beats)
            for future in finished:
                chunk = futures.pop(future)
                if not deliver_result(future, messages.deliver):
                    leftovers.append(chunk)
        messages.drain()
        return leftovers

    def _kill_stalled(self, pool, beats: dict[int, float]) -> None:
        """SIGKILL the workers silent for stall_seconds (the pool then breaks: their cases are
        retried as after a death)."""
        now = time.monotonic()
        for pid, process in processes(pool):
            if now - beats.setdefault(pid, now) > self.stall_seconds and process.is_alive():
                process.kill()  # a stopped process is killed too


@contextlib.contextmanager
def sigint_ignored() -> Iterator[None]:
    """Ignore SIGINT while child processes are started (an ignored signal stays ignored in them)."""
    try:
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # not the main thread: leave the signals alone
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
