"""Help texts keep their units: every bracketed unit of an option's help ([s], [m/s^2], [-] ...)
is in the --help of its command (rich markup would read [s] as a style and drop it)."""

from __future__ import annotations

import re

import pytest
import typer
from typer.testing import CliRunner

from upliftcli.cli import app

runner = CliRunner()


def commands(group, path: tuple[str, ...] = ()) -> list[tuple[tuple[str, ...], object]]:
    """(name path, command) of every command of a click group, sub-groups' commands too."""
    found = []
    for name, command in group.commands.items():
        found.append(((*path, name), command))
        if hasattr(command, "commands"):  # a group (typer ships its own click)
            found += commands(command, (*path, name))
    return found


ALL = commands(typer.main.get_command(app))


def test_the_commands_are_found():
    names = {" ".join(path) for path, _ in ALL}
    assert {"analyze", "modes", "sweep", "spectra", "record spectrum", "record info"} <= names


@pytest.mark.parametrize(("path", "command"), ALL, ids=[" ".join(p) for p, _ in ALL])
def test_units_in_brackets_are_kept(path, command):
    result = runner.invoke(app, [*path, "--help"], env={"CI": "true", "COLUMNS": "250"}, terminal_width=250)
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    helps = [(param.name, getattr(param, "help", None) or "") for param in command.params]
    for name, help_text in [("(command)", command.help or ""), *helps]:
        for unit in re.findall(r"\[[^\]]+\]", help_text):
            assert unit in text, (path, name, unit)


def test_record_spectrum_help_shows_the_period_units():
    result = runner.invoke(app, ["record", "spectrum", "--help"], env={"CI": "true"})
    text = " ".join(result.output.split())
    assert "log-spaced periods [s], or a comma list of periods [s]" in text
    assert "Time step [s] of a plain-text file" in text


#: options that take a quantity as text, and the unit their help must state
TEXT_QUANTITIES = {"--periods": "[s]", "--window": "[s]", "--damping": "[-]"}


@pytest.mark.parametrize(("path", "command"), ALL, ids=[" ".join(p) for p, _ in ALL])
def test_every_option_with_units_states_them(path, command):
    """Issue 27: units in every help text. A number option states its unit in brackets ([s],
    [-]); the options that take quantities as text (periods, a time window, damping ratios) state
    theirs; --set and --vary say their values are in the deck's units; --units names both
    systems; the file-writing options of results say they are SI."""
    for param in command.params:
        if getattr(param, "hidden", False) or not getattr(param, "opts", None):
            continue
        help_text, opts = " ".join((getattr(param, "help", None) or "").split()), set(param.opts)
        if getattr(param.type, "name", "") == "float":
            assert re.search(r"\[[^\]]+\]", help_text), (path, param.opts, help_text)
        for option in opts & set(TEXT_QUANTITIES):
            assert TEXT_QUANTITIES[option] in help_text, (path, option, help_text)
        if opts & {"--set", "--vary"}:
            assert "in the deck's units" in help_text, (path, param.opts)
        if "--units" in opts:
            assert re.search(r"\bsi\b.*\bus\b", help_text), (path, help_text)
    if path in (("analyze",), ("sweep",), ("spectra",)):
        outputs = [param.help for param in command.params if "--out" in getattr(param, "opts", ())]
        assert outputs and "SI" in outputs[0], (path, outputs)
