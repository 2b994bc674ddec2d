"""Terminal tables (rich) for modes and analysis results. Falls back to plain text when
there is no terminal (CI=true, pipes): rich handles that itself."""

from __future__ import annotations

import numpy as np
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from ..engines.quantities import ELEMENT, FLOOR, INTERMEDIATES, QUANTITIES, STORY, quantities
from ..engines.result import AnalysisResult
from ..engines.suite_result import SuiteResult
from ..model.system import System

#: floor and story quantities in table order
STORY_QUANTITIES = [q for q in QUANTITIES.values() if q.where in (FLOOR, STORY)]


def console(stderr: bool = False) -> Console:
    """A console that never needs a terminal (width 120 when output is not a terminal)."""
    probe = Console(stderr=stderr)
    return Console(stderr=stderr, width=None if probe.is_terminal else 120, highlight=False)


def modes_table(system: System, n_modes: int | None = None) -> Table:
    """Periods, w_n/w_1, m_n*/m_t (and cumulative), h_n* and h_n*/b (THEORY.md sections 5, 6)."""
    modes = system.modes
    n = n_modes or modes.n_modes
    m_t = system.total_mass
    cumulative = np.cumsum(modes.effective_mass) / m_t
    table = Table(title=escape(f"Fixed-base modes (m_t = {m_t:.6g} kg, b = {system.half_width:.4g} m)"))
    for header in ("mode", "T_n [s]", "w_n/w_1", "m_n*/m_t", "cumulative", "h_n* [m]", "h_n*/b"):
        table.add_column(escape(header), justify="right")
    if system.mat_mass > 0.0:
        table.caption = escape(f"m_t includes the mat mass m_0 = {system.mat_mass:.6g} kg: the m_n* add up to "
                               f"the building mass, {1 - system.mat_mass / m_t:.4f} m_t")
    for i in range(n):
        table.add_row(str(i + 1), f"{modes.periods[i]:.4f}", f"{modes.omega[i] / modes.omega[0]:.3f}",
                      f"{modes.effective_mass[i] / m_t:.4f}", f"{cumulative[i]:.4f}",
                      f"{modes.effective_height[i]:.3f}", f"{modes.effective_height[i] / system.half_width:.3f}")
    return table


def story_table(result: AnalysisResult) -> Table:
    """Per story (top first): elevation and the peak of every floor and story quantity the
    engine gives (engines/quantities.py), in the display units."""
    title = f"{result.engine} engine, {result.support} support"
    if isinstance(result, SuiteResult):
        title += f": {result.statistic} of {result.count} records ({result.rule_label})"
    table = Table(title=escape(title))
    shown = [q for q in STORY_QUANTITIES if q.name in result.peaks]
    for header in ["story", "elevation [m]"] + [q.heading for q in shown]:
        table.add_column(escape(header), justify="right")
    for j in range(result.elevations.size - 1, -1, -1):
        table.add_row(str(j + 1), f"{result.elevations[j]:.2f}",
                      *[_display(q, result.peaks[q.name][j]) for q in shown])
    return table


def elements_table(result: AnalysisResult) -> Table | None:
    """Per foundation contact element (left to right): position and its peak reactions."""
    shown = [q for q in quantities(ELEMENT) if q.name in result.peaks and result.peaks[q.name].size]
    if not shown:
        return None
    table = Table(title=escape(f"Foundation elements ({engine_label(result)}, {result.support}): largest compression"))
    for header in ["element", "position x [m]"] + [q.heading for q in shown]:
        table.add_column(escape(header), justify="right")
    for i, x in enumerate(result.element_positions):
        table.add_row(str(i + 1), f"{x:.3f}", *[_display(q, result.peaks[q.name][i]) for q in shown])
    return table


def _display(quantity, value: float) -> str:
    """A peak in the display unit and format of its quantity ('-' when there is none)."""
    unit, factor, spec = quantity.display
    return format(value * factor, spec) if np.isfinite(value) else "-"


def summary_table(results: list[AnalysisResult]) -> Table:
    """One row per result: base shear and moment, coefficients, critical values, uplift."""
    table = Table(title="Summary")
    for header in ("engine", "support", "V_b [kN]", "V_b/(m_t g)", "M_b [kN m]", "M_b/(m_t g h_1*)",
                   "V_c [kN]", "M_c [kN m]", "b/h_1*", "uplift"):
        table.add_column(escape(header), justify="right")
    for r in results:
        table.add_row(escape(engine_label(r)), r.support, f"{1e-3 * r.base_shear:.1f}",
                      f"{r.base_shear_coefficient:.4f}", f"{1e-3 * r.base_moment:.1f}",
                      f"{r.base_moment_coefficient:.4f}",
                      f"{1e-3 * r.critical_base_shear:.1f}", f"{1e-3 * r.critical_base_moment:.1f}",
                      f"{r.critical_coefficient:.4f}", "yes" if r.uplift else "no")
    return table


