"""sweep/table.py: the summary and the envelope over foundation fields."""


import pytest
from sweep_cases import EXAMPLE, memory_store

from upliftcli.sweep import table as sweep_table
from upliftcli.sweep.executors import SerialExecutor
from upliftcli.sweep.plan import (
    plan_sweep,
)
from upliftcli.sweep.run import run_sweep

# ----------------------------------------------------------------------------- parsing


def test_envelope_over_foundation_stiffness():
    """Bonded tends to rigid as k_f grows (T1bar -> T_1): the upper-bound row equals the rigid one
    to the period lengthening; lower and upper bound are the rows at the smallest and largest k_f."""
    plan = plan_sweep(EXAMPLE, [], ["foundation.k_f=1e8:1e15:8:log"], ["simplified"], ["rigid", "bonded"])
    rows = run_sweep(plan, SerialExecutor(), memory_store()).rows
    envelope = sweep_table.envelope(plan, rows)
    assert [e["group"] for e in envelope] == [{"engine": "simplified", "support": "rigid"},
                                              {"engine": "simplified", "support": "bonded"}]
    bonded = [r for r in rows if r["support"] == "bonded"]
    rigid = rows[0]
    item = envelope[1]["outputs"]["base_shear_coefficient"]
    assert item["at_lower_bound"] == bonded[0]["base_shear_coefficient"]
    assert item["at_upper_bound"] == bonded[-1]["base_shear_coefficient"]
    assert item["highest"] == max(r["base_shear_coefficient"] for r in bonded)
    assert item["lowest"] == min(r["base_shear_coefficient"] for r in bonded)
    assert bonded[-1]["T1bar_s"] == pytest.approx(rigid["T1_s"], rel=1e-4)
    assert bonded[-1]["base_shear_coefficient"] == pytest.approx(rigid["base_shear_coefficient"], rel=1e-3)
    rigid_item = envelope[0]["outputs"]["max_drift_ratio"]
    assert rigid_item["lowest"] == rigid_item["highest"]  # a rigid base does not see k_f
    governing = sweep_table.governing(plan, rows)
    top = max(rows, key=lambda r: r["base_shear_coefficient"])
    assert governing["base_shear_coefficient"]["case"] == top["case"]
    summary = sweep_table.summarize(plan, rows)
    assert summary["ok"] == len(rows) and summary["ranges"][0]["lowest"] == 1e8


def test_tables_carry_the_sweep_provenance(small_plan, serial_rows, tmp_path):
    """CSV ('#' lines), JSON and Parquet hold the same provenance: the record's SHA-256 computed
    here, the varied values, and the deck's model with the --set overrides (and --engine, --support)."""
    import hashlib
    import json

    from sweep_cases import ROOT

    from upliftcli.provenance.record import read_csv_provenance

    record = ROOT / "records" / "elcentro_1940_ns_chopra.txt"
    paths = sweep_table.write_tables(small_plan, serial_rows, tmp_path, "p", "json")
    csv_record = read_csv_provenance(paths[0].read_text())
    json_record = json.loads(paths[1].read_text())["provenance"]
    assert csv_record == json_record
    (entry,) = [f for f in json_record["files"] if f["role"] == "record"]
    assert entry["sha256"] == hashlib.sha256(record.read_bytes()).hexdigest() and entry["format"] == "shared"
    assert json_record["files"][0]["sha256"] == hashlib.sha256(EXAMPLE.read_bytes()).hexdigest()
    assert json_record["sweep"]["varied"] == [{"path": v.path, "unit": v.unit, "spacing": v.spacing,
                                               "values": list(v.values)} for v in small_plan.varies]
    assert json_record["sweep"]["cases"] == len(small_plan.cases) == 14
    # --engine and --support are the deck's analysis.engine and analysis.supports of every case
    assert json_record["deck"]["set"] == {"ground_motion.window": [0, 6], "analysis.engine": ["simplified", "exact"],
                                          "analysis.supports": ["rigid", "bonded", "uplift"]}
    pq = pytest.importorskip("pyarrow.parquet")
    parquet = sweep_table.write_tables(small_plan, serial_rows, tmp_path, "q", "parquet")[1]
    metadata = pq.read_schema(parquet).metadata
    assert json.loads(metadata[b"provenance"])["files"] == json_record["files"]


def test_a_varied_simplified_error_limit_is_each_cases_own():
    """add_checks judges each simplified row by its own criteria.simplified_error when it is varied
    (it used the deck's, so --vary criteria.simplified_error=0.01,1 found no violation at all)."""
    from types import SimpleNamespace

    from upliftcli.engines.quantities import COMPARED

    name = next(iter(COMPARED))
    path = "criteria.simplified_error"
    plan = SimpleNamespace(varies=[SimpleNamespace(path=path)], criteria={}, motion_band=(0.5, 2.0))
    rows = [{"engine": engine, "support": "uplift", "status": "ok", path: limit, "violations": "",
             "compared": {name: value}}
            for limit in (0.01, 1.0) for engine, value in (("simplified", 1.2), ("exact", 1.0))]
    checked = sweep_table.add_checks(plan, rows)
    simplified = [row for row in checked if row["engine"] == "simplified"]
    assert [row[f"check_{name}"] for row in simplified] == pytest.approx([1.2, 1.2])
    assert simplified[0]["violations"].startswith(f"simplified_error: {COMPARED[name].symbol} simplified / exact = "
                                                  "1.2 outside [0.99, 1.01]")
    assert simplified[1]["violations"] == ""  # 1.2 is within [0.5, 2]


