"""The append-only rows file of a sweep (JSON lines): one line per finished case,
opened with O_NOFOLLOW (a symbolic link at it is refused: rows are never written outside --out), flushed as
it arrives (it survives the process being killed) and fsynced at most FSYNC_SECONDS later and at
close (a crash of the machine loses at most that much, which --resume runs again; an fsync per
row cost 0.2-1.6 s per 300 rows here). A torn last line (the process was killed while writing
it) is ignored and cut off before appending.

Each run first appends a header line {"run": {"fingerprint", "deck", "records", "version"}}
and every row carries the fingerprint of the run that computed it, so that `--resume`
can tell rows computed from another record file or tool version (sweep/run.py). The
output stem is locked while a sweep writes it (stem_lock): a second sweep with the same
--out and --name is refused instead of mixing its rows with the first one's.
"""

from __future__ import annotations

import contextlib
import errno
import functools
import json
import os
import sys
import time
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..runtime import locks
from ..runtime.atomic import refuse_symlink
from .plan import STATUSES

FSYNC_SECONDS = 0.5  # [s]
#: open flags that never follow a symbolic link at the rows file (where the system has them)
NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)


class RowStore:
    """Append-only JSON-lines file of finished rows: one line per case, flushed, fsynced soon."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        self._file = None
        self.appended = 0
        self._created = False
        self._synced = -float("inf")  # time.monotonic() of the last fsync

    def _lines(self) -> Iterator[tuple[int, Any]]:
        """(byte offset, JSON value) of each line of the file, read line by line (none if there is
        no file); lines that are not JSON (a torn last line: killed while writing) are skipped."""
        refuse_symlink(self.path)
        if not self.path.exists():
            return
        offset = 0
        with open(self.path, "rb") as handle:
            for line in handle:
                item = _parsed(line)
                if item is not None:
                    yield offset, item
                offset += len(line)

    def _items(self) -> Iterator[Any]:
        """The JSON value of each line of the file (_lines)."""
        return (item for _, item in self._lines())

    def read(self) -> dict[str, dict]:
        """key -> last row (with its "fingerprint", if any); a torn last line (killed while writing) is ignored."""
        return {row["key"]: row for row in self._items() if _is_row(row)}

    def scan(self) -> dict[str, Entry]:
        """key -> where its last row is, its status and fingerprint (Entry), in order of first appearance."""
        return {item["key"]: _entry(offset, item) for offset, item in self._lines() if _is_row(item)}

    def fields(self) -> set[str]:
        """The dotted names of the rows (their varied fields: no output column has a dot)."""
        return {name for item in self._items() if _is_row(item) for name in item if "." in name}

    def rows_of(self, keys: Iterable[str]) -> StoredRows:
        """The last rows of the cases `keys` (those the file holds), in that order, read back from the file."""
        entries = self.scan()
        return StoredRows(self.path, [entries[key].offset for key in keys if key in entries])

    def runs(self) -> dict[str, dict]:
        """fingerprint -> the header of the run that wrote rows with it (what it read)."""
        return {str(item["run"].get("fingerprint")): item["run"] for item in self._items() if _is_header(item)}

    def open(self, fresh: bool, header: dict | None = None) -> None:
        """Open for appending (fresh: discard the previous rows), then write the run's header."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        refuse_symlink(self.path)
        self._created = fresh or self._empty()
        if not fresh:
            self._drop_torn_line()
        mode = os.O_TRUNC if fresh else os.O_APPEND
        self._file = os.fdopen(self._open_fd(os.O_WRONLY | os.O_CREAT | mode), "w", encoding="utf-8")
        if header is not None:
            self._write({"run": header})

    def _empty(self) -> bool:
        """Whether there is no file, or an empty one."""
        return not self.path.exists() or self.path.stat().st_size == 0

    def _drop_torn_line(self) -> None:
        """Cut off a torn last line (no newline at the end) before appending."""
        end = _whole_lines_end(self.path) if self.path.exists() else None
        if end is not None:
            fd = self._open_fd(os.O_WRONLY)
            try:
                os.ftruncate(fd, end)
            finally:
                os.close(fd)

    def _open_fd(self, flags: int) -> int:
        """The rows file opened with `flags`, never through a symbolic link (O_NOFOLLOW): one put
        there meanwhile is refused naming --out."""
        try:
            return os.open(self.path, flags | NOFOLLOW, 0o666)
        except OSError as error:
            if error.errno == errno.ELOOP:
                refuse_symlink(self.path)
            raise

    def _write(self, item: dict) -> None:
        from ..output import to_jsonable

        self._file.write(json.dumps(to_jsonable(item), allow_nan=False) + "\n")
        self._file.flush()
        now = time.monotonic()
        if now - self._synced >= FSYNC_SECONDS:
            os.fsync(self._file.fileno())
            self._synced = now

    def append(self, row: dict, fingerprint: str | None = None) -> None:
        self._write(row if fingerprint is None else {**row, "fingerprint": fingerprint})
        self.appended += 1

    def close(self, discard_if_empty: bool = False) -> None:
        """Fsync and close the file (an error while flushing, e.g. a full disk, is not raised
        again: the rows already written are flushed). discard_if_empty: remove a file this run
        created and wrote no row to (a sweep that stopped before its first case)."""
        if self._file is not None:
            self._close_file()
        if discard_if_empty and self._created and self.appended == 0:
            with contextlib.suppress(OSError):
                self.path.unlink()

    def _close_file(self) -> None:
        """Flush, fsync and close the file, each error of them ignored."""
        with contextlib.suppress(OSError):
            self._file.flush()
            os.fsync(self._file.fileno())
        with contextlib.suppress(OSError):
            self._file.close()
        self._file = None


