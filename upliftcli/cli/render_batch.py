"""The terminal summary of `uplift analyze` on several decks: one row per deck, engine and
support (V_b, the coefficients, b/h_1*, uplift and the deck's criteria verdict)."""

from __future__ import annotations

from collections.abc import Iterator, Mapping

from rich.markup import escape
from rich.table import Table

from ..deck.criteria import check_criteria, outcomes
from ..display import WEIGHT_LEGEND, summary_columns, verdicts
from ..engines.result import AnalysisResult
from .tables import add_columns, add_rows, engine_label, summary_cells, verdict_legend

#: the columns of the several decks' summary (display.SUMMARY)
BATCH_COLUMNS = ("base_shear", "base_shear_coefficient", "base_moment", "base_moment_coefficient",
                 "critical_coefficient")


def batch_table(runs, units: str = "si", checks=None) -> Table:
    """One row per deck, engine and support: V_b, coefficients, b/h_1*, uplift, criteria (runs:
    (deck path, Deck, results) of each deck; checks: each deck's accuracy checks, for [criteria]
    simplified_error)."""
    table = Table(title=f"Summary of {len(runs)} decks")
    shown = verdicts([r for _, _, results in runs for r in results])
    table.caption = escape(f"{WEIGHT_LEGEND}{verdict_legend(shown)}; criteria: the deck's [criteria] limits")
    columns = summary_columns(BATCH_COLUMNS + shown)
    table.add_column("deck", justify="left", no_wrap=True)
    add_columns(table, ("engine", "support", *(column.heading(units) for column in columns), "criteria"))
    return add_rows(table, _batch_rows(runs, checks or [()] * len(runs), columns, units))


def _batch_rows(runs, checks, columns: list, units: str) -> Iterator[list[str]]:
    """A row per deck and result, each deck's verdict by its criteria and accuracy checks."""
    for name, (_, item, results), checked in zip(_deck_names(runs), runs, checks, strict=True):
        for r in results:
            yield _result_cells(name, r, columns, units, item.criteria, checked)


def _result_cells(name: str, result: AnalysisResult, columns: list, units: str, criteria: Mapping,
                  checks) -> list[str]:
    """A deck's result: deck, engine, support, the summary columns and the criteria verdict."""
    return [escape(name), escape(engine_label(result)), result.support, *summary_cells(result, columns, units),
            _criteria_verdict(result, criteria, checks)]


def _deck_names(runs) -> list[str]:
    """Each deck's name, or its path when two decks have the same name."""
    names = [deck.name for deck, _, _ in runs]
    if len(set(names)) == len(names):
        return names
    return [str(deck) for deck, _, _ in runs]


def _criteria_verdict(result: AnalysisResult, criteria: Mapping, checks) -> str:
    """'-' without criteria (nor [design]'s drift check); else 'violated' or 'ok' (deck/criteria.check_criteria)."""
    if not criteria and not outcomes([result], criteria, checks):
        return "-"
    return "violated" if check_criteria([result], criteria, checks) else "ok"
