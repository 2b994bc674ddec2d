"""The terminal table of ASCE 7-22's linear design values (engines/design.py, docs/theory.md 16): the rows
of report/design.py; None for a result without them (cli/render.print_results prints those it has)."""

from __future__ import annotations

from rich.markup import escape
from rich.table import Table

from ..engines.design import has_design
from ..engines.result import AnalysisResult
from .tables import add_columns, add_rows


def design_table(result: AnalysisResult, units: str = "si") -> Table | None:
    """Per story (top first): design shear, elastic and design drift ratio, the allowable one and the verdict."""
    if not has_design(result):
        return None
    from ..report import design  # the report's rows: loaded for a result that has them

    table = Table(title=escape(design.title(result, units)))
    add_columns(table, design.headers(units))
    table.caption = escape(design.NOTE)
    return add_rows(table, design.rows(result, units))
