"""The tidy table of a sweep (one row per case) and its summary: ranges, governing cases, envelope.

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
import io
import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..engines.quantities import ALL_ENGINES, COMPARED, MAT, QUANTITIES, ROCKING, SCALARS
from ..errors import InputError
from ..output import to_jsonable
from ..provenance.record import csv_comments, number_text, to_text_numbers
from ..runtime.atomic import write_set
from .plan import STATUSES, SweepPlan

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
#: outputs summarised on the terminal: governing case and envelope
SUMMARY_OUTPUTS = ("base_shear_coefficient", "base_moment_coefficient", "max_drift_ratio")


#: sweep --check: check_<name> = the simplified case's value / the exact case's (same fields, same
#: support) of each value of engines/quantities.COMPARED (the rows carry them under "compared")
CHECK_COLUMNS: dict[str, tuple[str, str]] = {
    f"check_{c.name}": ("-", f"simplified / exact: {c.meaning} (sweep --check: the exact case with the "
                             "deck's modes)") for c in COMPARED.values()
}


def columns(plan: SweepPlan) -> list[str]:
    lead, tail = (["statistic", "record"], ["records", "factor"]) if plan.suite_records else ([], [])
    checks = list(CHECK_COLUMNS) if plan.check else []
    return (["case", "engine", "support"] + lead + [v.path for v in plan.varies] + list(OUTPUT_COLUMNS)
            + list(rocking_columns(plan)) + checks + tail + ["key"])


def rocking_columns(plan: SweepPlan) -> dict[str, tuple[str, str]]:
    """ROCKING_COLUMNS when the sweep runs the exact engine on the uplift support, else none."""
    return ROCKING_COLUMNS if "exact" in plan.engines and "uplift" in plan.supports else {}


def units(plan: SweepPlan) -> dict[str, str]:
    suite = SUITE_COLUMNS if plan.suite_records else {}
    checks = CHECK_COLUMNS if plan.check else {}
    return {**{v.path: v.unit for v in plan.varies},
            **{name: unit for name, (unit, _) in {**OUTPUT_COLUMNS, **rocking_columns(plan), **suite,
                                                  **checks}.items()}}


def add_checks(plan: SweepPlan, rows: Sequence[dict]) -> list[dict]:
    """The rows, each finished simplified case with the ratios simplified / exact of the exact
    case of the same varied values and support (CHECK_COLUMNS; empty where there is none); with
    [criteria] simplified_error = e, a ratio outside [1/(1 + e), 1 + e] is a violation of the
    simplified case (deck/criteria.py); a varied criteria.simplified_error is each case's own."""
    paths = [v.path for v in plan.varies]
    deck_limit = plan.criteria.get("simplified_error")

    def key(row: dict) -> str:
        return json.dumps([row.get("support"), *(row.get(p) for p in paths)], default=str)

    exact = {key(row): row for row in rows if row.get("engine") == "exact" and row.get("status") == "ok"}
    out = []
    for row in rows:
        reference = exact.get(key(row)) if row.get("engine") == "simplified" and row.get("status") == "ok" else None
        if reference is not None:
            row = dict(row)
            mine, theirs = row.get("compared") or {}, reference.get("compared") or {}
            failed = []
            limit = row.get("criteria.simplified_error", deck_limit)
            for name in COMPARED:
                value, base = _number(mine.get(name)), _number(theirs.get(name))
                ratio = row[f"check_{name}"] = value / base if value is not None and base else None
                if limit is not None and ratio is not None and not 1.0 / (1.0 + limit) <= ratio <= 1.0 + limit:
                    failed.append(f"simplified_error: {COMPARED[name].symbol} simplified / exact = {ratio:.3g} "
                                  f"outside [{1.0 / (1.0 + limit):.3g}, {1.0 + limit:g}]")
            if failed:
                row["violations"] = "; ".join(filter(None, [row.get("violations"), *failed]))
        out.append(row)
    return out


def table_rows(plan: SweepPlan, rows: Sequence[dict]) -> list[dict]:
    """The rows of the tables: each case's row and, with plan.per_record, the rows of its records
    after it (the case's inputs, engine, support and key, each record's outputs; criteria apply
    to the case's row, so a record's 'violations' is empty)."""
    if not plan.per_record:
        return list(rows)
    out = []
    for row in rows:
        out.append(row)
        for record in row.get("record_rows") or ():
            head = {name: row.get(name) for name in _CASE_HEAD}
            out.append({**head, **{v.path: row.get(v.path) for v in plan.varies}, "violations": "", **record})
    return out


