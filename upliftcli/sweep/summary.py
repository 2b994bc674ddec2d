"""The summary of a sweep's rows: counts, ranges of the varied fields, governing cases, envelope
and the cases violating the deck's criteria (sweep/table.py names them too). Pure functions of
the plan and the rows, made in one pass over the rows (Tally): a sweep's rows are read back from
its rows file one at a time, never all in memory; only what the summary reports is kept (the
largest value of each output and its case, each envelope group's extremes, the failed and
violating cases).
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Sequence
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


def _is_finished(row: dict) -> bool:
    """Whether a row is of a finished case (status 'ok')."""
    return row.get("status") == "ok"


def _valued(row: dict, name: str) -> bool:
    """Whether a row has a finite number under `name`."""
    return finite_number(row.get(name)) is not None


class Extremes:
    """One output over rows given one at a time: its smallest value and its largest (the first of
    equal ones, as min and max give them), the row of the largest as `keep` gives it, and with a
    bound field (`bound`: its path) the values at the bound's smallest value (the first such row)
    and at its largest (the last such row), as a stable sort by the bound gives them."""

    def __init__(self, keep, bound: str | None = None):
        self.keep, self.bound = keep, bound
        self.count = 0
        self.lowest = self.highest = self.top = None
        self.lower = self.upper = None  # (bound value, output value)

    def add(self, row: dict, value: Any) -> None:
        if self.count == 0:
            self.lowest, self.highest, self.top = value, value, self.keep(row)
        else:
            self._extend(row, value)
        self.count += 1
        if self.bound is not None:
            self._bounds(row[self.bound], value)

    def _extend(self, row: dict, value: Any) -> None:
        """A later row: a smaller value replaces the lowest, a larger one the highest and its row."""
        if value < self.lowest:
            self.lowest = value
        if value > self.highest:
            self.highest, self.top = value, self.keep(row)

    def _bounds(self, at: Any, value: Any) -> None:
        """The value at the bound's smallest value (first met) and at its largest (last met)."""
        if self.lower is None or at < self.lower[0]:
            self.lower = (at, value)
        if self.upper is None or not at < self.upper[0]:
            self.upper = (at, value)


def _first_top(plan: SweepPlan, outputs: Sequence[str]) -> dict[str, Extremes]:
    """Per output: its Extremes over the finished cases, keeping the governing case and its inputs."""
    return {name: Extremes(lambda row: {"case": row["case"], "inputs": inputs_of(plan, row)}) for name in outputs}


def _add_valued(extremes: dict[str, Extremes], row: dict) -> None:
    """The row's finite values of each output to their Extremes."""
    for name, item in extremes.items():
        if _valued(row, name):
            item.add(row, row[name])


def _governing_entries(extremes: dict[str, Extremes]) -> dict[str, dict]:
    """{value, case, inputs} of each output with a finished value."""
    return {name: {"value": item.highest, **item.top} for name, item in extremes.items() if item.count}


def governing(plan: SweepPlan, rows: Iterable[dict], outputs: Sequence[str] = SUMMARY_OUTPUTS) -> dict[str, dict]:
    """Per output: the finished case with the largest value, {value, case, inputs}."""
    extremes = _first_top(plan, outputs)
    for row in rows:
        if _is_finished(row):
            _add_valued(extremes, row)
    return _governing_entries(extremes)


def _enveloped(plan: SweepPlan) -> list[Vary]:
    """The varied fields enveloped over: the foundation's, else all."""
    foundation = [v for v in plan.varies if v.path.startswith("foundation.")]
    return foundation or list(plan.varies)


def _bound_field(over: Sequence[Vary]) -> Vary | None:
    """The one numeric field enveloped over, whose bounds are reported; None otherwise."""
    if len(over) != 1 or not all(finite_number(x) is not None for x in over[0].values):
        return None
    return over[0]


class _Group:
    """One envelope group: its fields' values (of its first row), its cases, whether one lifts off,
    and the Extremes of each output over its rows."""

    def __init__(self, row: dict, group_paths: Sequence[str], over_paths: Sequence[str], bound: str | None,
                 outputs: Sequence[str]):
        self.group = {p: row.get(p) for p in group_paths}
        self.over = list(over_paths)
        self.cases, self.uplift = 0, False
        self.outputs = {name: Extremes(lambda r: {p: r.get(p) for p in over_paths}, bound) for name in outputs}

    def add(self, row: dict) -> None:
        self.cases += 1
        self.uplift = self.uplift or bool(row.get("uplift"))
        _add_valued(self.outputs, row)

    def entry(self) -> dict:
        return {"group": self.group, "over": self.over, "cases": self.cases, "uplift": self.uplift,
                "outputs": {name: _envelope_item(item) for name, item in self.outputs.items() if item.count}}


