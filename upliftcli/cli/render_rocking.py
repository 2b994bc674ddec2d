"""Terminal table of the rocking quantities (engines/quantities.ROCKING, docs/theory.md 14.7):
the mat's peak and residual rotation and settlement, and with a bearing capacity the number of
elements that yielded and the plastic work, in the display units of display.py (the elements'
plastic settlement is in the foundation table, cli/render.py)."""

from __future__ import annotations

from rich.markup import escape
from rich.table import Table

from ..display import label, show
from ..engines.quantities import rocking_entries
from ..engines.result import AnalysisResult


def rocking_table(result: AnalysisResult, units: str = "si") -> Table | None:
    """One row per value: quantity, where (the mat, or its left edge, centre, right edge), value,
    unit and the instant of a peak [s]; None for a result without rocking quantities."""
    entries = rocking_entries(result)
    if not entries:
        return None
    from .render import engine_label

    table = Table(title=escape(f"Rocking of the mat ({engine_label(result)}, {result.support}): ASCE 41-17 8.4"))
    for header, justify in (("quantity", "left"), ("where", "left"), ("value", "right"), ("unit", "left"),
                            ("time [s]", "right")):
        table.add_column(escape(header), justify=justify)
    for q, _, place, value, instant in entries:
        when = "end" if q.name.startswith("residual") else "-" if instant is None else f"{instant:.3f}"
        table.add_row(escape(q.name.replace("_", " ")), escape(place), show(value, q.display, units),
                      escape(label(q.display, units)), when)
    table.caption = escape("rotation |theta|; settlement: downward from the rest position under gravity (< 0: "
                           "above it); residual: at the end of the analysis; docs/theory.md 14.7")
    return table
