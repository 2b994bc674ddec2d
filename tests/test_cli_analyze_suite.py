"""`uplift analyze` on a record suite deck, end to end: the JSON `suite` object, the terminal
tables (statistics, each record, the simplified engine beside the suite), the CSV rows per
record, the warnings, criteria on the design statistic, histories per record, bad input."""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import invoke

from upliftcli.engines.quantities import COMPARED

ROOT = Path(__file__).resolve().parents[1]
ASCE = ROOT / "inputs" / "ten_story_asce7_suite.toml"
THREE = "ground_motion.suite=" + json.dumps([f"../records/ten_story_asce7_suite/artificial_2024_{k:02d}.txt"
                                             for k in (1, 2, 3)])



@pytest.fixture(scope="module")
def document():
    result = invoke("analyze", ASCE, "--set", THREE, "--support", "rigid", "--support", "uplift", "-f", "json")
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout), result.stderr


def test_json_suite_object(document):
    doc, _ = document
    rigid, uplift = doc["results"]
    suite = uplift["suite"]
    assert suite["rule"] == "asce7-22" and suite["statistic"] == "mean" and suite["count"] == 3
    assert suite["scaling"] == "none" and len(suite["period_range"]) == 2 and suite["period_note"]
    assert [r["name"] for r in suite["records"]] == ["artificial_2024_01", "artificial_2024_02", "artificial_2024_03"]
    manifest = json.loads((ROOT / "records" / "ten_story_asce7_suite" / "manifest.json").read_text())
    assert [r["sha256"] for r in suite["records"]] == [r["sha256"] for r in manifest["records"][:3]]
    assert all(r["factor"] == 1.0 and r["result"]["engine"] == "exact" for r in suite["records"])
    shears = [r["result"]["base_shear"] for r in suite["records"]]
    assert uplift["base_shear"] == pytest.approx(np.mean(shears), rel=1e-14)  # the design value
    assert suite["statistics"]["max"]["base_shear"] == max(shears)
    assert suite["statistics"]["median"]["stories"][0]["shear"] == pytest.approx(np.median(shears), rel=1e-14)
    assert set(suite["statistics"]) == {"mean", "median", "p84", "max"}
    compared = suite["simplified"]["compared"]
    assert list(compared) == list(COMPARED)  # the one list of compared values, uplift's motion included
    assert compared["base_shear"]["ratio"] == pytest.approx(compared["base_shear"]["simplified"] / uplift["base_shear"])
    assert compared["roof_displacement"]["statistic"] == pytest.approx(uplift["stories"][-1]["displacement"])
    assert suite["uplift_records"] == 3 and rigid["suite"]["uplift_records"] == 0 and uplift["uplift"] is True
    assert doc["units"]["factor"] == "-" and doc["units"]["roof_displacement"] == "m"


def test_too_few_records_is_a_warning_naming_the_rule(document):
    _, stderr = document
    lines = [line for line in stderr.splitlines() if "at least 11 records" in line]
    assert lines == ["warning: ASCE 7-22 16.2 asks for at least 11 records; the suite has 3"]  # once, not per support


def test_tables(tmp_path):
    result = invoke("analyze", ASCE, "--set", THREE, "--support", "uplift")
    assert result.exit_code == 0, result.output
    out = result.stdout
    for words in ("exact engine, uplift support: mean of 3 records (ASCE 7-22 16.2)",
                  "statistics of 3 records", "84th percentile", "mean *", "each record", "artificial_2024_02",
                  "Simplified engine on the target spectrum against the suite", "simplified / suite",
                  "roof displacement [mm]", "exact (mean of 3)", "uplift under 3 of 3 records"):
        assert words in out, words


def table_lines(path):
    """The lines of a CSV result after its '#' provenance lines."""
    return [line for line in path.read_text().splitlines() if not line.startswith("#")]


def test_csv_rows_per_record_and_files(tmp_path):
    out = tmp_path / "results"
    result = invoke("analyze", ASCE, "--set", THREE, "--support", "uplift", "--out", out)
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader(table_lines(out / "ten_story_asce7_suite.csv")))
    assert [key for key in rows[0]][:5] == ["engine", "support", "statistic", "record", "story"]
    statistic = [r for r in rows if r["statistic"] == "mean"]
    per_record = {name: [r for r in rows if r["record"] == name] for name in {r["record"] for r in rows} if name}
    assert len(statistic) == 10 and sorted(per_record) == [f"artificial_2024_{k:02d}" for k in (1, 2, 3)]
    for j in range(10):
        values = [float(per_record[name][j]["drift_ratio"]) for name in sorted(per_record)]
        assert float(statistic[j]["drift_ratio"]) == pytest.approx(np.mean(values), rel=1e-14)
    elements = list(csv.DictReader(table_lines(out / "ten_story_asce7_suite.elements.csv")))
    assert len(elements) == 2 * 4 and elements[0]["statistic"] == "mean" and elements[2]["record"]
    doc = json.loads((out / "ten_story_asce7_suite.json").read_text())
    assert doc["suite"]["count"] == 3


def test_criteria_on_the_design_statistic(document):
    doc, _ = document
    uplift = doc["results"][1]
    mean = max(s["drift_ratio"] for s in uplift["stories"])
    largest = max(s["drift_ratio"] for s in uplift["suite"]["statistics"]["max"]["stories"])
    between = f"criteria.drift_ratio={0.5 * (mean + largest)!r}"
    assert invoke("analyze", ASCE, "--set", THREE, "--support", "uplift", "--set", between,
                  "-f", "json").exit_code == 0
    result = invoke("analyze", ASCE, "--set", THREE, "--support", "uplift", "--set",
                    f"criteria.drift_ratio={0.99 * mean!r}", "-f", "json")
    assert result.exit_code == 3
    assert "criterion violated: exact/uplift (mean of 3 records): drift_ratio" in result.stderr


def test_histories_one_file_per_record(tmp_path):
    target = tmp_path / "h.npz"
    result = invoke("analyze", ASCE, "--set", THREE, "--support", "uplift", "-f", "json", "--histories", target)
    assert result.exit_code == 0, result.output
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == [f"h_exact_uplift_r0{k}.npz" for k in (1, 2, 3)]
    doc = json.loads(result.stdout)
    assert all("histories" not in r["result"]["details"] for r in doc["suite"]["records"])
    with np.load(tmp_path / "h_exact_uplift_r02.npz") as data:  # the peak lies between the samples
        sampled, peak = float(np.max(np.abs(data["base_shear"]))), doc["suite"]["records"][1]["result"]["base_shear"]
        assert 0.99 * peak < sampled <= peak


def test_a_missing_record_stops_before_any_output(tmp_path):
    (tmp_path / "inputs").mkdir()
    folder = tmp_path / "records" / "suite"
    folder.mkdir(parents=True)
    for k in (1, 2):
        shutil.copy(ROOT / "records" / "ten_story_asce7_suite" / f"artificial_2024_{k:02d}.txt", folder)
    deck = tmp_path / "inputs" / "deck.toml"
    deck.write_text(ASCE.read_text().replace("../records/ten_story_asce7_suite", "../records/suite"))
    assert invoke("analyze", deck, "--support", "uplift", "-f", "json").exit_code == 0
    (folder / "artificial_2024_02.txt").write_text("# dt = 0.01 s\n0.0\nx\n")
    out = tmp_path / "out"
    result = invoke("analyze", deck, "--out", out)
    assert result.exit_code == 2 and result.stdout == ""
    assert len(result.stderr.strip().splitlines()) == 1 and "artificial_2024_02.txt" in result.stderr
    assert not out.exists()
