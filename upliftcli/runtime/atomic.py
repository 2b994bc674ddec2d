"""Atomic file output: write to a temporary file beside the target, flush it to the disk, then
rename; a set of files all or none; the guards that keep the outputs of a run off its inputs
and off the files of an earlier run.

A new file gets the permissions of any file the user creates (0666 less the umask); a file
that is replaced keeps its own permissions, and its owner and group where the user may set
them (mkstemp's private 0600 is never left behind). A target that is a symbolic link is refused
(refuse_symlink): an output is never written through one. The temporary files are named
`.<target>.uplift-tmp-<pid>-<random><suffix>`: they are removed when the write fails or the
command is stopped (SIGTERM, SIGHUP and Ctrl-C end it through the clean-up), and those a killed
process (SIGKILL) left behind are removed by the next write into their folder once that process
is gone (remove_stale).
"""

from __future__ import annotations

import contextlib
import os
import re
import stat
import tempfile
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path

from ..errors import InputError
from .patterns import lazy
from .portable import process_alive

#: what marks a temporary file of this tool; the pid of the process that writes it follows
TEMP_MARK = ".uplift-tmp-"
_TEMP_NAME = lazy(r"^\..+" + re.escape(TEMP_MARK) + r"(?P<pid>\d+)-[A-Za-z0-9_]+")
#: where Linux tells a process its umask (elsewhere it is set and restored to be read)
PROC_STATUS = "/proc/self/status"
#: folders whose stale temporary files this process has removed already
_SWEPT: set[str] = set()


def current_umask() -> int:
    """The process's umask (read from /proc on Linux, else set and restored)."""
    mask = _proc_umask()
    if mask is not None:
        return mask
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _proc_umask() -> int | None:
    """The umask that Linux gives in PROC_STATUS ('Umask:' line), or None where it gives none."""
    try:
        with open(PROC_STATUS, encoding="ascii") as handle:
            for line in handle:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    return None


def file_mode(target: Path) -> int:
    """Permissions for a file written at `target`: those of the file it replaces, else 0666 & ~umask."""
    try:
        return stat.S_IMODE(os.stat(target).st_mode)
    except OSError:
        return 0o666 & ~current_umask()


def remove_stale(directory: str | os.PathLike) -> list[Path]:
    """Remove the temporary files of this tool in `directory` whose writing process is gone (a
    SIGKILL leaves them); return them. Files of a running process are left alone."""
    removed = []
    try:
        names = os.listdir(directory)
    except OSError:
        return removed
    for path in (Path(directory) / name for name in names if _is_stale(name)):
        with contextlib.suppress(OSError):
            path.unlink()
            removed.append(path)
    return removed


def _is_stale(name: str) -> bool:
    """Whether a file name is that of a temporary file of this tool whose writing process is gone."""
    match = _TEMP_NAME.match(name)
    return bool(match) and not process_alive(int(match.group("pid")))


def _sweep_once(directory: Path) -> None:
    key = os.path.abspath(directory)
    if key not in _SWEPT:
        _SWEPT.add(key)
        remove_stale(directory)


def _fsync(path: Path, directory: bool = False) -> None:
    """Flush a file (or a folder's entries) to the disk; a file system that cannot is left as is."""
    try:
        fd = os.open(path, os.O_RDONLY | (getattr(os, "O_DIRECTORY", 0) if directory else 0))
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        if not directory:
            raise
    finally:
        os.close(fd)


def _keep_owner(tmp: Path, target: Path) -> None:
    """Give `tmp` the owner and group of the file it replaces, where the user may."""
    try:
        status = os.stat(target)
    except OSError:
        return
    with contextlib.suppress(OSError, AttributeError):
        os.chown(tmp, status.st_uid, status.st_gid)


def refuse_symlink(path: str | os.PathLike, option: str = "--out") -> None:
    """InputError naming `option` and `path` if `path` is a symbolic link: an output is never
    written through one (it could point outside the output folder)."""
    if Path(path).is_symlink():
        raise InputError(option, str(path), "a path that is not a symbolic link (an output is never written "
                         "through one; remove the link or choose another output folder)")


def _temporary(target: Path) -> Path:
    refuse_symlink(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    _sweep_once(target.parent)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}{TEMP_MARK}{os.getpid()}-", suffix=target.suffix or ".tmp",
                               dir=target.parent)
    os.close(fd)
    return Path(tmp)


