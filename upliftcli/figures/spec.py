"""Figure data: what a figure shows, as plain arrays and labels (no matplotlib).

The functions of upliftcli.figures and upliftcli.sweep.figures return a FigureSpec; figures/draw.py
draws it. Values are in the plotted units (the axis labels say which), so a test can compare
a figure's data with the results it shows.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Series:
    """One line: label, x and y values (plotted units), line style ("-", "--", "-.", ":" or a
    dash tuple), colour (None: the palette's, by position), line width [pt], marker, opacity."""

    label: str
    x: np.ndarray
    y: np.ndarray
    style: str | tuple = "-"
    color: str | None = None
    width: float = 1.5
    marker: str | None = None
    alpha: float = 1.0


@dataclass
class Line:
    """A reference line across the panel: at y = value (axis "y", horizontal) or at x = value
    (axis "x", vertical); e.g. +-M_c, a [criteria] limit, the deck's value of a varied field."""

    value: float
    label: str = ""
    axis: str = "y"
    style: str = ":"
    color: str = "black"


@dataclass
class Span:
    """Shaded intervals along x, (k, 2) [start, end] in the x unit (e.g. the mat lifted)."""

    label: str
    intervals: np.ndarray
    color: str
    alpha: float = 0.25


@dataclass
class Bars:
    """One member of a grouped horizontal bar chart: a value per category (plotted units)."""

    label: str
    categories: list[str]
    values: np.ndarray
    color: str | None = None


@dataclass
class Panel:
    """One axes: title, y label, its lines, reference lines, shaded spans and bars; xlabel,
    xlog and ylog when they differ from the figure's; legend: whether its labels go into
    the figure's legend; xmin, ymin: lower axis limits (None: from the data)."""

    title: str
    ylabel: str
    series: list[Series] = field(default_factory=list)
    lines: list[Line] = field(default_factory=list)
    spans: list[Span] = field(default_factory=list)
    bars: list[Bars] = field(default_factory=list)
    xlabel: str | None = None
    xlog: bool | None = None
    ylog: bool | None = None
    legend: bool = True
    xmin: float | None = None
    ymin: float | None = None


@dataclass
class FigureSpec:
    """A figure of panels: title, x label (of every panel that names none), log axes, at most
    `columns` panels a row, panel size [in], whether the panels share x (stacked histories)
    or y (story profiles), and the width [in] left of each panel for its y tick labels."""

    title: str
    xlabel: str
    panels: list[Panel]
    xlog: bool = False
    ylog: bool = False
    columns: int = 3
    panel_size: tuple[float, float] = (4.6, 3.4)
    sharex: bool = False
    sharey: bool = False
    left: float = 0.85

    def panel_xlog(self, panel: Panel) -> bool:
        return self.xlog if panel.xlog is None else panel.xlog

    def panel_ylog(self, panel: Panel) -> bool:
        return self.ylog if panel.ylog is None else panel.ylog

    def labels(self) -> list[str]:
        """The legend entries, in order, each once (series, lines, spans and bars with a label)."""
        return list(dict.fromkeys(item.label for panel in self.panels for item in legend_items(panel)))


def legend_items(panel: Panel) -> list[Series | Line | Span | Bars]:
    """The items of a panel that go into the figure's legend: its series, lines, spans and bars
    with a label, in that order (none when the panel keeps out of the legend)."""
    if not panel.legend:
        return []
    return [item for item in (*panel.series, *panel.lines, *panel.spans, *panel.bars) if item.label]


def spans_of(times: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Intervals [t_start, t_end] (k, 2) where mask is true, a sample's value holding until
    the next sample (a state valid from each sample on)."""
    times = np.asarray(times, dtype=float)
    mask = np.asarray(mask, dtype=bool)
    if not mask.any():
        return np.zeros((0, 2))
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    starts = np.nonzero(edges == 1)[0]
    ends = np.nonzero(edges == -1)[0]  # first sample after each run (or one past the last)
    return np.column_stack((times[starts], times[np.minimum(ends, times.size - 1)]))
