"""The figures of a run (`uplift analyze --plot`, `uplift modes --plot`, `uplift report`): figure
name -> FigureSpec, from a deck and its results (nothing drawn, nothing written here)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..engines.result import AnalysisResult
from .analysis import profile_figure, suite_profile_figure
from .histories import (
    energy_figure,
    history_figure,
    hysteresis_figure,
    moment_rotation_figure,
    with_histories,
    yielding_stories,
)
from .modes import mode_shape_figure
from .spec import FigureSpec, Panel, Series
from .spectra import PERIOD_LABEL, period_marks, record_spectrum_figure, spectrum_panel, suite_figure
from .style import MOTION_COLOR

SPECTRUM_PERIODS = np.geomspace(0.05, 5.0, 90)  # s


def motion_label(deck) -> str:
    """The deck's ground motion in words: 'record <name>', 'suite of <n> records, target
    <name>' or 'design spectrum <name>' ('' when none is loaded)."""
    from ..motion.records import Record
    from ..motion.suites import Suite

    motion = deck.ground_motion
    if isinstance(motion, Record):
        return f"record {motion.name}"
    if isinstance(motion, Suite):
        return f"suite of {motion.count} records, target {motion.target.name}"
    if motion is not None and hasattr(motion, "name"):
        return f"design spectrum {motion.name}"
    return ""


def _title(deck, what: str) -> str:
    motion = motion_label(deck)
    return f"{what}: {deck.title}" + (f", {motion}" if motion else "")


def modes_figures(deck, units: str = "si") -> dict[str, FigureSpec]:
    """{"modes": the mode shapes of the deck's building}."""
    return {"modes": mode_shape_figure(deck.system, title=f"Fixed-base mode shapes: {deck.title}", units=units)}


def spectrum_figure(deck, results: Sequence[AnalysisResult] = (), units: str = "si") -> FigureSpec | None:
    """The ground motion's spectra at the building's damping, with T_1 (and T1bar when an
    engine reports it) marked: a record's S_d, S_v, S_a; a suite's scaled records, their
    statistic and the target; a design spectrum's S_a. None without a ground motion."""
    from ..motion.records import Record
    from ..motion.suites import Suite

    motion = deck.ground_motion
    if isinstance(motion, Record):
        return _record_spectra(deck, motion, _marks(deck, results), units)
    if isinstance(motion, Suite):
        return suite_figure(motion, title=_title(deck, "Response spectra of the suite"))
    if motion is None or not hasattr(motion, "sa"):
        return None
    return _design_spectrum(deck, motion, _marks(deck, results), units)


def _marks(deck, results: Sequence[AnalysisResult]) -> list[tuple[str, float]]:
    """(label, T [s]) of the periods marked: T_1, and T1bar when an engine reports it."""
    marks = [("T_1", float(deck.system.modes.periods[0]))]
    t1bar = next((r.intermediates["T1bar"] for r in results if "T1bar" in r.intermediates), None)
    if t1bar is not None:
        marks.append(("T1bar", float(t1bar)))
    return marks


def _record_spectra(deck, motion, marks: list[tuple[str, float]], units: str) -> FigureSpec:
    """A record's S_d, S_v and S_a at the building's damping and at 5 %."""
    from ..motion.spectra import response_spectrum

    dampings = sorted({float(deck.system.building.damping[0]), 0.05})
    spectrum = response_spectrum(motion.acceleration, motion.dt, SPECTRUM_PERIODS, dampings)
    return record_spectrum_figure(spectrum, f"{motion.name} ({deck.title})", periods_marked=marks, units=units)


def _design_spectrum(deck, motion, marks: list[tuple[str, float]], units: str) -> FigureSpec:
    """A design spectrum's S_a at the building's damping over its period range (of SPECTRUM_PERIODS)."""
    xi = float(deck.system.building.damping[0])
    grid = SPECTRUM_PERIODS
    low, high = getattr(motion, "period_range", (grid[0], grid[-1]))
    periods = grid[(grid >= low) & (grid <= high)]
    _, heading, label, factor = spectrum_panel("pseudo_acceleration", units)
    line = Series(f"{motion.name}, damping {100 * xi:g} %", periods, factor * np.asarray(motion.sa(periods, xi)),
                  "-", MOTION_COLOR)
    return FigureSpec(f"Design spectrum: {motion.name}", PERIOD_LABEL,
                      [Panel(heading, label, [line], period_marks(marks), ymin=0.0)], xlog=True, columns=1,
                      panel_size=(6.0, 3.8))


def suite_results(results: Sequence[AnalysisResult]) -> list:
    """The results of a record suite (engines/suite_result.SuiteResult: each record's result
    kept)."""
    return [r for r in results if getattr(r, "record_results", ())]


def profiles(deck, results: Sequence[AnalysisResult], units: str = "si") -> FigureSpec:
    """The story profiles of a run; on a record suite each record thin, the design statistic
    thick and the simplified engine on the target spectrum dashed (the run's, else the one
    each suite result carries)."""
    title = _title(deck, "Peak response over the height")
    suites = suite_results(results)
    if not suites:
        return profile_figure(results, deck.criteria, title, units)
    records = [record for result in suites for record in result.record_results]
    return suite_profile_figure(records, suites[0].statistic, _targets(results, suites), deck.criteria, title, units)


def _targets(results: Sequence[AnalysisResult], suites: list) -> list[AnalysisResult]:
    """The results on the target spectrum: the run's single analyses, then the simplified
    engine's each suite result carries for a support the run has none of."""
    target = [r for r in results if not getattr(r, "record_results", ())]
    supports = {r.support for r in target}
    return target + [simplified for simplified in _carried_simplified(suites) if simplified.support not in supports]


def _carried_simplified(suites: list) -> list[AnalysisResult]:
    """The simplified engine's results on the target spectrum the suite results carry."""
    return [r.simplified for r in suites if getattr(r, "simplified", None) is not None]


def analysis_figures(deck, results: Sequence[AnalysisResult], units: str = "si") -> dict[str, FigureSpec]:
    """Story profiles, mode shapes, the ground motion's spectra and, per history engine (of a
    single record), histories (paper Fig. 5 style), base moment against mat rotation and
    energy balance, in the display units (display.py)."""
    figures = {"profiles": profiles(deck, results, units)}
    figures.update(modes_figures(deck, units))
    spectrum = spectrum_figure(deck, results, units)
    if spectrum is not None:
        figures["spectrum"] = spectrum
    for engine in dict.fromkeys(r.engine for r in with_histories(results)):
        figures.update(_engine_figures(deck, [r for r in with_histories(results) if r.engine == engine], engine,
                                       units))
    return figures


def _engine_figures(deck, mine: Sequence[AnalysisResult], engine: str, units: str = "si") -> dict[str, FigureSpec]:
    """The figures of one history engine's results: histories and, where they give them, base
    moment against mat rotation and the energy balance."""
    figures = {f"histories_{engine}": history_figure(mine, _title(deck, f"Response histories, {engine} engine"),
                                                     units)}
    if any("theta" in r.histories for r in mine):
        figures[f"moment_rotation_{engine}"] = moment_rotation_figure(
            mine, _title(deck, f"Base moment against mat rotation, {engine} engine"), units)
    if any(yielding_stories(r) for r in mine):
        figures[f"hysteresis_{engine}"] = hysteresis_figure(
            mine, _title(deck, f"Story shear against story drift, {engine} engine"), units)
    if any("energy" in r.details for r in mine):
        figures[f"energy_{engine}"] = energy_figure(mine, _title(deck, f"Energy balance, {engine} engine"), units)
    return figures
