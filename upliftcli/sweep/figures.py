"""Data of the paper-style figures (Yim & Chopra Figs. 3, 4, 6-10) and of sweep plots.

Pure functions of the tidy rows of a sweep (sweep/plan.py, sweep/table.py): they return
plots.FigureSpec objects (lines as arrays) that plots.plot_figure draws. The paper's
response spectra are maxima plotted against the fixed-base period T_1 with everything else
scaled with it (docs/theory.md section 6): a sweep of `building.period`.

- Figs. 3-4: V_b/(m_t g) and M_b/(m_t g h_1*) for rigid, bonded and uplift, with the
  critical value b/h_1* of both coefficients [16a, 16b];
- Fig. 7: modal contributions to the base shear (mode 1, modes 1-2, all modes) per support;
- Figs. 6, 10: total base shear by the engines compared (exact, approximate, simplified);
- Figs. 8, 9: mode-1 base shear by the engines compared.

The deck's own value of the varied field and its ground motion's name: sweep/nominal.py.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Iterable, Sequence
from dataclasses import replace

import numpy as np

from ..display import unit as display_unit
from ..engines.registry import ENGINES, SUPPORT_LABELS
from ..errors import InputError
from ..figures.spec import FigureSpec, Line, Panel, Series
from ..figures.style import ENGINE_LINES, ENGINE_STYLES, MARKERS, SUPPORT_COLORS, SUPPORT_STYLES, shades
from .nominal import (  # noqa: F401 - figures.nominal_value, motion_label, plan_motion_label: the CLI's and API's
    is_number,
    motion_label,
    nominal_line,
    nominal_value,
    plan_motion_label,
)
from .plan import SweepPlan
from .table import OUTPUT_COLUMNS
from .values import Vary, parse_values

PERIOD_PATH = "building.period"
PERIOD_LABEL = "fixed-base fundamental period T_1 [s]"
#: figure quantity -> row column (sweep/table.py); the axis label is the column's meaning
QUANTITIES = {"base_shear": "base_shear_coefficient", "base_moment": "base_moment_coefficient",
              "mode1_base_shear": "mode1_base_shear_coefficient",
              "two_mode_base_shear": "two_mode_base_shear_coefficient", "max_drift_ratio": "max_drift_ratio"}


#: row columns plotted in another unit than the rows': column -> (factor, unit); drift ratios in
#: percent, as in the story profiles (display.py)
PLOTTED = {"max_drift_ratio": (100.0, "%")}


#: the columns of a row the figures and the spectra's summary read (besides the varied fields)
FIGURE_COLUMNS = ("status", "engine", "support", *QUANTITIES.values(), "critical_coefficient", "uplift")


def figure_rows(plan: SweepPlan, rows: Iterable[dict]) -> list[dict]:
    """The finished rows ('ok': the figures draw no other) with only the columns the figures read
    (FIGURE_COLUMNS and the varied fields), their texts interned: a sweep's figures drawn from its
    rows read back one at a time, a small part of each kept."""
    names = (*FIGURE_COLUMNS, *(v.path for v in plan.varies))
    return [{name: _interned(row[name]) for name in names if name in row} for row in rows if row.get("status") == "ok"]


def _interned(value):
    """A text interned (the engine, support and status of every row held once); anything else as it is."""
    return sys.intern(value) if isinstance(value, str) else value


def axis_label(quantity: str) -> tuple[str, str]:
    """(row column, axis label with its plotted unit) of a figure quantity."""
    column = QUANTITIES[quantity]
    unit, meaning = OUTPUT_COLUMNS[column]
    unit = PLOTTED.get(column, (1.0, unit))[1]
    return column, meaning + ("" if unit in ("-", "") else f" [{unit}]")


def period_vary(text: str) -> Vary:
    """--periods START:STOP:N[:log|lin] (log-spaced unless told) or a list, all > 0 s."""
    values, spacing = parse_values(text, "--periods", default_spacing="log")
    if not all(is_number(v) and v > 0 for v in values):
        raise InputError("--periods", text, "periods > 0 s: START:STOP:N[:log|lin] or a comma list")
    return Vary(PERIOD_PATH, tuple(float(v) for v in values), spacing)


def _finished_with(row: dict, column: str) -> bool:
    """Whether a row is of a finished case ('ok') with a value of `column`."""
    return row.get("status") == "ok" and row.get(column) is not None


def _on_curve(row: dict, column: str, x_path: str, match: dict) -> bool:
    """Whether a row is a point of a curve: finished, with x and y, and matching `match`."""
    if not _finished_with(row, column) or row.get(x_path) is None:
        return False
    return all(row.get(k) == v for k, v in match.items())


def _plotted_factor(column: str) -> float:
    """The factor from a column's unit to the plotted one (PLOTTED; 1 for the others)."""
    return PLOTTED.get(column, (1.0, ""))[0]


