"""accuracy.py: the simplified engine checked against the exact engine on the same deck."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from upliftcli.accuracy import check_accuracy
from upliftcli.analysis import run, run_one
from upliftcli.cli import app
from upliftcli.deck import load_deck

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
SHORT = ["ground_motion.window=[0, 8]"]


def test_the_check_equals_separate_runs_of_the_two_engines():
    deck = load_deck(EXAMPLE, SHORT)
    results = run(deck)
    check_accuracy(deck, results)
    for result in results:
        check = result.details["accuracy"]
        exact = run_one(deck, "exact", result.support)
        assert check["exact"]["base_shear"] == exact.base_shear
        assert check["exact"]["base_moment"] == exact.base_moment
        assert check["exact"]["max_drift_ratio"] == float(exact.drift_ratio.max())
        assert check["exact"]["roof_displacement"] == float(exact.displacement[-1])
        assert check["simplified"]["base_shear"] == result.base_shear
        assert check["ratio"]["base_shear"] == pytest.approx(result.base_shear / exact.base_shear, rel=1e-15)


def test_exact_results_already_run_are_reused():
    deck = load_deck(EXAMPLE, [*SHORT, 'analysis.engine=["simplified", "exact"]', 'analysis.supports="uplift"'])
    results = run(deck)
    check_accuracy(deck, results)
    simplified, exact = results
    assert simplified.details["accuracy"]["exact"]["base_shear"] == exact.base_shear
    assert "accuracy" not in exact.details


def test_cli_reports_the_check_unless_told_not_to(tmp_path):
    runner = CliRunner()
    deck = str(EXAMPLE)
    document = json.loads(runner.invoke(app, ["analyze", deck, "--support", "uplift", "--set", SHORT[0],
                                              "--format", "json"]).stdout)
    assert set(document["accuracy"]["ratio"]) == {"base_shear", "base_moment", "max_drift_ratio",
                                                  "roof_displacement"}
    assert "accuracy" not in document["details"]
    document = json.loads(runner.invoke(app, ["analyze", deck, "--support", "uplift", "--set", SHORT[0],
                                              "--no-check", "--format", "json"]).stdout)
    assert "accuracy" not in document
    table = runner.invoke(app, ["analyze", deck, "--support", "uplift", "--set", SHORT[0]]).stdout
    assert "Accuracy check" in table and "simplified / exact" in table
    spectrum = json.loads(runner.invoke(app, ["analyze", str(ROOT / "inputs" / "ten_story_asce7.toml"),
                                              "--support", "uplift", "--format", "json"]).stdout)
    # a design spectrum: checked on a suite generated for it (suite_check.py, tests/test_suite_check.py)
    assert spectrum["accuracy"]["reference"] == "exact-suite"


def test_sweep_check_adds_the_ratios_of_matching_exact_cases(tmp_path):
    runner = CliRunner()
    result = runner.invoke(app, ["sweep", str(EXAMPLE), "--set", SHORT[0], "--vary", "building.period=0.5,1.0",
                                 "--support", "uplift", "--engine", "simplified", "--check", "--out",
                                 str(tmp_path), "--workers", "1", "-q", "--format", "json"])
    assert result.exit_code in (0, 3), result.output
    rows = json.loads(result.stdout)["rows"]
    assert {(r["engine"], r["building.period"]) for r in rows} == {(e, p) for e in ("simplified", "exact")
                                                                   for p in (0.5, 1.0)}
    for row in rows:
        if row["engine"] == "simplified":
            exact = next(r for r in rows if r["engine"] == "exact" and r["building.period"] == row["building.period"])
            assert row["check_base_shear"] == pytest.approx(row["base_shear_N"] / exact["base_shear_N"], rel=1e-15)
            assert row["check_max_drift_ratio"] == pytest.approx(row["max_drift_ratio"] / exact["max_drift_ratio"])
        else:
            assert row["check_base_shear"] is None


def test_sweep_check_needs_a_record_and_says_so():
    result = CliRunner().invoke(app, ["sweep", str(ROOT / "inputs" / "ten_story_asce7.toml"), "--vary",
                                      "building.period=0.5,1.0", "--check", "--workers", "1", "-q"],
                                env={"CI": "true"})
    assert result.exit_code == 2
    assert result.stderr.startswith("error: --check: ") and "a deck with a record or a record suite" in result.stderr
