"""Story profiles of peak response (`uplift analyze --plot`): floor displacement, story drift
ratio (with the deck's [criteria] limit), story shear, overturning moment and floor
acceleration against the elevation, every engine and support overlaid (support: colour,
engine: line style); a record suite as its records thin, their statistic thick and the
result on the target spectrum dashed.

Pure functions of engines/result.AnalysisResult; the values are those of result.peaks in
the display units (display.py) of engines/quantities.py, SI (the default) or US.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..display import unit as display_unit
from ..engines.quantities import QUANTITIES, STORY
from ..engines.result import AnalysisResult
from .ensemble import ensemble, target_series
from .spec import FigureSpec, Line, Panel, Series
from .style import ENGINE_LINES, SUPPORT_COLORS, cycle, scaled_unit

#: the quantities of the profile figure and their panel titles
PROFILES = {
    "displacement": "peak floor displacement",
    "drift_ratio": "peak story drift ratio",
    "shear": "peak story shear",
    "moment": "peak overturning moment",
    "floor_acceleration": "peak floor acceleration",
}
ELEVATION_LABEL = "elevation above the mat [m]"
#: panels a row of the profile figure: five panels print on A4 with text of 7 pt at least
COLUMNS = 3


def elevation_label(units: str = "si") -> str:
    """'elevation above the mat [m]' ([ft] in US units)."""
    return f"elevation above the mat [{display_unit('m', units).label}]"


def profile_xy(name: str, values: np.ndarray, elevations: np.ndarray, factor: float | None = None,
               elevation_factor: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) of a profile of a quantity's peaks (SI, one per floor or story) times factor
    (default: to its SI display unit) against the elevation [m] times elevation_factor: a story
    quantity constant over each story (a step, every value twice); the moment at the bottom of
    each story, zero at the roof; the displacement relative to the mat, zero at the mat; the
    floor acceleration at the floors."""
    quantity = QUANTITIES[name]
    values = np.asarray(values, dtype=float) * (display_unit(quantity.display).factor if factor is None else factor)
    levels = np.concatenate(([0.0], np.asarray(elevations, dtype=float))) * elevation_factor
    if name == "moment":
        return np.append(values, 0.0), levels
    if quantity.where == STORY:
        return np.repeat(values, 2), np.repeat(levels, 2)[1:-1]
    if name == "displacement":
        return np.concatenate(([0.0], values)), levels
    return values, levels[1:]  # FLOOR


def plotted_unit(name: str, results: Sequence[AnalysisResult], units: str = "si") -> tuple[float, str]:
    """(factor from SI, unit) of a profile: the display unit (display.py), except for forces
    and moments in SI, in kN or MN (kN m or MN m) by the size of the largest peak."""
    quantity = QUANTITIES[name]
    if quantity.unit in ("N", "N m"):
        return scaled_unit(_largest_peak(name, results), quantity.unit, units)
    shown = display_unit(quantity.display, units)
    return shown.factor, shown.label


def _largest_peak(name: str, results: Sequence[AnalysisResult]) -> float:
    """The largest |peak| of a quantity over the results (0 without one)."""
    return max((float(np.max(np.abs(r.peaks[name]))) for r in results if r.peaks.get(name) is not None
                and r.peaks[name].size), default=0.0)


def limit_lines(name: str, criteria: Mapping[str, float] | None, factor: float, unit: str) -> list[Line]:
    """The deck's [criteria] limit of the quantity (SI) as a vertical line (times factor, in unit)."""
    if not criteria or name not in criteria:
        return []
    value = float(criteria[name]) * factor
    return [Line(value, f"[criteria] limit {name.replace('_', ' ')} = {value:g} {unit}", "x", ":", "black")]


def _label(result: AnalysisResult, engines: set[str]) -> str:
    return f"{result.engine}, {result.support}" if len(engines) > 1 else result.support


def profile_figure(results: Sequence[AnalysisResult], criteria: Mapping[str, float] | None = None,
                   title: str = "", units: str = "si") -> FigureSpec:
    """One line per result (engine and support) in each panel of PROFILES the results give."""
    engines = {r.engine for r in results}
    groups = [(_label(r, engines), r.support, r.engine, [r]) for r in results]
    return _figure(groups, [], criteria, title, "mean", units)


