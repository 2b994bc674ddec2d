"""Standard output that a reader may close early (`uplift analyze deck | head`): the output stops
there, quietly, and the command runs to its end (its files written, its exit code its own: 0, 3
or 4), instead of an error (rich exits 1, Python prints a BrokenPipeError)."""

from __future__ import annotations

import os
import sys

import typer


def silence() -> None:
    """Send the rest of standard output to the null device (the reader has gone: what is still
    buffered, and the interpreter's last flush, go nowhere instead of failing)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):  # no file descriptor (a captured stream): nothing to redirect
        pass


def echo(text: str, nl: bool = True) -> None:
    """typer.echo to standard output; a closed pipe silences the rest (silence)."""
    try:
        typer.echo(text, nl=nl)
        sys.stdout.flush()
    except BrokenPipeError:
        silence()
