"""Data of the paper-style figures (Yim & Chopra Figs. 3, 4, 6-10) and of sweep plots.

Pure functions of the tidy rows of a sweep (sweep/plan.py, sweep/table.py): they return
plots.FigureSpec objects (lines as arrays) that plots.plot_figure draws. The paper's
response spectra are maxima plotted against the fixed-base period T_1 with everything else
scaled with it (THEORY.md section 6): a sweep of `building.period`.

- Figs. 3-4: V_b/(m_t g) and M_b/(m_t g h_1*) for rigid, bonded and uplift, with the
  critical value b/h_1* of both coefficients [16a, 16b];
- Fig. 7: modal contributions to the base shear (mode 1, modes 1-2, all modes) per support;
- Figs. 6, 10: total base shear by the engines compared (exact, approximate, simplified);
- Figs. 8, 9: mode-1 base shear by the engines compared.
"""

from __future__ import annotations

import json
from collections.abc import Sequence

import numpy as np

from ..engines.registry import ENGINES, SUPPORT_LABELS
from ..errors import InputError
from ..plots import FigureSpec, Panel, Series
from .plan import SweepPlan, Vary, parse_values
from .table import OUTPUT_COLUMNS

PERIOD_PATH = "building.period"
PERIOD_LABEL = "fixed-base fundamental period T_1 [s]"
SUPPORT_STYLES = {"rigid": ("-", "tab:gray"), "bonded": ("--", "tab:blue"), "uplift": ("-", "tab:red")}
ENGINE_STYLES = {"exact": ("-", "black"), "approximate": ("--", "tab:orange"), "simplified": (":", "tab:green")}
#: figure quantity -> row column (sweep/table.py); the axis label is the column's meaning
QUANTITIES = {"base_shear": "base_shear_coefficient", "base_moment": "base_moment_coefficient",
              "mode1_base_shear": "mode1_base_shear_coefficient",
              "two_mode_base_shear": "two_mode_base_shear_coefficient", "max_drift_ratio": "max_drift_ratio"}


def axis_label(quantity: str) -> tuple[str, str]:
    """(row column, axis label with its unit) of a figure quantity."""
    column = QUANTITIES[quantity]
    unit, meaning = OUTPUT_COLUMNS[column]
    return column, meaning + ("" if unit in ("-", "") else f" [{unit}]")


def period_vary(text: str) -> Vary:
    """--periods START:STOP:N[:log|lin] (log-spaced unless told) or a list, all > 0 s."""
    values, spacing = parse_values(text, "--periods", default_spacing="log")
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) and v > 0 for v in values):
        raise InputError("--periods", text, "periods > 0 s: START:STOP:N[:log|lin] or a comma list")
    return Vary(PERIOD_PATH, tuple(float(v) for v in values), spacing)


