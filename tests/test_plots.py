"""Figure data (upliftcli.figures) and figure files (upliftcli.figures.draw)."""

import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from upliftcli.errors import InputError
from upliftcli.figures import draw as plots
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


def _ran_alone(request) -> bool:
    """Forking is the figures' path only in a process that runs no other thread (plots.plot_figures);
    threads that earlier tests of this worker left (a Dask cluster's, pytest-xdist runs any test
    after any other) would send the test down the serial path. Then the test runs alone in a fresh
    interpreter, asserted to pass there, and True is returned (the caller returns)."""
    if threading.active_count() == 1 or os.environ.get("UPLIFT_TEST_ALONE"):
        return False
    done = subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-n", "0",
                           request.node.nodeid], cwd=request.config.rootpath, capture_output=True, text=True,
                          env={**os.environ, "UPLIFT_TEST_ALONE": "1"})
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "1 passed" in done.stdout
    return True


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
    assert spec.xlog and spec.xlabel == "foundation.k_f [kN/m]"  # the display unit (display.py)
    shear = spec.panels[0].series
    assert [s.label for s in shear] == ["simplified, uplift, building.period=0.5",
                                        "simplified, uplift, building.period=1.0", "critical b/h_1* = 0.1"]
    np.testing.assert_array_equal(shear[1].x, [1e5, 1e6])
    np.testing.assert_allclose(shear[1].y, [1.01, 1.1])
    # one support, two periods: the support's colour in two shades, with markers; the engine's line style
    assert shear[0].color == "#D55E00" and shear[1].color != shear[0].color and shear[1].marker
    assert shear[0].style == shear[1].style == "-."
    assert len(spec.panels[2].series) == 2  # no critical line on the drift panel
    np.testing.assert_allclose(spec.panels[2].series[0].y, [1.0, 1.0])  # drift ratios in %
    us = figures.sweep_figure(plan, rows, units="us")
    assert us.xlabel == "foundation.k_f [kip/in]"
    np.testing.assert_allclose(us.panels[0].series[1].x, np.array([1e8, 1e9]) * 0.0254 / 4448.2216152605)
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


def _paper_specs():
    return figures.paper_figures(make_rows(), ["exact", "simplified"], ["rigid", "bonded", "uplift"], "elcentro")


def _record_drawing(monkeypatch) -> list[int]:
    """figure_data wrapped: the list it returns gets the process id of each call made here."""
    drawn_by, draw = [], plots.figure_data

    def recording(spec, path, option="--plot"):
        drawn_by.append(os.getpid())
        return draw(spec, path, option)

    monkeypatch.setattr(plots, "figure_data", recording)
    return drawn_by


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="figures are shared out on Linux only")
def test_plot_figures_shares_the_work_and_writes_what_plot_figure_writes(tmp_path, monkeypatch, request):
    """Forked copies draw part of the figures (here: two cores): the same files, byte for byte,
    as one plot_figure after another; the paths in the order given."""
    if _ran_alone(request):
        return
    monkeypatch.setattr("upliftcli.runtime.process.available_cores", lambda: 2)
    specs = _paper_specs()
    items = [(spec, tmp_path / "shared" / f"{name}.png") for name, spec in specs.items()]
    (tmp_path / "shared").mkdir()
    parent = os.getpid()
    draw = plots.plot_figure
    drawn_by = _record_drawing(monkeypatch)
    assert plots.plot_figures(items) == [path for _, path in items]
    assert set(drawn_by) == {parent}  # the copies' calls are not seen here: they drew the rest
    assert len(drawn_by) < len(items)
    for name, spec in specs.items():
        alone = draw(spec, tmp_path / f"{name}.png")
        assert alone.read_bytes() == (tmp_path / "shared" / f"{name}.png").read_bytes()


def test_plot_figures_without_fork_draws_every_figure_here_and_writes_the_same_files(tmp_path, monkeypatch):
    """Where the figures are not shared out (FORK_FIGURES off: Windows, macOS), this process
    draws them all, one after the other: the same files, byte for byte, as the shared-out path
    (or plot_figure alone, where that path is not taken)."""
    monkeypatch.setattr("upliftcli.runtime.process.available_cores", lambda: 2)
    specs = dict(list(_paper_specs().items())[:3])  # three figures: two groups on two cores
    for folder in ("default", "serial"):
        (tmp_path / folder).mkdir()
    plots.plot_figures([(spec, tmp_path / "default" / f"{name}.png") for name, spec in specs.items()])
    monkeypatch.setattr(plots, "FORK_FIGURES", False)
    drawn_by = _record_drawing(monkeypatch)
    plots.plot_figures([(spec, tmp_path / "serial" / f"{name}.png") for name, spec in specs.items()])
    assert drawn_by == [os.getpid()] * len(specs)
    for name in specs:
        assert (tmp_path / "serial" / f"{name}.png").read_bytes() == (tmp_path / "default" / f"{name}.png").read_bytes()


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="figures are shared out on Linux only")
def test_plot_figures_waits_for_a_background_preload_and_still_shares_the_work(tmp_path, monkeypatch, request):
    """preload(background=True) imports matplotlib in a thread (uplift spectra, while the workers
    run); plot_figures waits for it, so the process has one thread again and forks its copies."""
    if _ran_alone(request):
        return
    monkeypatch.setattr("upliftcli.runtime.process.available_cores", lambda: 2)
    imported = plots._import_matplotlib

    def slow_import():
        time.sleep(0.3)  # still importing when the figures are asked for
        imported()

    monkeypatch.setattr(plots, "_import_matplotlib", slow_import)
    plots.preload(background=True)
    assert threading.active_count() == 2
    drawn_by = _record_drawing(monkeypatch)
    items = [(spec, tmp_path / f"{name}.png") for name, spec in _paper_specs().items()]
    plots.plot_figures(items)
    assert threading.active_count() == 1
    assert 0 < len(drawn_by) < len(items)  # the rest was drawn by a forked copy
    assert all(path.stat().st_size > 10_000 for _, path in items)


