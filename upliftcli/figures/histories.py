"""Figures of the response-history engines (exact, approximate), from the histories they keep
when asked (ExactOptions(histories=True): result.histories, signals and units in
engines/quantities.HISTORY_SIGNALS) and from their energy balance (details["energy"]):

- history_figure: in the style of the paper's Fig. 5, stacked on one time axis, the base
  shear V_b [14a], the base moment M_b [14b] with +-M_c = m_t g b [16b], the mat rotation
  theta and the vertical displacement of the mat edges (uplift +), with the intervals in
  which an edge is lifted shaded (contact_state); on a foundation with a bearing capacity also
  the settlement of the mat edges (down +, from the rest position under gravity) with the
  plastic settlement of the edge elements (the level each edge comes back to);
- moment_rotation_figure: M_b against theta, with +-M_c (on yielding soil the capacity's, and
  +-M_tip = m_t g b);
- energy_figure: the terms of the energy balance (docs/theory.md section 11.6) as bars.
- hysteresis_figure: with story strengths, the story shear against the story drift of each story
  that yields (docs/theory.md 15.5).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..display import unit as display_unit
from ..engines.result import AnalysisResult
from .spec import Bars, FigureSpec, Line, Panel, Series, Span, spans_of
from .style import ENGINE_LINES, LIFT_COLORS, SUPPORT_COLORS, cycle, scaled_unit

TIME_LABEL = "time t [s]"
#: plotted signal -> (history name, SI unit, axis label with {unit}); forces and moments in
#: kN or MN (kN m or MN m) by their size (style.scaled_unit)
SIGNALS = {
    "base_shear": ("base_shear", "N", "base shear V_b [{unit}]"),
    "base_moment": ("base_moment", "N m", "base moment M_b [{unit}]"),
    "theta": ("theta", "rad", "mat rotation theta [{unit}]"),
    "left_edge": ("left_edge_displacement", "m", "edge displacement, up + [{unit}]"),
    "right_edge": ("right_edge_displacement", "m", "edge displacement, up + [{unit}]"),
    "left_settlement": ("left_edge_settlement", "m", "settlement, down + [{unit}]"),
    "right_settlement": ("right_edge_settlement", "m", "settlement, down + [{unit}]"),
}
_MRAD = (1e3, "mrad")
#: energy terms (energy.energy_balance) in the order of the bars, with their labels
ENERGY_TERMS = {
    "input": "input work",
    "structural_damping": "structural damping",
    "foundation_damping": "foundation damping",
    "kinetic": "kinetic (change)",
    "strain": "strain (change)",
    "foundation_elastic": "foundation elastic (change)",
    "gravity": "gravity (change)",
    "residual": "residual",
}


def with_histories(results: Sequence[AnalysisResult]) -> list[AnalysisResult]:
    """The results that carry response histories."""
    return [r for r in results if r.histories]


def unit_of(results: Sequence[AnalysisResult], name: str, units: str = "si") -> tuple[float, str]:
    """(factor from SI, unit) of a plotted signal over these results: mrad, the display unit of
    a small length (mm or in, display.py), forces and moments by their size (style.scaled_unit)."""
    key, si, _ = SIGNALS[name]
    if si == "rad":
        return _MRAD
    if si == "m":
        shown = display_unit("mm", units)
        return shown.factor, shown.label
    return scaled_unit(_largest(results, key), si, units)


def _largest(results: Sequence[AnalysisResult], key: str) -> float:
    """The largest |value| of a history over the results (0 where none records it)."""
    return max((float(np.max(np.abs(r.histories[key]))) for r in results
                if key in r.histories and len(r.histories[key])), default=0.0)


def axis_label(results: Sequence[AnalysisResult], name: str, units: str = "si") -> str:
    return SIGNALS[name][2].format(unit=unit_of(results, name, units)[1])


def signal(result: AnalysisResult, name: str, factor: float = 1.0) -> tuple[np.ndarray, np.ndarray] | None:
    """(time [s], signal times factor) of SIGNALS[name] from SI, or None if not recorded."""
    histories = result.histories
    key = SIGNALS[name][0]
    if key not in histories:
        return None
    return np.asarray(histories["time"], dtype=float), np.asarray(histories[key], dtype=float) * factor


def lifted(result: AnalysisResult) -> dict[str, np.ndarray]:
    """Per edge ("left", "right"), whether it is lifted at each sample: bit i of
    contact_state is element i lifted (element 0 at the left edge, the last at the right)."""
    count = result.element_positions.size
    if "contact_state" not in result.histories or count == 0:
        return {}
    state = np.asarray(result.histories["contact_state"])
    return {"left": _bit(state, 0), "right": _bit(state, count - 1)}


def _bit(state: np.ndarray, i: int) -> np.ndarray:
    """Bit i of each contact state (a Python int where more elements than an int64 holds)."""
    if state.dtype == object:
        return np.array([(int(s) >> i) & 1 for s in state], dtype=bool)
    return ((state.astype(np.int64) >> i) & 1).astype(bool)


def lift_spans(results: Sequence[AnalysisResult]) -> list[Span]:
    """Shaded intervals in which the left or the right edge of the mat is lifted."""
    lifting = [r for r in results if _lifts(r)]
    return [span for result in lifting for span in _result_spans(result, results, len(lifting) > 1)]


def _lifts(result: AnalysisResult) -> bool:
    """Whether an edge of the mat lifts at some sample."""
    return any(mask.any() for mask in lifted(result).values())


def _result_spans(result: AnalysisResult, results: Sequence[AnalysisResult], named: bool) -> list[Span]:
    """The lifted intervals of each edge of one result (named: labelled with the result)."""
    times = np.asarray(result.histories["time"], dtype=float)
    prefix = f"{_label(result, results)}: " if named else ""
    return [Span(f"{prefix}{edge} edge lifted", spans_of(times, mask), LIFT_COLORS[edge])
            for edge, mask in lifted(result).items()]


def _label(result: AnalysisResult, results: Sequence[AnalysisResult]) -> str:
    return f"{result.engine}, {result.support}" if len({r.engine for r in results}) > 1 else result.support


def _line(result: AnalysisResult, results, name: str, suffix: str = "", style: str | None = None,
          units: str = "si") -> Series | None:
    found = signal(result, name, unit_of(results, name, units)[0])
    if found is None:
        return None
    return Series(_label(result, results) + suffix, found[0], found[1], style or ENGINE_LINES.get(result.engine, "-"),
                  SUPPORT_COLORS.get(result.support), 1.0)


def _signal_lines(result: AnalysisResult, results: Sequence[AnalysisResult],
                  names: Sequence[tuple[str, str, str | None]], units: str) -> list[Series]:
    """The recorded signals of a result: names (signal, label suffix, line style) in turn."""
    return [s for name, suffix, style in names if (s := _line(result, results, name, suffix, style, units)) is not None]


#: the edge displacements and settlements: (signal, label suffix, line style)
EDGES = (("left_edge", ", left edge", "-"), ("right_edge", ", right edge", "--"))
SETTLEMENTS = (("left_settlement", ", left edge", "-"), ("right_settlement", ", right edge", "--"))


def _settlements(result: AnalysisResult, results, units: str = "si") -> list[Series]:
    """The settlement of the left and right edge of the mat (down +) and the plastic settlement
    -s_i of its first and last element (histories plastic_settlement_<element>), the level to
    which each edge comes back (docs/theory.md 14.1)."""
    return _signal_lines(result, results, SETTLEMENTS, units) + _plastic_settlements(result, results, units)


def _plastic_settlements(result: AnalysisResult, results, units: str) -> list[Series]:
    """The plastic settlement of the first and last element of the mat (down +)."""
    factor = unit_of(results, "left_settlement", units)[0]
    time = np.asarray(result.histories["time"], dtype=float)
    count = result.element_positions.size
    return [Series(_label(result, results) + suffix, time, np.asarray(result.histories[key], dtype=float) * factor,
                   style, SUPPORT_COLORS.get(result.support), 1.0)
            for key, suffix, style in (("plastic_settlement_1", ", left element, plastic", ":"),
                                       (f"plastic_settlement_{count}", ", right element, plastic", "-."))
            if key in result.histories]


def critical_lines(results: Sequence[AnalysisResult], units: str = "si") -> list[Line]:
    """+-M_c = m_t g b [16b] in the unit of the base moment axis; on a foundation with a bearing
    capacity (a result that states the elastic tipping moment M_tip) M_c is the capacity's
    (docs/theory.md 14.4: the moment the yielding toe caps) and +-M_tip = m_t g b is drawn too."""
    if not results:
        return []
    factor, unit = unit_of(results, "base_moment", units)
    m_c = factor * results[0].critical_base_moment
    tip = _tipping_moment(results)
    if tip is None:
        return [Line(m_c, f"\u00b1M_c = m_t g b = {m_c:.4g} {unit} [16b]"), Line(-m_c)]
    return _capacity_lines(m_c, tip * factor, unit)


def _tipping_moment(results: Sequence[AnalysisResult]) -> float | None:
    """The elastic tipping moment M_tip [N m] of the first result that states it (yielding soil), or None."""
    return next((r.intermediates["M_tip"] for r in results if "M_tip" in r.intermediates), None)


def _capacity_lines(m_c: float, tip: float, unit: str) -> list[Line]:
    """+-M_c, the moment capacity on yielding soil, and +-M_tip = m_t g b (plotted units)."""
    return [Line(m_c, f"\u00b1M_c = {m_c:.4g} {unit}, the moment capacity on yielding soil (ASCE 41-17 8.4, "
                 "docs/theory.md 14.4)", color="#b22222"), Line(-m_c, color="#b22222"),
            Line(tip, f"\u00b1M_tip = m_t g b = {tip:.4g} {unit} [16b]", style="--", color="#777777"),
            Line(-tip, style="--", color="#777777")]


#: the signal panels of the histories: (signal, panel title)
SIGNAL_PANELS = (("base_shear", "base shear"), ("base_moment", "base overturning moment"),
                 ("theta", "rotation of the mat"))


def history_figure(results: Sequence[AnalysisResult], title: str = "", units: str = "si") -> FigureSpec:
    """Base shear, base moment (+-M_c), mat rotation and edge displacements against time (the
    last two for the flexible supports), every result with histories overlaid, the intervals
    with an edge lifted shaded in every panel."""
    results = with_histories(results)
    spans = lift_spans(results)
    panels = [_signal_panel(results, name, heading, spans, units) for name, heading in SIGNAL_PANELS]
    panels += [_edge_panel(results, spans, units), _settlement_panel(results, spans, units)]
    return FigureSpec(title or "Response histories", TIME_LABEL, [p for p in panels if p is not None], columns=1,
                      panel_size=(7.2, 1.8), sharex=True)


def _signal_panel(results: Sequence[AnalysisResult], name: str, heading: str, spans: list[Span], units: str
                  ) -> Panel | None:
    """A signal of every result (the base moment with +-M_c), or None where none records it."""
    series = [s for r in results if (s := _line(r, results, name, units=units)) is not None]
    if not series:
        return None
    lines = critical_lines(results, units) if name == "base_moment" else []
    return Panel(heading, axis_label(results, name, units), cycle(series), lines, spans)


def _edge_panel(results: Sequence[AnalysisResult], spans: list[Span], units: str) -> Panel | None:
    """The vertical displacement of the mat edges (uplift +), or None where none records it."""
    edges = [s for r in results for s in _signal_lines(r, results, EDGES, units)]
    if not edges:
        return None
    return Panel("vertical displacement of the mat edges (uplift)", axis_label(results, "left_edge", units),
                 cycle(edges), [Line(0.0, "", "y", "-", "#999999")], spans)


def _settlement_panel(results: Sequence[AnalysisResult], spans: list[Span], units: str) -> Panel | None:
    """The settlement of the mat edges and their elements' plastic settlement on yielding soil, or None."""
    settling = [s for r in results if "plastic_settlement_1" in r.histories for s in _settlements(r, results, units)]
    if not settling:
        return None
    return Panel("settlement of the mat edges (yielding soil)", axis_label(results, "left_settlement", units),
                 cycle(settling), [Line(0.0, "", "y", "-", "#999999")], spans)