def curve(rows: Sequence[dict], column: str, x_path: str = PERIOD_PATH, **match) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) of the finished rows matching `match` (e.g. engine="exact"), sorted by x; rows
    without a value of `column` are left out."""
    points = sorted((float(row[x_path]), float(row[column])) for row in rows
                    if row.get("status") == "ok" and row.get(column) is not None and row.get(x_path) is not None
                    and all(row.get(k) == v for k, v in match.items()))
    if not points:
        return np.empty(0), np.empty(0)
    x, y = zip(*points)
    return np.array(x), np.array(y)


def critical_series(rows: Sequence[dict], x_path: str = PERIOD_PATH) -> Series | None:
    """The critical coefficient b/h_1* (of V_b/(m_t g) and M_b/(m_t g h_1*)) against x."""
    by_x = {float(row[x_path]): float(row["critical_coefficient"]) for row in rows
            if row.get("status") == "ok" and row.get("critical_coefficient") is not None}
    if not by_x:
        return None
    x = np.array(sorted(by_x))
    y = np.array([by_x[v] for v in x])
    label = f"critical b/h_1* = {y[0]:.3g}" if np.ptp(y) <= 1e-9 * abs(y[0]) else "critical b/h_1*"
    return Series(label, x, y, ":", "black")


def _with_critical(series: list[Series], rows: Sequence[dict], x_path: str = PERIOD_PATH) -> list[Series]:
    critical = critical_series(rows, x_path)
    return series + ([critical] if critical is not None else [])


def support_figure(rows: Sequence[dict], engine: str, supports: Sequence[str], quantity: str,
                   record: str = "") -> FigureSpec:
    """Figs. 3 (base_shear) and 4 (base_moment): one line per support condition, and b/h_1*."""
    column, label = axis_label(quantity)
    series = []
    for support in supports:
        x, y = curve(rows, column, engine=engine, support=support)
        style, color = SUPPORT_STYLES[support]
        series.append(Series(SUPPORT_LABELS[support], x, y, style, color))
    what = "Base shear" if quantity == "base_shear" else "Base overturning moment"
    title = f"{what} response spectra for three support conditions, {ENGINES[engine].label}"
    return FigureSpec(f"{title}{', ' + record if record else ''}", PERIOD_LABEL,
                      [Panel(what, label, _with_critical(series, rows))], xlog=True, ylog=True)


def modal_figure(rows: Sequence[dict], engine: str, supports: Sequence[str], record: str = "") -> FigureSpec:
    """Fig. 7: per support, the base shear of mode 1, of modes 1-2 (when the engine gives it)
    and of all modes."""
    panels = []
    for letter, support in zip("abc", supports):
        series = []
        for column, name, style in (("mode1_base_shear_coefficient", "mode 1", "--"),
                                    ("two_mode_base_shear_coefficient", "modes 1-2", ":"),
                                    ("base_shear_coefficient", "all modes", "-")):
            x, y = curve(rows, column, engine=engine, support=support)
            if x.size:
                series.append(Series(name, x, y, style))
        panels.append(Panel(f"({letter}) {SUPPORT_LABELS[support]}", axis_label("base_shear")[1],
                            _with_critical(series, rows)))
    title = f"Modal contributions to the maximum base shear, {ENGINES[engine].label}"
    return FigureSpec(f"{title}{', ' + record if record else ''}", PERIOD_LABEL, panels, xlog=True, ylog=True)


def engine_figure(rows: Sequence[dict], engines: Sequence[str], supports: Sequence[str], quantity: str,
                  record: str = "") -> FigureSpec:
    """Figs. 6, 10 (base_shear) and 8, 9 (mode1_base_shear): one line per engine, a panel per support."""
    column, label = axis_label(quantity)
    panels = []
    for support in supports:
        series = []
        for engine in engines:
            x, y = curve(rows, column, engine=engine, support=support)
            style, color = ENGINE_STYLES[engine]
            series.append(Series(ENGINES[engine].label, x, y, style, color))
        panels.append(Panel(SUPPORT_LABELS[support], label, _with_critical(series, rows)))
    what = "fundamental-mode base shear" if quantity == "mode1_base_shear" else "base shear"
    title = f"Comparison of {what} response spectra by {', '.join(engines)} analysis"
    return FigureSpec(f"{title}{', ' + record if record else ''}", PERIOD_LABEL, panels, xlog=True, ylog=True)


def paper_figures(rows: Sequence[dict], engines: Sequence[str], supports: Sequence[str],
                  record: str = "") -> dict[str, FigureSpec]:
    """Every figure the rows allow, by file-name suffix: base_shear_<engine> (Fig. 3),
    base_moment_<engine> (Fig. 4), modal_<engine> (Fig. 7), and with two engines or more
    engines_base_shear (Figs. 6, 10) and engines_mode1_base_shear (Figs. 8, 9)."""
    figures = {}
    for engine in engines:
        figures[f"base_shear_{engine}"] = support_figure(rows, engine, supports, "base_shear", record)
        figures[f"base_moment_{engine}"] = support_figure(rows, engine, supports, "base_moment", record)
        figures[f"modal_{engine}"] = modal_figure(rows, engine, supports, record)
    if len(engines) > 1:
        figures["engines_base_shear"] = engine_figure(rows, engines, supports, "base_shear", record)
        figures["engines_mode1_base_shear"] = engine_figure(rows, engines, supports, "mode1_base_shear", record)
    return figures


def sweep_figure(plan: SweepPlan, rows: Sequence[dict]) -> FigureSpec:
    """Response against the first numeric varied field (log axis for a log range): one line per
    engine, support and value of the other varied fields; panels V_b/(m_t g), M_b/(m_t g h_1*),
    largest drift ratio; b/h_1* on the first two when it does not depend on the other fields."""
    numeric = [v for v in plan.varies if all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v.values)]
    if not numeric:
        raise InputError("--plot", "--vary", "a numeric varied field to plot against")
    axis = numeric[0]
    others = [v.path for v in plan.varies if v.path != axis.path]
    groups: dict[tuple, list[dict]] = {}
    for row in rows:
        if row.get("status") == "ok":
            key = (row["engine"], row["support"], *(json.dumps(row.get(p), default=str) for p in others))
            groups.setdefault(key, []).append(row)
    criticals = {round(float(row["critical_coefficient"]), 12) for row in rows
                 if row.get("status") == "ok" and row.get("critical_coefficient") is not None}
    panels = []
    for quantity in ("base_shear", "base_moment", "max_drift_ratio"):
        column, label = axis_label(quantity)
        series = []
        for (engine, support, *_), members in groups.items():
            x, y = curve(members, column, axis.path)
            extra = ", ".join(f"{p}={members[0].get(p)}" for p in others)
            series.append(Series(f"{engine}, {support}" + (f", {extra}" if extra else ""), x, y,
                                 SUPPORT_STYLES[support][0]))
        if quantity != "max_drift_ratio" and (len(criticals) == 1 or not others):
            series = _with_critical(series, rows, axis.path)
        panels.append(Panel(label, label, series))
    unit = f" [{axis.unit}]" if axis.unit and axis.unit != "-" else ""
    return FigureSpec(f"{plan.title}: sweep of {axis.path}", f"{axis.path}{unit}", panels,
                      xlog=axis.spacing == "log")
