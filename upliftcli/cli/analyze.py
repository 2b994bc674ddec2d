"""`uplift analyze` and `uplift modes`. Their helpers: options.py (the options shared with other
commands), plotting.py (--plot), histories.py (--histories), render.py and render_batch.py (the
terminal tables).

Only typer and the light modules are imported at module level: the analysis modules, numpy and
rich are imported by the commands that use them, so that `uplift --help` starts in about the time
of the interpreter; scipy is imported only where it is needed (the eigenvalue effective
properties, record matching and generation), never by the README's analysis.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from ..errors import InputError
from ..provenance import record as provenance
from ..provenance.files import input_files
from ..runtime.atomic import refuse_existing, refuse_inputs
from . import plotting, stdout
from .histories import check_histories, write_histories
from .options import ENGINE_HELP, SET_HELP, UNITS_HELP, DisplayUnits, OutputFormat, overrides, refuse_unchecked

if TYPE_CHECKING:
    from ..deck.load import Deck

#: what an existing result file is, in the message that refuses it
EARLIER = ": the results of an earlier run"


def named_files(loaded: Deck) -> list[str]:
    """The files a deck names, whether this run reads them or not (`modes` loads no ground motion):
    its record, its suite's files (or every file of its suite folder) and a spectrum table."""
    import os

    from ..provenance.record import absolute_paths

    motion = absolute_paths({"ground_motion": loaded.values.get("ground_motion", {})}, loaded.source)["ground_motion"]
    spectrum = motion.get("design_spectrum")
    paths = [motion.get("record"), spectrum.get("file") if isinstance(spectrum, dict) else None]
    suite = motion.get("suite")
    if isinstance(suite, str) and os.path.isdir(suite):
        paths += [os.path.join(suite, name) for name in os.listdir(suite)]
    elif isinstance(suite, list):
        paths += [item if isinstance(item, str) else item.get("file") for item in suite
                  if isinstance(item, (str, dict))]
    return [path for path in paths if isinstance(path, str)]


def result_paths(out: Path, stem: str) -> list[Path]:
    """The files --out may receive for one deck (output.write_results)."""
    from ..output import result_paths as paths

    return paths(out, stem, rocking=True)


