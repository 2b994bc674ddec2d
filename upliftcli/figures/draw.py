"""Drawing of figure data (figures/spec.FigureSpec: sweeps, the paper's spectra over T_1, story
profiles, mode shapes, histories, energy, record spectra) with matplotlib: the Agg canvas, no
pyplot state, matplotlib imported only when a figure is drawn.

One look everywhere: the colour-blind-safe palette of figures/style.py, the legend below the
panels (outside the data), plain tick labels on log axes (0.1, 0.2, 0.5, 1, 2 ...). The
layout is computed from fixed margins [in] (a measured layout sizes every text several times:
a third of the drawing time). Every file is written atomically (upliftcli.runtime.atomic); the format
follows the file extension.
"""

from __future__ import annotations

import io
import math
import os
import pickle
import sys
import textwrap
import threading
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..runtime.atomic import atomic_path
from .spec import Bars, FigureSpec, Line, Panel, Series, Span  # noqa: F401  (the figure data types)

FIGURE_FORMATS = (".png", ".pdf", ".svg")
DPI = 150
#: whether plot_figures shares figures out to forked copies of this process: on Linux only (no
#: fork on Windows; macOS's system libraries may not survive one); elsewhere one after the other
FORK_FIGURES = hasattr(os, "fork") and sys.platform.startswith("linux")

#: layout [in]: one line of a 10-pt title, tick and axis labels below a panel, right margin,
#: gap between panels sharing an axis, padding, one row of the legend
_LINE, _BOTTOM, _RIGHT, _SHARED_GAP, _PAD, _LEGEND_ROW = 0.19, 0.6, 0.25, 0.22, 0.12, 0.21
_CHAR = 0.08  # width of a character of a 10-pt title [in] (digits and capitals: an average that never overflows)
_LEGEND_CHAR, _LEGEND_HANDLE = 0.06, 0.75  # a character of a legend entry, handle and padding [in]


def check_figure_path(path: str | os.PathLike, option: str = "--plot") -> Path:
    """The figure path, or InputError if its extension is not a supported format."""
    path = Path(path)
    if path.suffix.lower() not in FIGURE_FORMATS:
        raise InputError(option, str(path), f"a file name ending {', '.join(FIGURE_FORMATS)}")
    return path


#: the thread importing matplotlib for preload(background=True), until a figure is drawn
_preloading: threading.Thread | None = None


def preload(background: bool = False) -> None:
    """Import what drawing a figure needs (matplotlib's Figure, Agg canvas, tickers): about 0.3 s
    that a caller can spend while other processes work. background: in a thread, for a caller
    whose main thread then only waits on worker processes (the drawing functions wait for it)."""
    global _preloading
    if not background:
        _wait_for_preload()
        _import_matplotlib()
    elif _preloading is None:
        _preloading = threading.Thread(target=_import_matplotlib, name="uplift-preload", daemon=True)
        _preloading.start()


def _import_matplotlib() -> None:
    import matplotlib.backends.backend_agg
    import matplotlib.figure
    import matplotlib.ticker  # noqa: F401


def _wait_for_preload() -> None:
    global _preloading
    if _preloading is not None:
        _preloading.join()
        _preloading = None