#: the bytes read at a time from the end of the file, looking for its last line break
TAIL_BYTES = 1 << 16


def _whole_lines_end(path: Path) -> int | None:
    """The size of the file's whole lines when its last line is torn (no newline at the end:
    killed while writing), read backwards from the end; None when it ends with one (or is empty)."""
    with open(path, "rb") as handle:
        size = handle.seek(0, os.SEEK_END)
        position = size
        while position > 0:
            start = max(0, position - TAIL_BYTES)
            handle.seek(start)
            block = handle.read(position - start)
            if position == size and block.endswith(b"\n"):
                return None
            if b"\n" in block:
                return start + block.rfind(b"\n") + 1
            position = start
    return 0 if size else None


def _parsed(line: bytes) -> Any:
    """The JSON value of a line of the file; None for a line that is not JSON (a torn last line)."""
    try:
        return json.loads(line)
    except ValueError:  # not JSON, or not UTF-8
        return None


@dataclass(frozen=True, slots=True)
class Entry:
    """Where a case's last row starts in the rows file, its status and fingerprint."""

    offset: int
    status: str
    fingerprint: str | None


def _interned(value: Any) -> Any:
    """A text interned (the same status and fingerprint of every row held once), anything else as it is."""
    return sys.intern(value) if isinstance(value, str) else value


def _entry(offset: int, row: dict) -> Entry:
    return Entry(offset, _interned(row["status"]), _interned(row.get("fingerprint")))


def without_fingerprint(row: dict) -> dict:
    """A stored row without the fingerprint of the run that wrote it."""
    return {name: value for name, value in row.items() if name != "fingerprint"}


class StoredRows:
    """The rows at `offsets` of a rows file, read back one at a time in that order each time it is
    iterated, without their fingerprint: a sweep's rows, never all in memory (the file must not
    change meanwhile: the sweep holds stem_lock)."""

    def __init__(self, path: Path, offsets: list[int]):
        self.path, self.offsets = Path(path), offsets

    def __len__(self) -> int:
        return len(self.offsets)

    def __iter__(self) -> Iterator[dict]:
        with open(self.path, "rb") as handle:
            for offset in self.offsets:
                handle.seek(offset)
                yield without_fingerprint(json.loads(handle.readline()))


def _is_row(item: Any) -> bool:
    """Whether a line of the file is a row: an object with a key and a known status."""
    return isinstance(item, dict) and "key" in item and item.get("status") in STATUSES


def _is_header(item: Any) -> bool:
    """Whether a line of the file is a run's header: {"run": {...}}."""
    return isinstance(item, dict) and isinstance(item.get("run"), dict)


@contextlib.contextmanager
def stem_lock(out: Path, stem: str) -> Iterator[None]:
    """Hold an exclusive lock on <out>/.<stem>.lock while a sweep writes <out>/<stem>.*;
    InputError naming --out if another sweep holds it. The lock file is removed afterwards
    (a lock left by a killed sweep is free again: the system releases it with the process, or
    the pid in it names a process that is gone; runtime/locks.py).
    A directory created here and left empty is removed too."""
    created = not out.exists()
    _writable(out, functools.partial(out.mkdir, parents=True, exist_ok=True))
    path = out / f".{stem}.lock"
    refuse_symlink(path)
    fd = _writable(out, functools.partial(locks.acquire, path))
    if fd is None:
        raise InputError("--out", str(out / stem), "an output stem no other sweep is writing (another "
                         "`uplift sweep` with the same --out and --name is running: wait for it to end or "
                         "choose another --name)")
    try:
        yield
    finally:
        locks.release(path, fd)
        if created:
            with contextlib.suppress(OSError):
                out.rmdir()  # only if empty


def _writable(out: Path, action: Callable[[], Any]) -> Any:
    """action() on the output directory; its OSError as an InputError naming --out."""
    try:
        return action()
    except OSError as error:
        raise InputError("--out", str(out), f"a writable directory ({error.strerror or error})") from None
