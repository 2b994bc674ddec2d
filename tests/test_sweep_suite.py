"""Sweeps of a record suite deck: one row per case holding the design statistic (equal to the
suite analysis of the case's own deck), each record's row on request, foundation-only
variations still one batch per record, the suite following the structure it is scaled for."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from upliftcli.analysis.run import run_one
from upliftcli.cli import app
from upliftcli.deck.load import load_deck
from upliftcli.errors import InputError
from upliftcli.sweep import table as sweep_table
from upliftcli.sweep.chunks import make_chunks
from upliftcli.sweep.executors import SerialExecutor
from upliftcli.sweep.plan import plan_sweep
from upliftcli.sweep.run import run_sweep
from upliftcli.sweep.store import RowStore
from upliftcli.sweep.worker import build_case_deck, run_chunk

ROOT = Path(__file__).resolve().parents[1]
ASCE = ROOT / "inputs" / "ten_story_asce7_suite.toml"
THREE = "ground_motion.suite=" + json.dumps([f"../records/ten_story_asce7_suite/artificial_2024_{k:02d}.txt"
                                             for k in (1, 2, 3)])
RATIOS = "foundation.frequency_ratio=4,8,16"
runner = CliRunner()


def table_lines(path: Path) -> list[str]:
    """The lines of a CSV table after its '#' provenance lines."""
    return [line for line in path.read_text().splitlines() if not line.startswith("#")]


@pytest.fixture(scope="module")
def plan():
    return plan_sweep(ASCE, [THREE], [RATIOS], ["exact"], ["uplift"], per_record=True)


@pytest.fixture(scope="module")
def rows(plan):
    return [row for chunk in make_chunks(plan, plan.cases, len(plan.cases)) for row in run_chunk(chunk)]


def test_a_case_row_holds_the_statistic_of_its_deck(plan, rows):
    assert plan.suite_records == 3
    assert any("at least 11 records" in message for message in plan.warnings)
    for case, row in zip(plan.cases, rows, strict=True):
        deck = load_deck(ASCE, [THREE] + [f"{path}={value}" for path, value in case.overrides])
        result = run_one(deck, "exact", "uplift")
        assert row["status"] == "ok" and row["statistic"] == "mean" and row["records"] == 3
        assert row["base_shear_N"] == result.base_shear and row["max_drift_ratio"] == result.value("drift_ratio")
        assert row["mode1_base_shear_coefficient"] == pytest.approx(
            np.mean([r.details["modal_base_shear"][0] for r in result.record_results]) / result.weight, rel=1e-14)
        records = row["record_rows"]
        assert [r["record"] for r in records] == [r.name for r in result.records]
        assert [r["max_reaction_N"] for r in records] == [r.value("reaction") for r in result.record_results]
        assert row["base_shear_N"] == pytest.approx(np.mean([r["base_shear_N"] for r in records]), rel=1e-14)


def test_foundation_only_variations_run_one_batch_per_record(plan, batch_sizes):
    """The three foundations change T1bar and so the suite's period range, not its records (scaling
    = "none"): one exact-engine batch of the three systems per record."""
    fresh = run_chunk(make_chunks(plan, plan.cases, len(plan.cases))[0])
    assert batch_sizes == [3, 3, 3] and all(row["status"] == "ok" for row in fresh)


def test_the_suite_follows_the_structure_it_is_scaled_for(plan):
    """The period range of a suite comes from the structure: each foundation gets its own suite."""
    ranges = set()
    for case in plan.cases:
        deck = build_case_deck(plan.raw, plan.source, list(plan.base_overrides) + list(case.overrides))
        assert deck.ground_motion.period_range == load_deck(
            ASCE, [THREE] + [f"{p}={v}" for p, v in case.overrides]).ground_motion.period_range
        ranges.add(deck.ground_motion.period_range)
    assert len(ranges) == 3


def test_tables_with_and_without_the_record_rows(plan, rows, tmp_path):
    names = sweep_table.columns(plan)
    assert names[:5] == ["case", "engine", "support", "statistic", "record"] and "factor" in names
    table = sweep_table.table_rows(plan, rows)
    assert len(table) == 3 * 4
    names = [r.get("record") for r in table[:4]]
    assert names == [None, "artificial_2024_01", "artificial_2024_02", "artificial_2024_03"]
    assert all(r["foundation.frequency_ratio"] == 4 and r["key"] == rows[0]["key"] for r in table[:4])
    written = sweep_table.write_tables(plan, rows, tmp_path, "s")
    csv_rows = list(csv.DictReader(line for line in written[0].read_text().splitlines() if not line.startswith("#")))
    assert len(csv_rows) == 12 and csv_rows[1]["factor"] == "1.0" and csv_rows[1]["statistic"] == ""
    document = json.loads(written[1].read_text())
    assert len(document["rows"]) == 12 and document["units"]["records"] == "-"
    plan.per_record = False
    try:
        assert len(sweep_table.table_rows(plan, rows)) == 3
        assert len(sweep_table.document(plan, rows)["rows"]) == 3
    finally:
        plan.per_record = True
    summary = sweep_table.summarize(plan, rows)  # over the cases' statistics only
    assert summary["governing"]["max_drift_ratio"]["value"] == max(row["max_drift_ratio"] for row in rows)


def test_record_rows_survive_a_resume(plan, rows, tmp_path):
    store = RowStore(tmp_path / "rows.jsonl")
    first = run_sweep(plan, SerialExecutor(), store)
    again = run_sweep(plan, SerialExecutor(), store, resume=True)
    assert again.reused == 3
    assert [r["record_rows"] for r in again.rows] == [r["record_rows"] for r in first.rows]
    assert sweep_table.table_rows(plan, again.rows) == sweep_table.table_rows(plan, first.rows)


def test_per_record_needs_a_suite_run_by_a_history_engine():
    with pytest.raises(InputError, match="--per-record"):
        plan_sweep(ASCE, [THREE], [], ["simplified"], ["uplift"], per_record=True)
    with pytest.raises(InputError, match="--per-record"):
        plan_sweep(ROOT / "inputs" / "ten_story_elcentro.toml", [], [], ["exact"], ["uplift"], per_record=True)


def test_sweep_and_spectra_commands_on_a_suite_deck(tmp_path):
    result = runner.invoke(app, ["sweep", str(ASCE), "--set", THREE, "--vary", "foundation.frequency_ratio=4,8",
                                 "--support", "uplift", "--per-record", "--out", str(tmp_path), "--workers", "1",
                                 "--quiet"], env={"CI": "true"})
    assert result.exit_code == 0, result.output
    assert result.stderr.count("at least 11 records") == 1
    rows = list(csv.DictReader(table_lines(tmp_path / "ten_story_asce7_suite.frequency_ratio.sweep.csv")))
    assert len(rows) == 2 * 4 and [r["statistic"] for r in rows[:2]] == ["mean", ""]
    result = runner.invoke(app, ["spectra", str(ASCE), "--set", THREE, "--periods", "0.8,1.2", "--support",
                                 "rigid,uplift", "--out", str(tmp_path), "--workers", "1", "--plot-format", "svg",
                                 "--quiet"], env={"CI": "true"})
    assert result.exit_code == 0, result.output
    spectra = list(csv.DictReader(table_lines(tmp_path / "ten_story_asce7_suite.spectra.csv")))
    assert len(spectra) == 4 and {(r["statistic"], r["records"]) for r in spectra} == {("mean", "3")}
    assert (tmp_path / "ten_story_asce7_suite.spectra.base_shear_exact.svg").exists()


def test_a_case_the_suite_cannot_serve_refuses_the_sweep_before_it_runs(tmp_path):
    """T_1 = 4 s asks for records of 4 x its period range's upper end, longer than the suite's
    20 s: the sweep is refused before any analysis (issue 36: minutes of work ended in exit 4),
    in one line naming --periods, the longest period the suite serves and the records' duration."""
    result = runner.invoke(app, ["spectra", str(ASCE), "--set", THREE, "--periods", "1,4", "--out", str(tmp_path),
                                 "--workers", "1", "--quiet"], env={"CI": "true"})
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("error: --periods: 1,4: values the deck's record suite can serve: up to "
                                    "building.period = 1 s, the longest value asked that it serves (1 of 2 asked it "
                                    "cannot, e.g. duration: a record of at least 4 x the upper period")
    assert len(result.stderr.splitlines()) == 1 and "building.period=4" in result.stderr
    assert not (tmp_path / "ten_story_asce7_suite.spectra.csv").exists()
    swept = runner.invoke(app, ["sweep", str(ASCE), "--set", THREE, "--vary", "building.period=1,4", "--out",
                                str(tmp_path), "--workers", "1", "--quiet"], env={"CI": "true"})
    assert swept.exit_code == 2 and swept.stderr.startswith("error: --vary: building.period: values the deck's "
                                                            "record suite can serve: up to building.period = 1 s")


