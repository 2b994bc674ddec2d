"""Terminal output of `uplift sweep` / `uplift spectra`: progress (rich bar with ETA on a
terminal, plain periodic lines otherwise) and the summary tables."""

from __future__ import annotations

import os
import sys
import time
from itertools import product

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from ..display import label, show
from ..errors import printable
from ..sweep.plan import SweepPlan
from ..sweep.summary import finite_number
from ..sweep.table import SUMMARY_OUTPUTS
from ..sweep.values import Vary
from . import stdout
from .tables import add_columns, add_rows, print_tables

LABELS = {"base_shear_coefficient": "V_b/(m_t g)", "base_moment_coefficient": "M_b/(m_t g h_1*)",
          "max_drift_ratio": "drift ratio [%]"}
SHORT = {"base_shear_coefficient": "V/W", "base_moment_coefficient": "M/Wh", "max_drift_ratio": "drift [%]"}
#: the display kind of the summarised outputs (display.py): drift ratios in %, as in the story tables
KINDS = {"max_drift_ratio": "%"}
MAX_ROWS = 60  # envelope rows printed; the files have them all
#: the envelope's columns of each output (sweep/table.envelope: key, word of the heading): without
#: bounds the smallest and the largest; with bounds the value at each bound and the largest (the
#: drift: its largest only)
PLAIN_KEYS = (("lowest", "min"), ("highest", "max"))
BOUND_KEYS = (("at_lower_bound", "lo"), ("at_upper_bound", "up"), ("highest", "max"))
LARGEST_KEYS = (("highest", "max"),)


#: the characters EchoBuffer gathers before it echoes them
ECHO_CHARS = 1 << 16


class EchoBuffer:
    """A text written in many pieces (write) echoed on standard output in a few (stdout.echo: made
    safe for the terminal, a closed pipe silenced), no newline added; flush: what is left."""

    def __init__(self, size: int = ECHO_CHARS):
        self.pieces: list[str] = []
        self.size, self.length = size, 0

    def write(self, text: str) -> None:
        self.pieces.append(text)
        self.length += len(text)
        if self.length >= self.size:
            self.flush()

    def flush(self) -> None:
        if self.pieces:
            stdout.echo("".join(self.pieces), nl=False)
        self.pieces.clear()
        self.length = 0


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
        failed = f" ({self.failed} failed)" if self.failed else ""
        return f"{self.done}/{self.total} cases{failed}, {rate:.3g} cases/s, elapsed {elapsed:.0f} s" + self._eta(rate)

    def _eta(self, rate: float) -> str:
        """', ETA 31 s' while cases are left and the rate is known, else ''."""
        if self.done < self.total and rate > 0:
            return f", ETA {(self.total - self.done) / rate:.0f} s"
        return ""

    def _line(self, text: str) -> None:
        print(printable(f"{self.label}: {text}"), file=self.stream, flush=True)


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
    if isinstance(value, (int, float)) and _has_unit(kind):
        return show(value, kind, units)
    return _plain(value)


def _plain(value) -> str:
    """A float to 4 significant digits, anything else as it prints."""
    return f"{value:.4g}" if isinstance(value, float) else str(value)


def _has_unit(unit: str) -> bool:
    """A unit or display kind that is not empty and not '-' (a pure number)."""
    return bool(unit) and unit != "-"


def _vary(plan: SweepPlan | None, path: str) -> Vary | None:
    """The varied field of a path (None if it is not one, or without a plan)."""
    if plan is None:
        return None
    return next((v for v in plan.varies if v.path == path), None)


def _heading(path: str, vary: Vary | None, units: str) -> str:
    """A varied field's heading: its path, and its display unit in brackets when it has one."""
    unit = vary.si_unit if vary else ""
    return f"{path} [{label(unit, units)}]" if _has_unit(unit) else path


def _field_value(value, vary: Vary | None, units: str) -> str:
    """A varied field's value (given in the deck's units) in its display unit: converted to SI
    (Vary.to_si), then shown as display.py shows its SI unit."""
    if vary is None or not _has_unit(vary.si_unit) or finite_number(value) is None:
        return _value(value)
    return show(value * vary.to_si, vary.si_unit, units)


