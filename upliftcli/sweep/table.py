"""The tidy table of a sweep (one row per case) and its summary: ranges, governing cases, envelope
(computed in sweep/summary.py, named here too).

Pure functions of the plan and the rows, plus writers of CSV / JSON / Parquet files (atomic),
each with the sweep's provenance (sweep_provenance, docs/provenance.md): the CSV's two leading
'#' lines, the JSON's "provenance", the Parquet file's metadata; numbers with 15 significant
digits (provenance.DIGITS) in the CSV and JSON. Columns: case, engine, support, the varied
fields (their deck units), then OUTPUT_COLUMNS; a sweep of a record suite adds SUITE_COLUMNS,
and with --per-record each case's row (the design statistic over the records) is followed by
one row per record (table_rows).
"""

from __future__ import annotations

import contextlib
import csv
import importlib
import io
import json
import math
import os
from collections.abc import Callable, Iterable, Iterator, Sequence
from pathlib import Path
from typing import Any

from ..engines.quantities import ALL_ENGINES, BUILDING, COMPARED, DESIGN, MAT, QUANTITIES, ROCKING, SCALARS, YIELDING
from ..errors import InputError
from ..output import to_jsonable
from ..provenance.record import csv_comments, number_text, to_text_numbers
from ..runtime.atomic import atomic_path
from . import file_units, stream
from .checks import add_checks, checked_rows  # noqa: F401 - table.add_checks: the checks' names here too
from .plan import SweepPlan
from .summary import (  # noqa: F401 - table.summarize, envelope ...: the summary's names here too
    SUMMARY_OUTPUTS,
    envelope,
    finite_number,
    governing,
    inputs_of,
    ranges,
    summarize,
    violating,
)

#: output column -> (unit, meaning): the row's own columns, the scalars and the largest value
#: of each response quantity (engines/quantities.py)
OUTPUT_COLUMNS: dict[str, tuple[str, str]] = {
    "T1_s": ("s", "fixed-base fundamental period T_1"),
    "T1bar_s": ("s", "effective period T1bar of the flexibly supported system [21] (T_1 for a rigid base)"),
    "xi1bar": ("-", "effective damping xi1bar [23] (xi_1 for a rigid base)"),
    **{scalar.column: (scalar.unit, scalar.meaning) for scalar in SCALARS.values()},
    "mode1_base_shear_coefficient": ("-", "peak mode-1 contribution to the base shear / (m_t g)"),
    "two_mode_base_shear_coefficient": ("-", "modes 1 and 2 combined / (m_t g) (simplified engine; empty otherwise)"),
    **{q.column: (q.unit, f"largest {q.meaning}" + ("" if q.engines == ALL_ENGINES else
                                                  f" ({', '.join(q.engines)} engines; empty otherwise)"))
       for q in QUANTITIES.values() if q.column},
    "max_drift_story": ("-", "story of the largest drift ratio (1 = lowest)"),
    "uplift": ("-", "whether the mat lifts off"),
    "V_c_N": ("N", "critical base shear V_c = m_t g b/h_1* [16a]"),
    "critical_coefficient": ("-", "b/h_1*, critical value of both coefficients"),
    "violations": ("", "acceptance criteria of the deck exceeded by this case"),
    "status": ("", "ok, failed (the analysis raised; see message) or crashed (its worker died)"),
    "message": ("", "error message of a failed or crashed case"),
}
#: columns of the rocking quantities (engines/quantities.ROCKING, docs/theory.md 14.7), in a sweep
#: that runs the exact engine on the uplift support (empty on the other rows)
ROCKING_COLUMNS: dict[str, tuple[str, str]] = {
    q.column: (q.unit, ("largest " if q.where != MAT or q.name == "plastic_settlement" else "") + q.meaning
               + " (exact engine, uplift; empty otherwise)") for q in ROCKING.values() if q.column}