def suite_profile_figure(records: Sequence[AnalysisResult], statistic: str = "mean",
                         target: Sequence[AnalysisResult] = (), criteria: Mapping[str, float] | None = None,
                         title: str = "", units: str = "si") -> FigureSpec:
    """A suite: the results of each record (grouped by engine and support) thin, their
    statistic ("mean", "max", "median" per floor or story) thick, the results on the target
    spectrum (e.g. the simplified engine's) dashed."""
    engines = {r.engine for r in [*records, *target]}
    groups = [(_label(members[0], engines), support, engine, members)
              for (engine, support), members in _by_analysis(records).items()]
    return _figure(groups, list(target), criteria, title, statistic, units)


def _by_analysis(records: Sequence[AnalysisResult]) -> dict[tuple[str, str], list[AnalysisResult]]:
    """The results grouped by (engine, support), in the order first met."""
    grouped: dict[tuple[str, str], list[AnalysisResult]] = {}
    for result in records:
        grouped.setdefault((result.engine, result.support), []).append(result)
    return grouped


def _figure(groups, target: list[AnalysisResult], criteria, title: str, statistic: str, units: str = "si"
            ) -> FigureSpec:
    """The profile figure of groups (label, support, engine, members: one result, or a suite's
    records drawn as an ensemble) and the results on the target spectrum."""
    everything = _everything(groups, target)
    panels = [_profile_panel(name, groups, target, criteria, statistic, units)
              for name in PROFILES if any(name in r.peaks for r in everything)]
    return FigureSpec(title or "Peak response over the height", "", panels, columns=min(len(panels), COLUMNS) or 1,
                      panel_size=(2.3, 3.0), sharey=True)


def _everything(groups, target: list[AnalysisResult]) -> list[AnalysisResult]:
    """Every result of the groups, then those on the target spectrum."""
    return [r for *_, members in groups for r in members] + target


def _profile_panel(name: str, groups, target: list[AnalysisResult], criteria, statistic: str, units: str) -> Panel:
    """The panel of one quantity: each group's line (or ensemble), the target's lines, the [criteria] limit."""
    everything = _everything(groups, target)
    factor, unit = plotted_unit(name, everything, units)
    level = display_unit("m", units).factor
    series = [s for group in groups for s in _group_series(name, group, factor, level, statistic)]
    series += [_target_line(name, r, {r.engine for r in everything}, factor, level) for r in target
               if name in r.peaks]
    return Panel(PROFILES[name], elevation_label(units), cycle(series), limit_lines(name, criteria, factor, unit),
                 xlabel=f"{PROFILES[name]} [{unit}]", xmin=0.0, ymin=0.0)


def _group_series(name: str, group, factor: float, level: float, statistic: str) -> list[Series]:
    """A group's profile of a quantity: one line for one result, an ensemble (each thin, the
    statistic thick) for several; none when no member gives the quantity."""
    label, support, engine, members = group
    profiles = _profiles(name, members, factor, level)
    if not profiles:
        return []
    color, style = SUPPORT_COLORS.get(support), ENGINE_LINES.get(engine, "-")
    if len(profiles) == 1:
        x, y = profiles[0]
        return [Series(label, x, y, style, color)]
    return ensemble(label, profiles[0][1], np.array([x for x, _ in profiles]), statistic, color, style, profile=True)


def _profiles(name: str, members: Sequence[AnalysisResult], factor: float, level: float
              ) -> list[tuple[np.ndarray, np.ndarray]]:
    """profile_xy of a quantity of each result that gives it."""
    return [profile_xy(name, r.peaks[name], r.elevations, factor, level) for r in members if name in r.peaks]


def _target_line(name: str, result: AnalysisResult, engines: set[str], factor: float, level: float) -> Series:
    """A result on the target spectrum, dashed."""
    x, y = profile_xy(name, result.peaks[name], result.elevations, factor, level)
    return target_series(f"{_label(result, engines)}: target spectrum", x, y,
                         SUPPORT_COLORS.get(result.support, "black"))
