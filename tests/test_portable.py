"""runtime/portable.py: whether a process is alive, on both paths; the stop signals of a system without
SIGHUP (Windows), simulated here by importing the package after removing it."""

from __future__ import annotations

import os
import subprocess
import sys

from upliftcli.runtime import atomic, portable


def _gone_pid() -> int:
    """The pid of a process that has ended (and been waited for)."""
    done = subprocess.Popen([sys.executable, "-c", "pass"])
    done.wait()
    return done.pid


def test_process_alive_on_posix_tells_a_running_process_from_one_that_ended():
    assert portable.process_alive(os.getpid())
    assert portable.process_alive(os.getppid())
    assert portable.process_alive(1)  # another user's (init): alive, though it may not be signalled
    assert not portable.process_alive(_gone_pid())


def test_without_the_posix_probe_nothing_of_a_process_that_may_run_is_removed(tmp_path, monkeypatch):
    """Off POSIX the Windows API is asked; where it is missing too (this machine), every process
    counts as alive: a killed writer's temporary file is kept, never a live one's removed."""
    monkeypatch.setattr(portable, "POSIX", False)
    gone = _gone_pid()
    assert portable.process_alive(gone) and portable.process_alive(os.getpid())
    left = tmp_path / f".fig.png{atomic.TEMP_MARK}{gone}-abc123.png"
    left.write_text("half")
    assert atomic.remove_stale(tmp_path) == [] and left.exists()
    monkeypatch.setattr(portable, "POSIX", True)  # the default path removes it
    assert atomic.remove_stale(tmp_path) == [left] and not left.exists()


WITHOUT_SIGHUP = """
import signal, sys
del signal.SIGHUP  # as on Windows
from upliftcli.runtime import portable, process
from upliftcli.sweep import executors, signals
from upliftcli.sweep.run import run_sweep
assert portable.STOP_SIGNALS == (signal.SIGTERM,), portable.STOP_SIGNALS
assert signals.STOP_SIGNALS == (signal.SIGINT, signal.SIGTERM)
process.exit_on_stop_signals()
assert signal.getsignal(signal.SIGTERM) is process._stop
with signals.stop_signals_interrupt():
    assert signal.getsignal(signal.SIGINT) is signals._handler
import queue
executors._init_worker(queue.SimpleQueue(), executors.run_chunk)  # a worker's set-up, SIGHUP left alone
assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
print("ok")
"""


def test_a_system_without_sighup_imports_and_sets_its_stop_signals():
    done = subprocess.run([sys.executable, "-c", WITHOUT_SIGHUP], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "ok" and not done.stderr
