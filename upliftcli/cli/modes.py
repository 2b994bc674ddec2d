"""`uplift modes`: the fixed-base modes of a deck's building (table, JSON, --plot). Apart from
analyze.py so that `uplift modes` neither imports nor builds the options of `uplift analyze`."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from . import plotting, stdout
from .options import SET_HELP, UNITS_HELP, DisplayUnits, OutputFormat, display_system, file_system, given_path

if TYPE_CHECKING:
    from ..deck.load import Deck


def named_files(loaded: Deck) -> list[str]:
    """The files a deck names, whether this run reads them or not (`modes` loads no ground motion):
    its record, its suite's files (or every file of its suite folder) and a spectrum table."""
    from ..provenance.record import absolute_paths

    motion = absolute_paths({"ground_motion": loaded.values.get("ground_motion", {})}, loaded.source)["ground_motion"]
    paths = [motion.get("record"), _spectrum_file(motion.get("design_spectrum")), *_suite_files(motion.get("suite"))]
    return [path for path in paths if isinstance(path, str)]


def _spectrum_file(spectrum) -> str | None:
    """The file of a design spectrum given as a table file, else None."""
    return spectrum.get("file") if isinstance(spectrum, dict) else None


def _suite_files(suite) -> list:
    """The files of a deck's suite: those its list names, or every file of its folder."""
    if isinstance(suite, list):
        return [_entry_file(item) for item in suite if isinstance(item, (str, dict))]
    return _folder_files(suite)


def _entry_file(item: str | dict):
    """The file of one suite entry: its path, or the 'file' of its table."""
    return item if isinstance(item, str) else item.get("file")


def _folder_files(suite) -> list[str]:
    """Every file of a suite given as a folder's name (none if it is no folder)."""
    if not (isinstance(suite, str) and os.path.isdir(suite)):
        return []
    return [os.path.join(suite, name) for name in os.listdir(suite)]


def modes(
    deck: Path = typer.Argument(..., parser=given_path, help="Deck file (TOML), see docs/deck.md."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    output_format: OutputFormat = typer.Option(OutputFormat.table, "--format", "-f", help="table or json."),
    plot: Path | None = typer.Option(None, "--plot", parser=given_path,
                                     help="Also draw the mode shapes (T_n, m_n*/m_t) into this directory as "
                                          "<deck>.modes.png."),
    plot_format: list[str] = typer.Option(["png"], "--plot-format", help=plotting.FORMAT_HELP),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace an existing --plot figure."),
    units: DisplayUnits | None = typer.Option(None, "--units", help=UNITS_HELP),
) -> None:
    """Fixed-base modes: periods, w_n/w_1, effective masses m_n*/m_t (and cumulative), heights h_n*, h_n*/b."""
    import numpy  # noqa: F401 - see below

    # numpy is imported here, near the top of the stack, not inside deck/load.py's imports: there
    # Python 3.11's frame stack sat on the edge of one of its 16 KiB chunks in a loop of
    # numpy._typing and mapped and unmapped it 1000-1400 times (strace), 60 ms of this command
    from ..deck.load import load_deck
    from .analyze_steps import warn_deck

    formats = plotting.check_plot(plot, plot_format)
    loaded = load_deck(deck, settings, load_ground_motion=False)
    warn_deck(loaded)
    if plot is not None:
        _plot_modes(deck, loaded, plot, formats, overwrite, display_system(units, loaded.raw))
    if output_format is OutputFormat.json:
        stdout.echo(json.dumps(_modes_document(loaded, file_system(units)), indent=2))
        return
    _print_modes(loaded, display_system(units, loaded.raw))


def _plot_modes(deck: Path, loaded: Deck, plot: Path, formats: list[str], overwrite: bool, units: str) -> None:
    """The mode-shape figures, refused first if one would replace a file the deck names or exists."""
    plotting.check_outputs(plotting.figure_paths(loaded, plot, deck.stem, formats, modes_only=True),
                           [loaded.source, *named_files(loaded)], overwrite)
    plotting.modes_plots(loaded, plot, deck.stem, formats, units)


def _modes_document(loaded: Deck, system_of_units: str = "si") -> dict:
    """The JSON document of `modes` (SI, or US under --units us; units stated)."""
    from ..display import file_unit, in_file_units
    from ..model.system import MODE_ROW_UNITS, fixed_base_mode_rows
    from ..output import to_jsonable
    from ..provenance.record import of_deck

    system = loaded.system
    units = {name: file_unit(unit, "", system_of_units)
             for name, unit in {"total_mass": "kg", "half_width": "m", **MODE_ROW_UNITS}.items()}
    document = in_file_units(to_jsonable({"source": loaded.source, "total_mass": system.total_mass,
                                          "half_width": system.half_width, "modes": fixed_base_mode_rows(system)}),
                             units)
    return {"source": document["source"], "total_mass": document["total_mass"], "half_width": document["half_width"],
            "units": {name: unit.label for name, unit in units.items()}, "modes": document["modes"],
            "provenance": to_jsonable(of_deck(loaded))}


def _print_modes(loaded: Deck, units: str) -> None:
    """The deck's title and the modes table on the terminal."""
    from rich.markup import escape

    from .fitting import console
    from .render_modes import modes_table

    out = console()
    out.print(f"[bold]{escape(loaded.title)}[/bold]")
    out.print(modes_table(loaded.system, units=units))


def register(app: typer.Typer) -> None:
    app.command("modes")(modes)
