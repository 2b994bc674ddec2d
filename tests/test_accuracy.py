"""analysis/accuracy.py: the simplified engine checked against the exact engine on the same deck."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from upliftcli.analysis.accuracy import DEFAULT_BAND, Check, Comparison, all_modes, check_accuracy, compare
from upliftcli.analysis.run import run, run_one
from upliftcli.cli import app
from upliftcli.deck.criteria import check_criteria
from upliftcli.deck.load import load_deck
from upliftcli.engines.quantities import COMPARED

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
WINKLER = ROOT / "inputs" / "ten_story_winkler.toml"
SHORT = ["ground_motion.window=[0, 8]"]


def test_the_check_equals_separate_runs_of_the_two_engines():
    deck = load_deck(EXAMPLE, SHORT)
    results = run(deck)
    checks = check_accuracy(deck, results)
    assert [c.support for c in checks] == [r.support for r in results]
    for result, check in zip(results, checks, strict=True):
        exact = run_one(deck, "exact", result.support)
        values = {c.name: c for c in check.comparisons}
        assert values["base_shear"].exact == exact.base_shear
        assert values["base_moment"].exact == exact.base_moment
        assert values["drift_ratio"].exact == float(exact.drift_ratio.max())
        assert values["roof_displacement"].exact == float(exact.displacement[-1])
        assert values["floor_acceleration"].exact == float(np.max(np.abs(exact.floor_acceleration)))
        assert values["base_shear"].simplified == result.base_shear
        assert check.ratios["base_shear"] == pytest.approx(result.base_shear / exact.base_shear, rel=1e-15)
        if result.support == "uplift":  # the mat lifts: edge uplift and rotation compared too
            assert values["max_uplift"].exact == max(exact.intermediates["max_uplift_left"],
                                                     exact.intermediates["max_uplift_right"])
            assert values["max_rotation"].simplified == result.intermediates["max_rotation"]
        else:
            assert "max_uplift" not in values
        assert "accuracy" not in result.details  # the result is not changed: the check is beside it


def test_exact_results_already_run_with_all_modes_are_reused():
    deck = load_deck(EXAMPLE, [*SHORT, 'analysis.engine=["simplified", "exact"]', 'analysis.supports="uplift"'])
    results = run(deck)
    _, exact = results
    (check,) = check_accuracy(deck, results)
    assert check.comparisons[0].exact == exact.base_shear
    assert check.reference == "exact engine, all 10 modes"


def test_the_check_does_not_inherit_the_decks_mode_truncation():
    """The Winkler deck keeps 3 modes: its exact result is not the check's, which has all 10."""
    deck = load_deck(WINKLER, [*SHORT, 'analysis.engine=["simplified", "exact"]', 'analysis.supports="uplift"'])
    simplified, truncated = run(deck)
    assert truncated.periods.size == 3
    (check,) = check_accuracy(deck, [simplified, truncated])
    full = run_one(all_modes(deck), "exact", "uplift")
    assert full.periods.size == 10
    assert {c.name: c.exact for c in check.comparisons}["floor_acceleration"] == full.value("floor_acceleration")
    assert check.reference == "exact engine, all 10 modes"


def test_a_ratio_outside_the_band_is_a_warning_naming_it():
    check = Check("uplift", "exact engine, all 10 modes", (0.8, 1.25),
                  (Comparison("base_shear", 2.0e6, 1.0e6), Comparison("base_moment", 1.0, 1.0),
                   Comparison("floor_acceleration", 1.0, 2.0)), ("both edges ... (flight)",))
    assert [c.name for c in check.out_of_band] == ["base_shear", "floor_acceleration"]
    lines = check.warnings()
    assert "V_b: simplified / exact = 2 (exact 1000.0 kN) is outside [0.8, 1.25]" in lines[0]  # display units
    assert "floor acceleration: simplified / exact = 0.5 (exact 0.2039 g)" in lines[1]
    assert lines[2] == "accuracy check, exact engine, all 10 modes: both edges ... (flight)"
    assert check.largest_error() == (1.0, check.comparisons[0])  # a factor 2 either way is an error of 1
    assert check.to_dict()["out_of_band"] == ["base_shear", "floor_acceleration"]
    assert Comparison("base_shear", 1.0, 0.0).ratio is None and not Comparison("base_shear", 1.0, 0.0).outside(
        DEFAULT_BAND)


def test_the_exact_runs_warnings_are_passed_on():
    deck = load_deck(EXAMPLE, SHORT)
    (simplified,) = run(deck, "simplified", "uplift")
    exact = run_one(deck, "exact", "uplift")
    flying = replace(exact, details={**exact.details, "warnings": ["both edges were off (flight)"]})
    check = compare(simplified, flying)
    assert check.warnings()[-1] == "accuracy check, exact engine: both edges were off (flight)"
    # the deck's own warnings (analysis.run_batch puts them in both results) are not passed on again
    deck_warning = "ten_story_elcentro.toml: building.damping: 0.35 is outside building practice"
    ours = replace(simplified, details={**simplified.details, "warnings": [deck_warning]})
    theirs = replace(flying, details={**flying.details, "warnings": [deck_warning, "both edges were off (flight)"]})
    assert compare(ours, theirs).reference_warnings == ("both edges were off (flight)",)


