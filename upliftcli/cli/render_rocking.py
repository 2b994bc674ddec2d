"""Terminal tables of the foundation and the rocking of the mat, in the display units of
display.py: per contact element its peak reactions and, on yielding soil, its plastic settlement
(elements_table); the rocking quantities (engines/quantities.ROCKING, docs/theory.md 14.7), the
mat's peak and residual rotation and settlement, and with a bearing capacity the number of
elements that yielded and the plastic work (rocking_table); None for a result without them
(cli/render.print_results prints those it has)."""

from __future__ import annotations

from rich.markup import escape
from rich.table import Table

from ..display import ROCKING_HEADINGS, label, rocking_rows, show
from ..engines.quantities import element_quantities, rocking_entries
from ..engines.result import AnalysisResult
from .tables import add_columns, add_rows, engine_label, has_peak


def elements_table(result: AnalysisResult, units: str = "si") -> Table | None:
    """Per foundation contact element (left to right): position, its peak reactions and, on
    yielding soil, its plastic settlement."""
    shown = _element_quantities(result)
    if not shown:
        return None
    table = Table(title=escape(f"Foundation elements ({engine_label(result)}, {result.support}): "
                               f"{_elements_shown(result)}"))
    add_columns(table, ["element", f"position x [{label('m', units)}]", *(q.heading(units) for q in shown)])
    return add_rows(table, (_element_cells(result, i, x, shown, units) for i, x in enumerate(result.element_positions)))


def _element_quantities(result: AnalysisResult) -> list:
    """The element quantities (engines/quantities.element_quantities) the result holds."""
    return [q for q in element_quantities() if has_peak(result, q.name)]


def _elements_shown(result: AnalysisResult) -> str:
    """What the elements table shows: the largest compression, and on yielding soil the plastic settlement."""
    return "largest compression" + (", plastic settlement" if "plastic_settlement" in result.peaks else "")


def _element_cells(result: AnalysisResult, i: int, x: float, shown: list, units: str) -> list[str]:
    """Element i+1: its position x and the peak of each quantity shown."""
    return [str(i + 1), show(x, "m", units), *[show(result.peaks[q.name][i], q.display, units) for q in shown]]


def rocking_table(result: AnalysisResult, units: str = "si") -> Table | None:
    """One row per value: quantity, where (the mat, or its left edge, centre, right edge), value,
    unit and the instant of a peak [s]; None for a result without rocking quantities."""
    entries = rocking_entries(result)
    if not entries:
        return None
    table = Table(title=escape(f"Rocking of the mat ({engine_label(result)}, {result.support}): ASCE 41-17 8.4"))
    add_columns(table, ROCKING_HEADINGS, left=("quantity", "where", "unit"))
    add_rows(table, ((escape(cell) for cell in row) for row in rocking_rows(entries, units)))
    table.caption = escape("rotation |theta|; settlement: downward from the rest position under gravity (< 0: "
                           "above it); residual: at the end of the analysis; docs/theory.md 14.7")
    return table
