"""The `uplift` command's entry point (pyproject.toml [project.scripts]), and `python -m upliftcli`.

It imports nothing heavy itself, so that it holds the whole start-up: a Ctrl-C while the command
line's modules load (typer, rich and the commands: most of the first second) or before a command
begins ends the process as a Ctrl-C during a command does (typer's Exit(130)): exit 130, no
traceback. Only the interpreter's own start and the console script's two first imports (re, sys)
come before it.
"""

from __future__ import annotations

import signal

#: the exit code of a command stopped by Ctrl-C (128 + SIGINT), as typer gives it
EXIT_INTERRUPTED = 128 + int(signal.SIGINT)


def console() -> None:
    """Run the `uplift` command (cli.console: it ends the process); Ctrl-C at any point of its
    start-up ends it with EXIT_INTERRUPTED."""
    try:
        from .cli import console as command

        command()
    except KeyboardInterrupt:
        interrupted()


def interrupted() -> None:
    """End the process with EXIT_INTERRUPTED, quietly; a second Ctrl-C does not cut it short."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    from .runtime.process import exit_now

    exit_now(EXIT_INTERRUPTED)


if __name__ == "__main__":
    console()
