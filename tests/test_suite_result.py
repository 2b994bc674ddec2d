"""Suite statistics (engines/suite_result.py) on made-up results, against numpy on the stacked peaks."""

from __future__ import annotations

import numpy as np
import pytest

from upliftcli.engines.result import AnalysisResult
from upliftcli.engines.suite_result import (
    STATISTICS,
    SuiteRecord,
    SuiteResult,
    compared_values,
    simplified_ratios,
    statistic_of,
    suite_result,
)

RNG = np.random.default_rng(12)


def made_up(k: int, uplift: bool = False, engine: str = "exact") -> AnalysisResult:
    """A three-story result with random positive peaks (record k)."""
    shear = np.sort(RNG.uniform(1e6, 3e6, 3))[::-1]
    peaks = {"displacement": np.cumsum(RNG.uniform(0.01, 0.02, 3)), "drift_ratio": RNG.uniform(1e-3, 5e-3, 3),
             "shear": shear, "moment": np.cumsum(shear[::-1])[::-1] * 3.0, "reaction": RNG.uniform(1e6, 2e6, 2)}
    return AnalysisResult(engine, "uplift", np.array([3.0, 6.0, 9.0]), peaks, 1.5e6, 1.2e7, 9.80665 * 6e5, 7.0, uplift,
                          np.array([0.5, 0.17, 0.1]), np.array([-2.0, 2.0]),
                          times={"shear": RNG.uniform(0, 10, 3)},
                          intermediates={"n_modes": 3, "max_rotation": float(RNG.uniform(0, 0.01)),
                                         "transitions": int(k), "criterion": "reaction"},
                          details={"modal_base_shear": list(RNG.uniform(0, 1e6, 3)), "energy": {"input": 1.0}})


@pytest.fixture(scope="module")
def results():
    return [made_up(k, uplift=k % 3 == 0) for k in range(7)]


@pytest.mark.parametrize("name, function", [("mean", np.mean), ("median", np.median), ("max", np.max),
                                            ("p84", lambda a, axis: np.percentile(a, 84, axis=axis))])
def test_each_statistic_is_taken_value_by_value(results, name, function):
    stat = statistic_of(results, name)
    for key in results[0].peaks:
        np.testing.assert_allclose(stat.peaks[key], function(np.stack([r.peaks[key] for r in results]), axis=0),
                                   rtol=1e-15)
    # the scalars are the story-1 values: the statistic of the records' scalars
    assert stat.base_shear == pytest.approx(function(np.array([r.base_shear for r in results]), axis=0), rel=1e-15)
    assert stat.base_moment_coefficient == pytest.approx(
        function(np.array([r.base_moment_coefficient for r in results]), axis=0), rel=1e-15)
    np.testing.assert_allclose(stat.details["modal_base_shear"],
                               function(np.array([r.details["modal_base_shear"] for r in results]), axis=0))
    assert stat.intermediates["max_rotation"] == pytest.approx(
        function(np.array([r.intermediates["max_rotation"] for r in results]), axis=0))


def test_what_does_not_average(results):
    stat = statistic_of(results, "mean")
    assert stat.uplift is True  # lifts off under records 0, 3, 6
    assert statistic_of(results[1:3], "mean").uplift is False
    assert stat.times == {}  # instants of one record's peaks have no statistic
    assert stat.intermediates["n_modes"] == 3 and stat.intermediates["criterion"] == "reaction"
    assert "transitions" not in stat.intermediates  # differs between records, not a peak
    assert "energy" not in stat.details
    np.testing.assert_array_equal(stat.elevations, results[0].elevations)


def test_percentile_84_of_eleven_values():
    """Linear between order statistics: rank 0.84 x 10 = 8.4 -> x(8) + 0.4 (x(9) - x(8))."""
    values = np.arange(11.0) ** 2
    assert STATISTICS["p84"][1](values) == pytest.approx(64 + 0.4 * (81 - 64))


def test_suite_result_is_the_design_statistic(results):
    records = [SuiteRecord(f"r{k}", f"r{k}.txt", 1.0 + k) for k in range(len(results))]
    result = suite_result(results, records, "max", rule="ec8", rule_label="EN 1998-1", warnings=["few"])
    assert isinstance(result, SuiteResult) and isinstance(result, AnalysisResult)
    assert result.count == 7 and result.uplift_count == 3 and result.label == "exact (max of 7)"
    np.testing.assert_array_equal(result.drift_ratio, result.statistics["max"].drift_ratio)
    assert result.value("drift_ratio") == max(float(r.drift_ratio.max()) for r in results)
    assert set(result.statistics) == set(STATISTICS)
    assert result.record_results[2] is results[2] and result.warnings == ("few",)
    result.peaks["shear"][0] = -1.0  # the design result owns its peaks dict, the statistic is not changed
    assert result.statistics["max"].peaks is not result.peaks
    with pytest.raises(ValueError):
        suite_result(results, records[:-1], "mean")


def test_simplified_ratios(results):
    simplified = made_up(99, engine="simplified")
    result = suite_result(results, [SuiteRecord(f"r{k}", "", 1.0) for k in range(7)], "mean", simplified=simplified)
    ratios = simplified_ratios(result)
    mine, theirs = compared_values(result), compared_values(simplified)
    assert theirs["roof_displacement"] == simplified.displacement[-1]
    assert theirs["drift_ratio"] == simplified.drift_ratio.max()
    assert {"base_shear", "base_moment", "drift_ratio", "roof_displacement", "floor_acceleration"} <= set(ratios)
    for name, item in ratios.items():
        assert item["ratio"] == pytest.approx(theirs[name] / mine[name]) if mine[name] else np.isnan(item["ratio"])
    assert simplified_ratios(suite_result(results, [SuiteRecord("r", "", 1.0)] * 7, "mean")) == {}