#: columns of the yielding stories (engines/quantities.YIELDING, docs/theory.md 15.5), in a sweep that runs the
#: exact engine on a building with story strengths (empty on the other rows)
YIELDING_COLUMNS: dict[str, tuple[str, str]] = {
    q.column: (q.unit, ("" if q.where == BUILDING else "largest ") + q.meaning
               + " (exact engine, story strengths; empty otherwise)") for q in YIELDING.values() if q.column}
#: columns of ASCE 7-22's linear design values (engines/quantities.DESIGN, docs/theory.md 16), in a sweep that
#: runs the simplified engine on a deck with a [design] table (empty on the other rows)
DESIGN_COLUMNS: dict[str, tuple[str, str]] = {
    q.column: (q.unit, ("" if q.where == BUILDING else "largest ") + q.meaning
               + " (simplified engine, [design]; empty otherwise)") for q in DESIGN.values() if q.column}
#: the deck fields that give the stories strengths (deck/strengths.py)
STRENGTH_FIELDS = ("building.story_strengths", "building.strength_coefficient")
#: columns of a sweep of a record suite: statistic and record after the support, the others at the end
SUITE_COLUMNS: dict[str, tuple[str, str]] = {
    "statistic": ("", "the design value of the case's row over the records: mean or max (the code's rule, "
                      "docs/suites.md); empty on a record's row and for the simplified engine"),
    "record": ("", "the record of a per-record row (--per-record); empty on the case's row"),
    "records": ("-", "records in the suite"),
    "factor": ("-", "amplitude factor of the record (per-record rows)"),
}
#: the columns a per-record row takes from its case's row
_CASE_HEAD = ("case", "key", "engine", "support", "status", "message", "violations")


#: sweep --check: check_<name> = the simplified case's value / the exact case's (same fields, same
#: support) of each value of engines/quantities.COMPARED (the rows carry them under "compared")
CHECK_COLUMNS: dict[str, tuple[str, str]] = {
    f"check_{c.name}": ("-", f"simplified / exact: {c.meaning} (sweep --check: the exact case with the "
                             "deck's modes)") for c in COMPARED.values()
}


def columns(plan: SweepPlan) -> list[str]:
    lead, tail = (["statistic", "record"], ["records", "factor"]) if plan.suite_records else ([], [])
    return (["case", "engine", "support"] + lead + [v.path for v in plan.varies] + list(OUTPUT_COLUMNS)
            + list(rocking_columns(plan)) + list(yielding_columns(plan)) + list(design_columns(plan))
            + list(_check_columns(plan)) + tail
            + ["key"])


def rocking_columns(plan: SweepPlan) -> dict[str, tuple[str, str]]:
    """ROCKING_COLUMNS when the sweep runs the exact engine on the uplift support, else none."""
    return ROCKING_COLUMNS if "exact" in plan.engines and "uplift" in plan.supports else {}


def yielding_columns(plan: SweepPlan) -> dict[str, tuple[str, str]]:
    """YIELDING_COLUMNS when the sweep runs the exact engine on a building with story strengths (given by the
    deck, a --set or a --vary), else none."""
    return YIELDING_COLUMNS if "exact" in plan.engines and _has_strengths(plan) else {}


def design_columns(plan: SweepPlan) -> dict[str, tuple[str, str]]:
    """DESIGN_COLUMNS when the sweep runs the simplified engine on a deck with a [design] table (given by the
    deck, a --set or a --vary), else none."""
    return DESIGN_COLUMNS if "simplified" in plan.engines and _has_design(plan) else {}


def _has_design(plan: SweepPlan) -> bool:
    """Whether the deck, its --set or its --vary give a [design] table."""
    given = {path for path, _ in plan.base_overrides} | {v.path for v in plan.varies}
    return "design" in plan.raw or any(path.startswith("design.") for path in given)


