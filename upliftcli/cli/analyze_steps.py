"""The steps `uplift analyze` takes alike for one deck (analyze.py) and for several (analyze_batch.py):
the --out files refused before the run and written after it, and the warnings on stderr."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..runtime.atomic import refuse_existing, refuse_inputs
from . import stdout
from .options import echo_warnings, echo_written, not_writable

if TYPE_CHECKING:
    from ..deck.load import Deck

#: what an existing result file is, in the message that refuses it
EARLIER = ": the results of an earlier run"


def result_paths(out: Path, stem: str) -> list[Path]:
    """The files --out may receive for one deck (output.write_results)."""
    from ..output import result_paths as paths

    return paths(out, stem, rocking=True)


def refuse_results(outputs: list[Path], inputs: list[str], overwrite: bool) -> None:
    """The --out files: none may be an input of the run, none may exist unless --overwrite."""
    refuse_inputs(outputs, inputs, "--out")
    refuse_existing(outputs, "--out", overwrite, EARLIER)


def write_results(results, out: Path, stem: str, loaded, record: dict | None = None, checks=(),
                  system: str = "si") -> None:
    """The --out files of one deck (in the units of `system`: options.file_system), each named on stderr."""
    from ..output import write_results as write

    try:
        written = write(results, out, stem, deck=loaded, provenance=record, checks=checks, system=system)
    except OSError as error:
        raise not_writable("--out", out, error) from None
    echo_written(written)


def warn_deck(deck: Deck) -> None:
    """The deck's warnings (values far outside building practice: Deck.warnings), one line each on
    stderr, each naming the deck (or --set) and the field; the exit code is unchanged."""
    echo_warnings(deck.warnings)


def warn_suite(results, prefix: str = "") -> None:
    """The warnings of a record suite (too few records for the code's rule, factors ...), once each."""
    echo_warnings(dict.fromkeys(message for r in results for message in getattr(r, "warnings", ())), prefix)


def warn(results, prefix: str = "", printed=(), checks=()) -> None:
    """The results' warnings (a result that cannot be right, a step refined ...) and those of their
    accuracy checks (a ratio out of band, the exact run's own: accuracy.Check.warnings) on stderr,
    each once, naming the analyses that gave it ('simplified/bonded, simplified/uplift: ...'); the
    JSON keeps them in `warnings`; the exit code is unchanged ([criteria] simplified_error turns an
    out-of-band check into exit code 3). prefix: the deck, when several are analysed; printed: the
    deck's warnings, printed once before (warn_deck), not again per result; checks: the accuracy
    checks (suite_check.check_deck)."""
    for message, analyses in _analyses_by_warning(results, printed, checks).items():
        stdout.echo(f"warning: {prefix}{', '.join(dict.fromkeys(analyses))}: {message}", err=True)


def _analyses_by_warning(results, printed, checks) -> dict[str, list[str]]:
    """Each warning not printed before -> the analyses ('engine/support') that gave it, in order."""
    from ..output import check_of

    given: dict[str, list[str]] = {}
    for result in results:
        for message in _result_warnings(result, check_of(result, checks)):
            if message not in printed:
                given.setdefault(message, []).append(f"{result.engine}/{result.support}")
    return given


def _result_warnings(result, check) -> dict:
    """The warnings of one result and of its accuracy check, each once, in order."""
    own = check.warnings() if check is not None else []
    return dict.fromkeys([*result.details.get("warnings", []), *own])