def test_simplified_error_judges_exactly_the_ratios_the_check_flags():
    """[criteria] simplified_error = e sets the check's band to [1/(1 + e), 1 + e] and widens the motion
    band to hold it (accuracy.deck_bands): the criterion fails exactly when the check flags a ratio
    (issue 36: e = 0.25 held the edge uplift to [0.8, 1.25], the check's band for it being [0.5, 2],
    and the README example exited 3 with nothing flagged: edge uplift 0.738)."""
    deck = load_deck(EXAMPLE, SHORT)
    results = run(deck, "simplified", "uplift")
    verdicts = []
    for limit in (0.01, 0.1, 0.25, 1.5):
        judged = load_deck(EXAMPLE, [*SHORT, f"criteria.simplified_error={limit}"])
        (check,) = check_accuracy(judged, results)
        assert check.band == pytest.approx((1 / (1 + limit), 1 + limit))
        assert check.motion_band == pytest.approx((min(0.5, 1 / (1 + limit)), max(2.0, 1 + limit)))
        messages = check_criteria(results, judged.criteria, [check])
        assert bool(messages) == bool(check.out_of_band)
        worst = max(check.out_of_band, key=lambda c: c.error, default=None)
        assert worst is None or worst.describe() in messages[0]
        verdicts.append(bool(messages))
    assert verdicts[0] and not verdicts[-1]  # both sides are reached
    assert check_criteria(results, {"simplified_error": 1e-6}) == []  # no check given: nothing to apply


def test_the_readme_example_with_simplified_error_exits_3_only_with_a_flag():
    """`uplift analyze inputs/ten_story_elcentro.toml` with simplified_error = 0.25: exit 3 if and only
    if the check's table flags a ratio ('!'); it exited 3 with nothing flagged."""
    result = CliRunner().invoke(app, ["analyze", str(EXAMPLE), "--set", "criteria.simplified_error=0.25"],
                                env={"CI": "true"})
    assert result.exit_code in (0, 3), result.output
    assert (result.exit_code == 3) == (" !" in result.stdout)


def test_cli_reports_the_check_unless_told_not_to(tmp_path):
    runner = CliRunner()
    deck = str(EXAMPLE)
    document = json.loads(runner.invoke(app, ["analyze", deck, "--support", "uplift", "--set", SHORT[0],
                                              "--format", "json"]).stdout)
    assert list(document["accuracy"]["ratio"]) == list(COMPARED)
    assert document["accuracy"]["band"] == [0.8, 1.25]
    assert all(line in document["warnings"] for line in document["accuracy"]["warnings"])
    assert "accuracy" not in document["details"]
    document = json.loads(runner.invoke(app, ["analyze", deck, "--support", "uplift", "--set", SHORT[0],
                                              "--no-check", "--format", "json"]).stdout)
    assert "accuracy" not in document
    table = runner.invoke(app, ["analyze", deck, "--support", "uplift", "--set", SHORT[0]]).stdout
    assert "Accuracy check" in table and "simplified / exact" in table
    spectrum = json.loads(runner.invoke(app, ["analyze", str(ROOT / "inputs" / "ten_story_asce7.toml"),
                                              "--support", "uplift", "--format", "json"]).stdout)
    # a design spectrum: checked on a suite generated for it (analysis/suite_check.py, tests/test_suite_check.py)
    assert spectrum["accuracy"]["reference"].startswith("exact engine on a spectrum-compatible suite (11 artificial")


def test_cli_band_option_warns_and_criterion_exits_3():
    runner = CliRunner()
    args = ["analyze", str(EXAMPLE), "--support", "uplift", "--set", SHORT[0]]
    narrow = runner.invoke(app, [*args, "--set", "analysis.check_band=[0.999, 1.001]", "--format", "json"])
    assert narrow.exit_code == 0
    document = json.loads(narrow.stdout)
    named = document["accuracy"]["out_of_band"]
    assert named and all(any(COMPARED[n].symbol in w for w in narrow.stderr.splitlines()) for n in named)
    failing = runner.invoke(app, [*args, "--set", "criteria.simplified_error=0.001"])
    assert failing.exit_code == 3 and "criterion violated: simplified/uplift: simplified_error" in failing.stderr
    bad = runner.invoke(app, [*args, "--set", "analysis.check_band=[1.1, 1.3]"], env={"CI": "true"})
    assert bad.exit_code == 2 and "analysis.check_band" in bad.stderr and "low < 1 < high" in bad.stderr