def new_figure(width: float = 7.0, height: float = 4.5):
    """A matplotlib Figure with the Agg canvas (no GUI, no global pyplot state)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(width, height))
    FigureCanvasAgg(figure)
    return figure


def save_figure(figure, path: str | os.PathLike, option: str = "--plot") -> Path:
    """Write the figure atomically; the format follows the extension."""
    path = check_figure_path(path, option)
    with atomic_path(path) as tmp:
        figure.savefig(tmp, format=path.suffix.lower().lstrip("."), dpi=DPI)
    return path


def plot_figure(spec: FigureSpec, path: str | os.PathLike, option: str = "--plot") -> Path:
    """Draw a FigureSpec and write it atomically."""
    check_figure_path(path, option)
    return save_figure(line_figure(spec), path, option)


def plot_figures(figures: Sequence[tuple[FigureSpec, str | os.PathLike]], option: str = "--plot") -> list[Path]:
    """Draw and write several figures (plot_figure each); their paths in the order given.

    Drawing is Python (threads would not help), so on Linux, when this process runs no other
    thread, the figures are shared out between it and forked copies of it, one per core, that
    start with matplotlib imported and the figure data in memory (the three figures of `uplift
    spectra` in 0.45 s instead of 0.85 s on two cores; elsewhere, FORK_FIGURES, one after the
    other). An error in any figure is raised here, after every copy has ended."""
    paths = [check_figure_path(path, option) for _, path in figures]
    _wait_for_preload()
    from ..runtime.process import available_cores

    groups = _shares(figures, min(available_cores(), len(figures)))
    if len(groups) < 2 or not FORK_FIGURES or threading.active_count() > 1:
        for spec, path in figures:
            _draw(spec, path, option)
        return paths
    preload()
    for stream in (sys.stdout, sys.stderr):  # nothing buffered is written twice
        stream.flush()
    children: list[tuple[int, int]] = []
    try:
        for group in groups[1:]:
            read, write = os.pipe()
            pid = os.fork()
            if pid == 0:  # the copy: draw its share, report an error through the pipe, never return
                os.close(read)
                code = 0
                try:
                    for spec, path in group:
                        _draw(spec, path, option)
                except BaseException as error:  # every error, Ctrl-C included, goes to the parent
                    code = 1
                    os.write(write, _carried(error))
                finally:
                    os._exit(code)
            os.close(write)
            children.append((pid, read))
        for spec, path in groups[0]:
            _draw(spec, path, option)
    finally:
        failures = [_child_failure(pid, read) for pid, read in children]
    for failure in failures:
        if failure is not None:
            raise failure
    return paths


def _draw(spec: FigureSpec, path, option: str) -> None:
    """plot_figure; an OSError names the figure's path (not its temporary file)."""
    try:
        plot_figure(spec, path, option)
    except OSError as error:
        raise OSError(error.errno, error.strerror or str(error), str(path)) from None


def _shares(figures: Sequence[tuple[FigureSpec, object]], count: int) -> list[list]:
    """The figures in `count` groups of about equal work (by number of panels, largest first)."""
    groups: list[list] = [[] for _ in range(max(count, 1))]
    loads = [0] * len(groups)
    for item in sorted(figures, key=lambda item: -max(len(item[0].panels), 1)):
        lightest = loads.index(min(loads))
        groups[lightest].append(item)
        loads[lightest] += max(len(item[0].panels), 1)
    return [group for group in groups if group]


def _carried(error: BaseException) -> bytes:
    """An error of a forked copy as bytes for the parent (an InputError by its fields)."""
    if isinstance(error, InputError):
        return pickle.dumps(("input", error.source, error.location, error.expected))
    try:
        return pickle.dumps(("error", error))
    except Exception:  # an error that does not pickle goes as its text
        return pickle.dumps(("text", f"{type(error).__name__}: {error}"))


def _child_failure(pid: int, read: int) -> BaseException | None:
    """Wait for a forked copy; the error it reported (or its death), None if it succeeded."""
    chunks = []
    while chunk := os.read(read, 65536):
        chunks.append(chunk)
    os.close(read)
    _, status = os.waitpid(pid, 0)
    if status == 0:
        return None
    if not chunks:
        return RuntimeError(f"a process drawing figures ended with status {status}")
    kind, *fields = pickle.loads(b"".join(chunks))
    if kind == "input":
        return InputError(*fields)
    return fields[0] if kind == "error" else RuntimeError(fields[0])


def figure_bytes(spec: FigureSpec, file_format: str = "png", dpi: int = 110) -> bytes:
    """A FigureSpec drawn into memory (png or svg), e.g. to embed in a report."""
    buffer = io.BytesIO()
    line_figure(spec).savefig(buffer, format=file_format, dpi=dpi)
    return buffer.getvalue()


