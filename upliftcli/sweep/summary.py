"""The summary of a sweep's rows: counts, ranges of the varied fields, governing cases, envelope
and the cases violating the deck's criteria (sweep/table.py names them too). Pure functions of
the plan and the rows.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import Any

from ..output import to_jsonable
from .plan import STATUSES, SweepPlan
from .values import Vary

#: outputs summarised on the terminal: governing case and envelope
SUMMARY_OUTPUTS = ("base_shear_coefficient", "base_moment_coefficient", "max_drift_ratio")


def finite_number(value: Any) -> float | None:
    """A finite int or float as a float (not a bool); None otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(value) else None


def _range_entry(vary: Vary) -> dict:
    """A varied field's unit, count, spacing, and smallest and largest (numbers) or its values."""
    numbers = [finite_number(v) for v in vary.values]
    entry = {"path": vary.path, "unit": vary.unit, "count": len(vary.values), "spacing": vary.spacing}
    if all(n is not None for n in numbers):
        entry.update(lowest=min(numbers), highest=max(numbers))
    else:
        entry["values"] = list(vary.values)
    return entry


def ranges(plan: SweepPlan) -> list[dict]:
    """Each varied field: unit, count, spacing, smallest and largest (numbers) or the values."""
    return [_range_entry(vary) for vary in plan.varies]


def inputs_of(plan: SweepPlan, row: dict) -> dict:
    return {"engine": row["engine"], "support": row["support"], **{v.path: row.get(v.path) for v in plan.varies}}


def _finished(rows: Sequence[dict]) -> list[dict]:
    """The rows of the finished cases (status 'ok')."""
    return [row for row in rows if row.get("status") == "ok"]


def _valued(rows: Sequence[dict], name: str) -> list[dict]:
    """The rows with a finite number under `name`."""
    return [row for row in rows if finite_number(row.get(name)) is not None]


def _top(rows: Sequence[dict], name: str) -> dict:
    """The first row with the largest value of `name`."""
    return max(rows, key=lambda row: row[name])


def governing(plan: SweepPlan, rows: Sequence[dict], outputs: Sequence[str] = SUMMARY_OUTPUTS) -> dict[str, dict]:
    """Per output: the finished case with the largest value, {value, case, inputs}."""
    result = {}
    finished = _finished(rows)
    for name in outputs:
        candidates = _valued(finished, name)
        if candidates:
            top = _top(candidates, name)
            result[name] = {"value": top[name], "case": top["case"], "inputs": inputs_of(plan, top)}
    return result


def envelope(plan: SweepPlan, rows: Sequence[dict], outputs: Sequence[str] = SUMMARY_OUTPUTS) -> list[dict]:
    """Envelope over the varied foundation fields (all varied fields if no foundation field is
    varied), per engine, support and value of the other varied fields.

    Each group: {group: {...}, over: [paths], outputs: {name: {lowest, highest, governing}}}; with
    one numeric field enveloped, also at_lower_bound / at_upper_bound: the values at its smallest
    and largest value. ASCE 7-22 section 19.1.1 asks for both bound estimates of the foundation
    stiffness and the case giving the greater response; `highest` includes interior points."""
    over = _enveloped(plan)
    over_paths = [v.path for v in over]
    group_paths = ["engine", "support"] + [v.path for v in plan.varies if v.path not in over_paths]
    bound = _bound_field(over)
    return [_envelope_group(members, group_paths, over_paths, bound, outputs)
            for members in _groups(_finished(rows), group_paths).values()]


def _enveloped(plan: SweepPlan) -> list[Vary]:
    """The varied fields enveloped over: the foundation's, else all."""
    foundation = [v for v in plan.varies if v.path.startswith("foundation.")]
    return foundation or list(plan.varies)


def _bound_field(over: Sequence[Vary]) -> Vary | None:
    """The one numeric field enveloped over, whose bounds are reported; None otherwise."""
    if len(over) != 1 or not all(finite_number(x) is not None for x in over[0].values):
        return None
    return over[0]


def _groups(rows: Sequence[dict], paths: Sequence[str]) -> dict[str, list[dict]]:
    """The rows by their values of `paths` (as JSON), in order of appearance."""
    groups: dict[str, list[dict]] = {}
    for row in rows:
        groups.setdefault(json.dumps([row.get(p) for p in paths], default=str), []).append(row)
    return groups


def _envelope_group(members: list[dict], group_paths: Sequence[str], over_paths: Sequence[str], bound: Vary | None,
                    outputs: Sequence[str]) -> dict:
    """The envelope entry of one group of rows."""
    entry = {"group": {p: members[0].get(p) for p in group_paths}, "over": over_paths, "cases": len(members),
             "uplift": any(row.get("uplift") for row in members), "outputs": {}}
    for name in outputs:
        valued = _valued(members, name)
        if valued:
            entry["outputs"][name] = _envelope_item(valued, name, over_paths, bound)
    return entry


def _envelope_item(valued: list[dict], name: str, over_paths: Sequence[str], bound: Vary | None) -> dict:
    """One output's lowest, highest and governing values of the enveloped fields (and the values
    at the bounds of the bound field, if any)."""
    top = _top(valued, name)
    item = {"lowest": min(row[name] for row in valued), "highest": top[name],
            "governing": {p: top.get(p) for p in over_paths}}
    if bound is not None:
        by_value = sorted(valued, key=lambda row: row[bound.path])
        item["at_lower_bound"] = by_value[0][name]
        item["at_upper_bound"] = by_value[-1][name]
    return item


def violating(rows: Sequence[dict]) -> list[dict]:
    return [row for row in rows if row.get("violations")]


def _failures(plan: SweepPlan, rows: Sequence[dict]) -> list[dict]:
    """The cases not finished: case, inputs, status and message."""
    return [{"case": row["case"], "inputs": inputs_of(plan, row), "status": row["status"],
             "message": row.get("message", "")} for row in rows if row.get("status") != "ok"]


def summarize(plan: SweepPlan, rows: Sequence[dict]) -> dict:
    """Counts, ranges, governing cases, envelope and the cases violating the deck's criteria."""
    counts = {status: sum(row.get("status") == status for row in rows) for status in STATUSES}
    return to_jsonable({
        "cases": len(plan.cases), "finished": len(rows), **counts,
        "ranges": ranges(plan),
        "governing": governing(plan, rows),
        "envelope": envelope(plan, rows),
        "violations": [{"case": row["case"], "inputs": inputs_of(plan, row), "violations": row["violations"]}
                       for row in violating(rows)],
        "failures": _failures(plan, rows),
    })
