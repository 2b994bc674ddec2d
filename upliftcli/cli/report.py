"""`uplift report`: a calculation report of a deck as one self-contained HTML file (its page frame a
Jinja2 template, --template), or a PDF written by reportlab (default) or printed from the HTML by
a headless Chromium (--pdf-engine chromium); the warnings of the run on stderr as `uplift analyze`
prints them (the work is in upliftcli.report; this module parses options and writes the file)."""

from __future__ import annotations

import sys
from enum import StrEnum
from pathlib import Path

import typer

from ..errors import InputError
from . import options, stdout
from .options import SET_HELP, UNITS_HELP, DisplayUnits, given_path

#: figures of the report are drawn at this resolution [dots per inch]
REPORT_DPI = 150


class PdfEngine(StrEnum):
    """What writes a PDF report: reportlab (a dependency, from the report's data) or a Chromium
    on PATH (prints the HTML report)."""

    reportlab = "reportlab"
    chromium = "chromium"


def report(
    deck: Path = typer.Argument(..., parser=given_path, help="Deck file (TOML), see docs/deck.md."),
    out: Path = typer.Option(..., "--out", "-o", parser=given_path,
                             help="The report file to write: .html (self-contained) or .pdf (see --pdf-engine)."),
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
    units: DisplayUnits | None = typer.Option(None, "--units", help=UNITS_HELP),
    project: str | None = typer.Option(None, "--project", help="Project name (title block and running header; "
                                       "replaces the deck's [project] project)."),
    job_number: str | None = typer.Option(None, "--job-number", help="Job number (replaces [project] job_number)."),
    engineer: str | None = typer.Option(None, "--engineer", help="Prepared by (replaces [project] engineer)."),
    checker: str | None = typer.Option(None, "--checker", help="Checked by (replaces [project] checker)."),
    revision: str | None = typer.Option(None, "--revision", help="Revision (replaces [project] revision)."),
    pdf_engine: PdfEngine = typer.Option(PdfEngine.reportlab, "--pdf-engine",
                                         help="What writes a .pdf: reportlab (built in) or chromium (prints the "
                                              "HTML report; needs Chromium on PATH)."),
    template: Path | None = typer.Option(None, "--template", help="A Jinja2 template of the HTML report's page "
                                         "frame (letterhead, title block) in place of the built-in one; see "
                                         "docs/report.md. Also for --pdf-engine chromium."),
) -> None:
    """A calculation report a checker can sign: title block (project, job number, revision, prepared
    by, checked by, date), summary and sign-off block, inputs (as given and resolved), derived model,
    modes, results of every engine and support, accuracy check, warnings, criteria verdict, figures,
    method (with the paper's equation numbers) and provenance, in one HTML file that needs no network.

    Print it from a browser (A4 portrait, "page N of M"), or give --out report.pdf (reportlab; or
    --pdf-engine chromium). The analysis warnings go to stderr, as with `uplift analyze`.

    Exit codes: 0 ok, 2 bad input, 3 an acceptance limit of the deck's criteria is exceeded (the
    report is written and says so), 4 analysis failure.
    """
    from ..analysis import run as analysis
    from ..deck.load import load_deck
    from ..provenance.files import input_files
    from ..report.build import build_report
    from ..report.provenance import provenance
    from ..runtime.atomic import refuse_existing, refuse_inputs
    from .analyze_steps import warn, warn_deck, warn_suite
    from .plotting import keep_histories

    executable = _check_out(out, pdf_engine)
    frame = _check_template(template, out, pdf_engine)
    given = {"project": project, "job_number": job_number, "engineer": engineer, "checker": checker,
             "revision": revision}
    overrides = options.overrides(settings, engine, support)
    loaded = keep_histories(load_deck(deck, overrides))
    options.refuse_unchecked(loaded.criteria, check)
    refuse_inputs([out], input_files(loaded), "--out")
    refuse_existing([out], "--out", overwrite)
    deck_text = deck.read_text(encoding="utf-8")
    warn_deck(loaded)
    results = analysis.run(loaded)
    checks = options.accuracy_checks(loaded, results, check)
    warn_suite(results)
    warn(results, printed=loaded.warnings, checks=checks)
    document, specs = build_report(loaded, results, deck_text, overrides, provenance(loaded, ["uplift", *sys.argv[1:]]),
                                   options.display_system(units, loaded.raw), given, checks)
    _write_report(document, _images(specs), out, executable, frame)
    stdout.echo(f"wrote {out}", err=True)
    _exit_on_verdict(document, results, loaded, checks)


def _check_out(out: Path, engine: PdfEngine = PdfEngine.reportlab) -> str | None:
    """--out an .html or .pdf file name (not a directory); the Chromium that prints a PDF with
    --pdf-engine chromium (None otherwise)."""
    from ..report.pdf import check_browser

    if out.suffix.lower() not in (".html", ".htm", ".pdf"):
        raise InputError("--out", str(out), "a file name ending .html or .pdf")
    options.refuse_directory(out)
    if out.suffix.lower() == ".pdf" and engine is PdfEngine.chromium:
        return check_browser("--out", str(out))
    return None


def _check_template(template: Path | None, out: Path, engine: PdfEngine):
    """The page frame of --template, read and parsed before the run (None: the built-in one);
    refused for a PDF that reportlab writes (its title block comes from the deck's [project])."""
    from ..report.template import load

    if template is None:
        return None
    if out.suffix.lower() == ".pdf" and engine is PdfEngine.reportlab:
        raise InputError("--template", str(template), "an HTML report or --pdf-engine chromium (the reportlab PDF "
                         "takes its title block from the deck's [project] table and the options)")
    return load(template)


def _images(specs: dict) -> dict[str, bytes]:
    """The report's figures as PNG drawn at REPORT_DPI."""
    from ..figures import draw as plots

    return {name: plots.figure_bytes(spec, dpi=REPORT_DPI) for name, spec in specs.items()}


def _write_report(document, images: dict[str, bytes], out: Path, executable: str | None, frame=None) -> None:
    """The report into --out: HTML (in the page frame `frame`), a PDF written by reportlab, or the
    HTML printed to PDF by the Chromium `executable`."""
    from ..report.html import render
    from ..report.pdf import print_pdf
    from ..report.pdf_document import write_pdf
    from ..runtime.atomic import write_text

    try:
        if out.suffix.lower() != ".pdf":
            write_text(out, render(document, images, REPORT_DPI, frame))
        elif executable is not None:
            print_pdf(render(document, images, REPORT_DPI, frame), out, executable)
        else:
            write_pdf(document, images, REPORT_DPI, out)
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
