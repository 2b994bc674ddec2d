"""The global acceptance of ASCE 7-22 16.4.1 (analysis/acceptance.py) from plain values, with
hand-checked means, and on a small suite analysed by the exact engine with story strengths."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from upliftcli.analysis import acceptance as acc

NAMES = ["a", "b", "c"]
# three records, two stories: story 1 means (0.02 + 0.04 + 0.03) / 3 = 0.03, story 2 (0.01 + 0.02 + 0.06) / 3 = 0.03
PEAKS = [[0.02, 0.01], [0.04, 0.02], [0.03, 0.06]]
RESIDUALS = [[0.001, 0.0], [0.004, -0.002], [0.001, 0.005]]


def test_permitted_unacceptable_responses_by_risk_category():
    assert [acc.permitted_unacceptable(rc) for rc in ("I", "II", "III", "IV")] == [1, 1, 0, 0]
    with pytest.raises(ValueError):
        acc.permitted_unacceptable("V")


def test_the_drift_limit_is_twice_table_12_12_1():
    assert acc.drift_limit(0.02) == 0.04
    assert acc.drift_limit(0.01) == 0.02
    assert acc.drift_limit(None) is None


def test_hand_checked_means_pass_under_twice_the_limit():
    result = acc.acceptance(NAMES, PEAKS, RESIDUALS, [None, None, None], "II", 0.02)
    assert result.mean_drift_ratio == pytest.approx((0.03, 0.03), rel=1e-15)
    assert result.limit == 0.04
    assert result.accepted and result.violations() == []
    # residuals: |values|; story 1 mean (0.001 + 0.004 + 0.001) / 3 = 0.002, max 0.004;
    # story 2 mean 0.007 / 3, max 0.005
    assert result.residual_mean == pytest.approx((0.002, 0.007 / 3), rel=1e-14)
    assert result.residual_max == (0.004, 0.005)


def test_a_mean_above_twice_the_limit_is_one_violation_per_story():
    # Risk Category IV, all other structures: 0.010, limit 0.020 < 0.03 in both stories
    result = acc.acceptance(NAMES, PEAKS, RESIDUALS, [None, None, None], "IV", 0.010)
    assert result.limit == 0.02
    assert result.exceeding_stories == [1, 2]
    lines = result.violations("exact/rigid")
    assert len(lines) == 2
    assert lines[0].startswith("exact/rigid: story 1: the mean peak drift ratio 0.03 exceeds 2 x")
    assert "ASCE 7-22 16.4.1.2" in lines[0]
    assert not result.accepted


def test_a_single_peak_above_the_limit_does_not_fail_a_mean_below_it():
    # record c's story 2 (0.06) exceeds 0.04, the mean 0.03 does not: 16.4.1.2 judges the mean
    result = acc.acceptance(NAMES, PEAKS, RESIDUALS, [None, None, None], "I", 0.02)
    assert result.accepted


def test_unacceptable_responses_one_permitted_for_risk_category_ii_none_for_iii():
    one = [None, "the mat flew", None]
    assert acc.acceptance(NAMES, PEAKS, RESIDUALS, one, "II", 0.02).accepted
    third = acc.acceptance(NAMES, PEAKS, RESIDUALS, one, "III", 0.015)
    assert third.unacceptable == {"b": "the mat flew"}
    assert not third.accepted
    assert third.violations() == ["1 of 3 ground motions gave an unacceptable response (b), 0 permitted for Risk "
                                  "Category III (ASCE 7-22 16.4.1.1)"]
    two = acc.acceptance(NAMES, PEAKS, RESIDUALS, ["x", "y", None], "II", 0.02)
    assert not two.unacceptable_ok


def test_no_limit_judges_no_drift():
    result = acc.acceptance(NAMES, PEAKS, RESIDUALS, [None] * 3, "II", None)
    assert result.limit is None and result.exceeding_stories == [] and result.accepted


def test_the_dictionary_holds_every_figure():
    document = acc.acceptance(NAMES, PEAKS, RESIDUALS, [None, "r", None], "II", 0.02).to_dict()
    assert document["clause"] == "ASCE 7-22 16.4.1"
    assert document["accepted"] is True
    assert document["unacceptable"] == {"b": "r"}
    assert document["drift_limit"] == 0.04
    assert document["mean_drift_ratio"] == pytest.approx([0.03, 0.03])
    assert document["residual_drift_ratio_max"] == [0.004, 0.005]


@pytest.mark.parametrize("peaks, residuals, reasons", [
    ([[0.01, 0.02]], RESIDUALS, [None]),
    (PEAKS, RESIDUALS, [None, None]),
    ([[0.01, float("nan")], [0.0, 0.0], [0.0, 0.0]], RESIDUALS, [None] * 3),
    ([], [], []),
])
def test_inconsistent_values_are_refused(peaks, residuals, reasons):
    with pytest.raises(ValueError):
        acc.acceptance(NAMES[:len(reasons)], peaks, residuals, reasons, "II", 0.02)


def test_flight_is_an_unacceptable_response():
    flew = SimpleNamespace(details={"uplift_summary": {"flight_time": 0.12}})
    stayed = SimpleNamespace(details={"uplift_summary": {"flight_time": 0.0}})
    assert "flew for 0.12 s" in acc.flight_reason(flew)
    assert acc.flight_reason(stayed) is None
    assert acc.flight_reason(SimpleNamespace(details={})) is None


def test_violations_of_results_without_an_acceptance_are_none():
    assert acc.acceptance_violations([SimpleNamespace(engine="exact", support="rigid")]) == []
    failing = acc.acceptance(NAMES, PEAKS, RESIDUALS, [None] * 3, "IV", 0.010)
    result = SimpleNamespace(engine="exact", support="bonded", acceptance=failing)
    assert acc.acceptance_violations([result])[0].startswith("exact/bonded: story 1:")
