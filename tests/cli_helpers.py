"""Shared by the CLI tests: the typer app run in process, as CI runs it (CI=true: no colour, no
progress bars)."""

from __future__ import annotations

from typer.testing import CliRunner

from upliftcli.cli import app

runner = CliRunner()


def invoke(*args, env=None):
    """`uplift ARGS...` (arguments made strings) with CI=true and the extra environment."""
    return runner.invoke(app, [str(a) for a in args], env={"CI": "true", **(env or {})})
