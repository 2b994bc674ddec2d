"""What the terminal tables (cli/render*.py, cli/sweep_render.py) share: the engine's label, the
columns and rows of a rich Table, the ratio cells and the verdict legend. Imports no other table
module, so that each of them may import it."""

from __future__ import annotations

from collections.abc import Collection, Iterable

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from ..display import VERDICT_LEGEND
from ..engines.result import AnalysisResult, is_suite_result


def engine_label(result: AnalysisResult) -> str:
    """The engine, and for a suite's result its design statistic ('exact, mean of 11 records')."""
    return result.label if is_suite_result(result) else result.engine


def add_columns(table: Table, headers: Iterable[str], left: Collection[str] = (), justify: str = "right",
                **options) -> Table:
    """A column per heading (escaped): left-justified those in `left`, the others `justify`."""
    for header in headers:
        table.add_column(escape(header), justify="left" if header in left else justify, **options)
    return table


def add_rows(table: Table, rows: Iterable[Iterable]) -> Table:
    """A row per sequence of cells."""
    for row in rows:
        table.add_row(*row)
    return table


def print_tables(out: Console, tables: Iterable[Table | None]) -> None:
    """Print each table given, in order; None (a table the run has not) is skipped."""
    for table in tables:
        if table is not None:
            out.print(table)


def summary_cells(result: AnalysisResult, columns: list, units: str = "si") -> list[str]:
    """The result's cells of the summary columns (display.SUMMARY) in the display units."""
    return [column.cell(result, units) for column in columns]


def has_peak(result: AnalysisResult, name: str) -> bool:
    """The result holds peaks of the quantity `name`, at least one."""
    return name in result.peaks and bool(result.peaks[name].size)


def ratio_cell(value: float | None) -> str:
    """A ratio to 3 decimals, '-' when there is none."""
    return "-" if value is None else f"{value:.3f}"


def verdict_legend(shown: Iterable[str]) -> str:
    """'; ' and the legend of the verdict columns when the yielded column is among those `shown`."""
    return f"; {VERDICT_LEGEND}" if "yielded" in shown else ""
