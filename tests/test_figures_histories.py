"""History, moment-rotation and energy figure data (upliftcli.figures.histories) against the
histories and energy balance the exact engine keeps."""

from dataclasses import replace

import numpy as np
import pytest
from figure_cases import small_run

from upliftcli.figures import histories as fh
from upliftcli.figures.spec import spans_of

UNITS = {"kN": 1e-3, "MN": 1e-6, "kN m": 1e-3, "MN m": 1e-6, "mrad": 1e3, "mm": 1e3, "kJ": 1e-3, "MJ": 1e-6}


def unit_factor(label: str) -> float:
    return UNITS[label[label.rindex("[") + 1:-1]]


def exact_results():
    _, results = small_run()
    return [r for r in results if r.engine == "exact"]


def test_only_the_history_engines_give_history_figures():
    _, results = small_run()
    assert [r.engine for r in fh.with_histories(results)] == ["exact"] * 3


def test_history_series_equal_the_kept_histories():
    results = exact_results()
    spec = fh.history_figure(results)
    assert spec.sharex and spec.columns == 1 and spec.xlabel == "time t [s]"
    shear, moment, theta, edges = spec.panels
    for panel, key, members in ((shear, "base_shear", results), (moment, "base_moment", results),
                                (theta, "theta", results[1:])):
        factor = unit_factor(panel.ylabel)
        assert [s.label for s in panel.series] == [r.support for r in members]
        for result, series in zip(members, panel.series, strict=True):
            np.testing.assert_array_equal(series.x, result.histories["time"])
            np.testing.assert_allclose(series.y, factor * result.histories[key], rtol=1e-15)
    # the sampled peak of the plotted base shear is at most the engine's peak V_b (found between
    # samples) and close to it
    for result, series in zip(results, shear.series, strict=True):
        sampled = np.max(np.abs(series.y)) / unit_factor(shear.ylabel)
        assert result.base_shear * 0.99 < sampled <= result.base_shear * (1 + 1e-9)
    factor = unit_factor(edges.ylabel)
    assert [s.label for s in edges.series] == ["bonded, left edge", "bonded, right edge", "uplift, left edge",
                                               "uplift, right edge"]
    np.testing.assert_allclose(edges.series[2].y, factor * results[2].histories["left_edge_displacement"])
    # the largest edge displacement is the engine's largest uplift
    lift = results[2].details["uplift_summary"]["max_uplift_left"]
    assert np.max(edges.series[2].y) == pytest.approx(factor * lift)


def test_plus_minus_critical_moment_lines():
    results = exact_results()
    system = small_run()[0].system
    m_c = results[0].critical_base_moment
    assert m_c == pytest.approx(system.total_mass * system.gravity * system.half_width)  # [16b]
    for spec, panel in ((fh.history_figure(results), 1), (fh.moment_rotation_figure(results), 0)):
        lines = spec.panels[panel].lines
        factor = unit_factor(spec.panels[panel].ylabel)
        assert [line.value for line in lines] == pytest.approx([factor * m_c, -factor * m_c])
        assert all(line.axis == "y" for line in lines) and "M_c = m_t g b" in lines[0].label


def test_lifted_intervals_shaded_where_the_contact_state_says():
    results = exact_results()
    uplift = results[2]
    spans = fh.history_figure(results).panels[0].spans
    assert [s.label for s in spans] == ["left edge lifted", "right edge lifted"]
    times = uplift.histories["time"]
    state = uplift.histories["contact_state"]
    for span, bit in zip(spans, (1, 2), strict=True):
        assert span.intervals.shape[1] == 2 and len(span.intervals) > 1
        for start, end in span.intervals:
            inside = (times >= start) & (times < end)
            assert np.all(state[inside] & bit)
            before = np.nonzero(times < start)[0]
            assert before.size == 0 or not state[before[-1]] & bit
    # total shaded time = the engine's time with an element lifted (no flight here)
    summary = uplift.details["uplift_summary"]
    assert summary["flight_time"] == 0.0
    shaded = sum(float(np.sum(s.intervals[:, 1] - s.intervals[:, 0])) for s in spans)
    assert shaded == pytest.approx(summary["uplift_time"], rel=1e-12)
    # every panel carries the same shading
    for panel in fh.history_figure(results).panels:
        assert [s.label for s in panel.spans] == [s.label for s in spans]
        for mine, first in zip(panel.spans, spans, strict=True):
            np.testing.assert_array_equal(mine.intervals, first.intervals)


def test_spans_of_a_mask():
    times = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 5.0])
    np.testing.assert_array_equal(spans_of(times, [False, True, True, False, True, True]), [[1, 3], [4, 5]])
    np.testing.assert_array_equal(spans_of(times, [True, False, False, False, False, False]), [[0, 1]])
    assert spans_of(times, np.zeros(6, bool)).shape == (0, 2)


def test_contact_state_of_many_elements():
    """A foundation of more elements than an int64 holds: Python integers, same bits."""
    uplift = exact_results()[2]
    state = uplift.histories["contact_state"]
    wide = np.array([(int(s) & 1) | ((int(s) >> 1) << 79) for s in state], dtype=object)
    many = replace(uplift, element_positions=np.linspace(-1, 1, 80),
                   histories={**uplift.histories, "contact_state": wide})
    for edge, mask in fh.lifted(many).items():
        np.testing.assert_array_equal(mask, fh.lifted(uplift)[edge])


def test_energy_bars_equal_the_balance():
    results = exact_results()
    (panel,) = fh.energy_figure(results).panels
    factor = unit_factor(panel.xlabel)
    assert [b.label for b in panel.bars] == ["rigid", "bonded", "uplift"]
    for result, bars in zip(results, panel.bars, strict=True):
        energy = result.details["energy"]
        assert bars.categories[0] == "input work" and bars.categories[-1] == "residual"
        np.testing.assert_allclose(bars.values, [factor * energy[k] for k in fh.ENERGY_TERMS])
        # input work = dissipated + change of stored energy + residual (the bars add up)
        assert bars.values[0] == pytest.approx(np.sum(bars.values[1:]), rel=1e-12)
        assert abs(energy["residual"]) < 1e-4 * energy["input"]
    assert "residual / input" in panel.title


def test_moment_rotation_of_the_flexible_supports():
    results = exact_results()
    (panel,) = fh.moment_rotation_figure(results).panels
    assert [s.label for s in panel.series] == ["bonded", "uplift"]
    for result, series in zip(results[1:], panel.series, strict=True):
        h = result.histories
        np.testing.assert_allclose(series.x, 1e3 * h["theta"])
        np.testing.assert_allclose(series.y, unit_factor(panel.ylabel) * h["base_moment"])
    # bonded: M_b follows K_theta theta (plus damping); the slope is near K_theta
    bonded = results[1].histories
    slope = np.polyfit(bonded["theta"], bonded["base_moment"], 1)[0]
    system = small_run()[0].system
    k_theta = 2 * system.foundation.stiffness * system.half_width**2  # [22]
    assert slope == pytest.approx(k_theta, rel=1e-3)  # measured 2.1e-4 (the dashpot's part)
