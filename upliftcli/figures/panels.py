"""One panel of a drawn figure (figures/draw.line_figure) in named steps: shaded spans, the
lines, bars, reference lines, log axes with plain labels, lower limits, axis labels and title;
and the legend's proxies of a FigureSpec's labelled items."""

from __future__ import annotations

import functools
import math

import numpy as np

from .spec import Bars, FigureSpec, Line, Panel, Series, Span, legend_items


def draw_panel(axes, spec: FigureSpec, panel: Panel, title: str) -> None:
    """Draw a panel on its axes (title: already wrapped to the panel's width)."""
    xlog, ylog = spec.panel_xlog(panel), spec.panel_ylog(panel)
    _draw_spans(axes, panel.spans)
    _draw_series(axes, panel.series, xlog, ylog)
    if panel.bars:
        draw_bars(axes, panel.bars)
    _draw_lines(axes, panel.lines, xlog, ylog)
    _set_log_axes(axes, xlog, ylog)
    _set_limits(axes, panel)
    _set_labels(axes, spec, panel, title)


def _draw_spans(axes, spans: list[Span]) -> None:
    """Shaded intervals along x, over the whole height of the panel."""
    for span in spans:
        intervals = np.asarray(span.intervals, dtype=float).reshape(-1, 2)
        if intervals.size:
            axes.broken_barh(list(zip(intervals[:, 0], intervals[:, 1] - intervals[:, 0], strict=True)), (0.0, 1.0),
                             transform=axes.get_xaxis_transform(), facecolor=span.color, alpha=span.alpha,
                             linewidth=0)


def _drawable(series: Series, xlog: bool, ylog: bool) -> tuple[np.ndarray, np.ndarray]:
    """The points of a series that can be drawn: finite, and positive on a log axis."""
    x, y = np.asarray(series.x, dtype=float), np.asarray(series.y, dtype=float)
    keep = np.isfinite(x) & np.isfinite(y)
    if xlog:
        keep &= x > 0.0
    if ylog:
        keep &= y > 0.0
    return x[keep], y[keep]


def _marker(series: Series, points: int) -> str | None:
    """The series' own marker, else a dot where fewer than three points would show no line."""
    return series.marker or ("." if points < 3 else None)


def _draw_series(axes, series_list: list[Series], xlog: bool, ylog: bool) -> None:
    for series in series_list:
        x, y = _drawable(series, xlog, ylog)
        axes.plot(x, y, linestyle=series.style, color=series.color, linewidth=series.width,
                  marker=_marker(series, x.size), markersize=4, alpha=series.alpha)


def _off_log_axis(line: Line, xlog: bool, ylog: bool) -> bool:
    """Whether a reference line lies at or below zero on a log axis (it cannot be drawn)."""
    return line.value <= 0.0 and (xlog if line.axis == "x" else ylog)


def _draw_lines(axes, lines: list[Line], xlog: bool, ylog: bool) -> None:
    """Reference lines across the panel: vertical (axis "x") or horizontal."""
    for line in lines:
        if _off_log_axis(line, xlog, ylog):
            continue
        draw = axes.axvline if line.axis == "x" else axes.axhline
        draw(line.value, linestyle=line.style, color=line.color, linewidth=1.2)


def draw_bars(axes, bars: list[Bars]) -> None:
    """Grouped horizontal bars: one group per category (top to bottom), one bar per member."""
    categories = _categories(bars)
    where = {c: i for i, c in enumerate(categories)}
    height = 0.8 / len(bars)
    for k, member in enumerate(bars):
        y = np.array([where[c] for c in member.categories], dtype=float) - 0.4 + height * (k + 0.5)
        axes.barh(y, member.values, height, color=member.color)
    axes.set_yticks(np.arange(len(categories)), categories)
    axes.set_ylim(len(categories) - 0.5, -0.5)


def _categories(bars: list[Bars]) -> list[str]:
    """Every member's categories, each once, in the order first met."""
    return list(dict.fromkeys(c for member in bars for c in member.categories))


def _set_log_axes(axes, xlog: bool, ylog: bool) -> None:
    """Log scales where asked, with plain tick labels."""
    if xlog:
        axes.set_xscale("log")
        _plain_log_labels(axes.xaxis)
    if ylog:
        axes.set_yscale("log")
        _plain_log_labels(axes.yaxis)


def _set_limits(axes, panel: Panel) -> None:
    """The panel's lower axis limits, where it gives them."""
    if panel.xmin is not None:
        axes.set_xlim(left=panel.xmin)
    if panel.ymin is not None:
        axes.set_ylim(bottom=panel.ymin)


def _set_labels(axes, spec: FigureSpec, panel: Panel, title: str) -> None:
    """Axis labels (the panel's x label, else the figure's), the title and the grid."""
    axes.set_xlabel(spec.xlabel if panel.xlabel is None else panel.xlabel)
    axes.set_ylabel(panel.ylabel)
    if title:  # placed, not measured: matplotlib's automatic title position sizes every tick label
        axes.set_title(title, fontsize="medium", y=1.0)
    axes.grid(True, which="both", alpha=0.3)


def legend_handles(spec: FigureSpec, labels: list[str]) -> list:
    """One legend proxy per label: the first item with that label."""
    found: dict[str, object] = {}
    for panel in spec.panels:
        for item in legend_items(panel):
            if item.label not in found:
                found[item.label] = _proxy(item)
    return [found[label] for label in labels]


def _proxy(item: Series | Line | Span | Bars):
    """The legend handle that looks like the item: a line, or a patch of a span's or a bar's colour."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    if isinstance(item, Series):
        return Line2D([], [], linestyle=item.style, color=item.color, linewidth=item.width, marker=item.marker,
                      alpha=item.alpha)
    if isinstance(item, Line):
        return Line2D([], [], linestyle=item.style, color=item.color, linewidth=1.2)
    if isinstance(item, Span):
        return Patch(facecolor=item.color, alpha=item.alpha, linewidth=0)
    return Patch(facecolor=item.color)


def _plain_log_labels(axis) -> None:
    """Log-axis labels as 0.1, 0.2, 0.5, 1, 2 ... instead of powers of ten (the 2 and 5 of
    each decade only when the axis spans at most 2.5 decades: _minor_label)."""
    from matplotlib.ticker import FuncFormatter

    axis.set_major_formatter(FuncFormatter(_major_label))
    axis.set_minor_formatter(FuncFormatter(functools.partial(_minor_label, axis)))


def _major_label(value: float, _position) -> str:
    return f"{value:g}"


def _minor_label(axis, value: float, _position) -> str:
    """The label of a minor tick of a log axis: 2 and 5 of each decade when the axis spans at
    most 2.5 decades, else none."""
    low, high = sorted(axis.get_view_interval())
    if value <= 0 or low <= 0 or math.log10(high / low) > 2.5:
        return ""
    mantissa = value / 10.0 ** np.floor(np.log10(value))
    return f"{value:g}" if any(abs(mantissa - m) < 1e-6 for m in (2.0, 5.0)) else ""
