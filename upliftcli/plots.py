"""Figures (matplotlib, no pyplot state): record response spectra, and line figures of panels
(FigureSpec: sweeps and the paper-style spectra over T_1, whose data upliftcli.figures builds).

Every figure is written atomically (upliftcli.atomic); the format follows the file extension.
"""

from __future__ import annotations

import os
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .atomic import atomic_path
from .errors import InputError
from .units import STANDARD_GRAVITY

FIGURE_FORMATS = (".png", ".pdf", ".svg")

#: spectrum quantity -> (attribute of spectra.Spectrum, axis label, factor from SI to the plotted unit)
SPECTRUM_QUANTITIES = {
    "pseudo_acceleration": ("pseudo_acceleration", "pseudo-acceleration S_a [g]", 1.0 / STANDARD_GRAVITY),
    "displacement": ("displacement", "deformation S_d [cm]", 100.0),
    "pseudo_velocity": ("pseudo_velocity", "pseudo-velocity S_v [cm/s]", 100.0),
    "absolute_acceleration": ("absolute_acceleration", "absolute acceleration [g]", 1.0 / STANDARD_GRAVITY),
}


def check_figure_path(path: str | os.PathLike, option: str = "--plot") -> Path:
    """The figure path, or InputError if its extension is not a supported format."""
    path = Path(path)
    if path.suffix.lower() not in FIGURE_FORMATS:
        raise InputError(option, str(path), f"a file name ending {', '.join(FIGURE_FORMATS)}")
    return path


def new_figure(width: float = 7.0, height: float = 4.5):
    """A matplotlib Figure with the Agg canvas (no GUI, no global pyplot state)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(figure)
    return figure


def save_figure(figure, path: str | os.PathLike, option: str = "--plot") -> Path:
    """Write the figure atomically; the format follows the extension."""
    path = check_figure_path(path, option)
    with atomic_path(path) as tmp:
        figure.savefig(tmp, format=path.suffix.lower().lstrip("."), dpi=150)
    return path


def plot_spectrum(spectrum, path: str | os.PathLike, title: str = "", quantity: str = "pseudo_acceleration",
                  option: str = "--plot") -> Path:
    """Plot a spectra.Spectrum: one line per damping, log period axis, labelled units."""
    attribute, label, factor = SPECTRUM_QUANTITIES[quantity]
    check_figure_path(path, option)
    figure = new_figure()
    axes = figure.add_subplot()
    values = getattr(spectrum, attribute) * factor
    periods = np.asarray(spectrum.periods)
    positive = periods > 0.0
    for index, damping in enumerate(spectrum.dampings):
        axes.plot(periods[positive], values[index, positive], label=f"damping {100 * damping:g} %")
    axes.set_xscale("log")
    axes.set_xlabel("period T [s]")
    axes.set_ylabel(label)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend()
    if title:
        axes.set_title(textwrap.fill(title, 70), fontsize="medium")
    return save_figure(figure, path, option)


# ----------------------------------------------------------------------------- line figures (sweeps, spectra)

@dataclass
class Series:
    """One line: label, x and y values (plotted units), line style ("-", "--", ":") and colour."""

    label: str
    x: np.ndarray
    y: np.ndarray
    style: str = "-"
    color: str | None = None


@dataclass
class Panel:
    """One axes: title, y-axis label and its lines."""

    title: str
    ylabel: str
    series: list[Series] = field(default_factory=list)


@dataclass
class FigureSpec:
    """A figure of panels sharing the x quantity: title, x label, log axes."""

    title: str
    xlabel: str
    panels: list[Panel]
    xlog: bool = False
    ylog: bool = False


def plot_figure(spec: FigureSpec, path: str | os.PathLike, option: str = "--plot") -> Path:
    """Draw the panels side by side (at most three a row) and write the figure atomically."""
    check_figure_path(path, option)
    count = max(1, len(spec.panels))
    columns = min(count, 3)
    rows = -(-count // columns)
    figure = new_figure(4.6 * columns + 0.6, 3.9 * rows + 0.5)
    for index, panel in enumerate(spec.panels):
        axes = figure.add_subplot(rows, columns, index + 1)
        for series in panel.series:
            x, y = np.asarray(series.x, dtype=float), np.asarray(series.y, dtype=float)
            keep = np.isfinite(x) & np.isfinite(y)
            if spec.xlog:
                keep &= x > 0.0
            if spec.ylog:
                keep &= y > 0.0
            axes.plot(x[keep], y[keep], linestyle=series.style, color=series.color, label=series.label,
                      marker="." if keep.sum() < 3 else None)
        if spec.xlog:
            axes.set_xscale("log")
            _plain_log_labels(axes.xaxis)
        if spec.ylog:
            axes.set_yscale("log")
            _plain_log_labels(axes.yaxis)
        axes.set_xlabel(spec.xlabel)
        axes.set_ylabel(panel.ylabel)
        axes.set_title(textwrap.fill(panel.title, 48), fontsize="medium")
        axes.grid(True, which="both", alpha=0.3)
        if panel.series:
            axes.legend(fontsize="small")
    if spec.title:
        figure.suptitle(textwrap.fill(spec.title, int(13 * (4.6 * columns + 0.6))), fontsize="medium")
    return save_figure(figure, path, option)


def _plain_log_labels(axis) -> None:
    """Log-axis labels as 0.1, 0.2, 0.5, 1, 2 ... instead of powers of ten."""
    from matplotlib.ticker import FuncFormatter

    def minor(value, _position) -> str:
        if value <= 0:
            return ""
        mantissa = value / 10.0 ** np.floor(np.log10(value))
        return f"{value:g}" if any(abs(mantissa - m) < 1e-6 for m in (2.0, 5.0)) else ""

    axis.set_major_formatter(FuncFormatter(lambda value, _position: f"{value:g}"))
    axis.set_minor_formatter(FuncFormatter(minor))
