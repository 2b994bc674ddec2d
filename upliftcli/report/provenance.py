"""Where a report came from: the provenance record every result file carries
(upliftcli.provenance.record, docs/provenance.md), under the keys the report reads: tool, version,
python, platform, libraries, command, time_utc and files [{role, path, sha256, bytes}]."""

from __future__ import annotations

import os
from collections.abc import Sequence
from datetime import datetime
from typing import Any

from ..provenance import files as provenance_files
from ..provenance import record


def sha256(path) -> str:
    """SHA-256 of a file's bytes (hex), '' if it cannot be read."""
    return provenance_files.sha256(path) or ""


def provenance(deck, argv: Sequence[str] | None = None, now: datetime | None = None) -> dict[str, Any]:
    """The provenance record of a run of `deck` (provenance.of_deck), its command from argv."""
    return record.of_deck(deck, record.command_line(argv), now)


def relative_path(path, folder) -> str:
    """`path` relative to `folder` (the deck's: the report names no absolute path); as given
    when there is no folder, or on another drive."""
    if not folder or not path:
        return str(path)
    try:
        return os.path.relpath(os.path.abspath(path), os.path.abspath(folder))
    except ValueError:  # another drive (Windows)
        return str(path)