def _has_strengths(plan: SweepPlan) -> bool:
    """Whether the deck, its --set or its --vary give the stories strengths (STRENGTH_FIELDS)."""
    given = {f"building.{name}" for name in plan.raw.get("building", {})}
    given |= {path for path, _ in plan.base_overrides} | {v.path for v in plan.varies}
    return any(name in given for name in STRENGTH_FIELDS)


def _check_columns(plan: SweepPlan) -> dict[str, tuple[str, str]]:
    """CHECK_COLUMNS for sweep --check, else none."""
    return CHECK_COLUMNS if plan.check else {}


def units(plan: SweepPlan) -> dict[str, str]:
    suite = SUITE_COLUMNS if plan.suite_records else {}
    described = {**OUTPUT_COLUMNS, **rocking_columns(plan), **yielding_columns(plan), **design_columns(plan),
                 **suite, **_check_columns(plan)}
    return {**{v.path: v.unit for v in plan.varies}, **{name: unit for name, (unit, _) in described.items()}}


def table_rows(plan: SweepPlan, rows: Iterable[dict]) -> list[dict]:
    """The rows of the tables: each case's row and, with plan.per_record, the rows of its records
    after it (the case's inputs, engine, support and key, each record's outputs; criteria apply
    to the case's row, so a record's 'violations' is empty)."""
    return list(iter_table_rows(plan, rows))


def iter_table_rows(plan: SweepPlan, rows: Iterable[dict]) -> Iterator[dict]:
    """table_rows one row at a time."""
    for row in rows:
        yield row
        if plan.per_record:
            yield from _record_rows(plan, row)


def _record_rows(plan: SweepPlan, row: dict) -> list[dict]:
    """The rows of a suite case's records: the case's head and varied values, each record's outputs."""
    head = {name: row.get(name) for name in _CASE_HEAD}
    varied = {v.path: row.get(v.path) for v in plan.varies}
    return [{**head, **varied, "violations": "", **record} for record in row.get("record_rows") or ()]


# ----------------------------------------------------------------------------- writers

def _varied(plan: SweepPlan, values: Callable[[tuple], Any]) -> list[dict]:
    """Each varied field: path, unit, spacing and its values (as `values` gives them)."""
    return [{"path": v.path, "unit": v.unit, "spacing": v.spacing, "values": values(v.values)} for v in plan.varies]


def sweep_provenance(plan: SweepPlan) -> dict:
    """The provenance of a sweep (docs/provenance.md): that of its deck with the --set overrides,
    before --vary, every record file a case reads, and `sweep`: the varied fields and their
    values, the engines, supports and the number of cases."""
    from ..provenance.record import of_deck, plain

    record = of_deck(plan.base_deck)
    record["files"] = [*record["files"], *plan.inputs]
    record["sweep"] = {"varied": _varied(plan, plain),
                       "engines": list(plan.engines), "supports": list(plan.supports), "cases": len(plan.cases),
                       "per_record": plan.per_record, "check": plan.check}
    return record


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return number_text(value) if math.isfinite(value) else ""
    if isinstance(value, (list, dict)):
        return json.dumps(to_text_numbers(to_jsonable(value)))
    return str(value)


def to_csv(rows: Iterable[dict], names: Sequence[str], provenance: dict | None = None) -> str:
    buffer = io.StringIO()
    write_csv(buffer, rows, names, provenance)
    return buffer.getvalue()


def write_csv(handle, rows: Iterable[dict], names: Sequence[str], provenance: dict | None = None) -> None:
    """The CSV table of the rows (the provenance's '#' lines, the names, a line per row) to a text handle."""
    if provenance is not None:
        handle.write(csv_comments(provenance))
    writer = csv.writer(handle, lineterminator="\n")
    writer.writerow(names)
    writer.writerows([_cell(row.get(name)) for name in names] for row in rows)


def _set_texts(plan: SweepPlan) -> list[str]:
    """The --set overrides as PATH=JSON texts."""
    return [f"{path}={json.dumps(to_jsonable(value))}" for path, value in plan.base_overrides]


