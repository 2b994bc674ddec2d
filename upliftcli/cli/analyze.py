"""`uplift analyze` (`uplift modes`: modes.py). Its helpers: options.py (the options shared with other
commands), plotting.py (--plot), histories.py (--histories), render.py and render_batch.py (the
terminal tables); one deck: analyze_deck.py, several decks at once: analyze_batch.py.

Only typer and the light modules are imported at module level: the analysis modules, numpy and
rich are imported by the commands that use them, so that `uplift --help` starts in about the time
of the interpreter; scipy is imported only where it is needed (the eigenvalue effective
properties, record matching and generation), never by the README's analysis.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import typer

from ..errors import InputError
from . import plotting
from .options import (
    ENGINE_HELP,
    SET_HELP,
    UNITS_HELP,
    DisplayUnits,
    OutputFormat,
    check_out_directory,
    given_path,
    overrides,
)

if TYPE_CHECKING:
    pass

def analyze(
    decks: list[Path] = typer.Argument(..., parser=given_path,
                                       help="Deck file(s) (TOML), see docs/deck.md; several: one summary table."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    engine: list[str] = typer.Option([], "--engine", "-e", help=ENGINE_HELP),
    support: list[str] = typer.Option([], "--support",
                                      help="Support condition(s): rigid, bonded, uplift or all; repeatable or comma "
                                           "separated (default: the deck's)."),
    output_format: OutputFormat = typer.Option(OutputFormat.table, "--format", "-f",
                                               help="table (terminal) or json (one document on stdout, SI units unless "
                                                    "--units is given)."),
    out: Path | None = typer.Option(None, "--out", "-o", parser=given_path,
                                    help="Also write <deck>.json, .csv (and .elements.csv, .rocking.csv) results "
                                         "(SI, or US under --units us; units stated: the JSON's units entry, "
                                         "the CSV column names) and "
                                         "<deck>.deck.toml (the resolved deck, which repeats the run) into this "
                                         "directory."),
    histories: Path | None = typer.Option(
        None, "--histories", parser=given_path,
        help="Exact/approximate engines: write the response histories to this file in SI (.csv, the unit "
             "in each column name, in US units under --units us; or .npz, SI); with "
             "several analyses, one file each, named <stem>_<engine>_<support><suffix>. An existing file "
             "is refused unless --overwrite."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace existing output files (of --out, --plot and "
                                   "--histories); without it an existing file is refused before the run."),
    check: bool = typer.Option(
        True, "--check/--no-check",
        help="Check the simplified engine against the exact engine for the supports it ran: with a record on "
             "that record, with all modes (10-100 ms each); with a design spectrum on the deck's suite, or on 11 "
             "records generated for the spectrum (once, then cached); reports simplified/exact for V_b, M_b, the "
             "largest drift ratio, the roof displacement, the largest floor acceleration, the edge uplift and the "
             "mat rotation; a ratio outside analysis.check_band is a warning."),
    plot: Path | None = typer.Option(None, "--plot", parser=given_path, help=plotting.PLOT_HELP),
    plot_format: list[str] = typer.Option(["png"], "--plot-format", help=plotting.FORMAT_HELP),
    units: DisplayUnits | None = typer.Option(None, "--units", help=UNITS_HELP),
) -> None:
    """Peak story shears, drifts, displacements and the uplift verdict of a deck (or of several decks).

    Exit codes: 0 ok, 2 bad input, 3 an acceptance limit (the deck's criteria table) is exceeded,
    4 analysis failure.
    """
    formats = _check_outputs_given(decks, out, plot, plot_format)
    if len(decks) > 1:
        from .analyze_batch import analyze_batch  # several decks' provenance: not loaded for one

        analyze_batch(decks, overrides(settings, engine, support), output_format, out, overwrite, units, check)
        return
    from .analyze_deck import Outputs, analyze_deck

    outputs = Outputs(output_format, out, plot, formats, histories, overwrite, units)
    analyze_deck(decks[0], overrides(settings, engine, support), outputs, check)


def _check_outputs_given(decks: list[Path], out: Path | None, plot: Path | None, plot_format: list[str]) -> list[str]:
    """--out a directory, --plot and its formats (one deck only), checked before any deck is read; the formats."""
    check_out_directory(out)
    formats = plotting.check_plot(plot, plot_format)
    if plot is not None and len(decks) > 1:
        raise InputError("--plot", str(plot), f"a single deck ({len(decks)} decks given)")
    return formats


def register(app: typer.Typer) -> None:
    app.command("analyze")(analyze)