def _finish(tmp: Path, target: Path) -> None:
    """Permissions, owner and a flush to the disk before `tmp` may replace `target`."""
    os.chmod(tmp, file_mode(target))
    _keep_owner(tmp, target)
    _fsync(tmp)


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside `path`; on success it is flushed to the disk and replaces
    `path`, on error (or a stop signal) it is removed."""
    target = Path(path)
    tmp_path = _temporary(target)
    try:
        yield tmp_path
        _finish(tmp_path, target)
        os.replace(tmp_path, target)
        _fsync(target.parent, directory=True)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()


def write_text(path: str | os.PathLike, text: str) -> None:
    """Write text atomically."""
    with atomic_path(path) as tmp:
        _write(tmp, text)


def write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """Write bytes atomically."""
    with atomic_path(path) as tmp:
        _write(tmp, data)


def _write(path: Path, content: str | bytes) -> None:
    """Write bytes as they are, text as UTF-8."""
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content, encoding="utf-8")


def write_set(files: Mapping[str | os.PathLike, str | bytes]) -> list[Path]:
    """Write several files all or none: every one to its temporary file first (flushed to the
    disk), and only when all are written are they renamed into place, in the order given (put
    a manifest last); a failure (a full disk) or a stop signal before that removes them all,
    and the folders this call created, and leaves the targets as they were."""
    targets = [Path(path) for path in files]
    created = _missing_folders(targets)
    temporaries: list[Path] = []
    renamed = False
    try:
        for target, content in zip(targets, files.values(), strict=True):
            temporaries.append(_temporary(target))
            _write(temporaries[-1], content)
            _finish(temporaries[-1], target)
        for tmp, target in zip(temporaries, targets, strict=True):
            os.replace(tmp, target)
        renamed = True
        _fsync_folders(targets)
    finally:
        _remove_all(temporaries)
        if not renamed:
            _remove_folders(created)
    return targets


def _fsync_folders(targets: list[Path]) -> None:
    """Flush the entries of the targets' folders to the disk (each folder once)."""
    for folder in {t.parent for t in targets}:
        _fsync(folder, directory=True)


def _missing_folders(targets: list[Path]) -> set[Path]:
    """The folders (and their parents) of the targets that do not exist yet."""
    return {folder for target in targets for folder in (target.parent, *target.parent.parents) if not folder.exists()}


def _remove_all(paths: list[Path]) -> None:
    """Remove the files that are still there (a temporary file renamed into place is not)."""
    for path in paths:
        with contextlib.suppress(OSError):
            path.unlink()


def _remove_folders(folders: set[Path]) -> None:
    """Remove the folders (those that are empty), the deepest first."""
    for folder in sorted(folders, key=lambda p: len(p.parts), reverse=True):
        with contextlib.suppress(OSError):
            folder.rmdir()


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def _same_path(a: Path, b: Path) -> bool:
    """The same file by inode, or the same resolved path (a file that does not exist yet)."""
    return _same_file(a, b) or a.resolve() == b.resolve()


def _replaced_input(output: Path, inputs: list[Path]) -> Path | None:
    """The first input that the output is, or would replace (_same_path); None when there is none."""
    return next((source for source in inputs if _same_path(output, source)), None)


def refuse_inputs(outputs: Iterable[str | os.PathLike], inputs: Iterable[str | os.PathLike], option: str,
                  what: str = "an input of the run") -> None:
    """InputError naming `option` if an output path is (or would replace) one of the inputs
    (the deck, a record): the same file by inode, or the same resolved path."""
    inputs = [Path(p) for p in inputs if p]
    for output in (Path(p) for p in outputs):
        source = _replaced_input(output, inputs)
        if source is not None:
            raise InputError(option, str(output), f"a path that does not replace {what} ({source} is read by "
                             "this run); choose another output directory or name")


def refuse_existing(outputs: Iterable[str | os.PathLike], option: str, overwrite: bool, what: str = "") -> None:
    """InputError naming `option` and the first output that exists already, unless `overwrite`
    (the option that allows it is --overwrite). what: whose file it is, in words."""
    if overwrite:
        return
    for output in (Path(p) for p in outputs):
        if output.exists() or output.is_symlink():
            raise InputError(option, str(output), f"a new file (it exists{what}; pass --overwrite to replace it)")