def ranges_table(plan: SweepPlan, summary: dict, units: str = "si") -> Table:
    table = Table(title="Varied fields")
    add_columns(table, ("field", "unit", "values", "spacing", "from", "to"), left=("field", "spacing"))
    return add_rows(table, (_range_cells(entry, _vary(plan, entry["path"]), units) for entry in summary["ranges"]))


def _range_cells(entry: dict, vary: Vary | None, units: str) -> tuple[str, ...]:
    """A varied field: path, display unit, number of values, spacing, and its values (a list) or its range."""
    unit = vary.si_unit if vary else entry["unit"]
    shown_unit = label(unit, units) if _has_unit(unit) else unit
    return (escape(entry["path"]), escape(shown_unit), str(entry["count"]), entry["spacing"],
            *_range_values(entry, vary, units))


def _range_values(entry: dict, vary: Vary | None, units: str) -> tuple[str, str]:
    """'from' and 'to' of a varied field: its values listed (and ''), else its lowest and highest."""
    if "values" in entry:
        return escape(", ".join(_field_value(v, vary, units) for v in entry["values"])), ""
    return _field_value(entry["lowest"], vary, units), _field_value(entry["highest"], vary, units)


def governing_table(plan: SweepPlan, summary: dict, units: str = "si") -> Table:
    table = Table(title="Governing cases (largest value over the sweep)")
    add_columns(table, ("output", "value", "case", "engine", "support",
                        *[_heading(v.path, v, units) for v in plan.varies]), left=("output",))
    return add_rows(table, (_governing_cells(plan, name, entry, units) for name, entry in summary["governing"].items()))


def _governing_cells(plan: SweepPlan, name: str, entry: dict, units: str) -> list[str]:
    """An output's largest value, its case, and the engine, support and varied fields of that case."""
    inputs = entry["inputs"]
    return [escape(LABELS.get(name, name)), _value(entry["value"], KINDS.get(name, ""), units),
            str(entry["case"]), inputs["engine"], inputs["support"],
            *[escape(_field_value(inputs.get(v.path), v, units)) for v in plan.varies]]


def envelope_table(summary: dict, units: str = "si", plan: SweepPlan | None = None) -> Table | None:
    """Per group of cases, each output's envelope over the enveloped fields (sweep/table.envelope):
    with one numeric field, at its bounds and the largest (ASCE 7-22 19.1.1), else the smallest and
    largest; at most MAX_ROWS rows."""
    groups = summary["envelope"]
    if not groups:
        return None
    bounds = _has_bounds(groups)
    table = Table(title=escape(_envelope_title(groups[0]["over"], bounds)))
    field_units = {path: _vary(plan, path) for path in groups[0]["group"]}
    # labels: a table split to fit the terminal repeats them (fitting.fit_table)
    add_columns(table, _field_headings(field_units, units), justify="left", no_wrap=True)
    columns = _envelope_columns(bounds)
    add_columns(table, [c[0] for c in columns] + ["uplift"], no_wrap=True)
    table.caption = escape(_envelope_caption(bounds)) + _rows_left_out(len(groups))
    return add_rows(table, (_envelope_cells(entry, field_units, columns, units) for entry in groups[:MAX_ROWS]))


def _field_headings(field_units: dict[str, Vary | None], units: str) -> list[str]:
    """The headings of the fields that group the cases (path and display unit)."""
    return [_heading(path, vary, units) for path, vary in field_units.items()]


def _has_bounds(groups: list[dict]) -> bool:
    """The envelope has the values at the lower and upper bound of its one field."""
    return any("at_lower_bound" in item for g in groups for item in g["outputs"].values())


def _envelope_title(over: list[str], bounds: bool) -> str:
    """Over the enveloped fields: at their bounds (ASCE 7-22 19.1.1) or smallest / largest; no field: 'Results'."""
    if bounds:
        return (f"Envelope over {', '.join(over)} (ASCE 7-22 19.1.1: lower and upper bound, the greater "
                "response governs)")
    if over:
        return f"Envelope over {', '.join(over)}: smallest / largest"
    return "Results"


def _envelope_columns(bounds: bool) -> list[tuple[str, str, str]]:
    """(heading, output, key) of each column of the outputs' envelope."""
    return [(f"{SHORT[name]} {word}", name, key) for name in SUMMARY_OUTPUTS for key, word in _keys(name, bounds)]