def _converted(plan: SweepPlan, system: str) -> dict:
    """The output columns that the files' unit system converts (sweep/file_units.py)."""
    return file_units.converted_columns(units(plan), [v.path for v in plan.varies], system)


def _document_head(plan: SweepPlan, provenance: dict | None, converted: dict) -> dict:
    """The JSON document of a sweep but its rows (stream.ROWS_MARK) and summary."""
    return {
        "source": plan.source, "title": plan.title,
        "set": _set_texts(plan),
        "varied": _varied(plan, list),
        "engines": plan.engines, "supports": plan.supports,
        "units": file_units.file_units(units(plan), converted),
        "provenance": provenance if provenance is not None else sweep_provenance(plan),
        "rows": stream.ROWS_MARK,
    }


def _document_row(row: dict, names: Sequence[str], converted: dict) -> dict:
    """A row of the tables in the JSON document: the plan's columns only, in their order, in the
    files' units, numbers to 15 significant digits."""
    return to_text_numbers(to_jsonable(file_units.file_row({name: row.get(name) for name in names}, converted)))


def document(plan: SweepPlan, rows: Iterable[dict], summary: dict | None = None,
             provenance: dict | None = None, system: str = "si") -> dict:
    """The JSON document of a sweep: deck, varied fields, units, provenance, rows (and summary);
    numbers rounded to 15 significant digits (json.dumps then writes their shortest text);
    system: the units of the output columns (sweep/file_units.py)."""
    converted = _converted(plan, system)
    names = columns(plan)
    doc = to_text_numbers(to_jsonable(_document_head(plan, provenance, converted)))
    doc["rows"] = [_document_row(row, names, converted) for row in iter_table_rows(plan, rows)]
    if summary is not None:
        doc["summary"] = to_text_numbers(to_jsonable(summary))
    return doc


def write_document(write: Callable[[str], Any], plan: SweepPlan, rows: Iterable[dict], summary: dict | None = None,
                   provenance: dict | None = None, system: str = "si") -> None:
    """json.dumps(document(...), indent=1) and a newline through `write`, a row at a time."""
    writer = _document_writer(write, plan, summary, provenance, system)
    for row in iter_table_rows(plan, rows):
        writer.add(row)
    writer.end()


class _DocumentRows:
    """The JSON document's writer (stream.JsonDocument) fed the rows of the tables."""

    def __init__(self, document: stream.JsonDocument, names: Sequence[str], converted: dict):
        self.document, self.names, self.converted = document, names, converted

    def add(self, row: dict) -> None:
        self.document.add(_document_row(row, self.names, self.converted))

    def end(self) -> None:
        self.document.end()


def _document_writer(write: Callable[[str], Any], plan: SweepPlan, summary: dict | None, provenance: dict | None,
                     system: str) -> _DocumentRows:
    """The writer of the JSON document (rows added one at a time), its head written."""
    converted = _converted(plan, system)
    head = _document_head(plan, provenance, converted)
    if summary is not None:
        head["summary"] = summary
    return _DocumentRows(stream.JsonDocument(write, to_text_numbers(to_jsonable(head))), columns(plan), converted)


