"""An exclusive lock on a file, held while this process writes what the file guards (a sweep's
output stem, sweep/store.py). How, chosen at run time (KIND; docs/platforms.md):

- "flock": fcntl.flock (POSIX: Linux, macOS);
- "msvcrt": msvcrt.locking of the file's first byte (Windows);
  both are released by the system with the process however it ends (a SIGKILL included);
- "exclusive": the file created with O_EXCL, holding its owner's pid (any system; where neither
  of the others exists, and in tests): a file left by a process that is gone is taken over
  (portable.process_alive); two processes taking over the same stale file at one instant are
  not told apart, which the system's locks above never leave to chance.

acquire(path) returns the open descriptor of the locked file, or None where another process
holds it; release(path, fd) removes the file and closes it.
"""

from __future__ import annotations

import contextlib
import os
from pathlib import Path

from . import portable

try:
    import fcntl
except ImportError:  # Windows
    fcntl = None
try:
    import msvcrt
except ImportError:  # POSIX
    msvcrt = None

#: a symbolic link at the lock file is not followed (OSError ELOOP; O_EXCL never follows one)
NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
KIND = "flock" if fcntl is not None else "msvcrt" if msvcrt is not None else "exclusive"


def acquire(path: str | os.PathLike) -> int | None:
    """Lock `path` (created if missing) and write this process's pid into it: the open
    descriptor, or None where another process holds the lock. OSError where it cannot be
    created (a read-only folder)."""
    path = Path(path)
    if KIND == "exclusive":
        return _create_exclusive(path)
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | NOFOLLOW, 0o666)
        if not _lock(fd):
            os.close(fd)
            return None
        if _is_file_at(path, fd):  # the file may have been removed by the process that held it
            _write_pid(path, fd)
            return fd
        os.close(fd)


def _is_file_at(path: Path, fd: int) -> bool:
    """Whether the open file is the one at `path` still (the lock to take is the one at the path)."""
    try:
        return os.fstat(fd).st_ino == os.stat(path).st_ino
    except FileNotFoundError:
        return False
    except OSError:
        release(path, fd)
        raise


def _write_pid(path: Path, fd: int) -> None:
    """Write this process's pid into the lock file; on an error (a full disk) release it and raise."""
    try:
        os.write(fd, f"{os.getpid()}\n".encode())
    except OSError:
        release(path, fd)
        raise


def release(path: str | os.PathLike, fd: int) -> None:
    """Remove the lock file and close it (Windows: close first, it cannot remove an open file;
    a process that locked it meanwhile keeps it open, so the removal fails and it stays)."""
    if KIND == "msvcrt":
        os.close(fd)
        with contextlib.suppress(OSError):
            os.unlink(path)
        return
    with contextlib.suppress(OSError):
        os.unlink(path)
    os.close(fd)


def _lock(fd: int) -> bool:
    try:
        if KIND == "flock":
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        else:
            os.lseek(fd, 0, os.SEEK_SET)
            msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)
    except OSError:
        return False
    return True


def _create_exclusive(path: Path) -> int | None:
    """The lock file created with O_EXCL; one a process that is gone left behind is taken over."""
    for _ in range(2):
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:
            if not _free_again(path):
                return None
            continue
        _write_pid(path, fd)
        return fd
    return None


def _free_again(path: Path) -> bool:
    """Whether the lock file at `path` may be created again: released meanwhile, or left behind by
    a process that is gone (then removed here); False while a process holds it, or for a file
    that is not a lock file of ours."""
    try:
        owner = _owner(path.read_text(encoding="ascii"))
    except FileNotFoundError:  # released meanwhile: try again
        return True
    except (OSError, UnicodeDecodeError):  # not a lock file of ours: held
        return False
    if owner is None or portable.process_alive(owner):
        return False
    with contextlib.suppress(FileNotFoundError):
        os.unlink(path)
    return True


def _owner(text: str) -> int | None:
    """The pid in a lock file's text; None while it is being written."""
    text = text.strip()
    return int(text) if text.isdigit() else None
