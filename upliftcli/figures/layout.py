"""The layout of a drawn figure (figures/draw.line_figure), computed from fixed margins [in]: a
measured layout sizes every text several times (a third of the drawing time). Panels in rows of
at most spec.columns, the figure title on top, one legend of every labelled item below the panels."""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass

from .spec import FigureSpec

#: layout [in]: one line of a 10-pt title, tick and axis labels below a panel, right margin,
#: gap between panels sharing an axis, padding, one row of the legend
LINE, BOTTOM, RIGHT, SHARED_GAP, PAD, LEGEND_ROW = 0.19, 0.6, 0.25, 0.22, 0.12, 0.21
CHAR = 0.08  # width of a character of a 10-pt title [in] (digits and capitals: an average that never overflows)
LEGEND_CHAR, LEGEND_HANDLE = 0.06, 0.75  # a character of a legend entry, handle and padding [in]


@dataclass
class Layout:
    """Where a figure's parts go [in]: panel count, columns and rows, figure width and height,
    the gap between panels across, the height above each panel (its title), below each row,
    above the panels (the figure title); the wrapped panel titles and figure title, the legend
    entries and the legend's columns."""

    count: int
    columns: int
    rows: int
    width: float
    height: float
    gap_x: float
    head: float
    below: list[float]
    top: float
    titles: list[str]
    suptitle: str
    labels: list[str]
    legend_columns: int

    def panel_box(self, spec: FigureSpec, index: int) -> tuple[float, float, float, float]:
        """(left, bottom, width, height) of panel `index` in figure fractions."""
        panel_w, panel_h = spec.panel_size
        row, column = divmod(index, self.columns)
        x0 = spec.left + column * (panel_w + self.gap_x)
        y_top = self.top + sum(self.head + panel_h + b for b in self.below[:row]) + self.head
        return (x0 / self.width, 1.0 - (y_top + panel_h) / self.height, panel_w / self.width,
                panel_h / self.height)

    def bottom_row(self, index: int) -> bool:
        """Whether panel `index` has no panel below it (it keeps its x tick labels)."""
        return index // self.columns == self.rows - 1 or index + self.columns >= self.count


def wrap(text: str, width_in: float) -> str:
    """The text in lines no wider than width_in [in] (its own line breaks kept)."""
    width = max(12, int(width_in / CHAR))
    return "\n".join(textwrap.fill(line, width) for line in text.splitlines()) if text else ""


def legend_shape(labels: list[str], width_in: float) -> tuple[int, int]:
    """(columns, rows) of a legend of these entries across width_in [in]."""
    if not labels:
        return 0, 0
    entry = LEGEND_HANDLE + LEGEND_CHAR * max(len(label) for label in labels)
    columns = max(1, min(len(labels), int(width_in // entry)))
    return columns, math.ceil(len(labels) / columns)


def _grid(spec: FigureSpec) -> tuple[int, int, int]:
    """(panels, columns, rows) of the figure (at least one panel)."""
    count = max(1, len(spec.panels))
    columns = max(1, min(count, spec.columns))
    return count, columns, -(-count // columns)


def _figure_width(spec: FigureSpec, columns: int, gap_x: float) -> float:
    return spec.left + columns * spec.panel_size[0] + (columns - 1) * gap_x + RIGHT


def _title_lines(titles: list[str]) -> int:
    """The most lines of a panel title."""
    return max((t.count("\n") + 1 for t in titles if t), default=0)


def _below(spec: FigureSpec, rows: int) -> list[float]:
    """The height below each row [in]: padding above a row that shares its x axis, else room for labels."""
    return [(PAD if spec.sharex and row < rows - 1 else BOTTOM) for row in range(rows)]


def layout(spec: FigureSpec) -> Layout:
    """The Layout of a FigureSpec."""
    count, columns, rows = _grid(spec)
    panel_w, panel_h = spec.panel_size
    gap_x = SHARED_GAP if spec.sharey else spec.left
    width = _figure_width(spec, columns, gap_x)
    titles = [wrap(panel.title, panel_w) for panel in spec.panels]
    head = PAD + LINE * _title_lines(titles)  # above each panel
    below = _below(spec, rows)
    suptitle = wrap(spec.title, width - 0.3)
    top = (PAD + LINE * (suptitle.count("\n") + 1)) if suptitle else 0.0
    labels = spec.labels()
    legend_columns, legend_rows = legend_shape(labels, width - 0.2)
    legend = (PAD + LEGEND_ROW * legend_rows) if legend_rows else 0.0
    height = top + sum(head + panel_h + b for b in below) + legend + PAD
    return Layout(count, columns, rows, width, height, gap_x, head, below, top, titles, suptitle, labels,
                  legend_columns)
