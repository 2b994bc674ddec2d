"""`uplift analyze` / `uplift modes` end to end through typer's test runner."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from upliftcli.cli import app

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"

runner = CliRunner()


def invoke(*args, env=None):
    return runner.invoke(app, [str(a) for a in args], env={"CI": "true", **(env or {})})


def test_modes_table_reproduces_the_paper():
    result = invoke("modes", EXAMPLE, "--format", "json")
    assert result.exit_code == 0, result.output
    modes = json.loads(result.stdout)["modes"]
    np.testing.assert_allclose([m["frequency_ratio"] for m in modes[:5]], [1, 2.98, 4.89, 6.69, 8.34], atol=0.01)
    np.testing.assert_allclose([m["effective_mass_ratio"] for m in modes[:5]], [0.844, 0.091, 0.031, 0.014, 0.007],
                               atol=0.005)
    np.testing.assert_allclose([m["effective_height_over_b"] for m in modes[:5]], [10, -3.4, 2, -1.5, 1.2], atol=0.05)
    assert modes[-1]["cumulative_mass_ratio"] == pytest.approx(1.0)
    table = invoke("modes", EXAMPLE)
    assert table.exit_code == 0
    assert "h_n*/b" in table.stdout and "2.978" in table.stdout


def test_analyze_table_without_terminal():
    result = invoke("analyze", EXAMPLE)
    assert result.exit_code == 0, result.output
    for words in ("rigid support", "bonded support", "uplift support", "Summary", "T1bar", "xi1bar", "V_c",
                  "drift ratio [%]"):
        assert words in result.stdout


def test_analyze_json_single_support_matches_paper_quantities():
    result = invoke("analyze", EXAMPLE, "--format", "json", "--support", "uplift")
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    for key in ("engine", "support", "base_shear", "base_shear_coefficient", "base_moment", "critical_base_shear",
                "uplift", "periods", "stories"):
        assert key in doc
    assert doc["engine"] == "simplified" and doc["support"] == "uplift"
    assert doc["uplift"] is True
    inter = doc["intermediates"]
    assert inter["T1bar/T1"] == pytest.approx(1.525, abs=5e-4)
    assert inter["xi1bar"] == pytest.approx(0.0328, abs=5e-5)
    # critical coefficient V_c/(m_t g) = b/h_1* = 0.1 for the paper's example
    assert doc["critical_base_shear"] / doc["weight"] == pytest.approx(0.1)
    stories = doc["stories"]
    assert [s["story"] for s in stories] == list(range(1, 11))
    assert stories[0]["shear"] == pytest.approx(doc["base_shear"])
    assert stories[0]["moment"] == pytest.approx(doc["base_moment"])
    for key in ("displacement", "drift", "drift_ratio"):
        assert all(s[key] > 0 for s in stories)


def test_three_supports_order_the_base_shears():
    doc = json.loads(invoke("analyze", EXAMPLE, "--format", "json").stdout)
    shears = {r["support"]: r["base_shear"] for r in doc["results"]}
    assert shears["uplift"] < shears["bonded"] < shears["rigid"]


def test_set_override_changes_the_period():
    doc = json.loads(invoke("analyze", EXAMPLE, "--format", "json", "--support", "rigid",
                            "--set", "building.period=1.0", "--set", "foundation.b=4").stdout)
    assert doc["periods"][0] == pytest.approx(1.0)


def test_out_writes_the_result_files(deck_dir):
    out = deck_dir / "results"
    result = invoke("analyze", deck_dir / "inputs" / "deck.toml", "--out", out)
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in out.iterdir()) == ["deck.csv", "deck.elements.csv", "deck.json", "deck.toml"]
    doc = json.loads((out / "deck.json").read_text())
    assert len(doc["results"]) == 3


def test_criteria_violation_exits_3(deck_dir):
    deck = deck_dir / "inputs" / "deck.toml"
    result = invoke("analyze", deck, "--set", "criteria.drift_ratio=0.001")
    assert result.exit_code == 3
    assert "criterion violated" in result.stderr and "drift_ratio" in result.stderr
    assert invoke("analyze", deck, "--set", "criteria.uplift=false", "--support", "bonded").exit_code == 0


BAD_DECKS = [
    ("floor_mass = 350e3", "flor_mass = 350e3", "building.flor_mass"),
    ("floor_mass = 350e3", "", "building.floor_mass"),
    ("floor_mass = 350e3", "floor_mass = -1.0", "building.floor_mass"),
    ("period = 0.5", "story_stiffness = 0.0", "building.story_stiffness"),
    ("story_height = 3.5", "story_height = -3.5", "building.story_height"),
    ("damping = 0.05", "damping = 1.2", "building.damping"),
    ("slenderness = 10", "b = 0.0", "foundation.b"),
    ("scale = 1.0", "scael = 1.0", "ground_motion.scael"),
    ("stories = 10", "stories = = 10", "line"),
    ('record = "../records/elcentro_1940_ns_chopra.txt"', 'record = "../records/missing.txt"', "missing.txt"),
]


@pytest.mark.parametrize("old, new, words", BAD_DECKS)
def test_bad_input_one_line_exit_2_no_output(deck_dir, old, new, words):
    deck = deck_dir / "inputs" / "deck.toml"
    text = deck.read_text()
    assert old in text
    deck.write_text(text.replace(old, new, 1))
    out = deck_dir / "results"
    result = invoke("analyze", deck, "--out", out)
    assert result.exit_code == 2, result.output
    assert result.stdout == ""
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0]
    assert "Traceback" not in result.output
    assert not out.exists()


def test_unreadable_record_content(deck_dir):
    (deck_dir / "records" / RECORD.name).write_text("# time_s accel_g\n0.0 0.0\n0.02 x\n")
    result = invoke("analyze", deck_dir / "inputs" / "deck.toml")
    assert result.exit_code == 2
    assert "line 3" in result.stderr and len(result.stderr.strip().splitlines()) == 1


def test_bad_set_path_and_value():
    result = invoke("analyze", EXAMPLE, "--set", "foundation.bb=4")
    assert result.exit_code == 2
    assert result.stderr.startswith("error: --set: foundation.bb:") and "did you mean 'foundation.b'" in result.stderr
    result = invoke("modes", EXAMPLE, "--set", "building.period=-1")
    assert result.exit_code == 2 and "--set: building.period" in result.stderr


def test_missing_deck_file(tmp_path):
    result = invoke("analyze", tmp_path / "none.toml")
    assert result.exit_code == 2 and "file not found" in result.stderr


def test_unknown_engine(deck_dir):
    deck = deck_dir / "inputs" / "deck.toml"
    result = invoke("analyze", deck, "--engine", "nonsense")
    assert result.exit_code == 2 and result.stderr.startswith("error: --engine: nonsense: one of")
    result = invoke("analyze", deck, "--engine", "EXACT")  # the option is named, not a --set of analysis.engine
    assert result.exit_code == 2
    assert result.stderr.strip() == ("error: --engine: EXACT: one of simplified, approximate, exact or all "
                                     "(names are lower case: 'exact')")


def test_main_entry_point_exit_code(deck_dir, monkeypatch, capsys):
    from upliftcli.cli import main

    monkeypatch.setattr("sys.argv", ["uplift", "analyze", str(deck_dir / "inputs" / "none.toml")])
    with pytest.raises(SystemExit) as info:
        main()
    assert info.value.code == 2
    assert "file not found" in capsys.readouterr().err


@pytest.mark.parametrize("deck", sorted((ROOT / "inputs").glob("*.toml")), ids=lambda p: p.name)
def test_every_bundled_deck_runs(deck):
    result = invoke("analyze", deck, "--format", "json")
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    for item in doc.get("results", [doc]):
        assert math.isfinite(item["base_shear"]) and item["base_shear"] > 0
        if "suite" in deck.name:  # record suites: the history engines run every record
            assert item["engine"] == "exact" and item["suite"]["count"] >= 11
            assert len(item["suite"]["records"]) == item["suite"]["count"]
    assert invoke("modes", deck).exit_code == 0


def test_out_must_be_a_directory(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    result = invoke("analyze", EXAMPLE, "--out", blocker)
    assert result.exit_code == 2 and "--out" in result.stderr
    assert blocker.read_text() == "x"
