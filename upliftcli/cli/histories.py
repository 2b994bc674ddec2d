"""`--histories FILE` of `uplift analyze`: the file names (one per engine, support and suite
record), checked before the run, and the response histories written after it with the run's
provenance (output.write_histories)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import typer

from ..errors import InputError
from ..runtime.atomic import refuse_existing, refuse_inputs
from .plotting import HISTORY_ENGINES

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


def _record_suffixes(loaded: Deck) -> list[str]:
    """'' for one record; '_r01', '_r02' ... for the records of a suite (as _with_histories names them)."""
    records = getattr(loaded.ground_motion, "records", None)
    if not records:
        return [""]
    return [record_suffix(k, len(records)) for k in range(len(records))]


def check_histories(path: Path, loaded: Deck, inputs: list[str], overwrite: bool) -> None:
    """--histories before the run: a .csv or .npz file in a directory, a history engine, no
    input of the run (`inputs`) replaced, no existing file unless `overwrite`."""
    if path.suffix.lower() not in (".csv", ".npz"):
        raise InputError("--histories", str(path), "a file name ending in .csv or .npz")
    if not set(loaded.analysis.engines) & set(HISTORY_ENGINES):
        raise InputError("--histories", str(path), "an exact or approximate engine (--engine exact)")
    if path.parent.exists() and not path.parent.is_dir():
        raise InputError("--histories", str(path), "a file in an existing directory")
    names = [(e, s, suffix) for e in loaded.analysis.engines if e in HISTORY_ENGINES
             for s in loaded.analysis.supports for suffix in _record_suffixes(loaded)]
    targets = history_paths(path, names)
    refuse_inputs(targets, inputs, "--histories")
    refuse_existing(targets, "--histories", overwrite)


def _with_histories(results) -> list[tuple[str, object]]:
    """(file-name suffix, result) of each analysis that holds histories: a suite's records each
    ('_r01', '_r02' ...)."""
    pairs = []
    for result in results:
        records = getattr(result, "record_results", ())
        pairs += [(record_suffix(k, len(records)), record) for k, record in enumerate(records)]
        pairs.append(("", result))
    return [(suffix, result) for suffix, result in pairs if result.histories]


def write_histories(path: Path, results, inputs: list[str], record: dict | None = None) -> None:
    """Write each analysis's histories with the provenance `record` (the results documents never
    hold them: AnalysisResult.histories); a suite's records one file each, <stem>_<engine>_<support>_r<k><suffix>."""
    from ..output import write_histories as write

    with_histories = _with_histories(results)
    targets = history_paths(path, [(result.engine, result.support, suffix) for suffix, result in with_histories])
    refuse_inputs(targets, inputs, "--histories")  # as checked before the run (the names are the same)
    for (_, result), target in zip(with_histories, targets, strict=True):
        try:
            write(target, result.histories, record)
        except OSError as error:
            raise InputError("--histories", str(target), f"a writable file ({error.strerror or error})") from None
        typer.echo(f"wrote {target}", err=True)
