"""sweep --check: each finished simplified case's ratios simplified / exact to the exact case of
the same varied values and support (table.CHECK_COLUMNS), and the ratios outside the deck's
[criteria] simplified_error band as its violations. checked_rows does it for rows read back from
the rows file (twice: the exact cases' compared values first, then each row as it is read)."""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator, Sequence
from typing import Any

from ..analysis.comparison import MOTION
from ..engines.quantities import COMPARED
from .plan import SweepPlan
from .summary import finite_number


def _check_key(row: dict, paths: Sequence[str]) -> str:
    """What a simplified case and its exact reference share: support and varied values (as JSON)."""
    return json.dumps([row.get("support"), *(row.get(p) for p in paths)], default=str)


def add_checks(plan: SweepPlan, rows: Sequence[dict]) -> list[dict]:
    """The rows, each finished simplified case with the ratios simplified / exact of the exact
    case of the same varied values and support (CHECK_COLUMNS; empty where there is none); with
    [criteria] simplified_error = e, a ratio outside the band `uplift analyze`'s check then flags
    (_band: [1/(1 + e), 1 + e], the mat's motion the deck's check_band_motion widened to hold it)
    is a violation of the simplified case (deck/criteria.py); a varied criteria.simplified_error is
    each case's own."""
    return list(checked_rows(plan, rows))


class CheckedRows:
    """The rows with their ratios to the exact cases (add_checks), made as they are read: `rows` is
    read once here for the exact cases' compared values (only those are kept), then once per
    iteration."""

    def __init__(self, plan: SweepPlan, rows: Iterable[dict]):
        self.plan, self.rows = plan, rows
        self.paths = [v.path for v in plan.varies]
        self.exact = {_check_key(row, self.paths): {"compared": row.get("compared")} for row in rows
                      if _finished_by(row, "exact")}

    def __iter__(self) -> Iterator[dict]:
        deck_limit = self.plan.criteria.get("simplified_error")
        for row in self.rows:
            yield _checked(row, self.exact.get(_check_key(row, self.paths)), deck_limit, self.plan.motion_band)


def checked_rows(plan: SweepPlan, rows: Iterable[dict]) -> CheckedRows:
    """add_checks as an iterable over `rows` (read twice: a list, or rows read back from the rows file)."""
    return CheckedRows(plan, rows)


def _checked(row: dict, reference: dict | None, deck_limit: float | None, motion_band: tuple) -> dict:
    """A finished simplified case's row with its ratios to the exact case's (`reference`, if any);
    any other row as it is."""
    if reference is None or not _finished_by(row, "simplified"):
        return row
    return _with_ratios(row, reference, deck_limit, motion_band)


def _finished_by(row: dict, engine: str) -> bool:
    """Whether a row is a finished case ('ok') of `engine`."""
    return row.get("engine") == engine and row.get("status") == "ok"


def _with_ratios(row: dict, reference: dict, deck_limit: float | None, motion_band: tuple) -> dict:
    """A copy of a simplified case's row with its check_<name> ratios to the exact case's, and the
    ratios outside the simplified_error limit's band (the case's own limit, else the deck's) as violations."""
    row = dict(row)
    mine, theirs = row.get("compared") or {}, reference.get("compared") or {}
    limit = row.get("criteria.simplified_error", deck_limit)
    failed = []
    for name in COMPARED:
        ratio = row[f"check_{name}"] = _ratio(mine.get(name), theirs.get(name))
        band = _band(limit, motion_band if name in MOTION else None)
        if band is not None and ratio is not None and not band[0] <= ratio <= band[1]:
            failed.append(f"simplified_error: {COMPARED[name].symbol} simplified / exact = {ratio:.3g} "
                          f"outside [{band[0]:.3g}, {band[1]:.3g}]")
    if failed:
        row["violations"] = "; ".join(filter(None, [row.get("violations"), *failed]))
    return row


def _band(limit: float | None, motion_band: tuple | None) -> tuple[float, float] | None:
    """[1/(1 + limit), 1 + limit], widened to hold motion_band for the mat's motion (None: no limit)."""
    if limit is None:
        return None
    low, high = 1.0 / (1.0 + limit), 1.0 + limit
    return (low, high) if motion_band is None else (min(low, motion_band[0]), max(high, motion_band[1]))


def _ratio(value: Any, base: Any) -> float | None:
    """value / base when both are finite numbers and base is not zero, else None."""
    value, base = finite_number(value), finite_number(base)
    return value / base if value is not None and base else None