def _keys(name: str, bounds: bool) -> tuple[tuple[str, str], ...]:
    """The envelope's (key, word) of an output: PLAIN_KEYS, else BOUND_KEYS (the drift: LARGEST_KEYS)."""
    if not bounds:
        return PLAIN_KEYS
    return LARGEST_KEYS if name == "max_drift_ratio" else BOUND_KEYS


def _envelope_caption(bounds: bool) -> str:
    """The short headings, and what lo, up, min and max mean."""
    return ("V/W = V_b/(m_t g), M/Wh = M_b/(m_t g h_1*), drift = largest story drift ratio [%]; "
            + ("lo, up: at the lower and upper bound, max: largest over the range" if bounds
               else "min, max over the range"))


def _rows_left_out(count: int) -> str:
    """'; first 60 of 75 groups ...' when there are more groups than MAX_ROWS, else ''."""
    if count <= MAX_ROWS:
        return ""
    return escape(f"; first {MAX_ROWS} of {count} groups, all in the JSON file")


def _envelope_cells(entry: dict, field_units: dict[str, Vary | None], columns: list, units: str) -> list[str]:
    """A group: its fields' values, each output's envelope (as in the governing table) and its uplift."""
    fields = [escape(_field_value(entry["group"][path], vary, units)) for path, vary in field_units.items()]
    outputs = [_value(entry["outputs"].get(name, {}).get(key), KINDS.get(name, ""), units) for _, name, key in columns]
    return [*fields, *outputs, "some" if entry["uplift"] else "no"]


def print_summary(out: Console, plan: SweepPlan, summary: dict, units: str = "si") -> None:
    out.print(f"[bold]{escape(plan.title)}[/bold]: {summary['cases']} cases, {summary['ok']} ok"
              + "".join(f", {summary[key]} {key}" for key in ("failed", "crashed", "stale") if summary.get(key)))
    print_tables(out, _summary_tables(plan, summary, units))


def _summary_tables(plan: SweepPlan, summary: dict, units: str):
    """The varied fields and the governing cases (those the sweep has), and the envelope (or None)."""
    if summary["ranges"]:
        yield ranges_table(plan, summary, units)
    if summary["governing"]:
        yield governing_table(plan, summary, units)
    yield envelope_table(summary, units, plan)


def print_spectra_summary(console: Console, plan: SweepPlan, rows: list[dict]) -> None:
    """`uplift spectra`: per engine and support, the largest V_b/(m_t g) and the T_1 [s] it is at,
    the largest M_b/(m_t g h_1*), b/h_1* and the range of T_1 [s] that uplifts."""
    periods = plan.varies[0].values
    table = Table(title=escape(f"{plan.title}: spectra over T_1 = {periods[0]:g} .. "
                               f"{periods[-1]:g} s ({len(periods)} periods)"))
    add_columns(table, ("engine", "support", "max V_b/(m_t g)", "at T_1 [s]", "max M_b/(m_t g h_1*)", "b/h_1*",
                        "uplift for T_1 [s]"))
    for engine, support in product(plan.engines, plan.supports):
        mine = _ok_rows(rows, engine, support)
        if mine:
            table.add_row(engine, support, *_spectra_cells(mine))
    console.print(table)


def _ok_rows(rows: list[dict], engine: str, support: str) -> list[dict]:
    """The rows of the engine and support whose analysis succeeded."""
    return [r for r in rows if r["engine"] == engine and r["support"] == support and r["status"] == "ok"]


def _spectra_cells(mine: list[dict]) -> list[str]:
    """The largest V_b/(m_t g) and its T_1, the largest M_b/(m_t g h_1*), b/h_1* and the T_1 that uplift."""
    from ..sweep import figures

    top = max(mine, key=lambda r: r["base_shear_coefficient"])
    lifted = [r[figures.PERIOD_PATH] for r in mine if r["uplift"]]
    return [f"{top['base_shear_coefficient']:.4g}", f"{top[figures.PERIOD_PATH]:.4g}",
            f"{max(r['base_moment_coefficient'] for r in mine):.4g}", f"{top['critical_coefficient']:.4g}",
            _period_range(lifted)]


def _period_range(periods: list[float]) -> str:
    """'0.2 .. 1.1' (the smallest and largest of the periods) or 'none'."""
    return f"{min(periods):.3g} .. {max(periods):.3g}" if periods else "none"
