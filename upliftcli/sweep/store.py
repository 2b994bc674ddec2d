"""The append-only rows file of a sweep (JSON lines): one line per finished case, flushed
and fsynced as it arrives. A torn last line (the process was killed while writing it) is
ignored and cut off before appending.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from .plan import STATUSES


class RowStore:
    """Append-only JSON-lines file of finished rows: one line per case, flushed and fsynced."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        self._file = None

    def read(self) -> dict[str, dict]:
        """key -> last row; a torn last line (killed while writing) is ignored."""
        rows: dict[str, dict] = {}
        if not self.path.exists():
            return rows
        for line in self.path.read_text(encoding="utf-8").splitlines():
            try:
                row = json.loads(line)
            except json.JSONDecodeError:
                continue
            if isinstance(row, dict) and "key" in row and row.get("status") in STATUSES:
                rows[row["key"]] = row
        return rows

    def open(self, fresh: bool) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        if not fresh and self.path.exists():
            data = self.path.read_bytes()
            if data and not data.endswith(b"\n"):  # drop a torn last line before appending
                with open(self.path, "r+b") as handle:
                    handle.truncate(data.rfind(b"\n") + 1)
        self._file = open(self.path, "w" if fresh else "a", encoding="utf-8")

    def append(self, row: dict) -> None:
        from ..output import to_jsonable

        self._file.write(json.dumps(to_jsonable(row), allow_nan=False) + "\n")
        self._file.flush()
        os.fsync(self._file.fileno())

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None
