"""engines/exact/mat_motion.py: the mat rotation and the settlement of its edges and centre
(docs/theory.md 14.7), peak between samples and residual, on the exact engine's uplift runs."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from paper_example import paper_system

from upliftcli.engines.exact import engine as exact
from upliftcli.engines.exact.mat_motion import cubic_extrema
from upliftcli.engines.options import ExactOptions
from upliftcli.engines.quantities import ROCKING
from upliftcli.model.foundations import Winkler
from upliftcli.motion.records import read_record

RECORD = Path(__file__).resolve().parents[1] / "records" / "elcentro_1940_ns_chopra.txt"
MOTION = ("rotation", "residual_rotation", "settlement", "residual_settlement")


def _record(seconds: float = 12.0):
    record = read_record(RECORD, units="g")
    return SimpleNamespace(acceleration=record.acceleration[:round(seconds / record.dt) + 1], dt=record.dt)


def _settlements(histories: dict, half_width: float) -> np.ndarray:
    """-(v - x theta - v_rest) at x = -b, 0, +b from the engine's histories, (n, 3)."""
    x = np.array([-half_width, 0.0, half_width])
    v, theta = histories["v"][:, None], histories["theta"][:, None]
    return -(v - x * theta - (histories["v"][0] - x * histories["theta"][0]))


def test_cubic_extrema_against_dense_evaluation():
    rng = np.random.default_rng(7)
    p0, p1, m0, m1 = rng.normal(size=(4, 500))
    m0[:50] = 0.0  # a stationary end
    p1[50:100], m1[50:100] = p0[50:100], -m0[50:100]  # symmetric
    high, high_s, low, low_s = cubic_extrema(p0, p1, m0, m1)
    s = np.linspace(0.0, 1.0, 20001)[:, None]
    dense = (((2 * s - 3) * s * s + 1) * p0 + ((s - 2) * s + 1) * s * m0 + (3 - 2 * s) * s * s * p1
             + (s - 1) * s * s * m1)
    assert np.all(high >= dense.max(axis=0) - 1e-14) and np.all(low <= dense.min(axis=0) + 1e-14)
    np.testing.assert_allclose(high, dense.max(axis=0), atol=1e-7)
    np.testing.assert_allclose(low, dense.min(axis=0), atol=1e-7)
    # the bound by which MatMotion.add skips intervals: |p| <= max(|p0|, |p1|) + 4/27 (|m0| + |m1|)
    bound = np.maximum(np.abs(p0), np.abs(p1)) + 4.0 / 27.0 * (np.abs(m0) + np.abs(m1))
    assert np.all(np.abs(dense).max(axis=0) <= bound + 1e-14)
    grid = np.linspace(0.0, 1.0, 20001)
    np.testing.assert_allclose(high_s, grid[dense.argmax(axis=0)], atol=1e-3)
    np.testing.assert_allclose(low_s, grid[dense.argmin(axis=0)], atol=1e-3)