def _envelope_item(item: Extremes) -> dict:
    """One output's lowest, highest and governing values of the enveloped fields (and the values
    at the bounds of the bound field, if any)."""
    entry = {"lowest": item.lowest, "highest": item.highest, "governing": item.top}
    if item.bound is not None:
        entry["at_lower_bound"], entry["at_upper_bound"] = item.lower[1], item.upper[1]
    return entry


class Envelope:
    """The envelope over the varied foundation fields (all varied fields if no foundation field is
    varied), per engine, support and value of the other varied fields, made from rows given one at
    a time (envelope)."""

    def __init__(self, plan: SweepPlan, outputs: Sequence[str] = SUMMARY_OUTPUTS):
        over = _enveloped(plan)
        self.over_paths = [v.path for v in over]
        self.group_paths = ["engine", "support"] + [v.path for v in plan.varies if v.path not in self.over_paths]
        bound = _bound_field(over)
        self.bound = None if bound is None else bound.path
        self.outputs = outputs
        self.groups: dict[str, _Group] = {}

    def add(self, row: dict) -> None:
        """A finished row to its group (the groups in order of appearance)."""
        key = json.dumps([row.get(p) for p in self.group_paths], default=str)
        group = self.groups.get(key)
        if group is None:
            group = self.groups[key] = _Group(row, self.group_paths, self.over_paths, self.bound, self.outputs)
        group.add(row)

    def entries(self) -> list[dict]:
        return [group.entry() for group in self.groups.values()]


def envelope(plan: SweepPlan, rows: Iterable[dict], outputs: Sequence[str] = SUMMARY_OUTPUTS) -> list[dict]:
    """Envelope over the varied foundation fields (all varied fields if no foundation field is
    varied), per engine, support and value of the other varied fields.

    Each group: {group: {...}, over: [paths], outputs: {name: {lowest, highest, governing}}}; with
    one numeric field enveloped, also at_lower_bound / at_upper_bound: the values at its smallest
    and largest value. ASCE 7-22 section 19.1.1 asks for both bound estimates of the foundation
    stiffness and the case giving the greater response; `highest` includes interior points."""
    result = Envelope(plan, outputs)
    for row in rows:
        if _is_finished(row):
            result.add(row)
    return result.entries()


def violating(rows: Iterable[dict]) -> list[dict]:
    return [row for row in rows if row.get("violations")]


class Tally:
    """The summary of a sweep (summarize) made from its rows given one at a time (add)."""

    def __init__(self, plan: SweepPlan):
        self.plan = plan
        self.counts = dict.fromkeys(STATUSES, 0)
        self.finished = 0
        self.governing = _first_top(plan, SUMMARY_OUTPUTS)
        self.envelope = Envelope(plan)
        self.violations: list[dict] = []
        self.failures: list[dict] = []

    def add(self, row: dict) -> None:
        self.finished += 1
        status = row.get("status")
        if status in self.counts:
            self.counts[status] += 1
        if row.get("violations"):
            self.violations.append({"case": row["case"], "inputs": inputs_of(self.plan, row),
                                    "violations": row["violations"]})
        if _is_finished(row):
            _add_valued(self.governing, row)
            self.envelope.add(row)
        else:
            self.failures.append({"case": row["case"], "inputs": inputs_of(self.plan, row), "status": row["status"],
                                  "message": row.get("message", "")})

    def summary(self) -> dict:
        """Counts, ranges, governing cases, envelope and the cases violating the deck's criteria."""
        return to_jsonable({
            "cases": len(self.plan.cases), "finished": self.finished, **self.counts,
            "ranges": ranges(self.plan),
            "governing": _governing_entries(self.governing),
            "envelope": self.envelope.entries(),
            "violations": self.violations,
            "failures": self.failures,
        })


def summarize(plan: SweepPlan, rows: Iterable[dict]) -> dict:
    """Counts, ranges, governing cases, envelope and the cases violating the deck's criteria (one
    pass over the rows)."""
    tally = Tally(plan)
    for row in rows:
        tally.add(row)
    return tally.summary()
