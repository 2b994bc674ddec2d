"""`uplift analyze` and `uplift modes`."""

from __future__ import annotations

import json
from enum import Enum
from pathlib import Path

import numpy as np
import typer
from rich.markup import escape

from .. import analysis
from ..deck import load_deck
from ..errors import InputError
from ..results import to_json, to_jsonable, write_results
from . import render

SET_HELP = "Override a deck field by dotted path, e.g. --set building.period=0.5 (repeatable; TOML values)."


class OutputFormat(str, Enum):
    table = "table"
    json = "json"


def _overrides(settings: list[str], engines: list[str], supports: list[str]) -> list[str]:
    overrides = list(settings)
    if engines:
        overrides.append("analysis.engine=" + json.dumps(engines))
    if supports:
        overrides.append("analysis.supports=" + json.dumps(supports))
    return overrides


def analyze(
    deck: Path = typer.Argument(..., help="Deck file (TOML), see docs/deck.md."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    engine: list[str] = typer.Option([], "--engine", "-e",
                                     help="Engine(s): simplified, approximate, exact (default: the deck's)."),
    support: list[str] = typer.Option([], "--support",
                                      help="Support condition(s): rigid, bonded, uplift (default: the deck's)."),
    output_format: OutputFormat = typer.Option(OutputFormat.table, "--format", "-f",
                                               help="table (terminal) or json (one document on stdout, SI units)."),
    out: Path | None = typer.Option(None, "--out", "-o",
                                    help="Also write <deck>.json, .csv and .toml results into this directory."),
) -> None:
    """Peak story shears, drifts, displacements and the uplift verdict of a deck.

    Exit codes: 0 ok, 2 bad input, 3 an acceptance limit (the deck's criteria table) is exceeded,
    4 analysis failure.
    """
    if out is not None and out.exists() and not out.is_dir():
        raise InputError("--out", str(out), "a directory (a file of that name exists)")
    loaded = load_deck(deck, _overrides(settings, engine, support))
    results = analysis.run(loaded)
    if output_format is OutputFormat.json:
        typer.echo(to_json(results, loaded.source, loaded.title), nl=False)
    else:
        render.print_results(render.console(), results, loaded.title)
    if out is not None:
        try:
            written = write_results(results, out, deck.stem, loaded.source, loaded.title)
        except OSError as error:
            raise InputError("--out", str(out), f"a writable directory ({error.strerror or error})") from None
        for path in written:
            typer.echo(f"wrote {path}", err=True)
    violations = analysis.check_criteria(results, loaded.criteria)
    if violations:
        for message in violations:
            typer.echo(f"criterion violated: {message}", err=True)
        raise typer.Exit(3)


def modes(
    deck: Path = typer.Argument(..., help="Deck file (TOML), see docs/deck.md."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    output_format: OutputFormat = typer.Option(OutputFormat.table, "--format", "-f", help="table or json."),
) -> None:
    """Fixed-base modes: periods, w_n/w_1, effective masses m_n*/m_t (and cumulative), heights h_n*, h_n*/b."""
    loaded = load_deck(deck, settings, load_ground_motion=False)
    system = loaded.system
    if output_format is OutputFormat.json:
        m = system.modes
        m_t = system.total_mass
        document = {
            "source": loaded.source, "total_mass": m_t, "half_width": system.half_width,
            "units": {"period": "s", "total_mass": "kg", "half_width": "m", "effective_height": "m"},
            "modes": [
                {"mode": i + 1, "period": m.periods[i], "frequency_ratio": m.omega[i] / m.omega[0],
                 "effective_mass_ratio": m.effective_mass[i] / m_t,
                 "cumulative_mass_ratio": float(np.sum(m.effective_mass[: i + 1]) / m_t),
                 "effective_height": m.effective_height[i],
                 "effective_height_over_b": m.effective_height[i] / system.half_width}
                for i in range(m.n_modes)
            ],
        }
        typer.echo(json.dumps(to_jsonable(document), indent=2))
        return
    out = render.console()
    out.print(f"[bold]{escape(loaded.title)}[/bold]")
    out.print(render.modes_table(system))


def register(app: typer.Typer) -> None:
    app.command("analyze")(analyze)
    app.command("modes")(modes)
