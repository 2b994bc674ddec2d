"""Terminal output of `uplift sweep` / `uplift spectra`: progress (rich bar with ETA on a
terminal, plain periodic lines otherwise) and the summary tables."""

from __future__ import annotations

import os
import sys
import time

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from ..display import label, show
from ..sweep.plan import SweepPlan
from ..sweep.table import SUMMARY_OUTPUTS

LABELS = {"base_shear_coefficient": "V_b/(m_t g)", "base_moment_coefficient": "M_b/(m_t g h_1*)",
          "max_drift_ratio": "drift ratio [%]"}
SHORT = {"base_shear_coefficient": "V/W", "base_moment_coefficient": "M/Wh", "max_drift_ratio": "drift [%]"}
#: the display kind of the summarised outputs (display.py): drift ratios in %, as in the story tables
KINDS = {"max_drift_ratio": "%"}
MAX_ROWS = 60  # envelope rows printed; the files have them all


def use_rich_progress(console: Console) -> bool:
    return console.is_terminal and not os.environ.get("CI")


class PlainProgress:
    """'sweep: 120/500 cases (3 failed), 12.3 cases/s, ETA 31 s' every `interval` seconds, and at the end."""

    def __init__(self, label: str = "sweep", interval: float = 10.0, stream=None):
        self.label, self.interval, self.stream = label, interval, stream or sys.stderr
        self.total = self.done = self.failed = self.new = 0
        self.started = self.last = 0.0

    def start(self, total: int, done: int) -> None:
        self.total, self.done = total, done
        self.started = self.last = time.monotonic()
        kept = f" ({done} kept from the previous run)" if done else ""
        self._line(f"{self.total - done} cases to run{kept}")

    def advance(self, row: dict) -> None:
        self.done += 1
        self.new += 1
        self.failed += row.get("status") != "ok"
        now = time.monotonic()
        if now - self.last >= self.interval:
            self.last = now
            self._line(self._status(now))

    def stop(self) -> None:
        self._line(self._status(time.monotonic()))

    def _status(self, now: float) -> str:
        elapsed = max(now - self.started, 1e-9)
        rate = self.new / elapsed
        eta = (self.total - self.done) / rate if rate > 0 else float("nan")
        failed = f" ({self.failed} failed)" if self.failed else ""
        return (f"{self.done}/{self.total} cases{failed}, {rate:.3g} cases/s, elapsed {elapsed:.0f} s"
                + (f", ETA {eta:.0f} s" if self.done < self.total and eta == eta else ""))

    def _line(self, text: str) -> None:
        print(f"{self.label}: {text}", file=self.stream, flush=True)


class RichProgress:
    """A rich progress bar on stderr: done/total, rate, elapsed and ETA."""

    def __init__(self, console: Console, label: str = "sweep"):
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self.progress = Progress(TextColumn(f"{label}"), BarColumn(), MofNCompleteColumn(),
                                 TextColumn("{task.fields[failed]}"), TimeElapsedColumn(), TextColumn("ETA"),
                                 TimeRemainingColumn(), console=console)
        self.task = None
        self.failed = 0

    def start(self, total: int, done: int) -> None:
        self.progress.start()
        self.task = self.progress.add_task("cases", total=total, completed=done, failed="")

    def advance(self, row: dict) -> None:
        self.failed += row.get("status") != "ok"
        self.progress.update(self.task, advance=1, failed=f"{self.failed} failed" if self.failed else "")

    def stop(self) -> None:
        self.progress.stop()


def _value(value, kind: str = "", units: str = "si") -> str:
    """A value of the summary: a number of a field or an output in its display unit (kind: its SI
    unit or display kind, display.py), else to 4 significant digits."""
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float)) and kind and kind not in ("-", ""):
        return show(value, kind, units)
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def _unit(plan: SweepPlan, path: str) -> str:
    """The SI unit of a varied field ('' if it has none)."""
    return next((v.unit for v in plan.varies if v.path == path), "")


def _heading(path: str, unit: str, units: str) -> str:
    return f"{path} [{label(unit, units)}]" if unit and unit != "-" else path


def ranges_table(summary: dict, units: str = "si") -> Table:
    table = Table(title="Varied fields")
    for header in ("field", "unit", "values", "spacing", "from", "to"):
        table.add_column(escape(header), justify="left" if header in ("field", "spacing") else "right")
    for entry in summary["ranges"]:
        unit = entry["unit"]
        shown_unit = label(unit, units) if unit and unit != "-" else unit
        if "values" in entry:
            table.add_row(escape(entry["path"]), escape(shown_unit), str(entry["count"]), entry["spacing"],
                          escape(", ".join(_value(v, unit, units) for v in entry["values"])), "")
        else:
            table.add_row(escape(entry["path"]), escape(shown_unit), str(entry["count"]), entry["spacing"],
                          _value(entry["lowest"], unit, units), _value(entry["highest"], unit, units))
    return table


