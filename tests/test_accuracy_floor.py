"""The oracle of benchmarks/accuracy_floor.py (docs/accuracy.md, "Is the goal reachable"): the
least-squares fit, its out-of-fold predictions grouped by record, and the statistics, on synthetic
data with known answers."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import accuracy_floor as floor


def test_the_fit_recovers_known_coefficients_whatever_the_scale_of_a_column():
    rng = np.random.default_rng(1)
    features = np.column_stack([np.ones(200), rng.normal(size=200), 1e4 * rng.normal(size=200)])
    truth = np.array([0.3, -1.2, 2e-5])
    assert floor.fit(features, features @ truth) == pytest.approx(truth, rel=1e-9, abs=1e-12)


def test_out_of_fold_predictions_of_an_exact_linear_target_are_exact():
    rng = np.random.default_rng(2)
    features = np.column_stack([np.ones(120), rng.normal(size=(120, 2))])
    target = features @ np.array([1.0, 0.5, -0.25])
    groups = np.repeat(np.arange(6), 20)
    assert np.allclose(floor.grouped_oof(features, target, groups), target, atol=1e-12)


def test_out_of_fold_leaves_the_whole_group_out():
    """A target that is one constant per group, an intercept only: the prediction of a group is the
    mean of the OTHER groups' cases (leaving out single cases would give nearly the group's own)."""
    sizes, levels = np.array([3, 5, 4, 8]), np.array([1.0, -2.0, 0.5, 3.0])
    groups, target = np.repeat(np.arange(4), sizes), np.repeat(levels, sizes)
    out = floor.grouped_oof(np.ones((target.size, 1)), target, groups)
    for g in range(4):
        others = (levels @ sizes - levels[g] * sizes[g]) / (sizes.sum() - sizes[g])
        assert np.allclose(out[groups == g], others)


def test_out_of_fold_by_record_and_system_sees_neither():
    """Target = record level + system level, an intercept only: a cell (record r, system i) is
    predicted by the mean of the cases whose record is not r and whose system is not i."""
    rng = np.random.default_rng(3)
    records, systems = np.repeat(np.arange(5), 12), np.tile(np.repeat(np.arange(4), 3), 5)
    target = rng.normal(size=5)[records] + rng.normal(size=4)[systems]
    out = floor.grouped_oof(np.ones((target.size, 1)), target, records, systems)
    for r in range(5):
        for i in range(4):
            cell = (records == r) & (systems == i)
            assert np.allclose(out[cell], target[(records != r) & (systems != i)].mean())


def test_summary_counts_the_tails_and_the_quantile_width():
    ratios = np.array([0.5, 0.79, 0.81, 1.0, 1.0, 1.19, 1.21, 2.0])
    stats = floor.summary(np.log(ratios))
    assert stats["n"] == 8
    assert stats["low"] == pytest.approx(2 / 8) and stats["high"] == pytest.approx(2 / 8)
    assert stats["median"] == pytest.approx(1.0)
    q05, q80 = np.quantile(np.log(ratios), [0.05, 0.8])
    assert stats["width"] == pytest.approx(q80 - q05)


def test_the_log_normal_limit_on_the_scatter():
    """5 % below ln 0.8 and 20 % above ln 1.2 with the median between: s (z_0.95 + z_0.80) = ln 1.5."""
    from scipy.stats import norm

    assert np.log(1.5) / (norm.ppf(0.95) + norm.ppf(0.80)) == pytest.approx(floor.S_LIMIT, rel=1e-4)


def test_the_floor_factor_leaves_ten_percent_more_than_20_percent_low():
    log_ratios = np.log(np.linspace(0.5, 1.5, 1001))
    factor = floor.floor_factor(log_ratios)
    assert np.mean(log_ratios + np.log(factor) < np.log(0.8)) == pytest.approx(0.10, abs=2e-3)


def test_record_families():
    assert floor.family_of("nearfield-14a X") == "near-field pulse"
    assert floor.family_of("nearfield-15a X") == "near-field no pulse"
    assert floor.family_of("farfield-03a X") == "far field"
    assert floor.family_of("El Centro 1940") == "El Centro"


def test_the_factors_that_meet_the_goals():
    """Log-ratios with the quantiles of a normal distribution. s = 0.10 about the median 1: the
    median bounds the factor to 0.95-1.10 (the low tail alone allows 0.8 e^(1.645 s) = 0.943, the high
    tail 1.2 e^(-0.842 s) = 1.103). s = 0.15 about the median 1.3: the tails bind, 0.8 e^(1.645 s)/1.3
    to 1.2 e^(-0.842 s)/1.3. s = 0.25: none (1.645 s + 0.842 s > ln 1.5)."""
    from scipy.stats import norm

    grid = norm.ppf((np.arange(20000) + 0.5) / 20000)
    low, high = floor.factors(0.10 * grid)
    assert low == pytest.approx(0.95, rel=1e-6) and high == pytest.approx(1.10, rel=1e-6)
    low, high = floor.factors(np.log(1.3) + 0.15 * grid)
    assert low == pytest.approx(0.8 * np.exp(0.15 * norm.ppf(0.95)) / 1.3, rel=1e-3)
    assert high == pytest.approx(1.2 * np.exp(-0.15 * norm.ppf(0.80)) / 1.3, rel=1e-3)
    assert floor.factors(0.25 * grid) is None
