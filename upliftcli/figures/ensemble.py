"""A record suite drawn as one: each record thin, the statistic thick, the target dashed."""

from __future__ import annotations

import numpy as np

from ..engines.suite_result import STATISTICS
from .spec import Series

RECORD_WIDTH, STATISTIC_WIDTH, TARGET_WIDTH = 0.7, 2.6, 2.0


def statistic_of(values: np.ndarray, statistic: str) -> np.ndarray:
    """A statistic of a suite (engines/suite_result.STATISTICS: the codes take the mean, or
    the maximum of fewer records) over the first axis (records)."""
    if statistic not in STATISTICS:
        raise ValueError(f"statistic must be one of {', '.join(STATISTICS)}, got {statistic!r}")
    return STATISTICS[statistic][1](np.asarray(values, dtype=float))


def ensemble(label: str, position: np.ndarray, values: np.ndarray, statistic: str, color: str,
             style: str = "-", profile: bool = False) -> list[Series]:
    """One thin line per record (values (k, n): record k at the n positions), then the
    statistic over the records, thick; profile: the values on the x axis (story profiles)."""
    values = np.asarray(values, dtype=float)
    position = np.asarray(position, dtype=float)
    count = values.shape[0]
    lines = [_member(f"{label}: each of {count} records" if k == 0 else "", position, values[k], style, color,
                     RECORD_WIDTH, profile, 0.55) for k in range(count)]
    lines.append(_member(f"{label}: {statistic} of {count} records", position, statistic_of(values, statistic), style,
                         color, STATISTIC_WIDTH, profile))
    return lines


def _member(text: str, position: np.ndarray, values: np.ndarray, style: str, color: str, width: float,
            profile: bool, alpha: float = 1.0) -> Series:
    """A line of an ensemble: values at the positions (profile: the values on the x axis)."""
    x, y = (values, position) if profile else (position, values)
    return Series(text, x, y, style, color, width, alpha=alpha)


def target_series(label: str, x: np.ndarray, y: np.ndarray, color: str) -> Series:
    """The target (design spectrum, or a result on it), dashed."""
    return Series(label, np.asarray(x), np.asarray(y), "--", color, TARGET_WIDTH)
