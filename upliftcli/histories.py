"""The response histories of an analysis as a file (`uplift analyze --histories`): CSV with the
units in its header, or NPZ, written atomically with the provenance of the run, as every result
file (output.py) is.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .engines.quantities import HISTORY_SIGNALS, QUANTITIES, ROCKING, file_column
from .provenance.record import csv_comments
from .provenance.values import to_text_numbers
from .runtime.atomic import atomic_path, write_text


def _histories_csv(histories: dict[str, np.ndarray], provenance: dict | None, system: str = "si") -> str:
    """Response histories as CSV text: the provenance's '#' lines, a header with units (of `system`:
    history_column), values with 10 significant digits (write_histories)."""
    columns = {name: history_column(name, system) for name in histories}
    header = ",".join(column for column, _ in columns.values())
    table = np.column_stack([np.asarray(histories[name], dtype=float) * factor
                             for name, (_, factor) in columns.items()])
    lines = [header] + [",".join(f"{value:.10g}" for value in row) for row in table]
    return csv_comments(provenance) + "\n".join(lines) + "\n"


def write_histories(path, histories: dict[str, np.ndarray], provenance: dict | None = None,
                    system: str = "si") -> None:
    """Write response histories atomically: NPZ if the name ends in .npz (the provenance as JSON
    text in its array 'provenance'), else CSV with units in the header
    (history_unit) as every CSV result has them (column_name: time_s, drift_3_m,
    contact_state), after the provenance's '#' lines; values with 10
    significant digits (the histories are sampled at the record's step: more digits would
    only lengthen the file). system: the CSV's units (SI, or us: drift_3_in); the NPZ is SI."""
    path = Path(path)
    if path.suffix.lower() != ".npz":
        write_text(path, _histories_csv(histories, provenance, system))
        return
    extra = {} if provenance is None else {"provenance": np.array(json.dumps(to_text_numbers(provenance)))}
    with atomic_path(path) as tmp, open(tmp, "wb") as handle:
        np.savez_compressed(handle, **histories, **extra)


def history_column(name: str, system: str = "si") -> tuple[str, float]:
    """(column name, factor from SI) of a --histories column in a unit system (file_column; a
    length there is a displacement: in under --units us)."""
    unit = history_unit(name)
    return file_column(name, unit, "mm" if unit == "m" else "", system)


def history_unit(column: str) -> str:
    """Unit of a --histories column ('drift_3' -> 'm')."""
    if column in HISTORY_SIGNALS:
        return HISTORY_SIGNALS[column]
    name = column.rsplit("_", 1)[0]
    return (QUANTITIES.get(name) or ROCKING[name]).unit
