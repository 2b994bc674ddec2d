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

import csv
import importlib
import io
import json
import math
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from ..analysis.comparison import MOTION
from ..engines.quantities import ALL_ENGINES, BUILDING, COMPARED, MAT, QUANTITIES, ROCKING, SCALARS, YIELDING
from ..errors import InputError
from ..output import to_jsonable
from ..provenance.record import csv_comments, number_text, to_text_numbers
from ..runtime.atomic import write_set
from . import file_units
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
            + list(rocking_columns(plan)) + list(yielding_columns(plan)) + list(_check_columns(plan)) + tail
            + ["key"])


def rocking_columns(plan: SweepPlan) -> dict[str, tuple[str, str]]:
    """ROCKING_COLUMNS when the sweep runs the exact engine on the uplift support, else none."""
    return ROCKING_COLUMNS if "exact" in plan.engines and "uplift" in plan.supports else {}


def yielding_columns(plan: SweepPlan) -> dict[str, tuple[str, str]]:
    """YIELDING_COLUMNS when the sweep runs the exact engine on a building with story strengths (given by the
    deck, a --set or a --vary), else none."""
    return YIELDING_COLUMNS if "exact" in plan.engines and _has_strengths(plan) else {}


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
    described = {**OUTPUT_COLUMNS, **rocking_columns(plan), **yielding_columns(plan), **suite, **_check_columns(plan)}
    return {**{v.path: v.unit for v in plan.varies}, **{name: unit for name, (unit, _) in described.items()}}


def _check_key(row: dict, paths: Sequence[str]) -> str:
    """What a simplified case and its exact reference share: support and varied values (as JSON)."""
    return json.dumps([row.get("support"), *(row.get(p) for p in paths)], default=str)


def add_checks(plan: SweepPlan, rows: Sequence[dict]) -> list[dict]:
    """The rows, each finished simplified case with the ratios simplified / exact of the exact
    case of the same varied values and support (CHECK_COLUMNS; empty where there is none); with
    [criteria] simplified_error = e, a ratio outside the band `uplift analyze`'s check then flags
    (_band: [1/(1 + e), 1 + e], the mat's motion the deck's check_band_motion widened to hold it)
    is a violation of the simplified case (deck/criteria.py); a varied criteria.simplified_error is
    each case's own."""
    paths = [v.path for v in plan.varies]
    deck_limit = plan.criteria.get("simplified_error")
    exact = {_check_key(row, paths): row for row in rows if _finished_by(row, "exact")}
    return [_checked(row, exact.get(_check_key(row, paths)), deck_limit, plan.motion_band) for row in rows]


def _checked(row: dict, reference: dict | None, deck_limit: float | None, motion_band: tuple) -> dict:
    """A finished simplified case's row with its ratios to the exact case's (`reference`, if any);
    any other row as it is."""
    if reference is None or not _finished_by(row, "simplified"):
        return row
    return _with_ratios(row, reference, deck_limit, motion_band)


def _finished_by(row: dict, engine: str) -> bool:
    """Whether a row is a finished case ('ok') of `engine`."""
    return row.get("engine") == engine and row.get("status") == "ok"


def _with_ratios(row: dict, reference: dict, deck_limit: float | None, motion_band: tuple) -> dict:
    """A copy of a simplified case's row with its check_<name> ratios to the exact case's, and the
    ratios outside the simplified_error limit's band (the case's own limit, else the deck's) as violations."""
    row = dict(row)
    mine, theirs = row.get("compared") or {}, reference.get("compared") or {}
    limit = row.get("criteria.simplified_error", deck_limit)
    failed = []
    for name in COMPARED:
        ratio = row[f"check_{name}"] = _ratio(mine.get(name), theirs.get(name))
        band = _band(limit, motion_band if name in MOTION else None)
        if band is not None and ratio is not None and not band[0] <= ratio <= band[1]:
            failed.append(f"simplified_error: {COMPARED[name].symbol} simplified / exact = {ratio:.3g} "
                          f"outside [{band[0]:.3g}, {band[1]:.3g}]")
    if failed:
        row["violations"] = "; ".join(filter(None, [row.get("violations"), *failed]))
    return row


def _band(limit: float | None, motion_band: tuple | None) -> tuple[float, float] | None:
    """[1/(1 + limit), 1 + limit], widened to hold motion_band for the mat's motion (None: no limit)."""
    if limit is None:
        return None
    low, high = 1.0 / (1.0 + limit), 1.0 + limit
    return (low, high) if motion_band is None else (min(low, motion_band[0]), max(high, motion_band[1]))


def _ratio(value: Any, base: Any) -> float | None:
    """value / base when both are finite numbers and base is not zero, else None."""
    value, base = finite_number(value), finite_number(base)
    return value / base if value is not None and base else None


