"""`uplift analyze --engine exact` end to end: tables, JSON keys, histories, errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from typer.testing import CliRunner

from upliftcli.cli import app

DECK = Path(__file__).resolve().parents[1] / "inputs" / "ten_story_elcentro.toml"
runner = CliRunner()


def test_exact_json_has_the_simplified_keys_and_the_uplift_summary(tmp_path):
    result = runner.invoke(app, ["analyze", str(DECK), "--engine", "exact", "--support", "uplift",
                                 "--set", "ground_motion.window=[0.0, 8.0]", "--format", "json"])
    assert result.exit_code in (0, 3), result.output
    document = json.loads(result.stdout)
    for key in ("engine", "support", "base_shear", "base_shear_coefficient", "base_moment",
                "critical_base_shear", "uplift", "periods", "stories"):
        assert key in document
    assert document["engine"] == "exact" and document["uplift"] is True
    assert document["base_shear"] > document["critical_base_shear"]
    summary = document["details"]["uplift_summary"]
    assert summary["episodes"] >= 1 and summary["uplift_time"] > 0


def test_histories_csv_matches_the_reported_peak(tmp_path):
    target = tmp_path / "h.csv"
    result = runner.invoke(app, ["analyze", str(DECK), "--engine", "exact", "--support", "uplift",
                                 "--set", "ground_motion.window=[0.0, 8.0]", "--format", "json",
                                 "--histories", str(target)])
    assert result.exit_code in (0, 3), result.output
    document = json.loads(result.stdout)
    assert "histories" not in document["details"]
    lines = target.read_text().splitlines()
    assert lines[0].startswith("# uplift ") and lines[1].startswith("# provenance: ")  # docs/provenance.md
    header = lines[2].split(",")
    # the one column style of every CSV file: quantity_unit
    assert header[0] == "time_s" and "contact_state" in header and "drift_1_m" in header
    assert "ground_acceleration_m_s2" in header and "theta_rad" in header
    table = np.loadtxt(target, delimiter=",", skiprows=3)
    base_shear = table[:, header.index("base_shear_N")]
    # the sampled peak is at most the reported (between-samples) peak, and close to it
    assert np.abs(base_shear).max() <= document["base_shear"] * (1 + 1e-9)
    assert np.abs(base_shear).max() > 0.99 * document["base_shear"]


def test_histories_npz_one_file_per_analysis(tmp_path):
    target = tmp_path / "h.npz"
    result = runner.invoke(app, ["analyze", str(DECK), "--engine", "exact", "--support", "rigid",
                                 "--support", "uplift", "--set", "ground_motion.window=[0.0, 4.0]",
                                 "--histories", str(target)])
    assert result.exit_code in (0, 3), result.output
    for support in ("rigid", "uplift"):
        data = np.load(tmp_path / f"h_exact_{support}.npz")
        assert data["time"][0] == 0.0 and "drift_10" in data.files


def test_histories_needs_a_history_engine_and_a_known_suffix(tmp_path):
    result = runner.invoke(app, ["analyze", str(DECK), "--histories", str(tmp_path / "h.csv")])
    assert result.exit_code == 2 and "exact" in result.output
    result = runner.invoke(app, ["analyze", str(DECK), "--engine", "exact", "--histories", str(tmp_path / "h.txt")])
    assert result.exit_code == 2 and ".npz" in result.output
    assert not list(tmp_path.iterdir())


def test_flight_refused_exits_4_with_one_line():
    result = runner.invoke(app, ["analyze", str(DECK), "--engine", "exact", "--support", "uplift",
                                 "--set", "building.period=0.08", "--set", "analysis.exact.flight=\"error\""])
    assert result.exit_code == 4
    assert "flight" in result.output and "Traceback" not in result.output
