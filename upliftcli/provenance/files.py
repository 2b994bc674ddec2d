"""The input files of a provenance record (provenance/record.py): each file's SHA-256 (cached on its
path, size and modification time) and size, a record's entry (the digest of the bytes it was
read from, its format, units, dt [s], samples, scale) and the entries of a ground motion (a
record, each record of a suite with its factor, a design-spectrum table file).
docs/provenance.md describes the keys.
"""

from __future__ import annotations

import os
from functools import lru_cache
from pathlib import Path
from typing import Any


@lru_cache(maxsize=512)
def _digest(path: str, size: int, mtime_ns: int) -> str:
    import hashlib  # here, not at start-up: 7 ms of OpenSSL for a command that hashes nothing

    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def sha256(path: str | os.PathLike) -> str | None:
    """SHA-256 (hex) of a file's bytes, None when it cannot be read."""
    try:
        status = os.stat(path)
        return _digest(os.path.abspath(path), status.st_size, status.st_mtime_ns)
    except OSError:
        return None


def file_entry(role: str, path: str | os.PathLike, **extra: Any) -> dict[str, Any]:
    """{role, path (absolute), sha256, bytes, **extra} of an input file."""
    try:
        size = os.stat(path).st_size
    except OSError:
        size = None
    return {"role": role, "path": os.path.abspath(path), "sha256": sha256(path), "bytes": size, **extra}


def record_sha256(record) -> str | None:
    """The SHA-256 of the bytes a records.Record was parsed from (read once: a file replaced
    since does not change it); for a record made in code without one, its file's now, or None."""
    return getattr(record, "sha256", "") or (sha256(record.source) if record.source else None)


def record_entry(record, role: str = "record", **extra: Any) -> dict[str, Any]:
    """An input-file entry of a records.Record: the SHA-256 of the bytes it was read from
    (record_sha256) and its file's size, the format it was read as, units of the file, name,
    time step dt [s], samples, the scale applied [-]."""
    entry = {**file_entry(role, record.source), "sha256": record_sha256(record)} if record.source else \
        {"role": role, "path": None, "sha256": None, "bytes": None}
    return {**entry, "format": getattr(record, "format", ""), "units": record.units, "name": record.name,
            "dt": float(record.dt), "npts": record.npts, "scale": float(record.scale), **extra}


def _suite_files(suite) -> list[dict[str, Any]]:
    """Input-file entries of a motion.suites.Suite: each record with its amplitude factor and
    note, then its target spectrum's (motion_files)."""
    records = suite.records
    notes = tuple(suite.provenance) + ("",) * (len(records) - len(suite.provenance))
    entries = [record_entry(record, f"suite record {k + 1}", factor=float(factor), note=note)
               for k, (record, factor, note) in enumerate(zip(records, suite.factors, notes, strict=True))]
    return entries + motion_files(suite.target)


def motion_files(motion) -> list[dict[str, Any]]:
    """Input-file entries of a ground motion: a record, each record of a suite (with its
    amplitude factor), or a design spectrum read from a table file; none for None."""
    from ..motion.records import Record

    if isinstance(motion, Record):
        return [record_entry(motion)]
    if getattr(motion, "records", None) is not None:
        return _suite_files(motion)
    source = getattr(motion, "source", "")
    if source and Path(str(source)).is_file():
        return [file_entry("design spectrum table", source)]
    return []


def input_files(deck) -> list[str]:
    """The files a deck's run reads: the deck, its record or each record of its suite, and a
    design-spectrum table file (outputs must never replace them)."""
    return [str(deck.source), *(entry["path"] for entry in motion_files(deck.ground_motion) if entry["path"])]
