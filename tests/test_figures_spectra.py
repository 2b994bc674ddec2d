"""Spectrum figure data (upliftcli.figures.spectra): a record's S_d, S_v, S_a panels and a
suite's records, statistic and target."""

from pathlib import Path

import numpy as np
import pytest

from upliftcli.deck.load import load_deck
from upliftcli.figures import spectra as fs
from upliftcli.figures.ensemble import RECORD_WIDTH, STATISTIC_WIDTH
from upliftcli.motion import spectra
from upliftcli.motion.records import read_record
from upliftcli.units import STANDARD_GRAVITY

ROOT = Path(__file__).resolve().parents[1]
ELCENTRO = ROOT / "records" / "elcentro_1940_ns_chopra.txt"


def test_record_spectrum_panels_sd_sv_sa():
    record = read_record(ELCENTRO, units="g")
    periods = np.geomspace(0.05, 5.0, 30)
    spectrum = spectra.response_spectrum(record.acceleration, record.dt, periods, [0.02, 0.05])
    spec = fs.record_spectrum_figure(spectrum, record.name, periods_marked=[("T_1", 0.5)])
    assert spec.xlog and record.name in spec.title
    sd, sv, sa = spec.panels
    assert (sd.ylabel, sv.ylabel, sa.ylabel) == ("deformation S_d [mm]", "pseudo-velocity S_v [mm/s]",
                                                 "pseudo-acceleration S_a [g]")
    assert [s.label for s in sa.series] == ["damping 2 %", "damping 5 %"]
    for k in range(2):
        np.testing.assert_allclose(sd.series[k].y, 1000 * spectrum.displacement[k])
        # the panels are one spectrum: S_v = w S_d, S_a = w^2 S_d (in the plotted units)
        w = 2 * np.pi / periods
        np.testing.assert_allclose(sv.series[k].y, w * sd.series[k].y, rtol=1e-12)
        np.testing.assert_allclose(sa.series[k].y, w**2 * sd.series[k].y / 1000 / STANDARD_GRAVITY, rtol=1e-12)
        np.testing.assert_array_equal(sa.series[k].x, periods)
    assert all(p.lines[0].value == 0.5 and p.lines[0].axis == "x" for p in spec.panels)
    assert len({s.color for s in sa.series}) == 2


def test_record_spectra_in_us_units_and_laid_out_for_a4_portrait():
    """The display units' table (display.py) gives the US panels: in and in/s (1 in = 25.4 mm
    exactly), S_a in g. The three panels are stacked over one period axis, each as wide as the
    histories' panels (the report's widest), so that the figure printed across the A4 page's
    width fills its height as the histories do; before, two a row left a quarter of the grid
    empty and 33 % of the printed page."""
    from upliftcli.figures import draw as plots
    from upliftcli.figures.histories import history_figure  # noqa: F401 (the widest report figure)

    record = read_record(ELCENTRO)
    periods = np.geomspace(0.05, 5.0, 30)
    spectrum = spectra.response_spectrum(record.acceleration, record.dt, periods, [0.05])
    si, us = fs.record_spectrum_figure(spectrum), fs.record_spectrum_figure(spectrum, units="us")
    assert [p.ylabel for p in us.panels] == ["deformation S_d [in]", "pseudo-velocity S_v [in/s]",
                                             "pseudo-acceleration S_a [g]"]
    for a, b, factor in zip(si.panels, us.panels, (1 / 25.4, 1 / 25.4, 1.0), strict=True):
        np.testing.assert_allclose(b.series[0].y, a.series[0].y * factor, rtol=1e-12)
    assert si.columns == 1 and si.sharex and si.panel_size[0] == 7.2  # as the histories (figures/histories.py)
    figure = plots.line_figure(si)
    width, height = figure.get_figwidth(), figure.get_figheight()
    printable = (210 - 24) / 25.4, (297 - 32) / 25.4  # A4 less the report's margins [in]
    printed_height = height * printable[0] / width
    assert 0.85 * printable[1] < printed_height < printable[1]  # fills the page, and fits it
    panels = sum(axes.get_position().width * axes.get_position().height for axes in figure.axes)
    assert panels > 0.6  # of the figure's area: no empty slot in a grid


def test_suite_records_thin_statistic_thick_target_dashed():
    periods = np.array([0.1, 0.5, 1.0, 2.0])
    records = np.array([[1.0, 2.0, 3.0, 1.0], [3.0, 2.0, 1.0, 1.0], [2.0, 5.0, 2.0, 4.0]])
    target = np.array([2.0, 2.5, 2.0, 1.5])
    for statistic, combined in (("mean", records.mean(axis=0)), ("max", records.max(axis=0))):
        spec = fs.suite_spectrum_figure(periods, records, statistic, target, "ASCE 7-22", (0.2, 1.5))
        (panel,) = spec.panels
        thin, thick, dashed = panel.series[:3], panel.series[3], panel.series[4]
        for row, line in zip(records, thin, strict=True):
            np.testing.assert_allclose(line.y, row / STANDARD_GRAVITY)
            assert line.width == RECORD_WIDTH
        np.testing.assert_allclose(thick.y, combined / STANDARD_GRAVITY)
        assert thick.width == STATISTIC_WIDTH and thick.label == f"scaled records: {statistic} of 3 records"
        np.testing.assert_allclose(dashed.y, target / STANDARD_GRAVITY)
        assert dashed.style == "--" and dashed.label == "target: ASCE 7-22"
        (span,) = panel.spans
        np.testing.assert_array_equal(span.intervals, [[0.2, 1.5]])


def test_suite_figure_of_a_deck_suite():
    suite = load_deck(ROOT / "inputs" / "ten_story_asce7_suite.toml").ground_motion
    periods = np.geomspace(0.1, 3.0, 12)
    spec = fs.suite_figure(suite, periods)
    (panel,) = spec.panels
    assert len(panel.series) == suite.count + 2
    thick = panel.series[suite.count]
    assert thick.label.endswith(f"{suite.statistic} of {suite.count} records")
    np.testing.assert_allclose(thick.y, suite.spectra(periods).mean(axis=0) / STANDARD_GRAVITY)
    np.testing.assert_allclose(panel.series[-1].y, suite.target.sa(periods, suite.damping) / STANDARD_GRAVITY)
    assert suite.target.name in spec.title
    assert panel.spans[0].intervals.tolist() == [list(suite.period_range)]
    assert pytest.approx(suite.factors) == [1.0] * suite.count  # scaling = "none": the records as written
