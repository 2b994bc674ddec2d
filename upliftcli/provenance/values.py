"""The values of result files: plain, JSON-ready Python values (numpy arrays and scalars, tuples
and paths converted) and the text of their numbers (at most DIGITS significant digits, the
shortest text of that value). Imports nothing of the package: provenance/record.py and
provenance/model.py, output.py, the deck and the sweep all build on it.
"""

from __future__ import annotations

import math
import os
from typing import Any

#: significant digits of every number written to a result file (DBL_DIG: the digits a double
#: keeps through decimal text; 15.299999999999999 is written 15.3)
DIGITS = 15


#: the leaves that are already plain (by exact type: a numpy scalar, a float subclass, is converted)
_PLAIN = frozenset((str, int, bool, type(None)))


def plain(value: Any, finite: bool = False) -> Any:
    """numpy arrays and scalars, tuples and paths as plain Python lists, numbers and strings,
    recursively (mapping keys as text): the deck's mapping built in code, as TOML would give it,
    and every provenance entry. finite: a NaN or an infinity as None, as JSON has them (to_jsonable).
    The plain leaves (most of a result) are returned first, without the tests of the others."""
    if type(value) is float:
        return _plain_float(value, finite)
    if type(value) in _PLAIN:
        return value
    if isinstance(value, dict):
        return {str(k): plain(v, finite) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v, finite) for v in value]
    if hasattr(value, "tolist") and hasattr(value, "dtype"):  # numpy array or scalar
        return plain(value.tolist(), finite)
    return _plain_leaf(value, finite)


def _plain_float(value: float, finite: bool) -> float | None:
    """A float as it is; with finite, a NaN or an infinity as None."""
    return None if finite and not math.isfinite(value) else value


def _plain_leaf(value: Any, finite: bool) -> Any:
    """A path as its text; with finite, a NaN or an infinity as None; any other value as it is."""
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, float):
        return _plain_float(value, finite)
    return value


def to_jsonable(value: Any) -> Any:
    """plain(value) with every NaN and infinity as None: what the results, the sweep's rows and
    `uplift analyze --format json` write."""
    return plain(value, finite=True)


def rounded(value: float) -> float:
    """value rounded to DIGITS significant digits (its shortest text then has no noise digits)."""
    return float(f"{float(value):.{DIGITS}g}")


def number_text(value: float) -> str:
    """The text of a number in a result file: the shortest text of `rounded(value)`; '' for NaN
    and infinities (no value)."""
    value = float(value)
    return repr(rounded(value)) if math.isfinite(value) else ""


def to_text_numbers(value: Any) -> Any:
    """Every float rounded to DIGITS significant digits (non-finite -> None), recursively."""
    if isinstance(value, dict):
        return {k: to_text_numbers(v) for k, v in value.items()}
    if isinstance(value, list):
        return [to_text_numbers(v) for v in value]
    if isinstance(value, float):
        return rounded(value) if math.isfinite(value) else None
    return value
