"""What differs between the systems the tool runs on (docs/platforms.md): POSIX (Linux, macOS) or
Windows, the stop signals the system has, whether another process is alive. Each switch is read
when it is used, so that the tests take the other path on Linux by setting it
(tests/test_portable.py). Here are the two that several modules use:

- POSIX: whether this is a POSIX system (os.name); process_alive asks os.kill(pid, 0) there and
  the Windows API elsewhere (on Windows os.kill(pid, 0) would send a Ctrl-C event, not a probe).
- STOP_SIGNALS: the signals besides SIGINT that end a command through its clean-up (SIGTERM,
  and SIGHUP where it exists: Windows has none).

Each of the others sits beside the one code that reads it (docs/platforms.md lists them all):
sweep/executors.ProcessExecutor's start method (forkserver where there is one, else spawn),
executors.PARENT_DEATH_SIGNAL (Linux's prctl, else a watchdog thread) and the worker's SIGHUP
(ignored where it exists), figures/draw.FORK_FIGURES (figures drawn in forked copies on Linux only),
locks.KIND (flock, msvcrt or a lock file), process.keep_freed_memory (glibc's mallopt only),
process.available_cores (the CPU affinity where the system tells it) and atomic.PROC_STATUS
(the umask read from /proc where it exists).
"""

from __future__ import annotations

import ctypes
import os
import signal

POSIX = os.name == "posix"
#: the stop signals besides SIGINT this system has (Windows: SIGTERM only)
STOP_SIGNALS = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGHUP") if hasattr(signal, name))

#: Windows: the access to ask for, an exit code that means still running, and the error of a
#: process that exists but belongs to someone else
_QUERY_LIMITED_INFORMATION, _STILL_ACTIVE, _ACCESS_DENIED = 0x1000, 259, 5


def process_alive(pid: int) -> bool:
    """Whether process `pid` runs (another user's counts; where this cannot be told: True, so
    that nothing of a process that may still run is removed)."""
    if pid == os.getpid():
        return True
    if not POSIX:
        return _windows_process_alive(pid)
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # another user's process: alive
        return True
    return True


def _windows_process_alive(pid: int) -> bool:
    """OpenProcess and GetExitCodeProcess (kernel32); True where they are not available."""
    try:
        kernel32 = ctypes.WinDLL("kernel32", use_last_error=True)  # type: ignore[attr-defined]
    except (AttributeError, OSError):  # not Windows: cannot tell
        return True
    handle = kernel32.OpenProcess(_QUERY_LIMITED_INFORMATION, False, pid)
    if not handle:
        return ctypes.get_last_error() == _ACCESS_DENIED
    try:
        code = ctypes.c_ulong()
        return not kernel32.GetExitCodeProcess(handle, ctypes.byref(code)) or code.value == _STILL_ACTIVE
    finally:
        kernel32.CloseHandle(handle)
