"""`uplift analyze` and `uplift modes`.

Only typer and the light modules are imported at module level: the analysis modules, numpy and
rich are imported by the commands that use them, so that `uplift --help` starts in about the time
of the interpreter; scipy is imported only where it is needed (the eigenvalue effective
properties, record matching and generation), never by the README's analysis.
"""

from __future__ import annotations

import json
from dataclasses import replace
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from .. import provenance
from ..atomic import refuse_inputs
from ..errors import InputError
from ..fields import parse_choices
from . import plotting

if TYPE_CHECKING:
    from rich.table import Table

    from ..deck import Deck

SET_HELP = "Override a deck field by dotted path, e.g. --set building.period=0.5 (repeatable; TOML values)."


class OutputFormat(StrEnum):
    table = "table"
    json = "json"


def _overrides(settings: list[str], engines: list[str], supports: list[str]) -> list[str]:
    """The --set texts, then --engine and --support (checked here, so that a bad name is
    reported as the option's, not as a --set of analysis.engine)."""
    from ..engines.registry import ENGINES, SUPPORTS

    overrides = list(settings)
    engines = parse_choices(engines, tuple(ENGINES), "--engine")
    supports = parse_choices(supports, SUPPORTS, "--support")
    if engines:
        overrides.append("analysis.engine=" + json.dumps(engines))
    if supports:
        overrides.append("analysis.supports=" + json.dumps(supports))
    return overrides


def input_files(deck: Deck) -> list[str]:
    """The files a run reads: the deck, its record(s) (a suite: each record) and a design-spectrum
    table file (outputs must not replace them)."""
    motion = [] if deck.ground_motion is None else provenance.motion_files(deck.ground_motion)
    return [deck.source, *(entry["path"] for entry in motion if entry["path"])]


def result_paths(out: Path, stem: str) -> list[Path]:
    """The files --out may receive for one deck (output.write_results)."""
    from ..output import result_paths as paths

    return paths(out, stem)