def curve(rows: Sequence[dict], column: str, x_path: str = PERIOD_PATH, **match) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) of the finished rows matching `match` (e.g. engine="exact"), sorted by x; rows
    without a value of `column` are left out."""
    points = sorted((float(row[x_path]), float(row[column])) for row in rows if _on_curve(row, column, x_path, match))
    if not points:
        return np.empty(0), np.empty(0)
    x, y = zip(*points, strict=True)
    return np.array(x), np.array(y) * _plotted_factor(column)


def _critical_label(y: np.ndarray) -> str:
    """The critical line's label, with its value when it does not vary."""
    return f"critical b/h_1* = {y[0]:.3g}" if np.ptp(y) <= 1e-9 * abs(y[0]) else "critical b/h_1*"


def critical_series(rows: Sequence[dict], x_path: str = PERIOD_PATH) -> Series | None:
    """The critical coefficient b/h_1* (of V_b/(m_t g) and M_b/(m_t g h_1*)) against x."""
    by_x = {float(row[x_path]): float(row["critical_coefficient"]) for row in rows
            if _finished_with(row, "critical_coefficient")}
    if not by_x:
        return None
    x = np.array(sorted(by_x))
    y = np.array([by_x[v] for v in x])
    return Series(_critical_label(y), x, y, ":", "black")


def _with_critical(series: list[Series], rows: Sequence[dict], x_path: str = PERIOD_PATH) -> list[Series]:
    critical = critical_series(rows, x_path)
    return series + ([critical] if critical is not None else [])


def _titled(title: str, motion: str) -> str:
    """A figure title with its ground motion, if any, after a comma."""
    return f"{title}, {motion}" if motion else title


def support_figure(rows: Sequence[dict], engine: str, supports: Sequence[str], quantity: str,
                   record: str = "", nominal: float | None = None) -> FigureSpec:
    """Figs. 3 (base_shear) and 4 (base_moment): one line per support condition, and b/h_1*;
    record: the ground motion named in the title; nominal: the deck's T_1 [s], marked."""
    column, label = axis_label(quantity)
    series = [_support_series(rows, column, engine, support) for support in supports]
    what = "Base shear" if quantity == "base_shear" else "Base overturning moment"
    title = f"{what} response spectra for three support conditions, {ENGINES[engine].label}"
    return FigureSpec(_titled(title, record), PERIOD_LABEL,
                      [Panel(what, label, _with_critical(series, rows), _period_line(nominal))], xlog=True,
                      ylog=True, columns=1, panel_size=(6.0, 4.0))


def _support_series(rows: Sequence[dict], column: str, engine: str, support: str) -> Series:
    """The line of one support condition, in its style (figures/style.py)."""
    x, y = curve(rows, column, engine=engine, support=support)
    style, color = SUPPORT_STYLES[support]
    return Series(SUPPORT_LABELS[support], x, y, style, color)


def _period_line(nominal: float | None) -> list[Line]:
    return nominal_line(nominal, "T_1", "s")


#: the lines of Fig. 7: (column, name, line style)
MODAL_LINES = (("mode1_base_shear_coefficient", "mode 1", "--"),
               ("two_mode_base_shear_coefficient", "modes 1-2", "-."),
               ("base_shear_coefficient", "all modes", "-"))


def modal_figure(rows: Sequence[dict], engine: str, supports: Sequence[str], record: str = "",
                 nominal: float | None = None) -> FigureSpec:
    """Fig. 7: per support, the base shear of mode 1, of modes 1-2 (when the engine gives it)
    and of all modes, in the support's colour (style.py), told apart by line style."""
    panels = [_modal_panel(rows, engine, letter, support, nominal)
              for letter, support in zip("abc", supports, strict=False)]
    title = f"Modal contributions to the maximum base shear, {ENGINES[engine].label}"
    return FigureSpec(_titled(title, record), PERIOD_LABEL, panels, xlog=True, ylog=True)


def _modal_panel(rows: Sequence[dict], engine: str, letter: str, support: str, nominal: float | None) -> Panel:
    """Fig. 7's panel of one support: the MODAL_LINES the engine gives, and b/h_1*."""
    series = []
    for column, name, style in MODAL_LINES:
        x, y = curve(rows, column, engine=engine, support=support)
        if x.size:
            series.append(Series(name, x, y, style, SUPPORT_COLORS[support]))
    return Panel(f"({letter}) {SUPPORT_LABELS[support]}", axis_label("base_shear")[1],
                 _with_critical(series, rows), _period_line(nominal))