def _pyarrow(module: str = "pyarrow"):
    """A module of pyarrow, or an InputError naming --table parquet and how to install it."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise InputError("--table", "parquet", "pyarrow installed: pip install 'upliftcli[parquet]'") from None


def _write_parquet(handle, plan: SweepPlan, rows: Iterable[dict], provenance: dict, system: str = "si") -> None:
    """The Parquet table of the rows (one row group, as pq.write_table writes a whole table) to a binary handle; the
    columns built from chunks of rows (stream.ArrowColumns), a column of mixed types from a second pass over `rows`."""
    pa, pq = _pyarrow(), _pyarrow("pyarrow.parquet")

    converted = _converted(plan, system)
    names = file_units.renamed(columns(plan), converted)
    built = stream.ArrowColumns(pa, names)
    for row in _file_rows(plan, rows, converted):
        built.add({name: to_jsonable(row.get(name)) for name in names})
    arrays = built.arrays(lambda name: [to_jsonable(row.get(name)) for row in _file_rows(plan, rows, converted)])
    metadata = {"units": json.dumps(file_units.file_units(units(plan), converted)), "source": plan.source,
                "provenance": json.dumps(to_text_numbers(provenance))}
    pq.write_table(pa.table(arrays).replace_schema_metadata(metadata), handle)


def _file_rows(plan: SweepPlan, rows: Iterable[dict], converted: dict) -> Iterator[dict]:
    """The rows of the tables in the files' units, one at a time."""
    return file_units.iter_file_rows(iter_table_rows(plan, rows), converted)


def check_table_format(table_format: str) -> None:
    """Fail before any analysis if the Parquet writer is not installed."""
    if table_format == "parquet":
        _pyarrow()


def write_tables(plan: SweepPlan, rows: Iterable[dict], directory: str | Path, stem: str,
                 table_format: str = "json", summary: dict | None = None, provenance: dict | None = None,
                 system: str = "si") -> list[Path]:
    """<stem>.csv and <stem>.json or <stem>.parquet, each atomically with the provenance
    (default: sweep_provenance of the plan); written both or neither (each to its temporary file,
    flushed to the disk, before either replaces its target; the CSV first); system: the units of
    the output columns (SI, or us: sweep/file_units.py). `rows` is read once (twice for a Parquet
    column of mixed types): the rows read back from the rows file are never all in memory."""
    directory = Path(directory)
    provenance = sweep_provenance(plan) if provenance is None else provenance
    targets = [directory / f"{stem}.csv"] + ([directory / f"{stem}.{table_format}"]
                                             if table_format in ("json", "parquet") else [])
    with contextlib.ExitStack() as stack:
        # entered last, left first: the CSV replaces its target first, as write_set renames in order
        temporaries = [stack.enter_context(atomic_path(target)) for target in reversed(targets)][::-1]
        _write_files(plan, rows, temporaries, table_format, summary, provenance, system)
    return targets


def _write_files(plan: SweepPlan, rows: Iterable[dict], paths: list[Path], table_format: str, summary: dict | None,
                 provenance: dict, system: str) -> None:
    """The CSV table and the JSON document in one pass over the rows, or the CSV then the Parquet table; each file
    flushed to the disk."""
    converted = _converted(plan, system)
    with open(paths[0], "w", encoding="utf-8") as handle, _json_file(paths, table_format) as other:
        document = None if other is None else _document_writer(other.write, plan, summary, provenance, system)
        write_csv(handle, _teed(iter_table_rows(plan, rows), document, converted),
                  file_units.renamed(columns(plan), converted), provenance)
        if document is not None:
            document.end()
        _flushed(handle, other)
    if table_format == "parquet":
        with open(paths[1], "wb") as handle:
            _write_parquet(handle, plan, rows, provenance, system)
            _flushed(handle)


def _teed(rows: Iterable[dict], document: _DocumentRows | None, converted: dict) -> Iterator[dict]:
    """The rows in the files' units (for the CSV), each also added to the JSON document (if any)."""
    for row in rows:
        if document is not None:
            document.add(row)
        yield row if not converted else file_units.file_row(row, converted)


def _json_file(paths: list[Path], table_format: str):
    """The JSON document's file open for writing (json), else a context of None."""
    if table_format != "json":
        return contextlib.nullcontext()
    return open(paths[1], "w", encoding="utf-8")


def _flushed(*handles) -> None:
    """Flush the open files to the disk (before any replaces its target)."""
    for handle in handles:
        if handle is not None:
            handle.flush()
            os.fsync(handle.fileno())
