"""The terminal summary of `uplift analyze` on several decks: one row per deck, engine and
support (V_b, the coefficients, b/h_1*, uplift and the deck's criteria verdict)."""

from __future__ import annotations

from rich.markup import escape
from rich.table import Table

from ..deck.criteria import check_criteria
from ..display import VERDICT_LEGEND, WEIGHT_LEGEND, summary_columns, verdicts
from .render import engine_label

#: the columns of the several decks' summary (display.SUMMARY)
BATCH_COLUMNS = ("base_shear", "base_shear_coefficient", "base_moment", "base_moment_coefficient",
                 "critical_coefficient")


def batch_table(runs, units: str = "si", checks=None) -> Table:
    """One row per deck, engine and support: V_b, coefficients, b/h_1*, uplift, criteria (runs:
    (deck path, Deck, results) of each deck; checks: each deck's accuracy checks, for [criteria]
    simplified_error)."""
    table = Table(title=f"Summary of {len(runs)} decks")
    names = [deck.name for deck, _, _ in runs]
    label = (lambda deck: deck.name) if len(set(names)) == len(names) else str
    shown = verdicts([r for _, _, results in runs for r in results])
    legend = f"; {VERDICT_LEGEND}" if "yielded" in shown else ""
    table.caption = escape(f"{WEIGHT_LEGEND}{legend}; criteria: the deck's [criteria] limits")
    columns = summary_columns(BATCH_COLUMNS + shown)
    table.add_column("deck", justify="left", no_wrap=True)
    for header in ("engine", "support", *(column.heading(units) for column in columns), "criteria"):
        table.add_column(escape(header), justify="right")
    for (deck, item, results), checked in zip(runs, checks or [()] * len(runs), strict=True):
        for r in results:
            failed = check_criteria([r], item.criteria, checked)
            verdict = "-" if not item.criteria else ("violated" if failed else "ok")
            table.add_row(escape(label(deck)), escape(engine_label(r)), r.support,
                          *(column.cell(r, units) for column in columns), verdict)
    return table