def moment_rotation_figure(results: Sequence[AnalysisResult], title: str = "", units: str = "si") -> FigureSpec:
    """Base moment M_b against the mat rotation theta of the flexible supports, with +-M_c."""
    results = [r for r in with_histories(results) if "theta" in r.histories]
    moment_factor, _ = unit_of(results, "base_moment", units)
    series = [_moment_rotation(result, results, moment_factor) for result in results]
    panel = Panel("", axis_label(results, "base_moment", units), cycle(series), critical_lines(results, units),
                  xlabel=axis_label(results, "theta"))
    return FigureSpec(title or "Base moment against mat rotation", "", [panel], columns=1, panel_size=(5.0, 3.0))


def _moment_rotation(result: AnalysisResult, results: Sequence[AnalysisResult], moment_factor: float) -> Series:
    """Base moment against mat rotation [mrad] of one result."""
    _, theta = signal(result, "theta", _MRAD[0])
    _, moment = signal(result, "base_moment", moment_factor)
    return Series(_label(result, results), theta, moment, ENGINE_LINES.get(result.engine, "-"),
                  SUPPORT_COLORS.get(result.support), 0.8)


def energy_figure(results: Sequence[AnalysisResult], title: str = "", units: str = "si") -> FigureSpec:
    """The energy balance of each history result (input work = dissipated + change of stored
    energy + residual) as grouped bars [kJ or MJ; kip ft]."""
    results = [r for r in results if "energy" in r.details]
    largest = max((abs(float(r.details["energy"].get("input", 0.0))) for r in results), default=0.0)
    factor, unit = scaled_unit(largest, "J", units)
    bars = [_energy_bars(result, results, factor) for result in results]
    panel = Panel(f"residual / input: {_residuals(results)}", "", bars=bars, xlabel=f"energy [{unit}]",
                  lines=[Line(0.0, "", "x", "-", "#999999")])
    return FigureSpec(title or "Energy balance", "", [panel], columns=1, panel_size=(5.0, 2.6), left=2.3)


