"""The global acceptance of ASCE 7-22 16.4.1 on a suite deck with story strengths and a [design]
table, end to end (analysis/acceptance.py, cli/render_acceptance.py, report/acceptance.py): the
means checked by hand from each record's own peaks, the JSON, the terminal, the report, exit 3."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from cli_helpers import invoke

from upliftcli.analysis import run as analysis
from upliftcli.deck.criteria import check_criteria
from upliftcli.deck.load import load_deck

ROOT = Path(__file__).resolve().parents[1]
ASCE = ROOT / "inputs" / "ten_story_asce7_suite.toml"
THREE = "ground_motion.suite=" + json.dumps([f"../records/ten_story_asce7_suite/artificial_2024_{k:02d}.txt"
                                             for k in (1, 2, 3)])
#: a chapter 16 deck's [design]: the risk category and the structure's row of Table 12.12-1 (no R, C_d)
DESIGN = ["design.structure=all-other"]
#: Risk Category IV (limit 2 x 0.010) and a weak building: story 1 exceeds the limit
FAILING = [THREE, *DESIGN, "design.risk_category=IV", "building.strength_coefficient=0.1"]
#: Risk Category II (limit 2 x 0.020) and a strong building: every story within it
PASSING = [THREE, *DESIGN, "design.risk_category=II", "building.strength_coefficient=0.5"]


def settings(values):
    return [item for value in values for item in ("--set", value)]


@pytest.fixture(scope="module")
def failing():
    result = invoke("analyze", ASCE, *settings(FAILING), "--support", "rigid", "--no-check", "-f", "json")
    return result, json.loads(result.stdout)


def test_a_mean_drift_above_twice_the_limit_exits_3_and_says_so(failing):
    result, _ = failing
    assert result.exit_code == 3, result.output
    lines = [line for line in result.stderr.splitlines() if line.startswith("criterion violated:")]
    assert lines and "story 1: the mean peak drift ratio" in lines[0] and "ASCE 7-22 16.4.1.2" in lines[0]


def test_the_json_acceptance_is_the_hand_checked_mean_of_the_records(failing):
    _, doc = failing
    suite = doc["suite"]
    found = suite["acceptance"]
    assert found["clause"] == "ASCE 7-22 16.4.1" and found["risk_category"] == "IV"
    assert found["drift_limit"] == pytest.approx(0.02, rel=1e-15) and found["permitted_unacceptable"] == 0
    records = [record["result"]["stories"] for record in suite["records"]]
    assert len(records) == 3
    for j in range(10):
        a, b, c = (stories[j]["drift_ratio"] for stories in records)
        assert found["mean_drift_ratio"][j] == pytest.approx((a + b + c) / 3.0, rel=1e-14)
        ra, rb, rc = (abs(stories[j]["residual_drift_ratio"]) for stories in records)
        assert found["residual_drift_ratio_mean"][j] == pytest.approx((ra + rb + rc) / 3.0, rel=1e-14)
        assert found["residual_drift_ratio_max"][j] == max(ra, rb, rc)
    exceeding = [j + 1 for j in range(10) if found["mean_drift_ratio"][j] > 0.02]
    assert found["exceeding_stories"] == exceeding and 1 in exceeding
    assert found["accepted"] is False and found["unacceptable"] == {}


def test_a_passing_suite_exits_0_and_the_terminal_shows_the_table():
    result = invoke("analyze", ASCE, *settings(PASSING), "--support", "rigid", "--no-check")
    assert result.exit_code == 0, result.output
    text = " ".join(result.stdout.split())  # the terminal wraps the title
    assert "global acceptance of ASCE 7-22 16.4.1 (Risk Category II): accepted" in text
    assert "residual drift ratio: mean" in text
    assert "criterion violated" not in result.stderr


def test_the_acceptance_is_carried_by_each_support_and_judged_by_check_criteria():
    deck = load_deck(ASCE, [*PASSING, "analysis.supports=['rigid', 'uplift']"])
    results = analysis.run(deck)
    assert [r.support for r in results] == ["rigid", "uplift"]
    assert all(r.acceptance is not None and r.acceptance.accepted for r in results)
    assert check_criteria(results, deck.criteria) == []
    strict = load_deck(ASCE, [*FAILING, "analysis.supports=['uplift']"])
    lines = check_criteria(analysis.run(strict), strict.criteria)
    assert lines and all("16.4.1" in line for line in lines)


@pytest.mark.parametrize("dropped", ["design", "strengths"])
def test_no_acceptance_without_a_design_table_or_strengths(dropped):
    values = [THREE, "building.strength_coefficient=0.2"] if dropped == "design" else [THREE, *DESIGN,
                                                                                       "design.risk_category=II"]
    result = invoke("analyze", ASCE, *settings(values), "--support", "rigid", "--no-check", "-f", "json")
    assert result.exit_code == 0, result.output
    assert "acceptance" not in json.loads(result.stdout)["suite"]


def test_the_report_has_the_section_and_exits_3(tmp_path):
    out = tmp_path / "report.html"
    result = invoke("report", ASCE, *settings(FAILING), "--no-check", "--out", out)
    assert result.exit_code == 3, result.output
    html = out.read_text()
    assert "Global acceptance of ASCE 7-22 16.4.1, exact engine, rigid support: not accepted" in html
    assert "The global acceptance of ASCE 7-22 16.4.1 is not met" in html
