"""Figure data (upliftcli.figures) and figure files (upliftcli.plots)."""

import numpy as np
import pytest

from upliftcli import plots
from upliftcli.errors import InputError
from upliftcli.sweep import figures
from upliftcli.sweep.plan import SweepPlan, Vary

PERIODS = [2.0, 0.5, 1.0]  # deliberately unsorted


def make_rows(engines=("exact", "simplified"), supports=("rigid", "bonded", "uplift")):
    """Synthetic rows with values that encode (engine, support, period)."""
    rows = []
    for e, engine in enumerate(engines):
        for s, support in enumerate(supports):
            for period in PERIODS:
                value = 0.1 * (e + 1) + 0.01 * (s + 1) + period
                rows.append({"case": len(rows), "engine": engine, "support": support, "building.period": period,
                             "base_shear_coefficient": value, "base_moment_coefficient": value / 2,
                             "mode1_base_shear_coefficient": value / 3,
                             "two_mode_base_shear_coefficient": value / 1.5 if engine == "simplified" else None,
                             "max_drift_ratio": value / 100, "critical_coefficient": 0.1, "uplift": False,
                             "status": "ok"})
    rows.append({**rows[0], "case": 99, "building.period": 3.0, "status": "failed", "base_shear_coefficient": None})
    return rows


def expected(engine_index, support_index, scale=1.0):
    return np.array([(0.1 * (engine_index + 1) + 0.01 * (support_index + 1) + t) / scale for t in sorted(PERIODS)])


def test_support_spectra_fig_3_and_4():
    spec = figures.support_figure(make_rows(), "exact", ["rigid", "bonded", "uplift"], "base_shear", "elcentro")
    assert spec.xlog and spec.ylog and spec.xlabel.startswith("fixed-base fundamental period T_1")
    (panel,) = spec.panels
    labels = [s.label for s in panel.series]
    assert labels[:3] == ["rigid support", "flexible support, bonded mat", "flexible support, uplift permitted"]
    for index, series in enumerate(panel.series[:3]):
        np.testing.assert_array_equal(series.x, sorted(PERIODS))  # the failed row at 3 s is left out
        np.testing.assert_allclose(series.y, expected(0, index))
    critical = panel.series[3]
    assert critical.label == "critical b/h_1* = 0.1"
    np.testing.assert_array_equal(critical.y, [0.1, 0.1, 0.1])
    moment = figures.support_figure(make_rows(), "simplified", ["rigid"], "base_moment")
    np.testing.assert_allclose(moment.panels[0].series[0].y, expected(1, 0, 2.0))
    assert "M_b/(m_t g h_1*)" in moment.panels[0].ylabel


def test_modal_contributions_fig_7():
    rows = make_rows()
    spec = figures.modal_figure(rows, "simplified", ["rigid", "bonded", "uplift"])
    assert [p.title for p in spec.panels] == ["(a) rigid support", "(b) flexible support, bonded mat",
                                              "(c) flexible support, uplift permitted"]
    names = [s.label for s in spec.panels[1].series]
    assert names[:3] == ["mode 1", "modes 1-2", "all modes"]
    np.testing.assert_allclose(spec.panels[1].series[0].y, expected(1, 1, 3.0))
    exact = figures.modal_figure(rows, "exact", ["uplift"])
    assert [s.label for s in exact.panels[0].series][:2] == ["mode 1", "all modes"]  # no modes 1-2 from exact


def test_engine_comparison_figs_6_and_8_to_10():
    rows = make_rows()
    figure_set = figures.paper_figures(rows, ["exact", "simplified"], ["bonded", "uplift"])
    assert set(figure_set) == {"base_shear_exact", "base_moment_exact", "modal_exact", "base_shear_simplified",
                               "base_moment_simplified", "modal_simplified", "engines_base_shear",
                               "engines_mode1_base_shear"}
    spec = figure_set["engines_mode1_base_shear"]
    assert [p.title for p in spec.panels] == ["flexible support, bonded mat", "flexible support, uplift permitted"]
    series = spec.panels[1].series
    assert series[0].label.startswith("exact") and series[1].label.startswith("simplified")
    np.testing.assert_allclose(series[1].y, expected(1, 2, 3.0))
    assert "engines_base_shear" not in figures.paper_figures(rows, ["exact"], ["uplift"])


def test_period_range_option():
    vary = figures.period_vary("0.05:5:3")
    assert vary.path == "building.period" and vary.spacing == "log"
    assert vary.values == pytest.approx((0.05, 0.5, 5.0))
    assert figures.period_vary("0.5:2.5:3:lin").values == (0.5, 1.5, 2.5)
    with pytest.raises(InputError, match="--periods"):
        figures.period_vary("0,1")


def test_sweep_figure_against_the_first_varied_field():
    plan = SweepPlan({}, "deck.toml", "A deck", (), [Vary("foundation.k_f", (1e8, 1e9), "log"),
                                                     Vary("building.period", (0.5, 1.0), "list")],
                     ["simplified"], ["uplift"], [])
    rows = []
    for period in (0.5, 1.0):
        for k_f in (1e9, 1e8):
            rows.append({"case": len(rows), "engine": "simplified", "support": "uplift", "foundation.k_f": k_f,
                         "building.period": period, "base_shear_coefficient": k_f * 1e-10 + period,
                         "base_moment_coefficient": 0.2, "max_drift_ratio": 0.01, "critical_coefficient": 0.1,
                         "status": "ok"})
    spec = figures.sweep_figure(plan, rows)
    assert spec.xlog and spec.xlabel == "foundation.k_f [N/m]"
    shear = spec.panels[0].series
    assert [s.label for s in shear] == ["simplified, uplift, building.period=0.5",
                                        "simplified, uplift, building.period=1.0", "critical b/h_1* = 0.1"]
    np.testing.assert_array_equal(shear[1].x, [1e8, 1e9])
    np.testing.assert_allclose(shear[1].y, [1.01, 1.1])
    assert len(spec.panels[2].series) == 2  # no critical line on the drift panel
    text = SweepPlan({}, "d", "t", (), [Vary("analysis.combination", ("srss", "cqc"), "list")], [], [], [])
    with pytest.raises(InputError, match="numeric"):
        figures.sweep_figure(text, [])


def test_plot_figure_writes_png_and_svg(tmp_path):
    spec = figures.support_figure(make_rows(), "exact", ["rigid", "uplift"], "base_shear", "elcentro")
    png = plots.plot_figure(spec, tmp_path / "fig.png")
    assert png.read_bytes().startswith(b"\x89PNG\r\n\x1a\n") and png.stat().st_size > 10_000
    svg = plots.plot_figure(figures.modal_figure(make_rows(), "simplified", ["rigid", "bonded", "uplift"]),
                            tmp_path / "fig.svg").read_text()
    for words in ("<svg", "(c) flexible support, uplift permitted", "modes 1-2", "critical b/h_1*"):
        assert words in svg
    with pytest.raises(InputError, match="--plot"):
        plots.plot_figure(spec, tmp_path / "fig.jpg")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fig.png", "fig.svg"]  # no temporary file left
