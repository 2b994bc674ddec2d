"""Story-profile figure data (upliftcli.figures.analysis) against the results it shows."""

from dataclasses import replace

import numpy as np
import pytest
from figure_cases import small_run

from upliftcli.figures import analysis as fa
from upliftcli.figures.ensemble import STATISTIC_WIDTH
from upliftcli.figures.style import ENGINE_LINES, SUPPORT_COLORS
from upliftcli.units import STANDARD_GRAVITY

#: plotted unit -> factor from SI
UNITS = {"mm": 1e3, "%": 100.0, "kN": 1e-3, "MN": 1e-6, "kN m": 1e-3, "MN m": 1e-6, "g": 1 / STANDARD_GRAVITY}
STORY = ("drift_ratio", "shear")


def unit_factor(label: str) -> float:
    return UNITS[label[label.rindex("[") + 1:-1]]


def panel_of(spec, name):
    (panel,) = [p for p in spec.panels if p.title == fa.PROFILES[name]]
    return panel


def expected_profile(name, peaks, elevations, factor):
    """The profile written out point by point (independently of profile_xy)."""
    levels = [0.0, *elevations]
    x, y = [], []
    if name in STORY:  # constant over story j, from floor j-1 to floor j
        for j, value in enumerate(peaks):
            x += [value * factor, value * factor]
            y += [levels[j], levels[j + 1]]
    elif name == "moment":  # at the bottom of each story, 0 at the roof
        x, y = [*(peaks * factor), 0.0], levels
    elif name == "displacement":  # relative to the mat: 0 at the mat
        x, y = [0.0, *(peaks * factor)], levels
    else:
        x, y = list(peaks * factor), levels[1:]
    return np.array(x), np.array(y)


def test_profile_series_equal_the_peaks_of_every_result():
    deck, results = small_run()
    spec = fa.profile_figure(results, deck.criteria)
    assert [p.title for p in spec.panels] == list(fa.PROFILES.values())
    for name in fa.PROFILES:
        panel = panel_of(spec, name)
        factor = unit_factor(panel.xlabel)
        assert panel.ylabel == "elevation above the mat [m]"
        assert [s.label for s in panel.series] == [f"{r.engine}, {r.support}" for r in results]
        for result, series in zip(results, panel.series, strict=True):
            x, y = expected_profile(name, result.peaks[name], result.elevations, factor)
            np.testing.assert_allclose(series.x, x, rtol=1e-15)
            np.testing.assert_allclose(series.y, y, rtol=1e-15)
            assert series.color == SUPPORT_COLORS[result.support]
            assert series.style == ENGINE_LINES[result.engine]
    pairs = {(s.color, s.style) for s in panel_of(spec, "shear").series}
    assert len(pairs) == len(results)  # every engine and support distinct


def test_forces_in_kn_or_mn_by_their_size():
    _, results = small_run()
    largest = max(float(r.peaks["moment"].max()) for r in results)
    label = panel_of(fa.profile_figure(results), "moment").xlabel
    assert label.endswith("[MN m]" if largest * 1e-3 >= 1e4 else "[kN m]")
    tiny = [replace(r, peaks={**r.peaks, "moment": r.peaks["moment"] * 1e-6}) for r in results]
    assert panel_of(fa.profile_figure(tiny), "moment").xlabel.endswith("[kN m]")


def test_criteria_limit_drawn_at_the_decks_value():
    deck, results = small_run()
    assert deck.criteria == {"drift_ratio": 0.02}
    spec = fa.profile_figure(results, deck.criteria)
    (line,) = panel_of(spec, "drift_ratio").lines
    assert line.axis == "x" and line.value == pytest.approx(100 * 0.02) and "2 %" in line.label
    assert all(not panel_of(spec, name).lines for name in fa.PROFILES if name != "drift_ratio")
    spec = fa.profile_figure(results, {"displacement": 0.05, "floor_acceleration": 0.5 * STANDARD_GRAVITY})
    assert panel_of(spec, "displacement").lines[0].value == pytest.approx(50.0)  # mm
    assert panel_of(spec, "floor_acceleration").lines[0].value == pytest.approx(0.5)  # g
    assert "[criteria]" in spec.labels()[-1]


@pytest.mark.parametrize("statistic", ["mean", "max", "median"])
def test_suite_records_thin_statistic_thick_target_dashed(statistic):
    _, results = small_run()
    exact_uplift = next(r for r in results if r.engine == "exact" and r.support == "uplift")
    target = next(r for r in results if r.engine == "simplified" and r.support == "uplift")
    scales = (0.6, 1.0, 1.7)
    records = [replace(exact_uplift, peaks={k: v * s for k, v in exact_uplift.peaks.items()}) for s in scales]
    spec = fa.suite_profile_figure(records, statistic, [target])
    series = panel_of(spec, "shear").series
    assert len(series) == len(scales) + 2
    factor = unit_factor(panel_of(spec, "shear").xlabel)
    thin, thick, dashed = series[:3], series[3], series[4]
    for member, line in zip(records, thin, strict=True):
        np.testing.assert_allclose(line.x[::2], member.peaks["shear"] * factor)
        assert line.width < thick.width and line.style == "-"
    combine = {"mean": np.mean, "max": np.max, "median": np.median}[statistic]
    np.testing.assert_allclose(thick.x[::2], combine([m.peaks["shear"] for m in records], axis=0) * factor)
    assert thick.width == STATISTIC_WIDTH and thick.label == f"exact, uplift: {statistic} of 3 records"
    np.testing.assert_allclose(dashed.x[::2], target.peaks["shear"] * factor)
    assert dashed.style == "--" and dashed.label == "simplified, uplift: target spectrum"
    assert thin[0].label.endswith("each of 3 records") and not thin[1].label  # one legend entry


def test_unknown_statistic_is_refused_and_every_suite_statistic_is_drawn():
    _, results = small_run()
    with pytest.raises(ValueError, match="statistic"):
        fa.suite_profile_figure([results[0], results[0]], "p90")
    from upliftcli.engines.suite_result import STATISTICS
    from upliftcli.figures.ensemble import statistic_of

    values = np.array([[1.0, 4.0], [2.0, 8.0], [3.0, 6.0]])
    assert set(STATISTICS) >= {"mean", "median", "p84", "max"}
    np.testing.assert_allclose(statistic_of(values, "p84"), [2.68, 7.36])  # order statistic 1.68 of 0..2
    fa.suite_profile_figure([results[0], results[0]], "p84")
