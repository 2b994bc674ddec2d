"""`uplift analyze` with several decks: every deck is read and checked before any is run (bad
input: exit 2, no output); one summary table (or {"decks": [...]} in JSON); each analysis's
warnings and those of its accuracy check on stderr, once, naming its deck; exit 3 if any deck
violates its criteria."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

from ..errors import InputError
from ..provenance import record as provenance
from ..provenance.files import input_files
from . import stdout
from .analyze_steps import refuse_results, result_paths, warn, warn_deck, warn_suite, write_results
from .options import (
    OutputFormat,
    accuracy_checks,
    display_system,
    exit_on_violations,
    file_system,
    refuse_unchecked,
)


def analyze_batch(decks: list[Path], overrides: list[str], output_format: OutputFormat, out: Path | None,
                  overwrite: bool = False, units: str | None = None, check: bool = True) -> None:
    """Several decks (module docstring); check: suite_check.check_deck of each deck; units: --units
    (None: the decks' own when they agree, else SI; the files SI)."""
    _refuse_same_names(decks, out)
    loaded = _load_decks(decks, overrides, check)
    _refuse_outputs(decks, loaded, out, overwrite)
    runs, checks = _run_decks(decks, loaded, check)
    records = [provenance.of_deck(item) for item in loaded]
    _warn_decks(runs, checks)
    violations = _violations(runs, checks)
    _print_decks(runs, records, checks, output_format, units)
    _write_decks(runs, records, checks, out, units)
    exit_on_violations(violations)


def _refuse_same_names(decks: list[Path], out: Path | None) -> None:
    """--out receives <stem>.json ... of each deck: their file names must differ."""
    if out is None:
        return
    twice = [stem for stem, count in Counter(deck.stem for deck in decks).items() if count > 1]
    if twice:
        raise InputError("--out", str(out), f"decks with different file names ({twice[0]}.toml is given twice)")


def _load_decks(decks: list[Path], overrides: list[str], check: bool) -> list:
    """Every deck read and checked, then the warnings of each."""
    from ..deck.load import load_deck

    loaded = [load_deck(deck, overrides) for deck in decks]
    for item in loaded:
        refuse_unchecked(item.criteria, check)
    for item in loaded:
        warn_deck(item)
    return loaded


def _refuse_outputs(decks: list[Path], loaded: list, out: Path | None, overwrite: bool) -> None:
    """The --out files of all decks, refused before any is run (an input of any deck, an existing file)."""
    if out is None:
        return
    inputs = [path for item in loaded for path in input_files(item)]
    refuse_results(_result_files(decks, out), inputs, overwrite)


def _result_files(decks: list[Path], out: Path) -> list[Path]:
    """The files --out may receive for all decks."""
    return [path for deck in decks for path in result_paths(out, deck.stem)]


def _run_decks(decks: list[Path], loaded: list, check: bool) -> tuple[list[tuple], list[list]]:
    """([(deck, loaded deck, results)], the accuracy checks of each deck)."""
    from ..analysis import run as analysis

    runs = [(deck, item, analysis.run(item)) for deck, item in zip(decks, loaded, strict=True)]
    return runs, [accuracy_checks(item, results, check) for _, item, results in runs]


def _warn_decks(runs: list[tuple], checks: list[list]) -> None:
    """The warnings of each deck's suite and results, each line naming its deck."""
    for (deck, item, results), checked in zip(runs, checks, strict=True):
        warn_suite(results, f"{deck}: ")
        warn(results, f"{deck}: ", item.warnings, checked)


def _violations(runs: list[tuple], checks: list[list]) -> list[str]:
    """'<deck>: <criterion violated>' of every deck."""
    from ..deck.criteria import check_criteria

    return [f"{deck}: {message}" for (deck, item, results), checked in zip(runs, checks, strict=True)
            for message in check_criteria(results, item.criteria, checked)]


def _print_decks(runs: list[tuple], records: list[dict], checks: list[list], output_format: OutputFormat,
                 units: str) -> None:
    """One summary table of all decks, or {"decks": [...]} in JSON."""
    from ..output import dumps, results_document
    from . import render
    from .render_batch import batch_table

    if output_format is OutputFormat.json:
        document = {"decks": [results_document(results, item.source, item.title, record, checked, file_system(units))
                              for (_, item, results), record, checked in zip(runs, records, checks, strict=True)]}
        stdout.echo(dumps(document), nl=False)
        return
    render.console().print(batch_table(runs, _shared_units(units, [item for _, item, _ in runs]), checks))


def _shared_units(given: str | None, loaded: list) -> str:
    """The display units of the summary of several decks: --units, else the decks' own when all agree, else SI."""
    systems = {display_system(given, item.raw) for item in loaded}
    return systems.pop() if len(systems) == 1 else "si"


def _write_decks(runs: list[tuple], records: list[dict], checks: list[list], out: Path | None,
                 units: str | None) -> None:
    """The --out files of every deck."""
    if out is None:
        return
    for (deck, item, results), record, checked in zip(runs, records, checks, strict=True):
        write_results(results, out, deck.stem, item, record, checked, file_system(units))
