"""The end of `uplift sweep` and `uplift spectra`: the cases that failed, went stale or violate a
criterion, named on stderr, and the exit code they give (4, then 3). The rows are read once, one at
a time (a sweep's rows read back from its rows file: never all in memory)."""

from __future__ import annotations

from collections.abc import Iterable

import typer

from . import EXIT_ANALYSIS, stdout
from .options import EXIT_CRITERIA, echo_violations


def finish(rows: Iterable[dict], criteria: bool) -> None:
    """Failures: exit 4; else criteria violations: exit 3 (each case named on stderr)."""
    violating: list[str] = []
    failed = _echo_failures(rows, violating if criteria else None)
    echo_violations(violating)
    if failed:
        raise typer.Exit(EXIT_ANALYSIS)
    if violating:
        raise typer.Exit(EXIT_CRITERIA)


def _echo_failures(rows: Iterable[dict], violating: list[str] | None = None) -> list[int]:
    """The cases that failed or crashed, each named on stderr with its message; the stale ones
    (a record replaced during the sweep: thousands of cases) in one line (_echo_stale); their
    case numbers. violating: the lines naming the cases that violate a criterion, added to it
    (echoed after these)."""
    failed: list[int] = []
    stale = _Stale()
    for row in rows:
        if row.get("status") != "ok":
            failed.append(row["case"])
            _echo_failure(row)
            stale.add(row)
        if violating is not None and row.get("violations"):
            violating.append(f"case {row['case']}{_case_inputs(row)}: {row['violations']}")
    _echo_stale(stale)
    return failed


class _Stale:
    """The stale cases (a record changed during the sweep): how many, and the record files named."""

    def __init__(self):
        self.count = 0
        self.files: dict[str, None] = {}

    def add(self, row: dict) -> None:
        from ..sweep.worker import stale_records

        if row.get("status") == "stale":
            self.count += 1
            self.files.update(dict.fromkeys(stale_records([row])))


def _echo_failure(row: dict) -> None:
    """A failed or crashed case on stderr with its message (a stale one is counted by _echo_stale)."""
    if row.get("status") != "stale":
        stdout.echo(f"case {row['case']} ({row['engine']}/{row['support']}) {row['status']}: {row['message']}",
                    err=True)


def _plural(count: int, one: str, many: str) -> str:
    return one if count == 1 else many


def _echo_stale(stale: _Stale) -> None:
    """One line on stderr for the stale cases: how many, and the record files that changed."""
    if not stale.count:
        return
    files = list(stale.files)
    many = len(files)
    stdout.echo(f"{stale.count} {_plural(stale.count, 'case', 'cases')} stale (not computed): the record "
                f"{_plural(many, 'file', 'files')} {', '.join(files)} changed after the sweep read "
                f"{_plural(many, 'it', 'them')}; run the same command with --resume --rerun-stale once "
                f"{_plural(many, 'it is', 'they are')} settled", err=True)


def _case_inputs(row: dict) -> str:
    """' (building.period=0.5, ...)': the varied fields of a case (the dotted columns), or nothing."""
    inputs = ", ".join(f"{k}={v}" for k, v in row.items() if "." in k)
    return f" ({inputs})" if inputs else ""