def analyze(
    decks: list[Path] = typer.Argument(..., help="Deck file(s) (TOML), see docs/deck.md; several: one summary table."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    engine: list[str] = typer.Option([], "--engine", "-e",
                                     help="Engine(s): simplified, approximate, exact or all; repeatable or comma "
                                          "separated (default: the deck's)."),
    support: list[str] = typer.Option([], "--support",
                                      help="Support condition(s): rigid, bonded, uplift or all; repeatable or comma "
                                           "separated (default: the deck's)."),
    output_format: OutputFormat = typer.Option(OutputFormat.table, "--format", "-f",
                                               help="table (terminal) or json (one document on stdout, SI units)."),
    out: Path | None = typer.Option(None, "--out", "-o",
                                    help="Also write <deck>.json, .csv (and .elements.csv) results and "
                                         "<deck>.deck.toml (the resolved deck, which repeats the run) into this "
                                         "directory."),
    histories: Path | None = typer.Option(
        None, "--histories",
        help="Exact/approximate engines: write the response histories to this file (.csv or .npz); with "
             "several analyses, one file each, named <stem>_<engine>_<support><suffix>. An existing file "
             "is refused unless --overwrite."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace existing --histories files."),
    check: bool = typer.Option(
        True, "--check/--no-check",
        help="Check the simplified engine against the exact engine for the supports it ran: with a record on "
             "that record (about 10 ms each); with a design spectrum on the deck's suite, or on 11 records "
             "generated for the spectrum (once, then cached); reports simplified/exact for V_b, M_b, the "
             "largest drift ratio and the roof displacement."),
    plot: Path | None = typer.Option(None, "--plot", help=plotting.PLOT_HELP),
    plot_format: list[str] = typer.Option(["png"], "--plot-format", help=plotting.FORMAT_HELP),
) -> None:
    """Peak story shears, drifts, displacements and the uplift verdict of a deck (or of several decks).

    Exit codes: 0 ok, 2 bad input, 3 an acceptance limit (the deck's criteria table) is exceeded,
    4 analysis failure.
    """
    from .. import analysis
    from ..accuracy import check_accuracy
    from ..criteria import check_criteria
    from ..deck import load_deck
    from ..output import to_json
    from ..suite_check import check_suite_accuracy
    from . import render

    if out is not None and out.exists() and not out.is_dir():
        raise InputError("--out", str(out), "a directory (a file of that name exists)")
    formats = plotting.check_plot(plot, plot_format)
    if plot is not None and len(decks) > 1:
        raise InputError("--plot", str(plot), f"a single deck ({len(decks)} decks given)")
    if len(decks) > 1:
        _analyze_batch(decks, _overrides(settings, engine, support), output_format, out)
        return
    deck = decks[0]
    loaded = load_deck(deck, _overrides(settings, engine, support))
    if out is not None:
        refuse_inputs(result_paths(out, deck.stem), input_files(loaded), "--out")
    if histories is not None:
        _check_histories(histories, loaded, overwrite)
        loaded = replace(loaded, analysis=replace(loaded.analysis, exact=replace(loaded.analysis.exact,
                                                                                  histories=True)))
    if plot is not None:
        loaded = plotting.keep_histories(loaded)
    results = analysis.run(loaded)
    if check:
        check_accuracy(loaded, results)
        check_suite_accuracy(loaded, results, lambda text: typer.echo(f"note: {text}", err=True))
    _warn_suite(results)
    _warn(results)
    if plot is not None:
        plotting.analysis_plots(results, loaded, plot, deck.stem, formats)
    # the provenance of the files and the JSON (not built for the terminal alone: 30-60 ms of
    # package-metadata look-ups)
    record = provenance.of_deck(loaded) if histories is not None or out is not None or \
        output_format is OutputFormat.json else None
    if histories is not None:
        _write_histories(histories, results, input_files(loaded), record)
    plotting.drop_histories(results)
    if output_format is OutputFormat.json:
        typer.echo(to_json(results, loaded.source, loaded.title, record), nl=False)
    else:
        render.print_results(render.console(), results, loaded.title)
    if out is not None:
        _write(results, out, deck.stem, loaded, record)
    violations = check_criteria(results, loaded.criteria)
    if violations:
        for message in violations:
            typer.echo(f"criterion violated: {message}", err=True)
        raise typer.Exit(3)


def _history_paths(path: Path, names: list[tuple[str, str, str]]) -> list[Path]:
    """One file per (engine, support, record suffix) with histories: `path` alone, else
    <stem>_<engine>_<support><suffix><ext> (a suite's records '_r01', '_r02' ...)."""
    if len(names) == 1:
        return [path]
    return [path.with_name(f"{path.stem}_{engine}_{support}{suffix}{path.suffix}") for engine, support, suffix in names]


def _record_suffixes(loaded: Deck) -> list[str]:
    """'' for one record; '_r01', '_r02' ... for the records of a suite (as _with_histories names them)."""
    records = getattr(loaded.ground_motion, "records", None)
    if not records:
        return [""]
    width = max(2, len(str(len(records))))
    return [f"_r{k + 1:0{width}d}" for k in range(len(records))]


def _check_histories(path: Path, loaded: Deck, overwrite: bool) -> None:
    if path.suffix.lower() not in (".csv", ".npz"):
        raise InputError("--histories", str(path), "a file name ending in .csv or .npz")
    if not set(loaded.analysis.engines) & {"exact", "approximate"}:
        raise InputError("--histories", str(path), "an exact or approximate engine (--engine exact)")
    if path.parent.exists() and not path.parent.is_dir():
        raise InputError("--histories", str(path), "a file in an existing directory")
    names = [(e, s, suffix) for e in loaded.analysis.engines if e in ("exact", "approximate")
             for s in loaded.analysis.supports for suffix in _record_suffixes(loaded)]
    targets = _history_paths(path, names)
    refuse_inputs(targets, input_files(loaded), "--histories")
    existing = [target for target in targets if target.exists()]
    if existing and not overwrite:
        raise InputError("--histories", str(existing[0]), "a file that does not exist yet (pass --overwrite to "
                         "replace it)")


def _warn_suite(results, prefix: str = "") -> None:
    """The warnings of a record suite (too few records for the code's rule, factors ...), once each."""
    messages = dict.fromkeys(message for r in results for message in getattr(r, "warnings", ()))
    for message in messages:
        typer.echo(f"warning: {prefix}{message}", err=True)


def _warn(results) -> None:
    """Each result's warnings (a result that cannot be right, a step refined ...): one line each
    on stderr (the JSON keeps them in details.warnings); the exit code is unchanged."""
    for result in results:
        for message in dict.fromkeys(result.details.get("warnings", [])):
            typer.echo(f"warning: {result.engine}/{result.support}: {message}", err=True)


def _with_histories(results) -> list[tuple[str, object]]:
    """(file-name suffix, result) of each analysis that holds histories: a suite's records each
    ('_r01', '_r02' ...)."""
    pairs = []
    for result in results:
        records = getattr(result, "record_results", ())
        width = len(str(len(records)))
        pairs += [(f"_r{k + 1:0{max(2, width)}d}", record) for k, record in enumerate(records)]
        pairs.append(("", result))
    return [(suffix, result) for suffix, result in pairs if "histories" in result.details]


def _write_histories(path: Path, results, inputs: list[str], record: dict | None = None) -> None:
    """Write each analysis's histories with the provenance `record` (and drop them from the
    result documents); a suite's records one file each, <stem>_<engine>_<support>_r<k><suffix>."""
    from ..output import write_histories

    with_histories = _with_histories(results)
    targets = _history_paths(path, [(result.engine, result.support, suffix) for suffix, result in with_histories])
    refuse_inputs(targets, inputs, "--histories")  # as checked before the run (the names are the same)
    for (_, result), target in zip(with_histories, targets, strict=True):
        try:
            write_histories(target, result.details.pop("histories"), record)
        except OSError as error:
            raise InputError("--histories", str(target), f"a writable file ({error.strerror or error})") from None
        typer.echo(f"wrote {target}", err=True)


def _write(results, out: Path, stem: str, loaded, record: dict | None = None) -> None:
    from ..output import write_results

    try:
        written = write_results(results, out, stem, deck=loaded, provenance=record)
    except OSError as error:
        raise InputError("--out", str(out), f"a writable directory ({error.strerror or error})") from None
    for path in written:
        typer.echo(f"wrote {path}", err=True)


def _analyze_batch(decks: list[Path], overrides: list[str], output_format: OutputFormat, out: Path | None) -> None:
    """Several decks: every deck is read and checked before any is run (bad input: exit 2, no
    output); one summary table (or {"decks": [...]} in JSON); exit 3 if any deck violates its criteria."""
    from .. import analysis
    from ..criteria import check_criteria
    from ..deck import load_deck
    from ..output import dumps, results_document
    from . import render

    stems = [deck.stem for deck in decks]
    if out is not None and len(set(stems)) != len(stems):
        twice = next(stem for stem in stems if stems.count(stem) > 1)
        raise InputError("--out", str(out), f"decks with different file names ({twice}.toml is given twice)")
    loaded = [load_deck(deck, overrides) for deck in decks]
    if out is not None:
        inputs = [path for item in loaded for path in input_files(item)]
        refuse_inputs([path for deck in decks for path in result_paths(out, deck.stem)], inputs, "--out")
    runs = [(deck, item, analysis.run(item)) for deck, item in zip(decks, loaded, strict=True)]
    records = [provenance.of_deck(item) for item in loaded]
    for deck, _, results in runs:
        _warn_suite(results, f"{deck}: ")
    violations = [(deck, message) for deck, item, results in runs
                  for message in check_criteria(results, item.criteria)]
    if output_format is OutputFormat.json:
        document = {"decks": [results_document(results, item.source, item.title, record)
                              for (_, item, results), record in zip(runs, records, strict=True)]}
        typer.echo(dumps(document), nl=False)
    else:
        render.console().print(_batch_table(runs, {str(deck) for deck, _ in violations}))
    if out is not None:
        for (deck, item, results), record in zip(runs, records, strict=True):
            _write(results, out, deck.stem, item, record)
    for deck, message in violations:
        typer.echo(f"criterion violated: {deck}: {message}", err=True)
    if violations:
        raise typer.Exit(3)


def _batch_table(runs, violating: set[str]) -> Table:
    """One row per deck, engine and support: V_b, coefficients, V_c, uplift, criteria."""
    from rich.markup import escape
    from rich.table import Table

    from ..criteria import check_criteria
    from . import render

    table = Table(title=f"Summary of {len(runs)} decks")
    names = [deck.name for deck, _, _ in runs]
    label = (lambda deck: deck.name) if len(set(names)) == len(names) else str
    table.caption = escape("V_b/W = V_b/(m_t g), M_b/Wh = M_b/(m_t g h_1*); criteria: the deck's [criteria] limits")
    for header in ("deck", "engine", "support", "V_b [kN]", "V_b/W", "M_b [kN m]", "M_b/Wh", "b/h_1*", "uplift",
                   "criteria"):
        table.add_column(escape(header), justify="left" if header == "deck" else "right", no_wrap=header == "deck")
    for deck, item, results in runs:
        for r in results:
            failed = check_criteria([r], item.criteria)
            verdict = "-" if not item.criteria else ("violated" if failed else "ok")
            table.add_row(escape(label(deck)), escape(render.engine_label(r)), r.support, f"{1e-3 * r.base_shear:.1f}",
                          f"{r.base_shear_coefficient:.4f}", f"{1e-3 * r.base_moment:.1f}",
                          f"{r.base_moment_coefficient:.4f}", f"{r.critical_coefficient:.4f}",
                          "yes" if r.uplift else "no", verdict)
    return table


def modes(
    deck: Path = typer.Argument(..., help="Deck file (TOML), see docs/deck.md."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    output_format: OutputFormat = typer.Option(OutputFormat.table, "--format", "-f", help="table or json."),
    plot: Path | None = typer.Option(None, "--plot", help="Also draw the mode shapes (T_n, m_n*/m_t) into this "
                                     "directory as <deck>.modes.png."),
    plot_format: list[str] = typer.Option(["png"], "--plot-format", help=plotting.FORMAT_HELP),
) -> None:
    """Fixed-base modes: periods, w_n/w_1, effective masses m_n*/m_t (and cumulative), heights h_n*, h_n*/b."""
    from rich.markup import escape

    from ..deck import load_deck
    from ..model.system import MODE_ROW_UNITS, fixed_base_mode_rows
    from ..output import to_jsonable
    from . import render

    formats = plotting.check_plot(plot, plot_format)
    loaded = load_deck(deck, settings, load_ground_motion=False)
    system = loaded.system
    if plot is not None:
        plotting.modes_plots(loaded, plot, deck.stem, formats)
    if output_format is OutputFormat.json:
        document = {
            "source": loaded.source, "total_mass": system.total_mass, "half_width": system.half_width,
            "units": {"total_mass": "kg", "half_width": "m", **MODE_ROW_UNITS},
            "modes": fixed_base_mode_rows(system), "provenance": provenance.of_deck(loaded),
        }
        typer.echo(json.dumps(to_jsonable(document), indent=2))
        return
    out = render.console()
    out.print(f"[bold]{escape(loaded.title)}[/bold]")
    out.print(render.modes_table(system))


def register(app: typer.Typer) -> None:
    app.command("analyze")(analyze)
    app.command("modes")(modes)