def engine_figure(rows: Sequence[dict], engines: Sequence[str], supports: Sequence[str], quantity: str,
                  record: str = "", nominal: float | None = None) -> FigureSpec:
    """Figs. 6, 10 (base_shear) and 8, 9 (mode1_base_shear): one line per engine, a panel per support."""
    column, label = axis_label(quantity)
    panels = [Panel(SUPPORT_LABELS[support], label,
                    _with_critical([_engine_series(rows, column, engine, support) for engine in engines], rows),
                    _period_line(nominal)) for support in supports]
    what = "fundamental-mode base shear" if quantity == "mode1_base_shear" else "base shear"
    title = f"Comparison of {what} response spectra by {', '.join(engines)} analysis"
    return FigureSpec(_titled(title, record), PERIOD_LABEL, panels, xlog=True, ylog=True)


def _engine_series(rows: Sequence[dict], column: str, engine: str, support: str) -> Series:
    """The line of one engine, in its style (figures/style.py)."""
    x, y = curve(rows, column, engine=engine, support=support)
    style, color = ENGINE_STYLES[engine]
    return Series(ENGINES[engine].label, x, y, style, color)


def paper_figures(rows: Sequence[dict], engines: Sequence[str], supports: Sequence[str],
                  record: str = "", nominal: float | None = None) -> dict[str, FigureSpec]:
    """Every figure the rows allow, by file-name suffix: base_shear_<engine> (Fig. 3),
    base_moment_<engine> (Fig. 4), modal_<engine> (Fig. 7), and with two engines or more
    engines_base_shear (Figs. 6, 10) and engines_mode1_base_shear (Figs. 8, 9); record: the
    ground motion named in the titles; nominal: the deck's T_1 [s], marked in every panel."""
    figures = {}
    for engine in engines:
        figures[f"base_shear_{engine}"] = support_figure(rows, engine, supports, "base_shear", record, nominal)
        figures[f"base_moment_{engine}"] = support_figure(rows, engine, supports, "base_moment", record, nominal)
        figures[f"modal_{engine}"] = modal_figure(rows, engine, supports, record, nominal)
    if len(engines) > 1:
        figures["engines_base_shear"] = engine_figure(rows, engines, supports, "base_shear", record, nominal)
        figures["engines_mode1_base_shear"] = engine_figure(rows, engines, supports, "mode1_base_shear", record,
                                                            nominal)
    return figures


def sweep_figure(plan: SweepPlan, rows: Sequence[dict], motion: str = "", units: str = "si") -> FigureSpec:
    """Response against the first numeric varied field (log axis for a log range): one line per
    engine, support and value of the other varied fields (sweep_lines: the support's colour,
    the engine's line style, the other values as shades and markers); panels V_b/(m_t g),
    M_b/(m_t g h_1*), largest drift ratio [%] (with the deck's [criteria] drift_ratio limit);
    b/h_1* on the first two when it does not depend on the other fields; the deck's value of the
    varied field marked; motion: named in the title; the varied field in its display unit
    (display.py: units)."""
    axis = _numeric_axis(plan)
    others = [v.path for v in plan.varies if v.path != axis.path]
    groups = _line_groups(rows, others)
    shown = _shown_unit(axis, units)
    marks = _nominal_marks(plan, axis, shown)
    critical = len(_criticals(rows)) == 1 or not others
    panels = [_sweep_panel(plan, rows, quantity, groups, axis.path, others, marks, critical)
              for quantity in ("base_shear", "base_moment", "max_drift_ratio")]
    _scale_x(panels, axis.to_si * shown.factor if shown is not None else 1.0)
    unit = f" [{shown.label}]" if shown is not None else ""
    return FigureSpec(_titled(f"{plan.title}: sweep of {axis.path}", motion), f"{axis.path}{unit}",
                      panels, xlog=axis.spacing == "log")


def _numeric_axis(plan: SweepPlan) -> Vary:
    """The first varied field whose values are all numbers; InputError naming --plot if none."""
    numeric = [v for v in plan.varies if all(is_number(x) for x in v.values)]
    if not numeric:
        raise InputError("--plot", "--vary", "a numeric varied field to plot against")
    return numeric[0]


