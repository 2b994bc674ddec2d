"""Writers of a sweep's tables that take the rows one at a time (a sweep's rows are read back from
its rows file, never all in memory) and write what writing them all at once wrote, byte for byte:

- JsonDocument: json.dumps(document, indent=1), its "rows" list written row by row;
- ArrowColumns: the Arrow arrays of a Parquet table's columns, built from chunks of CHUNK_ROWS
  rows (Arrow's compact arrays, not Python values); a column whose chunks do not all take one
  type (ints in one, floats in another, mixed types) is built again from all its values, as
  pa.array of the whole column would have typed it.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from typing import Any

#: the value standing for the rows in the document given to JsonDocument
ROWS_MARK = "\x00rows of the sweep\x00"
#: the rows of one Arrow chunk of each column
CHUNK_ROWS = 4096


class JsonDocument:
    """json.dumps(document, indent=1) + a newline, written through `write` in pieces: the document
    (a dict whose "rows" is ROWS_MARK) before its rows (start), each row (add), the rest (end)."""

    def __init__(self, write: Callable[[str], Any], document: dict):
        text = json.dumps(document, indent=1)
        # "\n " starts only a key of the document itself (a string holds no raw line break)
        head, found, self.tail = text.partition('\n "rows": ' + json.dumps(ROWS_MARK))
        if not found:
            raise ValueError("the document has no top-level 'rows' standing for its rows")
        self.write = write
        self.count = 0
        write(head + '\n "rows": ')

    def add(self, row: dict) -> None:
        """One row, as json.dumps(indent=1) writes an item of the top-level "rows" list."""
        self.write(("[\n  " if self.count == 0 else ",\n  ") + json.dumps(row, indent=1).replace("\n", "\n  "))
        self.count += 1

    def end(self) -> None:
        self.write(("[]" if self.count == 0 else "\n ]") + self.tail + "\n")


def arrow_column(pa, values: list) -> Any:
    """The Arrow array of a column's values; JSON texts for mixed types (a varied column)."""
    try:
        return pa.array(values)
    except (pa.ArrowInvalid, pa.ArrowTypeError):
        return pa.array([None if v is None else json.dumps(v) for v in values])


class ArrowColumns:
    """The Arrow arrays of the columns `names` of rows given one at a time (add), each the array
    arrow_column makes of all its values (arrays): per column, chunks of `chunk` rows as pa.array
    types them, joined when they share one type (chunks of None only take it), else the column's
    values again from `values_of(name)` (a second pass over the rows)."""

    def __init__(self, pa, names: Sequence[str], chunk: int = CHUNK_ROWS):
        self.pa, self.names, self.chunk = pa, list(names), max(1, chunk)
        self.pending: dict[str, list] = {name: [] for name in self.names}
        self.chunks: dict[str, list | None] = {name: [] for name in self.names}  # None: not one type
        self.rows = 0

    def add(self, values: dict) -> None:
        """A row's values (by column name)."""
        for name in self.names:
            self.pending[name].append(values.get(name))
        self.rows += 1
        if self.rows % self.chunk == 0:
            self._flush()

    def _flush(self) -> None:
        """The pending values of each column as an Arrow chunk (a column of mixed types: none)."""
        for name, values in self.pending.items():
            if values and self.chunks[name] is not None:
                self.chunks[name] = _with_chunk(self.pa, self.chunks[name], values)
            values.clear()

    def arrays(self, values_of: Callable[[str], list]) -> dict[str, Any]:
        """Each column's array, in the order of `names` (once: each column's chunks are let go as it
        is joined, so that a column is never held twice over but while it is joined)."""
        self._flush()
        return {name: self._array(name, values_of) for name in self.names}

    def _array(self, name: str, values_of: Callable[[str], list]) -> Any:
        joined = _joined(self.pa, self.chunks.pop(name))
        return joined if joined is not None else arrow_column(self.pa, values_of(name))


def _with_chunk(pa, chunks: list, values: list) -> list | None:
    """The chunks and pa.array(values); None if Arrow cannot type the values as one type."""
    try:
        return [*chunks, pa.array(values)]
    except (pa.ArrowInvalid, pa.ArrowTypeError):
        return None


def _joined(pa, chunks: list | None) -> Any:
    """The chunks as one array, when all but those of None only share one type (those then take it);
    None when they do not (or a chunk could not be typed)."""
    if chunks is None:
        return None
    if not chunks:
        return pa.array([])
    types = {chunk.type for chunk in chunks if chunk.type != pa.null()}
    if len(types) > 1:
        return None
    kind = types.pop() if types else pa.null()
    return pa.concat_arrays([chunk if chunk.type == kind else pa.nulls(len(chunk), kind) for chunk in chunks])
