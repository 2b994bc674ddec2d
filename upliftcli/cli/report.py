"""`uplift report`: a calculation report of a deck as one self-contained HTML file, or a PDF
printed from it by a headless Chromium (the work is in upliftcli.report; this module parses
options and writes the file)."""

from __future__ import annotations

import sys
from pathlib import Path

import typer

from ..errors import InputError
from . import options
from .options import SET_HELP, UNITS_HELP, DisplayUnits

#: figures of the report are drawn at this resolution [dots per inch]
REPORT_DPI = 150


def report(
    deck: Path = typer.Argument(..., help="Deck file (TOML), see docs/deck.md."),
    out: Path = typer.Option(..., "--out", "-o", help="The report file to write: .html (self-contained) or .pdf "
                             "(printed by a headless Chromium, which must be installed)."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    engine: list[str] = typer.Option([], "--engine", "-e",
                                     help="Engine(s): simplified, approximate, exact (default: the deck's)."),
    support: list[str] = typer.Option([], "--support",
                                      help="Support condition(s): rigid, bonded, uplift (default: the deck's)."),
    check: bool = typer.Option(True, "--check/--no-check",
                               help="Check the simplified engine against the exact engine (as uplift analyze "
                                    "does: on the record, or on a suite for a design spectrum) and report "
                                    "simplified/exact."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace an existing --out file."),
    units: DisplayUnits = typer.Option(DisplayUnits.si, "--units", help=UNITS_HELP),
    project: str | None = typer.Option(None, "--project", help="Project name (title block and running header; "
                                       "replaces the deck's [project] project)."),
    job_number: str | None = typer.Option(None, "--job-number", help="Job number (replaces [project] job_number)."),
    engineer: str | None = typer.Option(None, "--engineer", help="Prepared by (replaces [project] engineer)."),
    checker: str | None = typer.Option(None, "--checker", help="Checked by (replaces [project] checker)."),
    revision: str | None = typer.Option(None, "--revision", help="Revision (replaces [project] revision)."),
) -> None:
    """A calculation report a checker can sign: title block (project, job number, revision, prepared
    by, checked by, date), summary and sign-off block, inputs (as given and resolved), derived model,
    modes, results of every engine and support, accuracy check, warnings, criteria verdict, figures,
    method (with the paper's equation numbers) and provenance, in one HTML file that needs no network.

    Print it from a browser (A4 portrait, "page N of M"), or give --out report.pdf (needs Chromium).

    Exit codes: 0 ok, 2 bad input, 3 an acceptance limit of the deck's criteria is exceeded (the
    report is written and says so), 4 analysis failure.
    """
    from ..analysis import run as analysis
    from ..deck.criteria import check_criteria
    from ..deck.load import load_deck
    from ..figures import draw as plots
    from ..provenance.files import input_files
    from ..report.build import build_report
    from ..report.html import render
    from ..report.pdf import check_browser, print_pdf
    from ..report.provenance import provenance
    from ..runtime.atomic import refuse_existing, refuse_inputs, write_text
    from .plotting import keep_histories

    suffix = out.suffix.lower()
    if suffix not in (".html", ".htm", ".pdf"):
        raise InputError("--out", str(out), "a file name ending .html or .pdf")
    if out.is_dir():
        raise InputError("--out", str(out), "a file name (a directory of that name exists)")
    executable = check_browser("--out", str(out)) if suffix == ".pdf" else None
    given = {"project": project, "job_number": job_number, "engineer": engineer, "checker": checker,
             "revision": revision}
    overrides = options.overrides(settings, engine, support)
    loaded = keep_histories(load_deck(deck, overrides))
    options.refuse_unchecked(loaded.criteria, check)
    refuse_inputs([out], input_files(loaded), "--out")
    refuse_existing([out], "--out", overwrite)
    deck_text = deck.read_text(encoding="utf-8")
    results = analysis.run(loaded)
    checks = []
    if check:
        from ..analysis.suite_check import check_deck

        checks = check_deck(loaded, results, lambda text: typer.echo(f"note: {text}", err=True))
    document, specs = build_report(loaded, results, deck_text, overrides, provenance(loaded, ["uplift", *sys.argv[1:]]),
                                   units.value, given, checks)
    images = {name: plots.figure_bytes(spec, dpi=REPORT_DPI) for name, spec in specs.items()}
    html = render(document, images, REPORT_DPI)
    try:
        if executable is not None:
            print_pdf(html, out, executable)
        else:
            write_text(out, html)
    except OSError as error:
        raise InputError("--out", str(out), f"a writable file ({error.strerror or error})") from None
    typer.echo(f"wrote {out}", err=True)
    if document.exit_code:
        for message in check_criteria(results, loaded.criteria, checks):
            typer.echo(f"criterion violated: {message}", err=True)
        raise typer.Exit(document.exit_code)


def register(app: typer.Typer) -> None:
    app.command("report")(report)