def analyze(
    decks: list[Path] = typer.Argument(..., help="Deck file(s) (TOML), see docs/deck.md; several: one summary table."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    engine: list[str] = typer.Option([], "--engine", "-e", help=ENGINE_HELP),
    support: list[str] = typer.Option([], "--support",
                                      help="Support condition(s): rigid, bonded, uplift or all; repeatable or comma "
                                           "separated (default: the deck's)."),
    output_format: OutputFormat = typer.Option(OutputFormat.table, "--format", "-f",
                                               help="table (terminal) or json (one document on stdout, SI units)."),
    out: Path | None = typer.Option(None, "--out", "-o",
                                    help="Also write <deck>.json, .csv (and .elements.csv, .rocking.csv) results "
                                         "(SI, units stated: the JSON's units entry, the CSV column names) and "
                                         "<deck>.deck.toml (the resolved deck, which repeats the run) into this "
                                         "directory."),
    histories: Path | None = typer.Option(
        None, "--histories",
        help="Exact/approximate engines: write the response histories to this file in SI (.csv, the unit "
             "in each column name, or .npz); with "
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
    plot: Path | None = typer.Option(None, "--plot", help=plotting.PLOT_HELP),
    plot_format: list[str] = typer.Option(["png"], "--plot-format", help=plotting.FORMAT_HELP),
    units: DisplayUnits = typer.Option(DisplayUnits.si, "--units", help=UNITS_HELP),
) -> None:
    """Peak story shears, drifts, displacements and the uplift verdict of a deck (or of several decks).

    Exit codes: 0 ok, 2 bad input, 3 an acceptance limit (the deck's criteria table) is exceeded,
    4 analysis failure.
    """
    from ..analysis import run as analysis
    from ..analysis.suite_check import check_deck
    from ..deck.criteria import check_criteria
    from ..deck.load import load_deck
    from ..output import to_json
    from . import render

    if out is not None and out.exists() and not out.is_dir():
        raise InputError("--out", str(out), "a directory (a file of that name exists)")
    formats = plotting.check_plot(plot, plot_format)
    if plot is not None and len(decks) > 1:
        raise InputError("--plot", str(plot), f"a single deck ({len(decks)} decks given)")
    if len(decks) > 1:
        _analyze_batch(decks, overrides(settings, engine, support), output_format, out, overwrite, units.value,
                       check)
        return
    deck = decks[0]
    loaded = load_deck(deck, overrides(settings, engine, support))
    refuse_unchecked(loaded.criteria, check)
    if out is not None:
        refuse_inputs(result_paths(out, deck.stem), input_files(loaded), "--out")
        refuse_existing(result_paths(out, deck.stem), "--out", overwrite, EARLIER)
    if plot is not None:
        plotting.check_outputs(plotting.figure_paths(loaded, plot, deck.stem, formats), input_files(loaded),
                               overwrite)
    if histories is not None:
        check_histories(histories, loaded, input_files(loaded), overwrite)
    if histories is not None or plot is not None:
        loaded = plotting.keep_histories(loaded)
    warn_deck(loaded)
    results = analysis.run(loaded)
    checks = check_deck(loaded, results, _note) if check else []
    _warn_suite(results)
    _warn(results, printed=loaded.warnings, checks=checks)
    if plot is not None:
        plotting.analysis_plots(results, loaded, plot, deck.stem, formats, units.value)
    # the provenance of the files and the JSON (not built for the terminal alone: 30-60 ms of
    # package-metadata look-ups)
    record = provenance.of_deck(loaded) if histories is not None or out is not None or \
        output_format is OutputFormat.json else None
    if histories is not None:
        write_histories(histories, results, input_files(loaded), record)
    if output_format is OutputFormat.json:
        stdout.echo(to_json(results, loaded.source, loaded.title, record, checks), nl=False)
    else:
        render.print_results(render.console(), results, loaded.title, units.value, checks)
    if out is not None:
        _write(results, out, deck.stem, loaded, record, checks)
    violations = check_criteria(results, loaded.criteria, checks)
    if violations:
        for message in violations:
            typer.echo(f"criterion violated: {message}", err=True)
        raise typer.Exit(3)


def _warn_suite(results, prefix: str = "") -> None:
    """The warnings of a record suite (too few records for the code's rule, factors ...), once each."""
    messages = dict.fromkeys(message for r in results for message in getattr(r, "warnings", ()))
    for message in messages:
        typer.echo(f"warning: {prefix}{message}", err=True)


def _warn(results, prefix: str = "", printed=(), checks=()) -> None:
    """The results' warnings (a result that cannot be right, a step refined ...) and those of their
    accuracy checks (a ratio out of band, the exact run's own: accuracy.Check.warnings) on stderr,
    each once, naming the analyses that gave it ('simplified/bonded, simplified/uplift: ...'); the
    JSON keeps them in `warnings`; the exit code is unchanged ([criteria] simplified_error turns an
    out-of-band check into exit code 3). prefix: the deck, when several are analysed; printed: the
    deck's warnings, printed once before (warn_deck), not again per result; checks: the accuracy
    checks (suite_check.check_deck)."""
    from ..output import check_of

    given: dict[str, list[str]] = {}
    for result in results:
        check = check_of(result, checks)
        lines = [*result.details.get("warnings", []), *(check.warnings() if check is not None else [])]
        for message in dict.fromkeys(lines):
            if message not in printed:
                given.setdefault(message, []).append(f"{result.engine}/{result.support}")
    for message, analyses in given.items():
        typer.echo(f"warning: {prefix}{', '.join(dict.fromkeys(analyses))}: {message}", err=True)


def _note(text: str) -> None:
    """A note on stderr (a check suite being generated: suite_check.check_suite)."""
    typer.echo(f"note: {text}", err=True)


def warn_deck(deck: Deck) -> None:
    """The deck's warnings (values far outside building practice: Deck.warnings), one line each on
    stderr, each naming the deck (or --set) and the field; the exit code is unchanged."""
    for message in deck.warnings:
        typer.echo(f"warning: {message}", err=True)


def _write(results, out: Path, stem: str, loaded, record: dict | None = None, checks=()) -> None:
    from ..output import write_results

    try:
        written = write_results(results, out, stem, deck=loaded, provenance=record, checks=checks)
    except OSError as error:
        raise InputError("--out", str(out), f"a writable directory ({error.strerror or error})") from None
    for path in written:
        typer.echo(f"wrote {path}", err=True)


def _analyze_batch(decks: list[Path], overrides: list[str], output_format: OutputFormat, out: Path | None,
                   overwrite: bool = False, units: str = "si", check: bool = True) -> None:
    """Several decks: every deck is read and checked before any is run (bad input: exit 2, no
    output); one summary table (or {"decks": [...]} in JSON); each analysis's warnings and those
    of its accuracy check (check: suite_check.check_deck of each deck) on stderr, once, naming its
    deck; exit 3 if any deck violates its criteria."""
    from ..analysis import run as analysis
    from ..analysis.suite_check import check_deck
    from ..deck.criteria import check_criteria
    from ..deck.load import load_deck
    from ..output import dumps, results_document
    from . import render
    from .render_batch import batch_table

    stems = [deck.stem for deck in decks]
    if out is not None and len(set(stems)) != len(stems):
        twice = next(stem for stem in stems if stems.count(stem) > 1)
        raise InputError("--out", str(out), f"decks with different file names ({twice}.toml is given twice)")
    loaded = [load_deck(deck, overrides) for deck in decks]
    for item in loaded:
        refuse_unchecked(item.criteria, check)
    for item in loaded:
        warn_deck(item)
    if out is not None:
        inputs = [path for item in loaded for path in input_files(item)]
        outputs = [path for deck in decks for path in result_paths(out, deck.stem)]
        refuse_inputs(outputs, inputs, "--out")
        refuse_existing(outputs, "--out", overwrite, EARLIER)
    runs = [(deck, item, analysis.run(item)) for deck, item in zip(decks, loaded, strict=True)]
    checks = [check_deck(item, results, _note) if check else [] for _, item, results in runs]
    records = [provenance.of_deck(item) for item in loaded]
    for (deck, item, results), checked in zip(runs, checks, strict=True):
        _warn_suite(results, f"{deck}: ")
        _warn(results, f"{deck}: ", item.warnings, checked)
    violations = [(deck, message) for (deck, item, results), checked in zip(runs, checks, strict=True)
                  for message in check_criteria(results, item.criteria, checked)]
    if output_format is OutputFormat.json:
        document = {"decks": [results_document(results, item.source, item.title, record, checked)
                              for (_, item, results), record, checked in zip(runs, records, checks, strict=True)]}
        stdout.echo(dumps(document), nl=False)
    else:
        render.console().print(batch_table(runs, units, checks))
    if out is not None:
        for (deck, item, results), record, checked in zip(runs, records, checks, strict=True):
            _write(results, out, deck.stem, item, record, checked)
    for deck, message in violations:
        typer.echo(f"criterion violated: {deck}: {message}", err=True)
    if violations:
        raise typer.Exit(3)


def modes(
    deck: Path = typer.Argument(..., help="Deck file (TOML), see docs/deck.md."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    output_format: OutputFormat = typer.Option(OutputFormat.table, "--format", "-f", help="table or json."),
    plot: Path | None = typer.Option(None, "--plot", help="Also draw the mode shapes (T_n, m_n*/m_t) into this "
                                     "directory as <deck>.modes.png."),
    plot_format: list[str] = typer.Option(["png"], "--plot-format", help=plotting.FORMAT_HELP),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace an existing --plot figure."),
    units: DisplayUnits = typer.Option(DisplayUnits.si, "--units", help=UNITS_HELP),
) -> None:
    """Fixed-base modes: periods, w_n/w_1, effective masses m_n*/m_t (and cumulative), heights h_n*, h_n*/b."""
    from rich.markup import escape

    from ..deck.load import load_deck
    from ..model.system import MODE_ROW_UNITS, fixed_base_mode_rows
    from ..output import to_jsonable
    from . import render

    formats = plotting.check_plot(plot, plot_format)
    loaded = load_deck(deck, settings, load_ground_motion=False)
    warn_deck(loaded)
    system = loaded.system
    if plot is not None:
        plotting.check_outputs(plotting.figure_paths(loaded, plot, deck.stem, formats, modes_only=True),
                               [loaded.source, *named_files(loaded)], overwrite)
        plotting.modes_plots(loaded, plot, deck.stem, formats, units.value)
    if output_format is OutputFormat.json:
        document = {
            "source": loaded.source, "total_mass": system.total_mass, "half_width": system.half_width,
            "units": {"total_mass": "kg", "half_width": "m", **MODE_ROW_UNITS},
            "modes": fixed_base_mode_rows(system), "provenance": provenance.of_deck(loaded),
        }
        stdout.echo(json.dumps(to_jsonable(document), indent=2))
        return
    out = render.console()
    out.print(f"[bold]{escape(loaded.title)}[/bold]")
    out.print(render.modes_table(system, units=units.value))


def register(app: typer.Typer) -> None:
    app.command("analyze")(analyze)
    app.command("modes")(modes)
