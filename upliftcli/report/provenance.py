"""Where a report came from: tool and library versions, the deck and record files with their
SHA-256, the command, the UTC time.

A stop-gap kept small and separate on purpose: issue 15 adds provenance helpers for every
output (JSON, CSV, sweep tables); when they land, `provenance` here is replaced by them and
the report reads the same keys.
"""

from __future__ import annotations

import hashlib
import platform
import sys
from collections.abc import Sequence
from datetime import UTC, datetime
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

LIBRARIES = ("numpy", "scipy", "numba", "matplotlib")


def sha256(path: str | Path) -> str:
    """SHA-256 of a file's bytes (hex), '' if it cannot be read."""
    digest = hashlib.sha256()
    try:
        with open(path, "rb") as handle:
            for block in iter(lambda: handle.read(1 << 16), b""):
                digest.update(block)
    except OSError:
        return ""
    return digest.hexdigest()


def package_version(name: str) -> str:
    try:
        return version(name)
    except PackageNotFoundError:
        return "not installed"


def input_files(deck) -> list[tuple[str, str]]:
    """(role, path) of every file the deck's analysis read: the deck, its record or the records
    of its suite, a design-spectrum table file."""
    from ..motion.records import Record
    from ..motion.suites import Suite

    files = [("deck", str(deck.source))]
    motion = deck.ground_motion
    if isinstance(motion, Record) and motion.source:
        files.append(("record", str(motion.source)))
    elif isinstance(motion, Suite):
        files += [(f"suite record {k + 1}", str(r.source)) for k, r in enumerate(motion.records) if r.source]
    target = getattr(motion, "target", motion)
    table_source = getattr(target, "source", "")
    if table_source and Path(str(table_source)).is_file() and str(table_source) != str(deck.source):
        files.append(("design spectrum table", str(table_source)))
    return files


def provenance(deck, argv: Sequence[str] | None = None, now: datetime | None = None) -> dict[str, Any]:
    """{tool, version, python, platform, libraries, command, time_utc, files: [{role, path,
    sha256, bytes}]} of a run of `deck`."""
    files = []
    for role, path in input_files(deck):
        size = Path(path).stat().st_size if Path(path).is_file() else None
        files.append({"role": role, "path": path, "sha256": sha256(path), "bytes": size})
    return {
        "tool": "uplift",
        "version": package_version("uplift"),
        "python": sys.version.split()[0],
        "platform": platform.platform(),
        "libraries": {name: package_version(name) for name in LIBRARIES},
        "command": " ".join(argv if argv is not None else sys.argv),
        "time_utc": (now or datetime.now(UTC)).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "files": files,
    }