@pytest.mark.parametrize("foundation", ["two-element", "winkler"])
def test_peaks_and_residuals_against_the_histories(foundation):
    """The peaks lie at or above the largest sampled values, by less than a sinusoid sampled six
    times a period can hide (1/cos(pi/6) = 1.155: the default step is the governing period / 6),
    the residuals are the last samples, and the settlements those of v and theta at x = -b, 0, +b
    (the accuracy between samples: test_peaks_converge_with_the_step)."""
    system = paper_system(1.0)
    if foundation == "winkler":
        k = system.foundation.stiffness
        system = replace(system, foundation=Winkler(3.0 * k / system.half_width, 0.0, 20))
    result = exact.analyze(system, _record(), "uplift", ExactOptions(histories=True))
    h = result.histories
    settlements = _settlements(h, system.half_width)
    sampled = np.abs(h["theta"]).max()
    assert result.intermediates["max_uplift_left"] > 0.0  # it lifts
    assert sampled == result.intermediates["max_rotation"]
    assert sampled <= result.peaks["rotation"][0] <= sampled * 1.155
    np.testing.assert_array_less(settlements.max(axis=0) - 1e-15, result.peaks["settlement"])
    np.testing.assert_array_less(result.peaks["settlement"], settlements.max(axis=0) * 1.155)
    assert result.peaks["residual_rotation"][0] == abs(h["theta"][-1])
    np.testing.assert_allclose(result.peaks["residual_settlement"], settlements[-1], rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(result.times["residual_settlement"], h["time"][-1])
    for name in MOTION:
        assert result.peaks[name].size == (3 if ROCKING[name].where == "mat-points" else 1)
        assert result.times[name].size == result.peaks[name].size


def test_peaks_converge_with_the_step():
    """The default step (6 per governing period) against a step 16 times finer: the peaks
    between samples (cubic Hermite, O(h^4)) agree to 5e-4 (measured 1.2e-4 at most over T_1 =
    0.2, 0.5, 1 s, two elements and Winkler; their sampled values: 4e-3)."""
    system = paper_system(0.5)
    coarse = exact.analyze(system, _record(), "uplift", ExactOptions())
    fine = exact.analyze(system, _record(), "uplift", ExactOptions(steps_per_period=96))
    for name in ("rotation", "settlement"):
        np.testing.assert_allclose(coarse.peaks[name], fine.peaks[name], rtol=5e-4, err_msg=name)
        np.testing.assert_allclose(coarse.times[name], fine.times[name], atol=0.02, err_msg=name)


def test_without_uplift_the_centre_stays_and_the_edges_follow_the_rotation():
    """A mat too wide to lift (h_1*/b = 0.5): every element stays in contact, the vertical motion
    of a symmetric mat is not excited by a horizontal record (v stays v_st), so the centre does
    not settle and each edge settles by b times the rotation that pushes it down."""
    system = paper_system(0.5, slenderness=0.5)
    result = exact.analyze(system, _record(6.0), "uplift", ExactOptions(histories=True))
    assert not result.uplift
    b = system.half_width
    static = system.weight / system.foundation.stiffness / 2.0
    assert abs(result.peaks["settlement"][1]) < 1e-9 * static
    theta = result.histories["theta"]
    assert result.peaks["settlement"][0] == pytest.approx(b * max(-theta.min(), 0.0), rel=1e-2)  # sampled
    assert result.peaks["settlement"][2] == pytest.approx(b * theta.max(), rel=1e-2)
    assert max(result.peaks["settlement"][[0, 2]]) == pytest.approx(b * result.peaks["rotation"][0], rel=1e-12)


@pytest.mark.parametrize("support", ["rigid", "bonded"])
def test_only_the_uplift_runs_of_the_exact_engine_report_them(support):
    result = exact.analyze(paper_system(0.5), _record(3.0), support, ExactOptions())
    assert not set(MOTION) & set(result.peaks)
    approximate = exact.analyze(paper_system(0.5), _record(3.0), "uplift", ExactOptions(), name="approximate")
    assert not set(MOTION) & set(approximate.peaks)


def test_at_rest_the_edges_have_settled_by_the_plastic_settlement():
    """On yielding soil (two elements, FS_v = 1.5: both yield under El Centro's first 8 s), once
    the mat has come to rest (10 s of free vibration) each element carries W/2 again, so its
    spring is back at the static deformation and the edge has settled by exactly the element's
    plastic settlement -s_i (docs/theory.md 14.1); the centre by their mean, the mat rotated by
    their difference over 2b. Measured 1.7e-5 of the settlement after 10 s (2e-3 after 2 s)."""
    system = paper_system(0.5)
    system = replace(system, foundation=replace(system.foundation, capacity=1.5 * system.weight / 2))
    result = exact.analyze(system, _record(8.0), "uplift", ExactOptions(free_vibration=10.0))
    plastic = result.peaks["plastic_settlement"]
    assert result.peaks["yielded_elements"][0] == 2 and plastic.min() > 0.01
    residual = result.peaks["residual_settlement"]
    np.testing.assert_allclose(residual[[0, 2]], plastic, rtol=1e-4)
    assert residual[1] == pytest.approx(plastic.mean(), rel=1e-4)
    rotation = abs(plastic[0] - plastic[1]) / (2.0 * system.half_width)
    assert result.peaks["residual_rotation"][0] == pytest.approx(rotation, rel=1e-3)
    assert np.all(result.peaks["settlement"] >= residual)
    # W_p = sum Q_i |s_i| (docs/theory.md 14.5)
    assert result.peaks["plastic_work"][0] == pytest.approx(1.5 * system.weight / 2 * plastic.sum(), rel=1e-12)


def test_both_backends_give_the_same_rocking_quantities():
    """The compiled loops and their numpy twins (tests/backends.py) on a yielding run: the same
    rotation, settlements and plastic quantities to 1e-9 (the post-processing of mat_motion.py is
    numpy on the signals, which agree to round-off)."""
    from backends import on_both

    system = paper_system(0.5)
    system = replace(system, foundation=replace(system.foundation, capacity=1.5 * system.weight / 2))
    compiled, twin = on_both(lambda: exact.analyze(system, _record(8.0), "uplift", ExactOptions()))
    for name in (*MOTION, "plastic_settlement", "yielded_elements", "plastic_work"):
        scale = np.abs(compiled.peaks[name.removeprefix("residual_")]).max()
        np.testing.assert_allclose(twin.peaks[name], compiled.peaks[name], rtol=0, atol=1e-9 * scale, err_msg=name)
        if name in compiled.times:
            np.testing.assert_allclose(twin.times[name], compiled.times[name], rtol=0, atol=1e-9, err_msg=name)