def test_plot_figures_raises_the_error_of_a_forked_copy(tmp_path, monkeypatch, request):
    if _ran_alone(request):
        return
    monkeypatch.setattr("upliftcli.runtime.process.available_cores", lambda: 2)
    specs = list(_paper_specs().values())
    (tmp_path / "file").write_text("not a directory")
    items = [(specs[0], tmp_path / "a.png"), (specs[1], tmp_path / "file" / "b.png"),
             (specs[2], tmp_path / "c.png")]
    with pytest.raises(OSError) as caught:
        plots.plot_figures(items)
    assert caught.value.filename == str(tmp_path / "file" / "b.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]  # all or none (issue 38)
    draw = plots.figure_data

    def refusing(spec, path, option="--plot"):  # an InputError raised in whichever process draws it
        if Path(path).name == "b.png":
            raise InputError("--plot", str(path), "a figure this test refuses")
        return draw(spec, path, option)

    monkeypatch.setattr(plots, "figure_data", refusing)
    items[1] = (specs[1], tmp_path / "b.png")
    with pytest.raises(InputError, match="a figure this test refuses"):
        plots.plot_figures(items)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]


def test_plot_figures_draws_in_this_process_while_another_thread_runs(tmp_path, monkeypatch):
    """Forking a process that runs threads is unsafe: then every figure is drawn here."""
    monkeypatch.setattr("upliftcli.runtime.process.available_cores", lambda: 2)
    stop = threading.Event()
    worker = threading.Thread(target=stop.wait)
    worker.start()
    drawn_by = _record_drawing(monkeypatch)
    try:
        items = [(spec, tmp_path / f"{name}.png") for name, spec in _paper_specs().items()]
        plots.plot_figures(items)
    finally:
        stop.set()
        worker.join()
    assert drawn_by == [os.getpid()] * len(items)
    assert all(path.stat().st_size > 10_000 for _, path in items)


# ----------------------------------------------------------------------------- deck values, palette, layout

EXAMPLE = Path(__file__).resolve().parents[1] / "inputs" / "ten_story_elcentro.toml"


def test_sweep_marks_the_decks_value_of_the_varied_field():
    from upliftcli.deck.load import load_deck
    from upliftcli.sweep.plan import plan_sweep

    plan = plan_sweep(EXAMPLE, ["building.period=0.8"], ["building.period=0.2:2:4:log"], ["simplified"], ["uplift"])
    (line,) = [line for line in figures.sweep_figure(plan, []).panels[0].lines if line.axis == "x"]
    assert line.value == 0.8 and "deck: building.period = 0.8" in line.label  # as --set gives it
    # a field the deck does not give: derived from the model (k_f from w_v/w_1 = 8)
    plan = plan_sweep(EXAMPLE, [], ["foundation.k_f=1e8:1e10:3:log"], ["simplified"], ["uplift"])
    deck = load_deck(EXAMPLE)
    assert figures.nominal_value(plan, "foundation.k_f") == pytest.approx(deck.system.foundation.stiffness)
    assert figures.nominal_value(plan, "foundation.mat_mass") == 0.0
    assert figures.nominal_value(plan, "analysis.combination") is None  # not a number
    spec = figures.sweep_figure(plan, [])
    # in the axis's display unit, kN/m
    assert all(p.lines[0].value == pytest.approx(1e-3 * deck.system.foundation.stiffness) for p in spec.panels)
    assert "kN/m" in spec.panels[0].lines[0].label
    # the deck's [criteria] drift limit on the drift panel
    (limit,) = [line for line in spec.panels[2].lines if line.axis == "y"]
    assert limit.value == 100 * deck.criteria["drift_ratio"] == 2.0  # in %, as the drift ratios of the figure
    assert spec.panels[2].ylabel.endswith("[%]")
    assert "record elcentro_1940_ns_chopra" in figures.plan_motion_label(plan)


