"""Figures (matplotlib, no pyplot state): response spectra; sweep plots are added by the sweep command.

Every figure is written atomically (upliftcli.atomic); the format follows the file extension.
"""

from __future__ import annotations

import os
import textwrap
from pathlib import Path

import numpy as np

from upliftcli.atomic import atomic_path
from upliftcli.errors import InputError
from upliftcli.records import STANDARD_GRAVITY

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