def _residuals(results: Sequence[AnalysisResult]) -> str:
    """Each result's residual of its energy balance relative to the input work."""
    return ", ".join(f"{_label(r, results)} {r.details['energy'].get('relative_residual', np.nan):.1e}"
                     for r in results)


def _energy_bars(result: AnalysisResult, results: Sequence[AnalysisResult], factor: float) -> Bars:
    """The terms of one result's energy balance it gives (ENERGY_TERMS), times factor."""
    energy = result.details["energy"]
    terms = [k for k in ENERGY_TERMS if k in energy]
    values = np.array([factor * energy[k] for k in terms])
    return Bars(_label(result, results), [ENERGY_TERMS[k] for k in terms], values, SUPPORT_COLORS.get(result.support))


def yielding_stories(result: AnalysisResult) -> list[int]:
    """The stories (from 1) of a result that yielded (quantities.YIELDING's story_yielded) whose shear and drift
    histories it keeps (shear_<story>, drift_<story>: docs/theory.md 15.5)."""
    stories = (np.flatnonzero(np.asarray(result.peaks.get("story_yielded", ()), dtype=float) > 0.0) + 1).tolist()
    return [j for j in stories if f"shear_{j}" in result.histories and f"drift_{j}" in result.histories]


def hysteresis_figure(results: Sequence[AnalysisResult], title: str = "", units: str = "si") -> FigureSpec:
    """Story shear against story drift of each story that yields (a panel per story, lowest first), every result
    whose story yielded overlaid: the hysteresis of the bilinear story springs (docs/theory.md 15)."""
    results = [r for r in with_histories(results) if yielding_stories(r)]
    stories = _yielded_stories(results)
    shear = scaled_unit(max((_largest(results, f"shear_{j}") for j in stories), default=0.0), "N", units)
    panels = [_hysteresis_panel(results, j, shear, units) for j in stories]
    return FigureSpec(title or "Story shear against story drift", "", panels, columns=min(3, max(len(panels), 1)),
                      panel_size=(4.0, 3.0))


def _yielded_stories(results: Sequence[AnalysisResult]) -> list[int]:
    """The stories (from 1, lowest first) that yield in some result (yielding_stories)."""
    return sorted({j for r in results for j in yielding_stories(r)})


def _hysteresis_panel(results: Sequence[AnalysisResult], story: int, shear: tuple[float, str], units: str) -> Panel:
    """Story `story`'s shear [shear's unit] against its drift [mm or in] of each result in which it yielded."""
    drift = display_unit("mm", units)
    series = [Series(_label(r, results), np.asarray(r.histories[f"drift_{story}"], dtype=float) * drift.factor,
                     np.asarray(r.histories[f"shear_{story}"], dtype=float) * shear[0],
                     ENGINE_LINES.get(r.engine, "-"), SUPPORT_COLORS.get(r.support), 0.8)
              for r in results if story in yielding_stories(r)]
    return Panel(f"story {story}", f"story shear V_{story} [{shear[1]}]", cycle(series),
                 [Line(0.0, "", "y", "-", "#999999")], xlabel=f"story drift [{drift.label}]")
