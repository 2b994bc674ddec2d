"""`uplift analyze` on one deck: read and checked, run, its warnings, its outputs (the tables or
JSON, --out, --plot, --histories) and the criteria verdict. Imported when the command runs, so
that registering the command (`uplift --help`, `uplift modes`) loads none of it."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from ..provenance.files import input_files
from . import plotting, stdout
from .analyze_steps import refuse_results, result_paths, warn, warn_deck, warn_suite, write_results
from .histories import check_histories, write_histories
from .options import (
    OutputFormat,
    accuracy_checks,
    display_system,
    exit_on_violations,
    file_system,
    refuse_unchecked,
)

if TYPE_CHECKING:
    from ..deck.load import Deck


@dataclass(frozen=True)
class Outputs:
    """What `analyze` writes for one deck: the table or JSON, --out, --plot (in its formats) and --histories."""

    output_format: OutputFormat
    out: Path | None
    plot: Path | None
    formats: list[str]
    histories: Path | None
    overwrite: bool
    units: str | None  # --units (None: the deck's display units, SI files)

    def display(self, loaded: Deck) -> str:
        """The display units of this deck's tables and figures (options.display_system)."""
        return display_system(self.units, loaded.raw)


def analyze_deck(deck: Path, given: list[str], outputs: Outputs, check: bool) -> None:
    """One deck: read and checked, run, its warnings, its outputs, then the criteria verdict (exit 3)."""
    from ..analysis import run as analysis
    from ..deck.criteria import check_criteria
    from ..deck.load import load_deck

    loaded = _prepare_deck(deck, load_deck(deck, given), outputs, check)
    results = analysis.run(loaded)
    checks = accuracy_checks(loaded, results, check)
    warn_suite(results)
    warn(results, printed=loaded.warnings, checks=checks)
    _write_outputs(deck, loaded, results, checks, outputs)
    exit_on_violations(check_criteria(results, loaded.criteria, checks))


def _prepare_deck(deck: Path, loaded: Deck, outputs: Outputs, check: bool) -> Deck:
    """The deck as the run needs it (its histories kept for --plot and --histories), its outputs
    refused before the run, its warnings printed."""
    refuse_unchecked(loaded.criteria, check)
    _refuse_outputs(deck, loaded, outputs)
    if outputs.histories is not None or outputs.plot is not None:
        loaded = plotting.keep_histories(loaded)
    warn_deck(loaded)
    return loaded


def _refuse_outputs(deck: Path, loaded: Deck, outputs: Outputs) -> None:
    """The files of --out, --plot and --histories: none may be an input, none may exist unless --overwrite."""
    if outputs.out is not None:
        refuse_results(result_paths(outputs.out, deck.stem), input_files(loaded), outputs.overwrite)
    if outputs.plot is not None:
        plotting.check_outputs(plotting.figure_paths(loaded, outputs.plot, deck.stem, outputs.formats),
                               input_files(loaded), outputs.overwrite)
    if outputs.histories is not None:
        check_histories(outputs.histories, loaded, input_files(loaded), outputs.overwrite)


def _write_outputs(deck: Path, loaded: Deck, results, checks: list, outputs: Outputs) -> None:
    """The figures, the histories, the table or JSON on stdout and the --out files, in that order."""
    if outputs.plot is not None:
        plotting.analysis_plots(results, loaded, outputs.plot, deck.stem, outputs.formats, outputs.display(loaded))
    record = _provenance(loaded, outputs)
    if outputs.histories is not None:
        write_histories(outputs.histories, results, input_files(loaded), record, file_system(outputs.units))
    _print_results(loaded, results, checks, record, outputs)
    if outputs.out is not None:
        write_results(results, outputs.out, deck.stem, loaded, record, checks, file_system(outputs.units))


def _provenance(loaded: Deck, outputs: Outputs) -> dict | None:
    """The provenance of the files and the JSON; not built for the terminal alone (30-60 ms of
    package-metadata look-ups)."""
    if outputs.histories is None and outputs.out is None and outputs.output_format is not OutputFormat.json:
        return None
    from ..provenance.record import of_deck

    return of_deck(loaded)


def _print_results(loaded: Deck, results, checks: list, record: dict | None, outputs: Outputs) -> None:
    """The results as one JSON document on stdout, or as the terminal tables."""
    from ..output import to_json
    from . import render

    if outputs.output_format is OutputFormat.json:
        stdout.echo(to_json(results, loaded.source, loaded.title, record, checks, file_system(outputs.units)), nl=False)
        return
    render.print_results(render.console(), results, loaded.title, outputs.display(loaded), checks)