# ----------------------------------------------------------------------------- writers

def sweep_provenance(plan: SweepPlan) -> dict:
    """The provenance of a sweep (docs/provenance.md): that of its deck with the --set overrides,
    before --vary, every record file a case reads, and `sweep`: the varied fields and their
    values, the engines, supports and the number of cases."""
    from ..provenance.record import of_deck, plain

    record = of_deck(plan.base_deck)
    record["files"] = [*record["files"], *plan.inputs]
    record["sweep"] = {"varied": [{"path": v.path, "unit": v.unit, "spacing": v.spacing, "values": plain(v.values)}
                                  for v in plan.varies],
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
    for row in rows:
        writer.writerow([_cell(row.get(name)) for name in names])
    return buffer.getvalue()


def document(plan: SweepPlan, rows: Sequence[dict], summary: dict | None = None,
             provenance: dict | None = None) -> dict:
    """The JSON document of a sweep: deck, varied fields, units, provenance, rows (and summary);
    numbers rounded to 15 significant digits (json.dumps then writes their shortest text)."""
    names = columns(plan)
    doc = {
        "source": plan.source, "title": plan.title,
        "set": [f"{path}={json.dumps(to_jsonable(value))}" for path, value in plan.base_overrides],
        "varied": [{"path": v.path, "unit": v.unit, "spacing": v.spacing, "values": list(v.values)}
                   for v in plan.varies],
        "engines": plan.engines, "supports": plan.supports,
        "units": units(plan),
        "provenance": provenance if provenance is not None else sweep_provenance(plan),
        "rows": [{name: row.get(name) for name in names} for row in table_rows(plan, rows)],
    }
    if summary is not None:
        doc["summary"] = summary
    return to_text_numbers(to_jsonable(doc))


def _parquet_bytes(plan: SweepPlan, rows: Sequence[dict], provenance: dict) -> bytes:
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        raise InputError("--table", "parquet", "pyarrow installed: pip install 'upliftcli[parquet]'") from None
    arrays = {}
    rows = table_rows(plan, rows)
    for name in columns(plan):
        values = [to_jsonable(row.get(name)) for row in rows]
        try:
            arrays[name] = pa.array(values)
        except (pa.ArrowInvalid, pa.ArrowTypeError):  # mixed types in one varied column
            arrays[name] = pa.array([None if v is None else json.dumps(v) for v in values])
    metadata = {"units": json.dumps(units(plan)), "source": plan.source,
                "provenance": json.dumps(to_text_numbers(provenance))}
    sink = io.BytesIO()
    pq.write_table(pa.table(arrays).replace_schema_metadata(metadata), sink)
    return sink.getvalue()


def check_table_format(table_format: str) -> None:
    """Fail before any analysis if the Parquet writer is not installed."""
    if table_format == "parquet":
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            raise InputError("--table", "parquet", "pyarrow installed: pip install 'upliftcli[parquet]'") from None


def write_tables(plan: SweepPlan, rows: Sequence[dict], directory: str | Path, stem: str,
                 table_format: str = "json", summary: dict | None = None, provenance: dict | None = None
                 ) -> list[Path]:
    """<stem>.csv and <stem>.json or <stem>.parquet, each atomically with the provenance
    (default: sweep_provenance of the plan); both built before writing, written both or neither."""
    directory = Path(directory)
    provenance = sweep_provenance(plan) if provenance is None else provenance
    outputs: dict[Path, Any] = {directory / f"{stem}.csv": to_csv(table_rows(plan, rows), columns(plan), provenance)}
    if table_format == "json":
        outputs[directory / f"{stem}.json"] = json.dumps(document(plan, rows, summary, provenance), indent=1) + "\n"
    elif table_format == "parquet":
        outputs[directory / f"{stem}.parquet"] = _parquet_bytes(plan, rows, provenance)
    write_set(outputs)  # both or neither
    return list(outputs)


# ----------------------------------------------------------------------------- summary

def _number(value: Any) -> float | None:
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) \
        and math.isfinite(value) else None


