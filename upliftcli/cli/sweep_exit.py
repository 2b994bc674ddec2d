"""The end of `uplift sweep` and `uplift spectra`: the cases that failed, went stale or violate a
criterion, named on stderr, and the exit code they give (4, then 3)."""

from __future__ import annotations

import typer

from . import EXIT_ANALYSIS, stdout
from .options import EXIT_CRITERIA, echo_violations


def finish(rows: list[dict], criteria: bool) -> None:
    """Failures: exit 4; else criteria violations: exit 3 (each case named on stderr)."""
    failed = _echo_failures(rows)
    violating = _echo_violating(rows) if criteria else []
    if failed:
        raise typer.Exit(EXIT_ANALYSIS)
    if violating:
        raise typer.Exit(EXIT_CRITERIA)


def _echo_failures(rows: list[dict]) -> list[dict]:
    """The cases that failed or crashed, each named on stderr with its message; the stale ones
    (a record replaced during the sweep: thousands of cases) in one line (_echo_stale)."""
    failed = [row for row in rows if row.get("status") != "ok"]
    for row in failed:
        _echo_failure(row)
    _echo_stale(_stale(failed))
    return failed


def _stale(rows: list[dict]) -> list[dict]:
    """The rows of the cases not computed because a record changed during the sweep."""
    return [row for row in rows if row.get("status") == "stale"]


def _echo_failure(row: dict) -> None:
    """A failed or crashed case on stderr with its message (a stale one is counted by _echo_stale)."""
    if row.get("status") != "stale":
        stdout.echo(f"case {row['case']} ({row['engine']}/{row['support']}) {row['status']}: {row['message']}",
                    err=True)


def _plural(count: int, one: str, many: str) -> str:
    return one if count == 1 else many


def _echo_stale(stale: list[dict]) -> None:
    """One line on stderr for the stale cases: how many, and the record files that changed."""
    from ..sweep.worker import stale_records

    if not stale:
        return
    files = stale_records(stale)
    many = len(files)
    stdout.echo(f"{len(stale)} {_plural(len(stale), 'case', 'cases')} stale (not computed): the record "
                f"{_plural(many, 'file', 'files')} {', '.join(files)} changed after the sweep read "
                f"{_plural(many, 'it', 'them')}; run the same command with --resume --rerun-stale once "
                f"{_plural(many, 'it is', 'they are')} settled", err=True)


def _echo_violating(rows: list[dict]) -> list[dict]:
    """The cases that violate a criterion, each named on stderr with its varied inputs."""
    violating = [row for row in rows if row.get("violations")]
    echo_violations([f"case {row['case']}{_case_inputs(row)}: {row['violations']}" for row in violating])
    return violating


def _case_inputs(row: dict) -> str:
    """' (building.period=0.5, ...)': the varied fields of a case (the dotted columns), or nothing."""
    inputs = ", ".join(f"{k}={v}" for k, v in row.items() if "." in k)
    return f" ({inputs})" if inputs else ""
