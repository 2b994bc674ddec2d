"""Standard output that a reader may close early (`uplift analyze deck | head`): the output stops
there, quietly, and the command runs to its end (its files written, its exit code its own: 0, 3
or 4), instead of an error (rich exits 1, Python prints a BrokenPipeError)."""

from __future__ import annotations

import os
import sys

import typer

from ..errors import printable


def silence() -> None:
    """Send the rest of standard output to the null device (the reader has gone: what is still
    buffered, and the interpreter's last flush, go nowhere instead of failing)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):  # no file descriptor (a captured stream): nothing to redirect
        pass


def echo(text: str, nl: bool = True, err: bool = False) -> None:
    """typer.echo of text made safe for the terminal (errors.printable: line breaks kept), to
    standard output, or standard error with `err`: every line the commands print but the rich
    tables' (cli/fitting.py) comes through here. On standard output a closed pipe silences the
    rest (silence)."""
    if err:
        typer.echo(printable(text, lines=True), nl=nl, err=True)
        return
    try:
        typer.echo(printable(text, lines=True), nl=nl)
        sys.stdout.flush()
    except BrokenPipeError:
        silence()


def show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """warnings.showwarning of the `uplift` command (cli.main): a Python warning (a library's:
    matplotlib's missing glyph quotes the character of a deck's title) on standard error through
    echo, made safe for the terminal like every other line."""
    import warnings

    echo(warnings.formatwarning(message, category, filename, lineno, line).rstrip("\n"), err=True)
