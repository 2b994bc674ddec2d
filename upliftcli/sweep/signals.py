"""Stop signals of a sweep: SIGINT (Ctrl-C), SIGTERM and SIGHUP raise Interrupted in the main
thread while a sweep runs; after the first one all three are ignored, so a second Ctrl-C
cannot cut the clean-up short. Code that must not be cut in the middle (reading a message
from the workers' queue and storing its row) runs under `deferred()`: a signal arriving there
takes effect at its end.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator

from ..runtime import portable

#: signals that stop a sweep as Ctrl-C does (SIGHUP where the system has it)
STOP_SIGNALS = (signal.SIGINT, *portable.STOP_SIGNALS)

_deferring = 0  # depth of deferred() blocks (main thread)
_pending: int | None = None  # a signal that arrived inside one


class Interrupted(KeyboardInterrupt):
    """A stop signal (SIGINT, SIGTERM or SIGHUP) arrived; signum says which."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = int(signum)


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def ignore_stop_signals() -> None:
    """Ignore further stop signals (main thread only): the process is about to exit."""
    if _main_thread():
        for signum in STOP_SIGNALS:
            signal.signal(signum, signal.SIG_IGN)


def _handler(signum, frame) -> None:
    global _pending
    ignore_stop_signals()
    if _deferring:
        _pending = signum
        return
    raise Interrupted(signum)


@contextlib.contextmanager
def stop_signals_interrupt(stay_ignored: bool = False) -> Iterator[None]:
    """While the block runs, the stop signals raise Interrupted (once); the previous handlers
    are restored afterwards, unless one arrived and stay_ignored (a process that is about to
    exit: a second Ctrl-C must not cut its last message). Outside the main thread, signals
    are left alone."""
    if not _main_thread():
        yield
        return
    previous = {signum: signal.signal(signum, _handler) for signum in STOP_SIGNALS}
    stopped = False
    try:
        yield
    except KeyboardInterrupt:
        stopped = True
        raise
    finally:
        if not (stopped and stay_ignored):
            _restore_handlers(previous)


def _restore_handlers(previous: dict) -> None:
    """Put back the handlers of the signals as they were (signal number -> handler)."""
    for signum, action in previous.items():
        signal.signal(signum, action)


@contextlib.contextmanager
def deferred() -> Iterator[None]:
    """A stop signal arriving inside the block raises Interrupted at its end, not inside it."""
    global _deferring, _pending
    _deferring += 1
    try:
        yield
    finally:
        _deferring -= 1
        if not _deferring and _pending is not None:
            signum, _pending = _pending, None
            raise Interrupted(signum)