def test_the_bundled_suite_deck_under_spectra_is_refused_at_once_with_the_default_periods(tmp_path):
    """inputs/ten_story_asce7_suite.toml and the default --periods (0.05-5 s, 100): the cases'
    suites are built from 5 s down and the first served period ends the planning, before any
    analysis: one line naming --periods and the longest period its 20 s records serve."""
    result = runner.invoke(app, ["spectra", str(ASCE), "--out", str(tmp_path), "--quiet"], env={"CI": "true"})
    assert result.exit_code == 2, result.output
    (line,) = result.stderr.splitlines()
    served = re.search(r"^error: --periods: 0\.05:5:100: values the deck's record suite can serve: up to "
                       r"building\.period = ([\d.]+) s, the longest value asked that it serves \((\d+) of 100 asked "
                       r"it cannot, e\.g\. duration: a record of at least 4 x the upper period", line)
    assert served and 1.5 < float(served.group(1)) < 2.5 and int(served.group(2)) == 20
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
@pytest.mark.parametrize("deck", ["ten_story_asce7_suite.toml", "ten_story_ec8_suite.toml"])
def test_the_example_suite_decks_run_under_spectra(deck, tmp_path):
    """The example suite decks under `uplift spectra`: the default periods (0.05-5 s, 100) are
    refused at planning, naming the longest period their 20 s records serve (T_1 above about
    2 s, where the suite's period range asks for longer records); a period they serve runs (the
    default grid would take minutes of the exact engine on 11 and 7 records)."""
    from upliftcli.sweep import figures

    with pytest.raises(InputError, match=r"^--vary: building\.period: values the deck's record suite can serve: up "
                                         r"to building\.period = [\d.]+ s"):
        plan_sweep(ROOT / "inputs" / deck, varies=[figures.period_vary("0.05:5:100")])
    result = runner.invoke(app, ["spectra", str(ROOT / "inputs" / deck), "--periods", "0.5", "--support", "uplift",
                                 "--out", str(tmp_path), "--workers", "1", "--quiet"], env={"CI": "true"})
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader(table_lines(tmp_path / f"{Path(deck).stem}.spectra.csv")))
    assert [row["status"] for row in rows] == ["ok"]
