"""Options of `uplift sweep` and `uplift spectra`: their help texts and --table choices; those
checked before anything starts: --name (a plain file stem) and --workers (capped at the cores
unless --oversubscribe, docs/sweep.md#limits); the tables they write, and an error writing their
figures as one line."""

from __future__ import annotations

import contextlib
import hashlib
from enum import StrEnum
from pathlib import Path

from ..errors import InputError
from ..runtime import limits
from . import stdout
from .options import not_writable

WORKERS_HELP = ("Local worker processes (default: all cores when the sweep is long enough to gain from them, "
                "else 1 = in this process); capped at the cores unless --oversubscribe.")
OVERSUBSCRIBE_HELP = ("Start --workers N local processes even when N exceeds the cores (at most 256); without it "
                      "N is capped at the cores.")
VARY_HELP = ("Vary a deck field (same dotted paths as --set): PATH=START:STOP:N (linear), PATH=START:STOP:N:log, "
             "PATH=a,b,c or PATH=\\[a, b], values in the deck's units (as --set); repeatable, cases are the "
             "cartesian product.")
SUPPORT_HELP = "Support condition(s): rigid, bonded, uplift; repeatable or comma separated (default: the deck's)."
OUT_HELP = ("Directory of the output files (tables in SI, or US units under --units us; the unit in each column "
            "name).")
SCHEDULER_HELP = "Run the cases on a Dask cluster at this address (tcp://host:8786), or 'local' for a local one."
DASK_HELP = "'local': run on a Dask LocalCluster of --workers processes on this machine (same as --scheduler local)."
CHECK_HELP = ("Also run the exact engine (record decks) and add to the tables the ratios simplified / exact of V_b, "
              "M_b, the largest drift ratio and the largest floor displacement of each simplified case "
              "(columns check_*).")
PER_RECORD_HELP = ("Record suite decks: after each case's row (the design statistic over the records) one row per "
                   "record in the tables (columns record and factor).")


class TableFormat(StrEnum):
    json = "json"
    parquet = "parquet"
    csv = "csv"


#: the longest list of varied fields in a default sweep name; a longer one is cut and a hash of the paths added
MAX_FIELDS_TEXT = 40


def default_stem(deck: Path, vary_texts: list[str]) -> str:
    """The stem of a sweep's files without --name: <deck>.sweep, or with --vary <deck>.<fields>.sweep,
    the fields the last part of each varied path, sorted by path, joined by '-' (ten_story.period-k_f.sweep),
    so that sweeps of one deck over other fields never share files; a list longer than
    MAX_FIELDS_TEXT is cut and the first 8 hex digits of the paths' SHA-256 added."""
    paths = sorted({text.partition("=")[0].strip() for text in vary_texts})
    if not paths:
        return f"{deck.stem}.sweep"
    return f"{deck.stem}.{_fields_text(paths)}.sweep"


def _fields_text(paths: list[str]) -> str:
    """'period-k_f': the last part of each path (letters, digits and '_' only), cut with a hash when long."""
    text = "-".join("".join(c for c in path.rsplit(".", 1)[-1] if c.isalnum() or c == "_") for path in paths)
    if len(text) <= MAX_FIELDS_TEXT:
        return text
    digest = hashlib.sha256("\n".join(paths).encode()).hexdigest()[:8]
    return f"{text[:MAX_FIELDS_TEXT - 9]}-{digest}"


def check_name(name: str | None) -> None:
    """--name must be a plain file stem: not empty, no folder separator, no control character, not
    hidden (a leading '.': `--name .` wrote '..csv'), at most 200 characters."""
    problem = _name_problem(name) if name is not None else ""
    if problem:
        raise InputError("--name", name, f"a plain file stem such as 'tall_frames' (letters, digits, '_', '-', '.' "
                         f"inside; {problem}), at most 200 characters")


def _name_problem(name: str) -> str:
    """Why --name is no plain file stem, or "" if it is one."""
    if not name.strip():
        return "it is empty"
    if name.startswith("."):
        return "it starts with '.' (a hidden file)"
    if "/" in name or "\\" in name:
        return "it holds a folder separator"
    if not name.isprintable():
        return "it holds a control character"
    return f"it has {len(name)} characters" if len(name) > 200 else ""


def check_workers(workers: int) -> None:
    """--workers is a positive integer."""
    if workers < 1:
        raise InputError("--workers", str(workers), "an integer >= 1")


def local_workers(workers: int | None, oversubscribe: bool, scheduler: str | None) -> int | None:
    """--workers checked before anything starts: an integer from 1 to limits.MAX_WORKERS, capped
    (with a warning) at the cores this process may use unless `oversubscribe` (--workers 1000
    started 127 processes and 4 GiB in 14 s); a remote Dask cluster's workers are its own."""
    if workers is None:
        return None
    check_workers(workers)
    if scheduler not in (None, "local"):
        return workers
    return _capped_at_cores(workers, oversubscribe)


def _capped_at_cores(workers: int, oversubscribe: bool) -> int:
    """Local --workers: at most limits.MAX_WORKERS, and at most the cores unless `oversubscribe` (with a warning)."""
    from ..runtime.process import available_cores

    if workers > limits.MAX_WORKERS:
        raise InputError("--workers", str(workers), f"at most {limits.MAX_WORKERS} worker processes (limit of the "
                         "tool)")
    cores = available_cores()
    if workers > cores and not oversubscribe:
        stdout.echo(f"warning: --workers {workers} capped at the {cores} cores this process may use (--oversubscribe "
                   f"starts {workers} processes)", err=True)
        return cores
    return workers


def table_paths(out: Path, stem: str, table: str) -> list[Path]:
    """The tables sweep_table.write_tables writes for --table `table`: <stem>.csv and .json or .parquet."""
    return [out / f"{stem}.csv"] + ([out / f"{stem}.{table}"] if table != "csv" else [])


@contextlib.contextmanager
def figure_errors(out: Path, tables: list[Path]):
    """An OSError drawing the figures (a full disk) as one line naming the figure: each figure is
    whole or absent (atomic), the tables written before it are named, --resume writes them again."""
    try:
        yield
    except OSError as error:
        raise not_writable("--out", error.filename or out, error, more="; the figures were not all written, the "
                           f"tables were ({', '.join(p.name for p in tables)}): run the same command with --resume "
                           "once there is room") from None
