"""What the package sets in the processes it runs (the `uplift` command and the local sweep
workers), never on import, so that a program using the Python API keeps its own: how many cores
the work may use, an allocator that keeps freed memory for reuse, stop signals (SIGTERM, SIGHUP)
that end a command through its clean-up, and an exit that skips the interpreter's teardown.

The exact engine allocates arrays of the same few megabytes chunk after chunk and analysis after
analysis (the states, the signals and the responses at the samples: 3-8 MB each for ten stories at
T_1 = 0.1 s). glibc serves blocks that large from fresh mappings and unmaps them when they are
freed, so every chunk page-faults its memory in again: 12 % of the Fig. 3 spectrum's time went to
the kernel's page handling (perf), and keeping the memory took its 300 analyses from 2.6-3.0 s to
2.0-2.3 s in one process. Peak memory is unchanged: only what would be handed back is kept.
"""

from __future__ import annotations

import atexit
import ctypes
import os
import platform
import signal
import sys
import threading

from ..errors import printable
from .portable import STOP_SIGNALS

#: glibc's mallopt parameters
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
#: blocks below this come from the heap (glibc's largest allowed on 64-bit systems) [bytes]
MMAP_THRESHOLD = 32 * 2**20
#: freed memory at the top of the heap is handed back to the system beyond this [bytes]
TRIM_THRESHOLD = 256 * 2**20


def keep_freed_memory() -> bool:
    """Serve blocks below MMAP_THRESHOLD from the heap and keep up to TRIM_THRESHOLD of freed
    memory; False (nothing changed) where the C library is not glibc (macOS, Windows, musl:
    their allocators are left as they are; the results are the same, tests/test_process.py)."""
    if platform.libc_ver()[0] != "glibc":
        return False
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):
        return False
    return bool(mallopt(_M_TRIM_THRESHOLD, TRIM_THRESHOLD)) and bool(mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD))


class Stopped(SystemExit):
    """SIGTERM or SIGHUP ended the command (exit code 128 + the signal): raised where the process
    is, so that the `finally` blocks run (runtime/atomic.py removes its temporary files)."""


def _stop(signum, frame) -> None:
    for each in STOP_SIGNALS:
        signal.signal(each, signal.SIG_IGN)  # the clean-up is not cut short by a second one
    raise Stopped(128 + signum)


def exit_on_stop_signals() -> None:
    """SIGTERM and SIGHUP (where the system has it: portable.STOP_SIGNALS) end the command as an
    exception (Stopped), not at once, so that its clean-up runs; sweeps install their own
    handlers while they run (sweep/signals.py). Main thread only; set by the `uplift` command,
    never on import."""
    if threading.current_thread() is threading.main_thread():
        for each in STOP_SIGNALS:
            signal.signal(each, _stop)


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system tells it)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def exit_now(code: int | str | None) -> None:
    """End the process as SystemExit(code) would, without the interpreter's teardown.

    As at a normal exit, the threads that are not daemons are waited for, the atexit handlers run
    (the pool's and the forkserver's clean-up among them) and the standard streams are flushed.
    What is skipped is freeing every module and object one by one, which nothing needs at the end
    of a command: 0.13 s after the Fig. 3 spectrum with its figures (strace: from the last handler
    to exit_group). Files are all closed by then (the writers are atomic: written, closed and
    renamed). A failed flush of stdout exits 120, as Python does."""
    code = _exit_code(code)
    shutdown = getattr(threading, "_shutdown", None)  # what the interpreter calls first at exit
    if shutdown is not None:
        shutdown()
    atexit._run_exitfuncs()
    if not _flushed():
        code = code or 120
    os._exit(code)


def _exit_code(code: int | str | None) -> int:
    """The exit status of SystemExit(code): 0 for None, the number, else 1 with the message on stderr."""
    if code is None:
        return 0
    if not isinstance(code, int):
        print(printable(code, lines=True), file=sys.stderr)
        return 1
    return code


def _flushed() -> bool:
    """Flush stdout and stderr; False when one cannot be (a closed pipe or a full disk: the output is not whole)."""
    whole = True
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe or a full disk: the output is not whole
            whole = False
    return whole