def engine_label(result: AnalysisResult) -> str:
    """The engine, and for a suite's result its design statistic ('exact, mean of 11 records')."""
    return result.label if isinstance(result, SuiteResult) else result.engine


def _format(value) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (list, tuple, np.ndarray)):
        return ", ".join(_format(v) for v in value)
    if isinstance(value, (int, float, np.floating)):
        return f"{float(value):.5g}"
    return str(value)


MODAL_LISTS = ("T_n", "Sa_n", "m_n*/m_t", "h_n*", "V_n")


def modal_table(result: AnalysisResult) -> Table:
    """Per-mode intermediates: T_n, S_a(T_n, xi_n), m_n*/m_t, h_n*, V_n."""
    inter = result.intermediates
    table = Table(title=escape(f"Modal base shears ({result.engine}, {result.support}); "
                               "mode 1 of bonded/uplift uses T1bar, xi1bar"))
    for header in ("mode", "T_n [s]", "S_a(T_n) [m/s^2]", "m_n*/m_t", "h_n* [m]", "V_n [kN]"):
        table.add_column(escape(header), justify="right")
    for i, period in enumerate(inter["T_n"]):
        table.add_row(str(i + 1), f"{period:.4f}", f"{inter['Sa_n'][i]:.4f}", f"{inter['m_n*/m_t'][i]:.4f}",
                      f"{inter['h_n*'][i]:.3f}", f"{1e-3 * inter['V_n'][i]:.1f}")
    return table


def intermediates_table(result: AnalysisResult) -> Table:
    """Scalar intermediates with unit and meaning (engines/quantities.INTERMEDIATES)."""
    table = Table(title=escape(f"Intermediate values ({engine_label(result)}, {result.support})"))
    for header in ("quantity", "value", "unit", "meaning"):
        table.add_column(escape(header), justify="left")
    for name, value in result.intermediates.items():
        if name in MODAL_LISTS:
            continue
        unit, meaning = INTERMEDIATES.get(name, ("", ""))
        table.add_row(escape(name), _format(value), escape(unit), escape(meaning))
    return table


def print_results(out: Console, results: list[AnalysisResult], title: str | None = None) -> None:
    """Every table of every result, then the summary (a suite's result: its statistics and its
    records too, and the simplified engine beside it: cli/render_suite.py)."""
    from . import render_suite

    if title:
        out.print(f"[bold]{escape(title)}[/bold]")
    for result in results:
        out.print(story_table(result))
        elements = elements_table(result)
        if elements is not None:
            out.print(elements)
        if all(name in result.intermediates for name in MODAL_LISTS):
            out.print(modal_table(result))
        if result.intermediates:
            out.print(intermediates_table(result))
        if isinstance(result, SuiteResult):
            out.print(render_suite.statistics_table(result))
            out.print(render_suite.records_table(result))
    out.print(summary_table(results))
    comparison = render_suite.comparison_table(results)
    if comparison is not None:
        out.print(comparison)
    checked = accuracy_table(results)
    if checked is not None:
        out.print(checked)


def accuracy_table(results: list[AnalysisResult]) -> Table | None:
    """The simplified engine against the exact engine, per support (accuracy.py), or None."""
    from ..accuracy import CHECKED

    checks = [r.details["accuracy"] for r in results if "accuracy" in r.details]
    if not checks:
        return None
    table = Table(title="Accuracy check: the simplified engine against the exact engine, same deck and record")
    table.caption = escape("ratio = simplified / exact; the measured spread of these ratios: docs/accuracy.md; "
                           "--no-check skips this check")
    for header in ("support", "quantity", "simplified", "exact", "ratio"):
        table.add_column(escape(header), justify="left" if header in ("support", "quantity") else "right")
    for check in checks:
        if "error" in check:
            table.add_row(check["support"], "-", "-", "-", escape(f"exact engine failed: {check['error']}"))
            continue
        for name, (unit, meaning, _) in CHECKED.items():
            ratio = check["ratio"][name]
            table.add_row(check["support"], escape(f"{meaning} [{unit}]"), f"{check['simplified'][name]:.4g}",
                          f"{check['exact'][name]:.4g}", "-" if ratio is None else f"{ratio:.3f}")
    return table
