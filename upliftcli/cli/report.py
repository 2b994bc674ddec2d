"""`uplift report`: a calculation report of a deck as one self-contained HTML file, or a PDF
printed from it by a headless Chromium (the work is in upliftcli.report; this module parses
options and writes the file)."""

from __future__ import annotations

import sys
from pathlib import Path

import typer

from ..errors import InputError
from . import options, stdout
from .options import SET_HELP, UNITS_HELP, DisplayUnits, given_path

#: figures of the report are drawn at this resolution [dots per inch]
REPORT_DPI = 150


def report(
    deck: Path = typer.Argument(..., parser=given_path, help="Deck file (TOML), see docs/deck.md."),
    out: Path = typer.Option(..., "--out", "-o", parser=given_path,
                             help="The report file to write: .html (self-contained) or .pdf (printed by a headless "
                                  "Chromium, which must be installed)."),
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
    from ..deck.load import load_deck
    from ..provenance.files import input_files
    from ..report.build import build_report
    from ..report.provenance import provenance
    from ..runtime.atomic import refuse_existing, refuse_inputs
    from .plotting import keep_histories

    executable = _check_out(out)
    given = {"project": project, "job_number": job_number, "engineer": engineer, "checker": checker,
             "revision": revision}
    overrides = options.overrides(settings, engine, support)
    loaded = keep_histories(load_deck(deck, overrides))
    options.refuse_unchecked(loaded.criteria, check)
    refuse_inputs([out], input_files(loaded), "--out")
    refuse_existing([out], "--out", overwrite)
    deck_text = deck.read_text(encoding="utf-8")
    results = analysis.run(loaded)
    checks = options.accuracy_checks(loaded, results, check)
    document, specs = build_report(loaded, results, deck_text, overrides, provenance(loaded, ["uplift", *sys.argv[1:]]),
                                   units.value, given, checks)
    _write_report(_html(document, specs), out, executable)
    stdout.echo(f"wrote {out}", err=True)
    _exit_on_verdict(document, results, loaded, checks)


def _check_out(out: Path) -> str | None:
    """--out an .html or .pdf file name (not a directory); the Chromium that prints a PDF (None for HTML)."""
    from ..report.pdf import check_browser

    if out.suffix.lower() not in (".html", ".htm", ".pdf"):
        raise InputError("--out", str(out), "a file name ending .html or .pdf")
    options.refuse_directory(out)
    return check_browser("--out", str(out)) if out.suffix.lower() == ".pdf" else None


def _html(document, specs: dict) -> str:
    """The report as one self-contained HTML text, its figures drawn at REPORT_DPI."""
    from ..figures import draw as plots
    from ..report.html import render

    images = {name: plots.figure_bytes(spec, dpi=REPORT_DPI) for name, spec in specs.items()}
    return render(document, images, REPORT_DPI)


def _write_report(html: str, out: Path, executable: str | None) -> None:
    """The HTML into --out, or printed to PDF by the Chromium `executable`."""
    from ..report.pdf import print_pdf
    from ..runtime.atomic import write_text

    try:
        if executable is not None:
            print_pdf(html, out, executable)
        else:
            write_text(out, html)
    except OSError as error:
        raise options.not_writable("--out", out, error, "a writable file") from None


def _exit_on_verdict(document, results, loaded, checks: list) -> None:
    """The report's verdict: the violated criteria on stderr and the report's exit code (3), if any."""
    from ..deck.criteria import check_criteria

    if document.exit_code:
        options.echo_violations(check_criteria(results, loaded.criteria, checks))
        raise typer.Exit(document.exit_code)


def register(app: typer.Typer) -> None:
    app.command("report")(report)
