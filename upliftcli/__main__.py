"""`python -m upliftcli`: the `uplift` command (upliftcli.cli.console), for where the console
script is not on PATH."""

from __future__ import annotations

from .cli import console

if __name__ == "__main__":
    console()
