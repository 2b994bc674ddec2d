"""runtime/locks.py: an exclusive lock on a file, by each method this system has (flock here; the
O_EXCL lock file forced; msvcrt.locking is Windows', not run here: docs/platforms.md); a sweep's
output stem refused while another process holds it, free again once that process is gone."""

from __future__ import annotations

import os
import signal
import subprocess
import sys

import pytest

from upliftcli.errors import InputError
from upliftcli.runtime import locks
from upliftcli.sweep.store import stem_lock

KINDS = ["flock", "exclusive"] if locks.fcntl is not None else ["exclusive"]


class FlockAsMsvcrt:
    """msvcrt's locking() emulated by flock, for the order of the calls of the "msvcrt" path (a
    lock of the whole file per open file, refused at once when held, as Windows' byte lock of
    LK_NBLCK); Windows itself is not run here."""

    LK_NBLCK, LK_UNLCK = 2, 0

    @staticmethod
    def locking(fd: int, mode: int, nbytes: int) -> None:
        assert nbytes == 1 and os.lseek(fd, 0, os.SEEK_CUR) == 0  # the first byte
        locks.fcntl.flock(fd, locks.fcntl.LOCK_EX | locks.fcntl.LOCK_NB if mode else locks.fcntl.LOCK_UN)

HOLDER = """
import sys, time
from upliftcli.runtime import locks
locks.KIND = sys.argv[2]
fd = locks.acquire(sys.argv[1])
print("held" if fd is not None else "refused", flush=True)
time.sleep(60)
"""


@pytest.fixture(params=KINDS)
def kind(request, monkeypatch):
    monkeypatch.setattr(locks, "KIND", request.param)
    return request.param


@pytest.mark.skipif(locks.fcntl is None, reason="the emulation uses flock")
def test_the_msvcrt_path_locks_the_first_byte_and_closes_before_removing(tmp_path, monkeypatch):
    monkeypatch.setattr(locks, "KIND", "msvcrt")
    monkeypatch.setattr(locks, "msvcrt", FlockAsMsvcrt)
    closed_before_unlink = []
    unlink = os.unlink

    def checked_unlink(path, *args, **kwargs):
        closed_before_unlink.append(_closed(fd))
        return unlink(path, *args, **kwargs)

    path = tmp_path / ".deck.lock"
    fd = locks.acquire(path)
    assert fd is not None and path.read_text().strip() == str(os.getpid())
    assert locks.acquire(path) is None
    monkeypatch.setattr(os, "unlink", checked_unlink)
    locks.release(path, fd)
    assert closed_before_unlink == [True] and not path.exists()


def _closed(fd: int) -> bool:
    try:
        os.fstat(fd)
    except OSError:
        return True
    return False


def _holder(path, kind) -> subprocess.Popen:
    """Another process holding the lock on `path`."""
    child = subprocess.Popen([sys.executable, "-c", HOLDER, str(path), kind], stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "held"
    return child


def test_a_held_lock_is_refused_until_released(tmp_path, kind):
    path = tmp_path / ".deck.lock"
    fd = locks.acquire(path)
    assert fd is not None and path.read_text().strip() == str(os.getpid())
    assert locks.acquire(path) is None  # held (by this process, through another descriptor)
    locks.release(path, fd)
    assert not path.exists()
    again = locks.acquire(path)
    assert again is not None
    locks.release(path, again)


def test_a_lock_of_a_killed_process_is_free_again(tmp_path, kind):
    """SIGKILL releases a flock with the process; an O_EXCL lock file it leaves names a pid that
    is gone, and is taken over."""
    path = tmp_path / ".deck.lock"
    child = _holder(path, kind)
    try:
        assert locks.acquire(path) is None
    finally:
        child.send_signal(signal.SIGKILL)
        child.wait(timeout=30)
    assert path.exists()  # the killed process removed nothing
    fd = locks.acquire(path)
    assert fd is not None
    locks.release(path, fd)


def test_stem_lock_refuses_a_second_sweep_by_every_method(tmp_path, kind):
    out, held = tmp_path / "out", tmp_path / "held"
    held.mkdir()
    child = _holder(held / ".deck.sweep.lock", kind)  # another sweep's process
    try:
        with pytest.raises(InputError, match=r"^--out: .*deck.sweep: an output stem no other sweep is writing"), \
                stem_lock(held, "deck.sweep"):
            pass
    finally:
        child.send_signal(signal.SIGKILL)
        child.wait(timeout=30)
    with stem_lock(out, "deck.sweep"):
        assert (out / ".deck.sweep.lock").exists()
        with pytest.raises(InputError, match="an output stem no other sweep is writing"), \
                stem_lock(out, "deck.sweep"):
            pass
        with stem_lock(out, "other.sweep"):
            pass
    assert not out.exists()  # created for the lock, left empty: removed


def test_a_symlinked_lock_file_is_refused(tmp_path):
    outside = tmp_path / "outside"
    outside.write_text("keep")
    (tmp_path / "o").mkdir()
    (tmp_path / "o" / ".stem.lock").symlink_to(outside)
    with pytest.raises(InputError, match=r"^--out: .*\.stem\.lock: a path that is not a symbolic link"), \
            stem_lock(tmp_path / "o", "stem"):
        pass
    assert outside.read_text() == "keep"
    if locks.KIND == "flock":
        with pytest.raises(OSError):
            locks.acquire(tmp_path / "o" / ".stem.lock")
        assert outside.read_text() == "keep"
