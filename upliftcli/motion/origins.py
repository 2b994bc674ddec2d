"""How each record of a suite was made: "recorded", "matched" (spectrally matched) or "artificial"
(generated), read from the manifest.json that `uplift record generate | match | select` write
beside their records, or from a suite entry's `made` key (docs/deck.md).

The code rules depend on it wherever the records are loaded: ASCE 7-22 16.2.3.3 asks 110 % of the
target of the mean of spectrally matched records (90 % of amplitude-scaled ones), whatever the
deck's `scaling` says of how they are used, and 16.2.2 asks for recorded motions, simulated ones
only to supplement them (a warning names it).
"""

from __future__ import annotations

import functools
from pathlib import Path

ORIGINS = ("recorded", "matched", "artificial")
#: the command of a manifest -> how its records were made
COMMAND_ORIGINS = {"record generate": "artificial", "record match": "matched", "record select": "recorded"}


@functools.lru_cache(maxsize=64)
def _manifest_files(folder: str, mtime: float) -> dict[str, str]:
    """{file name: origin} of a folder's manifest.json (empty when there is none or it is not one of ours)."""
    import json

    try:
        document = json.loads((Path(folder) / "manifest.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    origin = _manifest_origin(document)
    records = document.get("records") if origin is not None else None
    if not isinstance(records, list):
        return {}
    return {str(row["file"]): origin for row in records if isinstance(row, dict) and "file" in row}


def _manifest_origin(document) -> str | None:
    """How the records of a manifest were made: its `made`, else by its command (COMMAND_ORIGINS);
    None for a document that is not a manifest of ours or says neither."""
    if not isinstance(document, dict) or document.get("tool") != "uplift":
        return None
    made = document.get("made")
    return made if made in ORIGINS else COMMAND_ORIGINS.get(document.get("command"))


def origin_of(path: str | Path, given: str | None = None) -> str:
    """How the record file at `path` was made: `given` (a suite entry's `made`), else its
    folder's manifest, else "recorded"."""
    if given is not None:
        return given
    path = Path(path)
    manifest = path.parent / "manifest.json"
    try:
        mtime = manifest.stat().st_mtime
    except OSError:
        return "recorded"
    return _manifest_files(str(path.parent.resolve()), mtime).get(path.name, "recorded")
