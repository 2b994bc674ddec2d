"""An empty path option (`--out ""`, `--from ""`, `--plot ""`, `--histories ""`) is refused with one
line naming the option, on every command that takes one: Path("") is Path("."), so it named the
current folder (a sweep wrote there, record select read it). So is an empty deck or record
argument (it was reported as '.', a directory)."""

from __future__ import annotations

import pytest
import typer
from cli_helpers import invoke

from upliftcli.cli import app

PATH_OPTIONS = ("--out", "--from", "--plot", "--histories")


def commands(group=None, prefix=()):
    """(words of the command, its click command) of every command of the app."""
    group = group or typer.main.get_command(app)
    for name, command in sorted(group.commands.items()):
        if hasattr(command, "commands"):
            yield from commands(command, (*prefix, name))
        else:
            yield (*prefix, name), command


def cases():
    """(command words, its other arguments, the option) for each path option of each command."""
    found = []
    for words, command in commands():
        options = {opt: param for param in command.params for opt in param.opts}
        arguments = [param for param in command.params if param.param_type_name == "argument"]
        others = [param.opts[0] for param in command.params if param.param_type_name == "option" and param.required]
        for option in PATH_OPTIONS:
            if option in options and not options[option].is_flag:
                given = [["x"] * (2 if arg.nargs == -1 else 1) for arg in arguments]
                rest = [w for other in others if other != option for w in (other, "1")]
                found.append(pytest.param(words, [w for g in given for w in g] + rest, option,
                                          id=" ".join((*words, option))))
    return found


def test_every_command_with_an_output_or_source_option_is_covered():
    covered = {(" ".join(c.values[0]), c.values[2]) for c in cases()}
    for expected in [("analyze", "--out"), ("analyze", "--plot"), ("analyze", "--histories"), ("modes", "--plot"),
                     ("sweep", "--out"), ("spectra", "--out"), ("report", "--out"), ("record spectrum", "--out"),
                     ("record spectrum", "--plot"), ("record select", "--from"), ("record select", "--out"),
                     ("record generate", "--out"), ("record match", "--out")]:
        assert expected in covered, (expected, sorted(covered))


@pytest.mark.parametrize(("words", "rest", "option"), cases())
def test_an_empty_path_option_is_one_line_naming_it(tmp_path, monkeypatch, words, rest, option):
    monkeypatch.chdir(tmp_path)
    for form in ([option, ""], [f"{option}="]):
        result = invoke(*words, *rest, *form)
        assert result.exit_code == 2, (form, result.output)
        assert result.stderr == f"error: {option}: a path, not empty (name the current folder as '.')\n", result.stderr
    assert list(tmp_path.iterdir()) == []  # nothing written in the current folder


def argument_cases():
    """(command words, its arguments with one of them empty, that argument's name)."""
    found = []
    for words, command in commands():
        arguments = [param for param in command.params if param.param_type_name == "argument"]
        others = [w for param in command.params if param.param_type_name == "option" and param.required
                  for w in (param.opts[0], "1")]
        for k, empty in enumerate(arguments):
            given = ["" if arg is empty else "x" for arg in arguments[:k + 1]]
            name = empty.metavar or empty.name  # as the message names it (examples: DIR)
            found.append(pytest.param(words, given + others, name, id=" ".join((*words, empty.name))))
    return found


def test_every_command_with_a_path_argument_is_covered():
    covered = {" ".join(c.values[0]) for c in argument_cases()}
    assert {"analyze", "modes", "sweep", "spectra", "report", "record info", "record spectrum", "record select",
            "record generate", "record match", "record scale", "examples"} <= covered, sorted(covered)


@pytest.mark.parametrize(("words", "args", "name"), argument_cases())
def test_an_empty_path_argument_is_one_line_naming_it(tmp_path, monkeypatch, words, args, name):
    monkeypatch.chdir(tmp_path)
    result = invoke(*words, *args)
    assert result.exit_code == 2, result.output
    assert result.stderr == f"error: {name}: a path, not empty (name the current folder as '.')\n", result.stderr
    assert list(tmp_path.iterdir()) == []