def test_sweep_check_adds_the_ratios_of_matching_exact_cases(tmp_path):
    runner = CliRunner()
    result = runner.invoke(app, ["sweep", str(EXAMPLE), "--set", SHORT[0], "--vary", "building.period=0.5,1.0",
                                 "--support", "uplift", "--engine", "simplified", "--check", "--out",
                                 str(tmp_path), "--workers", "1", "-q", "--format", "json",
                                 "--set", "criteria.simplified_error=0.001"])
    assert result.exit_code == 3, result.output  # no simplified value is within 0.1 % of the exact one
    rows = json.loads(result.stdout)["rows"]
    assert all("simplified_error: " in r["violations"] for r in rows if r["engine"] == "simplified")
    assert not any("simplified_error" in r["violations"] for r in rows if r["engine"] == "exact")
    assert {(r["engine"], r["building.period"]) for r in rows} == {(e, p) for e in ("simplified", "exact")
                                                                   for p in (0.5, 1.0)}
    for row in rows:
        assert {f"check_{name}" for name in COMPARED} <= set(row)
        if row["engine"] == "simplified":
            exact = next(r for r in rows if r["engine"] == "exact" and r["building.period"] == row["building.period"])
            assert row["check_base_shear"] == pytest.approx(row["base_shear_N"] / exact["base_shear_N"], rel=1e-15)
            assert row["check_drift_ratio"] == pytest.approx(row["max_drift_ratio"] / exact["max_drift_ratio"])
            assert row["check_floor_acceleration"] == pytest.approx(
                row["max_floor_acceleration_m_s2"] / exact["max_floor_acceleration_m_s2"])
        else:
            assert row["check_base_shear"] is None


def test_sweep_check_needs_a_record_and_says_so():
    result = CliRunner().invoke(app, ["sweep", str(ROOT / "inputs" / "ten_story_asce7.toml"), "--vary",
                                      "building.period=0.5,1.0", "--check", "--workers", "1", "-q"],
                                env={"CI": "true"})
    assert result.exit_code == 2
    assert result.stderr.startswith("error: --check: ") and "a deck with a record or a record suite" in result.stderr


def test_the_edge_uplift_is_left_out_where_the_soil_yielded():
    """FS_v = 1.5 on the Winkler example: the toes yield and the mat lifts. The exact engine's edge
    uplift is then the gap above the settled level, which is not the rise of the edge above its
    rest position (measured here from the histories: 3.4 and 0.70 times it at the two edges), the
    quantity the simplified procedure estimates: it is left out of the check, with the reason, and
    of compared_values (sweep --check, simplified_error); the mat rotation stays compared. With
    FS_v = 3 on two elements no element yields: the edge uplift is compared as without a capacity."""
    from upliftcli.engines.quantities import compared_values

    deck = load_deck(WINKLER, [*SHORT, "foundation.safety_factor=1.5"])
    with_histories = replace(deck, analysis=replace(deck.analysis, exact=replace(deck.analysis.exact,
                                                                                   histories=True)))
    exact = run_one(with_histories, "exact", "uplift")
    assert exact.uplift and exact.yielded
    for side in ("left", "right"):
        edge = exact.histories[f"{side}_edge_displacement"]
        rise, gap = float(np.max(edge - edge[0])), exact.intermediates[f"max_uplift_{side}"]
        assert rise > 0.0 and gap > 0.0 and abs(gap / rise - 1.0) > 0.25
    simplified = run_one(deck, "simplified", "uplift")
    check = compare(simplified, exact)
    assert "max_uplift" not in check.ratios and "max_rotation" in check.ratios
    assert "gap above the settled level" in check.left_out["max_uplift"]
    assert check.to_dict()["left_out"] == {"max_uplift": check.left_out["max_uplift"]}
    assert compared_values(exact)["max_uplift"] is None and compared_values(simplified)["max_uplift"] > 0.0
    assert not any("edge uplift" in line for line in check.warnings())

    elastic_soil = load_deck(EXAMPLE, [*SHORT, "foundation.safety_factor=3"])
    exact = run_one(elastic_soil, "exact", "uplift")
    assert exact.uplift and exact.yielded is False
    check = compare(run_one(elastic_soil, "simplified", "uplift"), exact)
    assert check.left_out == {} and check.ratios["max_uplift"] > 0.0
    assert "left_out" not in check.to_dict()


def test_the_cli_says_why_the_edge_uplift_is_left_out():
    result = CliRunner().invoke(app, ["analyze", str(EXAMPLE), "--engine", "simplified", "--support", "uplift",
                                      "--set", "ground_motion.window=[0, 8]", "--set", "foundation.safety_factor=2"])
    assert result.exit_code == 0, result.output
    table = result.stdout[result.stdout.index("Accuracy check"):]
    row = next(line for line in table.splitlines() if "edge uplift" in line)
    assert row.split("│")[-2].strip() == "left out"
    assert "edge uplift left out: the soil yielded" in " ".join(table.split())


def test_the_report_lists_a_left_out_value_with_its_reason():
    from upliftcli.report.checks import accuracy_section

    check = Check("uplift", "exact engine, all 10 modes", comparisons=(Comparison("base_shear", 2.0e6, 2.5e6),),
                  left_out={"max_uplift": "the soil yielded"})
    (table,) = accuracy_section([], checks=[check]).blocks
    assert table.rows[-1][1:] == ["largest gap under an edge of the mat (uplift) [mm]", "-", "-", "-", "left out"]
    assert table.note.endswith("largest gap under an edge of the mat (uplift) left out: the soil yielded.")
