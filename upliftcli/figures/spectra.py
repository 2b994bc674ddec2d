"""Response spectra of a record (S_d, S_v, S_a panels: `uplift record spectrum --plot`) and of a
record suite (each scaled record thin, the code's statistic thick, the target dashed, the
period range shaded); docs/theory.md section 10."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .. import display
from ..units import STANDARD_GRAVITY
from .ensemble import ensemble, target_series
from .spec import FigureSpec, Line, Panel, Series, Span
from .style import DARK_GREY, GREY, LIGHT_GREY, MOTION_COLOR, cycle

PERIOD_LABEL = "period T [s]"
#: a panel of the stacked record spectra [in]: three fill an A4 page across its width
A4_PANEL = (7.2, 2.8)
#: spectrum quantity -> (attribute of spectra.Spectrum, panel title, axis label, display kind:
#: display.py gives its unit, mm and mm/s or in and in/s; S_a in g)
SPECTRUM_PANELS = {
    "displacement": ("displacement", "deformation", "deformation S_d", "mm"),
    "pseudo_velocity": ("pseudo_velocity", "pseudo-velocity", "pseudo-velocity S_v", "mm/s"),
    "pseudo_acceleration": ("pseudo_acceleration", "pseudo-acceleration", "pseudo-acceleration S_a", "g"),
}


def spectrum_panel(name: str, units: str = "si") -> tuple[str, str, str, float]:
    """(attribute, panel title, axis label with its display unit, factor from SI) of a
    SPECTRUM_PANELS quantity in the display units (display.py)."""
    attribute, title, label, kind = SPECTRUM_PANELS[name]
    unit = display.unit(kind, units)
    return attribute, title, f"{label} [{unit.label}]", unit.factor


def period_marks(marks: Sequence[tuple[str, float]]) -> list[Line]:
    """Vertical lines at periods (label, T [s]), each in its own grey and style (reference lines:
    no colour of a support or an engine)."""
    looks = ((":", "#000000"), ("--", DARK_GREY), ("-.", GREY))
    return [Line(float(t), f"{label} = {t:.3g} s", "x", style, color)
            for (label, t), (style, color) in zip(marks, looks, strict=False)]


def record_spectrum_figure(spectrum, title: str = "", quantities: Sequence[str] = tuple(SPECTRUM_PANELS),
                           periods_marked: Sequence[tuple[str, float]] = (), units: str = "si") -> FigureSpec:
    """Panels S_d, S_v, S_a of a spectra.Spectrum against log T in the display units (mm, mm/s,
    g; in, in/s, g: display.py), one line per damping (T = 0 left out of the log axis), stacked
    over one shared period axis across the width of an A4 page (as the histories: the
    report prints it on a page of its own, filled); periods_marked: (label, T [s]) drawn as
    vertical lines (e.g. T_1 and T1bar of the deck's building)."""
    periods = np.asarray(spectrum.periods, dtype=float)
    marks = period_marks(periods_marked)
    panels = []
    for name in quantities:
        attribute, heading, label, factor = spectrum_panel(name, units)
        values = np.asarray(getattr(spectrum, attribute)) * factor
        series = [Series(f"damping {100 * xi:g} %", periods, values[k]) for k, xi in enumerate(spectrum.dampings)]
        panels.append(Panel(heading, label, cycle(series), list(marks), ymin=0.0))
    return FigureSpec(f"Response spectra: {title}" if title else "Response spectra", PERIOD_LABEL, panels,
                      xlog=True, columns=1, panel_size=A4_PANEL, sharex=True)


def suite_spectrum_figure(periods: np.ndarray, spectra: np.ndarray, statistic: str, target: np.ndarray | None = None,
                          target_name: str = "target", period_range: tuple[float, float] | None = None,
                          damping: float = 0.05, title: str = "") -> FigureSpec:
    """S_a [g] of each scaled record of a suite (spectra (k, n) [m/s^2] at periods [s]) thin,
    their statistic ("mean", "max") thick, the target S_a [m/s^2] dashed, the period range of
    the code check shaded."""
    g = STANDARD_GRAVITY
    series = ensemble("scaled records", periods, np.asarray(spectra) / g, statistic, DARK_GREY)
    if target is not None:
        series.append(target_series(f"target: {target_name}", periods, np.asarray(target) / g, MOTION_COLOR))
    panel = Panel(f"pseudo-acceleration, damping {100 * damping:g} %", spectrum_panel("pseudo_acceleration")[2],
                  series, spans=_range_spans(period_range), ymin=0.0)
    return FigureSpec(title or "Response spectra of the suite", PERIOD_LABEL, [panel], xlog=True, columns=1,
                      panel_size=(7.0, 4.2))


def _range_spans(period_range: tuple[float, float] | None) -> list[Span]:
    """The period range of the code check, shaded (none without one)."""
    if period_range is None:
        return []
    return [Span(f"period range {period_range[0]:.3g}-{period_range[1]:.3g} s", np.array([period_range], dtype=float),
                 LIGHT_GREY, 0.3)]


def suite_figure(suite, periods: np.ndarray | None = None, title: str = "") -> FigureSpec:
    """suite_spectrum_figure of a motion.suites.Suite (spectra of its scaled records)."""
    low, high = suite.period_range
    if periods is None:
        periods = np.geomspace(min(0.05, 0.5 * low), max(5.0, 1.5 * high), 90)
    lo, hi = suite.target.period_range
    periods = periods[(periods >= lo) & (periods <= hi)] if hi > lo else periods
    return suite_spectrum_figure(periods, suite.spectra(periods), suite.statistic,
                                 suite.target.sa(periods, suite.damping), suite.target.name, suite.period_range,
                                 suite.damping, title or f"{suite.count} records, target {suite.target.name}")