def _line_groups(rows: Sequence[dict], others: Sequence[str]) -> dict[tuple, list[dict]]:
    """The finished rows by (engine, support, values of the other varied fields as JSON)."""
    groups: dict[tuple, list[dict]] = {}
    for row in rows:
        if row.get("status") == "ok":
            key = (row["engine"], row["support"], *(json.dumps(row.get(p), default=str) for p in others))
            groups.setdefault(key, []).append(row)
    return groups


def _shown_unit(axis: Vary, units: str):
    """The display unit of the varied field (display.py, of its SI unit), None if it has none."""
    return display_unit(axis.si_unit, units) if axis.si_unit and axis.si_unit != "-" else None


def _nominal_marks(plan: SweepPlan, axis: Vary, shown) -> list[Line]:
    """The line at the deck's value of the varied field (SI: nominal_value), in its display unit."""
    nominal = nominal_value(plan, axis.path, axis.to_si)
    factor = shown.factor if shown else 1.0
    return nominal_line(None if nominal is None else nominal * factor, axis.path,
                        shown.label if shown else axis.unit)


def _criticals(rows: Sequence[dict]) -> set[float]:
    """The distinct critical coefficients b/h_1* of the finished rows (to 12 decimals)."""
    return {round(float(row["critical_coefficient"]), 12) for row in rows
            if _finished_with(row, "critical_coefficient")}


def _sweep_panel(plan: SweepPlan, rows: Sequence[dict], quantity: str, groups: dict[tuple, list[dict]], x_path: str,
                 others: Sequence[str], marks: list[Line], critical: bool) -> Panel:
    """One panel of sweep_figure: the lines of the groups, b/h_1* (not on the drift panel) when
    `critical`, the deck's value and, on the drift panel, the [criteria] limit."""
    column, label = axis_label(quantity)
    series = sweep_lines(groups, column, x_path, others)
    if quantity != "max_drift_ratio" and critical:
        series = _with_critical(series, rows, x_path)
    return Panel(label, label, series, list(marks) + _drift_limit(plan, quantity, column))


def _drift_limit(plan: SweepPlan, quantity: str, column: str) -> list[Line]:
    """The deck's [criteria] drift_ratio limit on the drift panel (none elsewhere)."""
    if quantity != "max_drift_ratio" or "drift_ratio" not in plan.criteria:
        return []
    factor, unit = PLOTTED[column]
    limit = factor * float(plan.criteria["drift_ratio"])
    return [Line(limit, f"[criteria] limit drift ratio = {limit:g} {unit}", "y", ":", "black")]


def _scale_x(panels: list[Panel], factor: float) -> None:
    """The panels' x values (the varied field as the deck gives it) times `factor`: in its display unit (in place)."""
    if factor == 1.0:
        return
    for panel in panels:
        panel.series = [replace(series, x=np.asarray(series.x) * factor) for series in panel.series]


def sweep_lines(groups: dict[tuple, list[dict]], column: str, x_path: str, others: Sequence[str]) -> list[Series]:
    """One line per (engine, support, values of the other fields) group: the support's colour
    (figures/style.py), the engine's line style, and per value of the other fields a shade of
    that colour with a marker, so that no two lines look alike (nine lines: three supports
    times three values, say)."""
    values = _other_values(groups)
    return [_group_line(key, groups[key], column, x_path, others, values[key[1]]) for key in groups]


def _other_values(groups: dict[tuple, list[dict]]) -> dict[str, list[tuple]]:
    """Per support: the distinct values of the other varied fields of its groups, in order."""
    keys = list(groups)
    return {support: list(dict.fromkeys(tuple(key[2:]) for key in keys if key[1] == support))
            for support in dict.fromkeys(key[1] for key in keys)}


def _group_line(key: tuple, members: list[dict], column: str, x_path: str, others: Sequence[str],
                values: list[tuple]) -> Series:
    """The line of one group: labelled by engine, support and the other values; the support's
    shade and marker of its other values (`values`: those of its support)."""
    engine, support, *rest = key
    x, y = curve(members, column, x_path)
    k = values.index(tuple(rest))
    color = shades(SUPPORT_COLORS.get(support, "#000000"), len(values))[k]
    marker = MARKERS[k % len(MARKERS)] if len(values) > 1 else None
    return Series(_group_label(engine, support, members[0], others), x, y, ENGINE_LINES.get(engine, "-"), color,
                  marker=marker)


def _group_label(engine: str, support: str, row: dict, others: Sequence[str]) -> str:
    """'engine, support' and the group's values of the other varied fields."""
    extra = ", ".join(f"{p}={row.get(p)}" for p in others)
    return f"{engine}, {support}" + (f", {extra}" if extra else "")
