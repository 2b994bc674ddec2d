"""`--histories FILE` of `uplift analyze`: the file names (one per engine, support and suite
record), checked before the run, and the response histories written after it with the run's
provenance (histories.write_histories)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InputError
from ..runtime.atomic import refuse_existing, refuse_inputs
from . import stdout
from .plotting import error_reason, history_engines, not_a_directory

if TYPE_CHECKING:
    from ..deck.load import Deck


def history_paths(path: Path, names: list[tuple[str, str, str]]) -> list[Path]:
    """One file per (engine, support, record suffix) with histories: `path` alone, else
    <stem>_<engine>_<support><suffix><ext> (a suite's records '_r01', '_r02' ...)."""
    if len(names) == 1:
        return [path]
    return [path.with_name(f"{path.stem}_{engine}_{support}{suffix}{path.suffix}") for engine, support, suffix in names]


def record_suffix(k: int, count: int) -> str:
    """'_r01', '_r02' ... for record k (from 0) of a suite of `count` records (at least two digits)."""
    return f"_r{k + 1:0{max(2, len(str(count)))}d}"


def _suffixes(count: int) -> list[str]:
    """The record suffixes of a suite of `count` records (record_suffix)."""
    return [record_suffix(k, count) for k in range(count)]


def _record_suffixes(loaded: Deck) -> list[str]:
    """'' for one record; '_r01', '_r02' ... for the records of a suite (as _with_histories names them)."""
    records = getattr(loaded.ground_motion, "records", None)
    return _suffixes(len(records)) if records else [""]


def check_histories(path: Path, loaded: Deck, inputs: list[str], overwrite: bool) -> None:
    """--histories before the run: a .csv or .npz file in a directory, a history engine, no
    input of the run (`inputs`) replaced, no existing file unless `overwrite`."""
    expected = _history_file_problem(path, loaded)
    if expected is not None:
        raise InputError("--histories", str(path), expected)
    targets = history_paths(path, _history_names(loaded))
    refuse_inputs(targets, inputs, "--histories")
    refuse_existing(targets, "--histories", overwrite)


def _history_file_problem(path: Path, loaded: Deck) -> str | None:
    """What --histories expects and the run does not give (None: nothing): the file's extension,
    a history engine, an existing directory."""
    if path.suffix.lower() not in (".csv", ".npz"):
        return "a file name ending in .csv or .npz"
    if not history_engines(loaded):
        return "an exact or approximate engine (--engine exact)"
    if not_a_directory(path.parent):
        return "a file in an existing directory"
    return None


def _history_names(loaded: Deck) -> list[tuple[str, str, str]]:
    """(engine, support, record suffix) of every analysis of the deck that writes histories."""
    suffixes = _record_suffixes(loaded)
    return [(e, s, suffix) for e in history_engines(loaded) for s in loaded.analysis.supports for suffix in suffixes]


def _with_histories(results) -> list[tuple[str, object]]:
    """(file-name suffix, result) of each analysis that holds histories: a suite's records each
    ('_r01', '_r02' ...)."""
    return [(suffix, analysis) for result in results for suffix, analysis in _analyses(result) if analysis.histories]


def _analyses(result) -> list[tuple[str, object]]:
    """(file-name suffix, analysis) of a result: a suite's records ('_r01', '_r02' ...), then the result."""
    records = getattr(result, "record_results", ())
    return [*zip(_suffixes(len(records)), records, strict=True), ("", result)]


def write_histories(path: Path, results, inputs: list[str], record: dict | None = None, system: str = "si") -> None:
    """Write each analysis's histories with the provenance `record` (the results documents never
    hold them: AnalysisResult.histories); a suite's records one file each, <stem>_<engine>_<support>_r<k><suffix>."""
    with_histories = _with_histories(results)
    targets = history_paths(path, [(result.engine, result.support, suffix) for suffix, result in with_histories])
    refuse_inputs(targets, inputs, "--histories")  # as checked before the run (the names are the same)
    for (_, result), target in zip(with_histories, targets, strict=True):
        _write(target, result.histories, record, system)
        stdout.echo(f"wrote {target}", err=True)


def _write(target: Path, histories, record: dict | None, system: str = "si") -> None:
    """Write one file of histories (histories.write_histories, in the units of `system`); a file not
    written: InputError."""
    from ..histories import write_histories as write

    try:
        write(target, histories, record, system)
    except OSError as error:
        raise InputError("--histories", str(target), f"a writable file ({error_reason(error)})") from None