def table_rows(plan: SweepPlan, rows: Sequence[dict]) -> list[dict]:
    """The rows of the tables: each case's row and, with plan.per_record, the rows of its records
    after it (the case's inputs, engine, support and key, each record's outputs; criteria apply
    to the case's row, so a record's 'violations' is empty)."""
    if not plan.per_record:
        return list(rows)
    out = []
    for row in rows:
        out.append(row)
        out.extend(_record_rows(plan, row))
    return out


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


def to_csv(rows: Sequence[dict], names: Sequence[str], provenance: dict | None = None) -> str:
    buffer = io.StringIO()
    if provenance is not None:
        buffer.write(csv_comments(provenance))
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(names)
    writer.writerows([_cell(row.get(name)) for name in names] for row in rows)
    return buffer.getvalue()


def _set_texts(plan: SweepPlan) -> list[str]:
    """The --set overrides as PATH=JSON texts."""
    return [f"{path}={json.dumps(to_jsonable(value))}" for path, value in plan.base_overrides]


def _column_rows(plan: SweepPlan, rows: Sequence[dict]) -> list[dict]:
    """The rows of the tables (table_rows), each with the plan's columns only, in their order."""
    names = columns(plan)
    return [{name: row.get(name) for name in names} for row in table_rows(plan, rows)]


def _converted(plan: SweepPlan, system: str) -> dict:
    """The output columns that the files' unit system converts (sweep/file_units.py)."""
    return file_units.converted_columns(units(plan), [v.path for v in plan.varies], system)


def document(plan: SweepPlan, rows: Sequence[dict], summary: dict | None = None,
             provenance: dict | None = None, system: str = "si") -> dict:
    """The JSON document of a sweep: deck, varied fields, units, provenance, rows (and summary);
    numbers rounded to 15 significant digits (json.dumps then writes their shortest text);
    system: the units of the output columns (sweep/file_units.py)."""
    converted = _converted(plan, system)
    doc = {
        "source": plan.source, "title": plan.title,
        "set": _set_texts(plan),
        "varied": _varied(plan, list),
        "engines": plan.engines, "supports": plan.supports,
        "units": file_units.file_units(units(plan), converted),
        "provenance": provenance if provenance is not None else sweep_provenance(plan),
        "rows": file_units.file_rows(_column_rows(plan, rows), converted),
    }
    if summary is not None:
        doc["summary"] = summary
    return to_text_numbers(to_jsonable(doc))


def _pyarrow(module: str = "pyarrow"):
    """A module of pyarrow, or an InputError naming --table parquet and how to install it."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise InputError("--table", "parquet", "pyarrow installed: pip install 'upliftcli[parquet]'") from None


def _arrow_column(pa, values: list) -> Any:
    """The Arrow array of a column's values; JSON texts for mixed types (a varied column)."""
    try:
        return pa.array(values)
    except (pa.ArrowInvalid, pa.ArrowTypeError):
        return pa.array([None if v is None else json.dumps(v) for v in values])


def _parquet_bytes(plan: SweepPlan, rows: Sequence[dict], provenance: dict, system: str = "si") -> bytes:
    pa, pq = _pyarrow(), _pyarrow("pyarrow.parquet")

    converted = _converted(plan, system)
    rows = file_units.file_rows(table_rows(plan, rows), converted)
    arrays = {name: _arrow_column(pa, [to_jsonable(row.get(name)) for row in rows])
              for name in file_units.renamed(columns(plan), converted)}
    metadata = {"units": json.dumps(file_units.file_units(units(plan), converted)), "source": plan.source,
                "provenance": json.dumps(to_text_numbers(provenance))}
    sink = io.BytesIO()
    pq.write_table(pa.table(arrays).replace_schema_metadata(metadata), sink)
    return sink.getvalue()


def check_table_format(table_format: str) -> None:
    """Fail before any analysis if the Parquet writer is not installed."""
    if table_format == "parquet":
        _pyarrow()


def write_tables(plan: SweepPlan, rows: Sequence[dict], directory: str | Path, stem: str,
                 table_format: str = "json", summary: dict | None = None, provenance: dict | None = None,
                 system: str = "si") -> list[Path]:
    """<stem>.csv and <stem>.json or <stem>.parquet, each atomically with the provenance
    (default: sweep_provenance of the plan); both built before writing, written both or neither;
    system: the units of the output columns (SI, or us: sweep/file_units.py)."""
    directory = Path(directory)
    provenance = sweep_provenance(plan) if provenance is None else provenance
    converted = _converted(plan, system)
    outputs: dict[Path, Any] = {directory / f"{stem}.csv": to_csv(
        file_units.file_rows(table_rows(plan, rows), converted), file_units.renamed(columns(plan), converted),
        provenance)}
    if table_format == "json":
        outputs[directory / f"{stem}.json"] = json.dumps(document(plan, rows, summary, provenance, system),
                                                         indent=1) + "\n"
    elif table_format == "parquet":
        outputs[directory / f"{stem}.parquet"] = _parquet_bytes(plan, rows, provenance, system)
    write_set(outputs)  # both or neither
    return list(outputs)