def governing_table(plan: SweepPlan, summary: dict, units: str = "si") -> Table:
    table = Table(title="Governing cases (largest value over the sweep)")
    for header in ("output", "value", "case", "engine", "support",
                   *[_heading(v.path, v.unit, units) for v in plan.varies]):
        table.add_column(escape(header), justify="left" if header == "output" else "right")
    for name, entry in summary["governing"].items():
        inputs = entry["inputs"]
        table.add_row(escape(LABELS.get(name, name)), _value(entry["value"], KINDS.get(name, ""), units),
                      str(entry["case"]), inputs["engine"], inputs["support"],
                      *[escape(_value(inputs.get(v.path), v.unit, units)) for v in plan.varies])
    return table


def envelope_table(summary: dict, units: str = "si", plan: SweepPlan | None = None) -> Table | None:
    groups = summary["envelope"]
    if not groups:
        return None
    over = groups[0]["over"]
    bounds = any("at_lower_bound" in item for g in groups for item in g["outputs"].values())
    if bounds:
        title = (f"Envelope over {', '.join(over)} (ASCE 7-22 19.1.1: lower and upper bound, the greater "
                 "response governs)")
    elif over:
        title = f"Envelope over {', '.join(over)}: smallest / largest"
    else:
        title = "Results"
    table = Table(title=escape(title))
    group_paths = list(groups[0]["group"])
    columns = []  # (header, output, key)
    for name in SUMMARY_OUTPUTS:
        if not bounds:
            keys = (("lowest", "min"), ("highest", "max"))
        elif name == "max_drift_ratio":
            keys = (("highest", "max"),)
        else:
            keys = (("at_lower_bound", "lo"), ("at_upper_bound", "up"), ("highest", "max"))
        columns += [(f"{SHORT[name]} {word}", name, key) for key, word in keys]
    field_units = {path: _unit(plan, path) if plan is not None else "" for path in group_paths}
    for header in group_paths:  # labels: a table split to fit the terminal repeats them (render.fit_table)
        table.add_column(escape(_heading(header, field_units[header], units)), justify="left", no_wrap=True)
    for header in [c[0] for c in columns] + ["uplift"]:
        table.add_column(escape(header), justify="right", no_wrap=True)
    table.caption = escape("V/W = V_b/(m_t g), M/Wh = M_b/(m_t g h_1*), drift = largest story drift ratio [%]; "
                           + ("lo, up: at the lower and upper bound, max: largest over the range" if bounds
                              else "min, max over the range"))
    for entry in groups[:MAX_ROWS]:
        cells = [escape(_value(entry["group"][p], field_units[p], units)) for p in group_paths]
        for _, name, key in columns:
            value = entry["outputs"].get(name, {}).get(key)
            cells.append(_value(value, KINDS.get(name, ""), units))  # as in the governing table
        cells.append("some" if entry["uplift"] else "no")
        table.add_row(*cells)
    if len(groups) > MAX_ROWS:
        table.caption += escape(f"; first {MAX_ROWS} of {len(groups)} groups, all in the JSON file")
    return table


def print_summary(out: Console, plan: SweepPlan, summary: dict, units: str = "si") -> None:
    out.print(f"[bold]{escape(plan.title)}[/bold]: {summary['cases']} cases, {summary['ok']} ok"
              + (f", {summary['failed']} failed" if summary["failed"] else "")
              + (f", {summary['crashed']} crashed" if summary["crashed"] else "")
              + (f", {summary['stale']} stale" if summary.get("stale") else ""))
    if summary["ranges"]:
        out.print(ranges_table(summary, units))
    if summary["governing"]:
        out.print(governing_table(plan, summary, units))
    table = envelope_table(summary, units, plan)
    if table is not None:
        out.print(table)


def print_spectra_summary(console: Console, plan: SweepPlan, rows: list[dict]) -> None:
    """`uplift spectra`: per engine and support, the largest V_b/(m_t g) and the T_1 [s] it is at,
    the largest M_b/(m_t g h_1*), b/h_1* and the range of T_1 [s] that uplifts."""
    from ..sweep import figures

    table = Table(title=escape(f"{plan.title}: spectra over T_1 = {plan.varies[0].values[0]:g} .. "
                               f"{plan.varies[0].values[-1]:g} s ({len(plan.varies[0].values)} periods)"))
    for header in ("engine", "support", "max V_b/(m_t g)", "at T_1 [s]", "max M_b/(m_t g h_1*)", "b/h_1*",
                   "uplift for T_1 [s]"):
        table.add_column(escape(header), justify="right")
    for engine in plan.engines:
        for support in plan.supports:
            mine = [r for r in rows if r["engine"] == engine and r["support"] == support and r["status"] == "ok"]
            if not mine:
                continue
            top = max(mine, key=lambda r: r["base_shear_coefficient"])
            lifted = [r[figures.PERIOD_PATH] for r in mine if r["uplift"]]
            table.add_row(engine, support, f"{top['base_shear_coefficient']:.4g}", f"{top[figures.PERIOD_PATH]:.4g}",
                          f"{max(r['base_moment_coefficient'] for r in mine):.4g}",
                          f"{top['critical_coefficient']:.4g}",
                          f"{min(lifted):.3g} .. {max(lifted):.3g}" if lifted else "none")
    console.print(table)