def ranges(plan: SweepPlan) -> list[dict]:
    """Each varied field: unit, count, spacing, smallest and largest (numbers) or the values."""
    out = []
    for vary in plan.varies:
        numbers = [_number(v) for v in vary.values]
        entry = {"path": vary.path, "unit": vary.unit, "count": len(vary.values), "spacing": vary.spacing}
        if all(n is not None for n in numbers):
            entry.update(lowest=min(numbers), highest=max(numbers))
        else:
            entry["values"] = list(vary.values)
        out.append(entry)
    return out


def inputs_of(plan: SweepPlan, row: dict) -> dict:
    return {"engine": row["engine"], "support": row["support"], **{v.path: row.get(v.path) for v in plan.varies}}


def governing(plan: SweepPlan, rows: Sequence[dict], outputs: Sequence[str] = SUMMARY_OUTPUTS) -> dict[str, dict]:
    """Per output: the finished case with the largest value, {value, case, inputs}."""
    result = {}
    for name in outputs:
        candidates = [row for row in rows if row.get("status") == "ok" and _number(row.get(name)) is not None]
        if candidates:
            top = max(candidates, key=lambda row: row[name])
            result[name] = {"value": top[name], "case": top["case"], "inputs": inputs_of(plan, top)}
    return result


def envelope(plan: SweepPlan, rows: Sequence[dict], outputs: Sequence[str] = SUMMARY_OUTPUTS) -> list[dict]:
    """Envelope over the varied foundation fields (all varied fields if no foundation field is
    varied), per engine, support and value of the other varied fields.

    Each group: {group: {...}, over: [paths], outputs: {name: {lowest, highest, governing}}}; with
    one numeric field enveloped, also at_lower_bound / at_upper_bound: the values at its smallest
    and largest value. ASCE 7-22 section 19.1.1 asks for both bound estimates of the foundation
    stiffness and the case giving the greater response; `highest` includes interior points."""
    foundation = [v for v in plan.varies if v.path.startswith("foundation.")]
    over = foundation or list(plan.varies)
    over_paths = [v.path for v in over]
    group_paths = ["engine", "support"] + [v.path for v in plan.varies if v.path not in over_paths]
    bound = over[0] if len(over) == 1 and all(_number(x) is not None for x in over[0].values) else None
    groups: dict[str, list[dict]] = {}
    for row in rows:
        if row.get("status") == "ok":
            groups.setdefault(json.dumps([row.get(p) for p in group_paths], default=str), []).append(row)
    result = []
    for members in groups.values():
        entry = {"group": {p: members[0].get(p) for p in group_paths}, "over": over_paths, "cases": len(members),
                 "uplift": any(row.get("uplift") for row in members), "outputs": {}}
        for name in outputs:
            valued = [row for row in members if _number(row.get(name)) is not None]
            if not valued:
                continue
            top = max(valued, key=lambda row: row[name])
            item = {"lowest": min(row[name] for row in valued), "highest": top[name],
                    "governing": {p: top.get(p) for p in over_paths}}
            if bound is not None:
                by_value = sorted(valued, key=lambda row: row[bound.path])
                item["at_lower_bound"] = by_value[0][name]
                item["at_upper_bound"] = by_value[-1][name]
            entry["outputs"][name] = item
        result.append(entry)
    return result


def violating(rows: Sequence[dict]) -> list[dict]:
    return [row for row in rows if row.get("violations")]


def summarize(plan: SweepPlan, rows: Sequence[dict]) -> dict:
    """Counts, ranges, governing cases, envelope and the cases violating the deck's criteria."""
    counts = {status: sum(row.get("status") == status for row in rows) for status in STATUSES}
    return to_jsonable({
        "cases": len(plan.cases), "finished": len(rows), **counts,
        "ranges": ranges(plan),
        "governing": governing(plan, rows),
        "envelope": envelope(plan, rows),
        "violations": [{"case": row["case"], "inputs": inputs_of(plan, row), "violations": row["violations"]}
                       for row in violating(rows)],
        "failures": [{"case": row["case"], "inputs": inputs_of(plan, row), "status": row["status"],
                      "message": row.get("message", "")} for row in rows if row.get("status") != "ok"],
    })