def plot_spectrum(spectrum, path: str | os.PathLike, title: str = "", option: str = "--plot",
                  units: str = "si") -> Path:
    """Plot a spectra.Spectrum: S_d, S_v and S_a panels, one line per damping, log period axis,
    in the display units (display.py)."""
    from .spectra import record_spectrum_figure

    return plot_figure(record_spectrum_figure(spectrum, title, units=units), path, option)


# ----------------------------------------------------------------------------- layout

def _wrap(text: str, width_in: float) -> str:
    """The text in lines no wider than width_in [in] (its own line breaks kept)."""
    width = max(12, int(width_in / _CHAR))
    return "\n".join(textwrap.fill(line, width) for line in text.splitlines()) if text else ""


def _legend_shape(labels: list[str], width_in: float) -> tuple[int, int]:
    """(columns, rows) of a legend of these entries across width_in [in]."""
    if not labels:
        return 0, 0
    entry = _LEGEND_HANDLE + _LEGEND_CHAR * max(len(label) for label in labels)
    columns = max(1, min(len(labels), int(width_in // entry)))
    return columns, math.ceil(len(labels) / columns)


def line_figure(spec: FigureSpec):
    """The matplotlib Figure of a FigureSpec: panels in rows of at most spec.columns, the
    figure title on top, one legend of every labelled item below the panels."""
    count = max(1, len(spec.panels))
    columns = max(1, min(count, spec.columns))
    rows = -(-count // columns)
    panel_w, panel_h = spec.panel_size
    gap_x = _SHARED_GAP if spec.sharey else spec.left
    width = spec.left + columns * panel_w + (columns - 1) * gap_x + _RIGHT
    titles = [_wrap(panel.title, panel_w) for panel in spec.panels]
    title_lines = max((t.count("\n") + 1 for t in titles if t), default=0)
    head = _PAD + _LINE * title_lines  # above each panel
    below = [(_PAD if spec.sharex and row < rows - 1 else _BOTTOM) for row in range(rows)]
    suptitle = _wrap(spec.title, width - 0.3)
    top = (_PAD + _LINE * (suptitle.count("\n") + 1)) if suptitle else 0.0
    labels = spec.labels()
    legend_columns, legend_rows = _legend_shape(labels, width - 0.2)
    legend = (_PAD + _LEGEND_ROW * legend_rows) if legend_rows else 0.0
    height = top + sum(head + panel_h + b for b in below) + legend + _PAD
    figure = new_figure(width, height)
    axes_list = []
    for index, panel in enumerate(spec.panels):
        row, column = divmod(index, columns)
        x0 = spec.left + column * (panel_w + gap_x)
        y_top = top + sum(head + panel_h + b for b in below[:row]) + head
        share = {"sharex": axes_list[0] if spec.sharex and axes_list else None,
                 "sharey": axes_list[0] if spec.sharey and axes_list else None}
        axes = figure.add_axes((x0 / width, 1.0 - (y_top + panel_h) / height, panel_w / width, panel_h / height),
                               **share)
        _draw_panel(axes, spec, panel, titles[index])
        if spec.sharey and column > 0:
            axes.tick_params(which="both", labelleft=False)
            axes.set_ylabel("")
        if spec.sharex and row < rows - 1 and index + columns < count:
            axes.tick_params(which="both", labelbottom=False)
            axes.set_xlabel("")
        axes_list.append(axes)
    if suptitle:
        figure.suptitle(suptitle, fontsize="medium", y=1.0 - _PAD / height, va="top")
    if labels:
        figure.legend(_handles(spec, labels), labels, loc="lower center", ncol=legend_columns, fontsize="small",
                      bbox_to_anchor=(0.5, _PAD / 2 / height), frameon=False)
    return figure


# ----------------------------------------------------------------------------- panels

def _draw_panel(axes, spec: FigureSpec, panel: Panel, title: str) -> None:
    xlog, ylog = spec.panel_xlog(panel), spec.panel_ylog(panel)
    for span in panel.spans:
        intervals = np.asarray(span.intervals, dtype=float).reshape(-1, 2)
        if intervals.size:
            axes.broken_barh(list(zip(intervals[:, 0], intervals[:, 1] - intervals[:, 0], strict=True)), (0.0, 1.0),
                             transform=axes.get_xaxis_transform(), facecolor=span.color, alpha=span.alpha,
                             linewidth=0)
    for series in panel.series:
        x, y = np.asarray(series.x, dtype=float), np.asarray(series.y, dtype=float)
        keep = np.isfinite(x) & np.isfinite(y)
        if xlog:
            keep &= x > 0.0
        if ylog:
            keep &= y > 0.0
        marker = series.marker or ("." if keep.sum() < 3 else None)
        axes.plot(x[keep], y[keep], linestyle=series.style, color=series.color, linewidth=series.width,
                  marker=marker, markersize=4, alpha=series.alpha)
    if panel.bars:
        _draw_bars(axes, panel.bars)
    for line in panel.lines:
        if line.value <= 0.0 and (xlog if line.axis == "x" else ylog):
            continue
        draw = axes.axvline if line.axis == "x" else axes.axhline
        draw(line.value, linestyle=line.style, color=line.color, linewidth=1.2)
    if xlog:
        axes.set_xscale("log")
        _plain_log_labels(axes.xaxis)
    if ylog:
        axes.set_yscale("log")
        _plain_log_labels(axes.yaxis)
    if panel.xmin is not None:
        axes.set_xlim(left=panel.xmin)
    if panel.ymin is not None:
        axes.set_ylim(bottom=panel.ymin)
    axes.set_xlabel(spec.xlabel if panel.xlabel is None else panel.xlabel)
    axes.set_ylabel(panel.ylabel)
    if title:  # placed, not measured: matplotlib's automatic title position sizes every tick label
        axes.set_title(title, fontsize="medium", y=1.0)
    axes.grid(True, which="both", alpha=0.3)


def _draw_bars(axes, bars: list[Bars]) -> None:
    """Grouped horizontal bars: one group per category (top to bottom), one bar per member."""
    categories = list(dict.fromkeys(c for member in bars for c in member.categories))
    height = 0.8 / len(bars)
    for k, member in enumerate(bars):
        where = {c: i for i, c in enumerate(categories)}
        y = np.array([where[c] for c in member.categories], dtype=float) - 0.4 + height * (k + 0.5)
        axes.barh(y, member.values, height, color=member.color)
    axes.set_yticks(np.arange(len(categories)), categories)
    axes.set_ylim(len(categories) - 0.5, -0.5)


def _handles(spec: FigureSpec, labels: list[str]) -> list:
    """One legend proxy per label: the first item with that label."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    found: dict[str, object] = {}
    for panel in spec.panels:
        if not panel.legend:
            continue
        for series in panel.series:
            found.setdefault(series.label, Line2D([], [], linestyle=series.style, color=series.color,
                                                  linewidth=series.width, marker=series.marker, alpha=series.alpha))
        for line in panel.lines:
            found.setdefault(line.label, Line2D([], [], linestyle=line.style, color=line.color, linewidth=1.2))
        for span in panel.spans:
            found.setdefault(span.label, Patch(facecolor=span.color, alpha=span.alpha, linewidth=0))
        for member in panel.bars:
            found.setdefault(member.label, Patch(facecolor=member.color))
    return [found[label] for label in labels]


def _plain_log_labels(axis) -> None:
    """Log-axis labels as 0.1, 0.2, 0.5, 1, 2 ... instead of powers of ten (the 2 and 5 of
    each decade only when the axis spans at most 2.5 decades)."""
    from matplotlib.ticker import FuncFormatter

    def minor(value, _position) -> str:
        low, high = sorted(axis.get_view_interval())
        if value <= 0 or low <= 0 or math.log10(high / low) > 2.5:
            return ""
        mantissa = value / 10.0 ** np.floor(np.log10(value))
        return f"{value:g}" if any(abs(mantissa - m) < 1e-6 for m in (2.0, 5.0)) else ""

    axis.set_major_formatter(FuncFormatter(lambda value, _position: f"{value:g}"))
    axis.set_minor_formatter(FuncFormatter(minor))
