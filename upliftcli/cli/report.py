"""`uplift report`: a calculation report of a deck as one self-contained HTML file (the work is
in upliftcli.report; this module parses options and writes the file)."""

from __future__ import annotations

import sys
from pathlib import Path

import typer

from ..errors import InputError
from .analyze import SET_HELP, _overrides


def report(
    deck: Path = typer.Argument(..., help="Deck file (TOML), see docs/deck.md."),
    out: Path = typer.Option(..., "--out", "-o", help="The report file to write (.html, self-contained)."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    engine: list[str] = typer.Option([], "--engine", "-e",
                                     help="Engine(s): simplified, approximate, exact (default: the deck's)."),
    support: list[str] = typer.Option([], "--support",
                                      help="Support condition(s): rigid, bonded, uplift (default: the deck's)."),
    check: bool = typer.Option(True, "--check/--no-check",
                               help="Check the simplified engine against the exact engine (as uplift analyze "
                                    "does: on the record, or on a suite for a design spectrum) and report "
                                    "simplified/exact."),
) -> None:
    """A calculation report a checker can sign: inputs (as given and resolved), derived model, modes,
    results of every engine and support, accuracy check, warnings, criteria verdict, figures, method
    (with the paper's equation numbers) and provenance, in one HTML file that needs no network.

    Print it from a browser (print CSS: A4); for a PDF: chromium --headless --print-to-pdf=report.pdf report.html.

    Exit codes: 0 ok, 2 bad input, 3 an acceptance limit of the deck's criteria is exceeded (the
    report is written and says so), 4 analysis failure.
    """
    from .. import analysis, plots
    from ..atomic import refuse_inputs, write_text
    from ..criteria import check_criteria
    from ..deck import load_deck
    from ..report.build import build_report
    from ..report.html import render
    from ..report.provenance import input_files, provenance
    from .plotting import keep_histories

    if out.suffix.lower() not in (".html", ".htm"):
        raise InputError("--out", str(out), "a file name ending .html")
    if out.is_dir():
        raise InputError("--out", str(out), "a file name (a directory of that name exists)")
    overrides = _overrides(settings, engine, support)
    loaded = keep_histories(load_deck(deck, overrides))
    refuse_inputs([out], [path for _, path in input_files(loaded)], "--out")
    deck_text = deck.read_text(encoding="utf-8")
    results = analysis.run(loaded)
    if check:
        from ..accuracy import check_accuracy
        from ..suite_check import check_suite_accuracy

        check_accuracy(loaded, results)
        check_suite_accuracy(loaded, results, lambda text: typer.echo(f"note: {text}", err=True))
    document, specs = build_report(loaded, results, deck_text, overrides, provenance(loaded, ["uplift", *sys.argv[1:]]))
    images = {name: plots.figure_bytes(spec) for name, spec in specs.items()}
    try:
        write_text(out, render(document, images))
    except OSError as error:
        raise InputError("--out", str(out), f"a writable file ({error.strerror or error})") from None
    typer.echo(f"wrote {out}", err=True)
    if document.exit_code:
        for message in check_criteria(results, loaded.criteria):
            typer.echo(f"criterion violated: {message}", err=True)
        raise typer.Exit(document.exit_code)


def register(app: typer.Typer) -> None:
    app.command("report")(report)