def test_paper_figures_mark_the_decks_period_and_name_the_motion():
    set_ = figures.paper_figures(make_rows(), ["exact", "simplified"], ["rigid", "uplift"], "record X", 0.5)
    for spec in set_.values():
        assert spec.title.endswith("record X")
        assert all(p.lines and p.lines[0].value == 0.5 and p.lines[0].axis == "x" for p in spec.panels)
    design = {"ground_motion": {"design_spectrum": {"type": "asce7", "sds": 1.0, "sd1": 0.6, "tl": 8.0}}}
    assert figures.motion_label(design, "deck.toml").startswith("design spectrum ASCE 7-22")


def test_many_sweep_lines_take_distinct_colours_and_styles():
    plan = SweepPlan({}, "deck.toml", "A deck", (), [Vary("foundation.k_f", (1e8, 1e9), "log"),
                                                     Vary("building.period", tuple(0.1 * k for k in range(1, 9)),
                                                          "list")], ["simplified"], ["uplift"], [])
    rows = [{"engine": "simplified", "support": "uplift", "foundation.k_f": k_f, "building.period": 0.1 * p,
             "base_shear_coefficient": 0.1 * p, "base_moment_coefficient": 0.1, "max_drift_ratio": 0.01,
             "critical_coefficient": 0.1, "status": "ok"} for p in range(1, 9) for k_f in (1e8, 1e9)]
    series = figures.sweep_figure(plan, rows).panels[0].series
    assert len({(s.color, str(s.style)) for s in series}) == len(series) == 9  # 8 lines and b/h_1*


def _geometry(figure):
    """Every axes with its texts inside the figure and clear of the other axes; the legend inside
    the figure and clear of every axes; the title clear of every axes."""
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()
    width, height = figure.canvas.get_width_height()
    boxes = [ax.get_tightbbox(renderer) for ax in figure.axes]
    for box in boxes:
        assert box.x0 >= -1 and box.y0 >= -1 and box.x1 <= width + 1 and box.y1 <= height + 1
    for i, box in enumerate(boxes):
        for j, ax in enumerate(figure.axes):
            if i != j:
                assert not box.overlaps(ax.get_window_extent())
    for legend in figure.legends:
        extent = legend.get_window_extent(renderer)
        assert extent.x0 >= 0 and extent.y0 >= 0 and extent.x1 <= width and extent.y1 <= height
        assert all(not extent.overlaps(ax.get_window_extent()) for ax in figure.axes)
    if figure.get_suptitle():
        title = figure._suptitle.get_window_extent(renderer)
        assert title.y1 <= height and all(not title.overlaps(ax.get_window_extent()) for ax in figure.axes)


@pytest.mark.parametrize("make", [
    lambda: figures.modal_figure(make_rows(), "simplified", ["rigid", "bonded", "uplift"], "elcentro", 0.5),
    lambda: figures.support_figure(make_rows(), "exact", ["rigid", "bonded", "uplift"], "base_shear",
                                   "a record with a long name that takes two lines of the figure title" * 2),
    lambda: figures.engine_figure(make_rows(), ["exact", "simplified"], ["bonded", "uplift"], "base_shear"),
], ids=["three-panels", "two-line-title", "two-panels"])
def test_layout_keeps_texts_inside_and_the_legend_outside_the_data(make):
    _geometry(plots.line_figure(make()))


def test_run_figures_layout_and_plain_log_ticks():
    from figure_cases import small_run

    from upliftcli.figures.sets import analysis_figures

    deck, results = small_run()
    specs = analysis_figures(deck, results)
    assert set(specs) == {"profiles", "modes", "spectrum", "histories_exact", "moment_rotation_exact",
                          "energy_exact"}
    for name, spec in specs.items():
        figure = plots.line_figure(spec)
        _geometry(figure)
        for axes in figure.axes:
            for axis in (axes.xaxis, axes.yaxis):
                if axis.get_scale() == "log":
                    texts = [t.get_text() for t in axis.get_ticklabels(which="both") if t.get_text()]
                    assert all(float(t) > 0 for t in texts), (name, texts)  # 0.1, 0.2, 0.5, 1 ...
                    # labelled, unless the axis is shared with the panel below (which="both": minor ones too)
                    shared = axis is axes.xaxis and spec.sharex and axes is not figure.axes[-1]
                    assert bool(texts) != shared, (name, texts)
    assert "record" in specs["profiles"].title and deck.title in specs["profiles"].title


def test_plot_spectrum_and_figure_bytes(tmp_path):
    from upliftcli.motion import spectra
    from upliftcli.motion.records import read_record

    record = read_record(EXAMPLE.parents[1] / "records" / "elcentro_1940_ns_chopra.txt", units="g")
    spectrum = spectra.response_spectrum(record.acceleration, record.dt, np.geomspace(0.05, 5, 20), [0.05])
    svg = plots.plot_spectrum(spectrum, tmp_path / "s.svg", record.name).read_text()
    for words in ("deformation S_d [mm]", "pseudo-velocity S_v [mm/s]", "pseudo-acceleration S_a [g]", "0.2"):
        assert words in svg
    spec = figures.support_figure(make_rows(), "exact", ["rigid"], "base_shear")
    assert plots.figure_bytes(spec).startswith(b"\x89PNG") and b"<svg" in plots.figure_bytes(spec, "svg")
