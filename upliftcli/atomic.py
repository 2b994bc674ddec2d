"""Atomic file output: write to a temporary file beside the target, then rename; and the
guard that keeps the outputs of a run off its inputs.

A new file gets the permissions of any file the user creates (0666 less the umask); a file
that is replaced keeps its own permissions (mkstemp's private 0600 is never left behind).
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path

from .errors import InputError


def current_umask() -> int:
    """The process's umask (read from /proc on Linux, else set and restored)."""
    try:
        with open("/proc/self/status", encoding="ascii") as handle:
            for line in handle:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def file_mode(target: Path) -> int:
    """Permissions for a file written at `target`: those of the file it replaces, else 0666 & ~umask."""
    try:
        return stat.S_IMODE(os.stat(target).st_mode)
    except OSError:
        return 0o666 & ~current_umask()


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside `path`; on success it replaces `path`, on error it is removed."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=target.suffix or ".tmp", dir=target.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        os.chmod(tmp_path, file_mode(target))
        os.replace(tmp_path, target)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()


def write_text(path: str | os.PathLike, text: str) -> None:
    """Write text atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """Write bytes atomically."""
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def refuse_inputs(outputs: Iterable[str | os.PathLike], inputs: Iterable[str | os.PathLike], option: str,
                  what: str = "an input of the run") -> None:
    """InputError naming `option` if an output path is (or would replace) one of the inputs
    (the deck, a record): the same file by inode, or the same resolved path."""
    inputs = [Path(p) for p in inputs if p]
    for output in (Path(p) for p in outputs):
        for source in inputs:
            if _same_file(output, source) or output.resolve() == source.resolve():
                raise InputError(option, str(output), f"a path that does not replace {what} ({source} is read by "
                                 "this run); choose another output directory or name")