def test_a_sweeps_simplified_error_judges_the_mats_motion_on_the_checks_motion_band():
    """simplified_error = 0.25 holds V_b to [0.8, 1.25] and the edge uplift and mat rotation to the
    check's motion band [0.5, 2] (widened to hold [0.8, 1.25]): what `uplift analyze` flags (issue 36:
    they were held to [0.8, 1.25])."""
    from types import SimpleNamespace

    plan = SimpleNamespace(varies=[], criteria={"simplified_error": 0.25}, motion_band=(0.5, 2.0))
    simplified = {"base_shear": 1.3, "max_uplift": 0.6, "max_rotation": 0.45}
    rows = [{"engine": engine, "support": "uplift", "status": "ok", "violations": "",
             "compared": simplified if engine == "simplified" else dict.fromkeys(simplified, 1.0)}
            for engine in ("simplified", "exact")]
    (checked, _) = sweep_table.add_checks(plan, rows)
    violations = checked["violations"].split("; ")
    assert [v.split(":")[1].strip().split(" simplified")[0] for v in violations] == ["V_b", "mat rotation"]
    assert violations[0].endswith("outside [0.8, 1.25]") and violations[1].endswith("outside [0.5, 2]")


# ----------------------------------------------------------------------------- streamed (issue 38 item 5)

def _once(rows):
    """The rows as an iterator: what reads them twice gets nothing the second time."""
    return iter(list(rows))


@pytest.mark.parametrize("count", [0, 1, 14])
def test_the_streamed_json_document_is_the_document_dumped_at_once(small_plan, serial_rows, count):
    """write_document writes json.dumps(document(...), indent=1) a row at a time (no row list; none, one, many
    rows), with the summary after the rows; the summary made in one pass over the rows is the same."""
    import json

    rows = serial_rows[:count]
    summary = sweep_table.summarize(small_plan, _once(rows))
    assert summary == sweep_table.summarize(small_plan, rows)
    pieces = []
    sweep_table.write_document(pieces.append, small_plan, _once(rows), summary)
    expected = json.dumps(sweep_table.document(small_plan, rows, summary), indent=1) + "\n"
    assert "".join(pieces) == expected and len(pieces) == count + 2


def test_the_summary_of_a_stream_keeps_the_first_largest_and_the_bounds_of_a_stable_sort(small_plan):
    """One pass: the governing case and the envelope's highest are the first of equal values (as max gives
    it), at_lower_bound the first row at the bound's smallest value and at_upper_bound the last at its
    largest (as a stable sort gives them)."""
    def row(case, ratio, shear):
        return {"case": case, "engine": "simplified", "support": "uplift", "status": "ok", "building.period": 0.4,
                "foundation.frequency_ratio": ratio, "base_shear_coefficient": shear}

    rows = [row(0, 16, 0.2), row(1, 4, 0.3), row(2, 4, 0.5), row(3, 16, 0.5), row(4, 4, 0.1), row(5, 16, 0.4)]
    summary = sweep_table.summarize(small_plan, _once(rows))
    assert summary["governing"]["base_shear_coefficient"]["case"] == 2
    (group,) = [g for g in summary["envelope"] if g["group"]["building.period"] == 0.4]
    item = group["outputs"]["base_shear_coefficient"]
    assert (item["lowest"], item["highest"], item["governing"]) == (0.1, 0.5, {"foundation.frequency_ratio": 4})
    assert (item["at_lower_bound"], item["at_upper_bound"]) == (0.3, 0.4)
    assert group["cases"] == 6 and summary["ok"] == 6 and summary["failures"] == []


def test_arrow_columns_built_in_chunks_write_the_parquet_file_of_whole_columns(tmp_path):
    """Columns built from chunks of 2 rows give the arrays (and the Parquet bytes) of pa.array over each
    whole column: one type; ints then floats; None only, then floats; text and numbers (JSON texts)."""
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    from upliftcli.sweep import stream

    columns = {"x": [1.5, 2.0, 3.25, None, 5.0], "n": [1, 2, 3.5, 4, 5], "e": [None, None, 1.0, 2.0, None],
               "m": [1, "a", 2, "b", None], "t": ["a", "b", "c", "d", "e"], "l": [[1], [2], [3.5], None, []]}
    rows = [{name: values[k] for name, values in columns.items()} for k in range(5)]
    built = stream.ArrowColumns(pa, list(columns), chunk=2)
    for row in rows:
        built.add(row)
    arrays = built.arrays(lambda name: list(columns[name]))
    whole = {name: stream.arrow_column(pa, values) for name, values in columns.items()}
    assert all(arrays[name].equals(whole[name]) and arrays[name].type == whole[name].type for name in columns)
    pq.write_table(pa.table(arrays), tmp_path / "chunked.parquet")
    pq.write_table(pa.table(whole), tmp_path / "whole.parquet")
    assert (tmp_path / "chunked.parquet").read_bytes() == (tmp_path / "whole.parquet").read_bytes()


def test_tables_are_written_from_rows_read_once(small_plan, serial_rows, tmp_path):
    """write_tables reads the rows once for the CSV and the JSON document (an iterator will do); written
    from rows given as a list, the files are the same."""
    once = sweep_table.write_tables(small_plan, _once(serial_rows), tmp_path / "once", "p", "json")
    listed = sweep_table.write_tables(small_plan, serial_rows, tmp_path / "listed", "p", "json")
    assert [p.read_bytes() for p in once] == [p.read_bytes() for p in listed]
    assert once[1].read_text().count('"case"') >= len(serial_rows)
