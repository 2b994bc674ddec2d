"""The records of a deck's suite: its entries (a folder of record files, or a list of paths and
tables {file, format, units, dt, scale, override_header_units, made}), each checked by the field
checker, and the records they name, read once per process while the file is unchanged.
suites.py builds the Suite from them (and names these functions too).
"""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path

from ..deck.fields import Field, check_mapping, raiser
from ..errors import InputError, deck_relative_path
from ..runtime import limits
from .origins import ORIGINS, origin_of
from .records import RECORD_FIELDS, Record, read_record

#: files of a suite folder that are read as records
RECORD_SUFFIXES = (".at2", ".txt", ".csv", ".dat", ".acc")


def suite_entries(value, source: str, field: str = "ground_motion.suite") -> list[tuple[Path, dict]]:
    """(path, reader options) of each record of a deck's suite: a folder (its record files, sorted
    by name) or a list of paths and tables {file, format, units, dt, scale, override_header_units,
    made} (check_entry); paths relative to the deck's folder."""
    if isinstance(value, str):
        return _folder_entries(deck_relative_path(value, source), source, field)
    _check_record_count(len(value), source, field, "")
    entries = []
    for k, item in enumerate(value):
        checked = check_entry({"file": item} if isinstance(item, str) else item, source, f"{field}[{k}]")
        options = {key: checked[key] for key in checked if key != "file"}
        entries.append((deck_relative_path(checked["file"], source), options))
    return entries


def _folder_entries(folder: Path, source: str, field: str) -> list[tuple[Path, dict]]:
    """The record files of a suite folder (named_as_record), sorted by name, with no options;
    InputError naming one that is not a regular file (check_regular)."""
    if not folder.is_dir():
        raise InputError(source, field, f"a folder of records (or a list of files), not found: {str(folder)!r}")
    files = sorted(path for path in folder.iterdir() if named_as_record(path))
    check_regular(files, source, field)
    if not files:
        raise InputError(source, field, f"record files ({', '.join(RECORD_SUFFIXES)}) in {str(folder)!r}")
    _check_record_count(len(files), source, field, f" in {str(folder)!r}")
    return [(path, {}) for path in files]


def named_as_record(path: Path) -> bool:
    """A file of a suite folder read as a record: named with one of RECORD_SUFFIXES, not a readme or manifest."""
    return path.suffix.lower() in RECORD_SUFFIXES and not path.name.lower().startswith(("readme", "manifest"))


#: what an entry of a folder that is not a regular file is, by the test of its mode
_KINDS = ((stat.S_ISFIFO, "a named pipe (FIFO)"), (stat.S_ISDIR, "a folder"), (stat.S_ISSOCK, "a socket"),
          (stat.S_ISCHR, "a device"), (stat.S_ISBLK, "a device"))


def not_regular(path: Path) -> str | None:
    """What a path is when it is not a regular file (after its links): 'a named pipe (FIFO)',
    'a folder', ..., or why it cannot be seen (a broken link); None for a regular file. It is
    never opened (a FIFO would block)."""
    try:
        mode = os.stat(path).st_mode
    except OSError as error:
        return f"not readable ({error.strerror or error})"
    if stat.S_ISREG(mode):
        return None
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")


def check_regular(paths: list[Path], source: str, field: str) -> None:
    """InputError naming the first path (a suite folder's record file) that is not a regular
    file: a FIFO among the records was passed over without a word (issue 38)."""
    for path in paths:
        kind = not_regular(path)
        if kind:
            raise InputError(source, field, f"regular record files in {str(path.parent)!r}: {path.name!r} is {kind} "
                             "(move it out of the folder, or list the records in the deck)")


def _check_record_count(count: int, source: str, field: str, where: str) -> None:
    """InputError for a suite of more than limits.MAX_SUITE_RECORDS records (where: ' in folder')."""
    if count > limits.MAX_SUITE_RECORDS:
        raise InputError(source, field, f"at most {limits.MAX_SUITE_RECORDS:,} records (limit of the tool), got "
                         f"{count:,}{where}")


#: the keys of a suite's record entry {file, format, units, dt, scale, override_header_units}
ENTRY_FIELDS: dict[str, Field] = {"file": Field("string", "-", "path of the record file (relative to the deck)"),
                                  **RECORD_FIELDS,
                                  "made": Field("string", "-", "how the record was made (default: from the "
                                                "manifest.json beside it, else recorded; motion/origins.py)",
                                                "", None, ORIGINS)}


def check_entry(item, source: str, where: str, error_for=None) -> dict:
    """A suite's record entry (a table) checked by the field checker (fields.check_mapping: every
    key, its type, unit and range; all errors together), with its `file`; error_for(path) gives
    the error function of a key (default: InputError(source, path, ...))."""
    error_for = error_for or raiser(source)
    if not isinstance(item, dict):
        error_for(where)(f"a file path or a table {{file = ..., units = ..., dt = ...}}, got {item!r}")
    checked = check_mapping(ENTRY_FIELDS, item, where, error_for, what="a key of a suite record")
    if "file" not in checked:
        error_for(f"{where}.file")("the path of a record file")
    return checked


#: the suites' records read in this process: (file, its size and time of change, options) -> Record
_READ: dict[tuple, Record] = {}
_READ_LIMIT = 64


def read_records(entries: list[tuple[Path, dict]]) -> list[Record]:
    """Read every record of suite_entries (format and units detected unless given); a file read
    before in this process and unchanged since (same size and time of change) is not read again:
    a sweep builds the suite of every case, whose records are the same (their scaling differs),
    and reading them was 60 % of planning `uplift spectra` on a suite deck."""
    records = []
    for path, options in entries:
        key = _read_key(path, options)
        record = _READ.get(key) if key else None
        if record is None:
            record = read_record(path, options.get("format"), options.get("units"), options.get("dt"),
                                 options.get("scale", 1.0),
                                 override_header_units=options.get("override_header_units", False))
            _remember(key, record)
        records.append(record)
    return records


def _read_key(path: Path, options: dict) -> tuple | None:
    """The key of a record in _READ: (file, its size and time of change, options); None when the
    file cannot be stat'ed or the options are not JSON."""
    try:
        status = os.stat(path)
        return (os.path.abspath(path), status.st_size, status.st_mtime_ns, json.dumps(options, sort_keys=True))
    except (OSError, TypeError):
        return None


def _remember(key: tuple | None, record: Record) -> None:
    """Keep a record read under its key (none without one); _READ is emptied at _READ_LIMIT records."""
    if not key:
        return
    if len(_READ) >= _READ_LIMIT:
        _READ.clear()
    _READ[key] = record


def entry_origins(entries: list[tuple[Path, dict]]) -> tuple[str, ...]:
    """How each record of suite_entries was made (its `made`, else its folder's manifest)."""
    return tuple(origin_of(path, options.get("made")) for path, options in entries)
