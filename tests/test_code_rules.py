"""Code rules of record suites: counts, statistic, period ranges against the clauses."""

from __future__ import annotations

import pytest

from upliftcli.motion.code_rules import RULES


def test_asce7_22_counts_and_mean():
    rule = RULES["asce7-22"]
    assert (rule.min_records, rule.scaled_mean, rule.matched_mean) == (11, 0.9, 1.1)
    assert rule.statistic(3) == "mean" and rule.mean_minimum("amplitude") == 0.9 and rule.mean_minimum("match") == 1.1
    (message,) = rule.count_warnings(7)
    assert message == "ASCE 7-22 16.2 asks for at least 11 records; the suite has 7"
    assert rule.count_warnings(11) == []


def test_ec8_takes_the_maximum_below_seven_records():
    rule = RULES["ec8"]
    assert [rule.statistic(n) for n in (3, 6, 7, 11)] == ["max", "max", "mean", "mean"]
    assert RULES["asce7-22"].statistic(5) == "mean" and RULES["mean"].statistic(1) == "mean"
    assert rule.count_warnings(7) == []
    (message,) = rule.count_warnings(5)
    assert "with fewer than 7 records the design value is the maximum" in message
    assert len(rule.count_warnings(2)) == 2  # fewer than 3 as well
    assert rule.stationary_duration == 10.0


def test_period_ranges():
    # ASCE 7-22 16.2.3.1: upper 2 x the largest first-mode period, lower min(0.2 T_1, T_90)
    (low, high), note = RULES["asce7-22"].period_range(1.2, 1.0, 0.33)
    assert (low, high) == pytest.approx((0.2, 2.4)) and "T_90 = 0.33 s" in note
    (low, high), _ = RULES["asce7-22"].period_range(1.2, 1.0, 0.15)
    assert low == pytest.approx(0.15)
    # EN 1998-1 3.2.3.1.2(4): 0.2 T_1 to 2 T_1
    (low, high), _ = RULES["ec8"].period_range(1.2, 1.0, 0.15)
    assert (low, high) == pytest.approx((0.2, 2.4))


