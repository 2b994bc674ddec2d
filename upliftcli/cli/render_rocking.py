"""Terminal tables of the foundation and the rocking of the mat, in the display units of
display.py: per contact element its peak reactions and, on yielding soil, its plastic settlement
(elements_table); the rocking quantities (engines/quantities.ROCKING, docs/theory.md 14.7), the
mat's peak and residual rotation and settlement, and with a bearing capacity the number of
elements that yielded and the plastic work (rocking_table)."""

from __future__ import annotations

from rich.markup import escape
from rich.table import Table

from ..display import ROCKING_HEADINGS, label, rocking_rows, show
from ..engines.quantities import element_quantities, rocking_entries
from ..engines.result import AnalysisResult


def foundation_tables(result: AnalysisResult, units: str = "si") -> list[Table]:
    """The foundation table and the rocking table of a result, those it has (cli/render.print_results)."""
    return [table for table in (elements_table(result, units), rocking_table(result, units)) if table is not None]


def elements_table(result: AnalysisResult, units: str = "si") -> Table | None:
    """Per foundation contact element (left to right): position, its peak reactions and, on
    yielding soil, its plastic settlement."""
    shown = [q for q in element_quantities() if q.name in result.peaks and result.peaks[q.name].size]
    if not shown:
        return None
    what = "largest compression" + (", plastic settlement" if "plastic_settlement" in result.peaks else "")
    from .render import engine_label

    table = Table(title=escape(f"Foundation elements ({engine_label(result)}, {result.support}): {what}"))
    for header in ["element", f"position x [{label('m', units)}]"] + [q.heading(units) for q in shown]:
        table.add_column(escape(header), justify="right")
    for i, x in enumerate(result.element_positions):
        table.add_row(str(i + 1), show(x, "m", units), *[show(result.peaks[q.name][i], q.display, units)
                                                         for q in shown])
    return table


def rocking_table(result: AnalysisResult, units: str = "si") -> Table | None:
    """One row per value: quantity, where (the mat, or its left edge, centre, right edge), value,
    unit and the instant of a peak [s]; None for a result without rocking quantities."""
    entries = rocking_entries(result)
    if not entries:
        return None
    from .render import engine_label

    table = Table(title=escape(f"Rocking of the mat ({engine_label(result)}, {result.support}): ASCE 41-17 8.4"))
    for header in ROCKING_HEADINGS:
        table.add_column(escape(header), justify="right" if header in ("value", "time [s]") else "left")
    for row in rocking_rows(entries, units):
        table.add_row(*(escape(cell) for cell in row))
    table.caption = escape("rotation |theta|; settlement: downward from the rest position under gravity (< 0: "
                           "above it); residual: at the end of the analysis; docs/theory.md 14.7")
    return table
