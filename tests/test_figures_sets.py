"""The figures of a run (upliftcli.figures.sets): which figures, titles naming the ground
motion, the design spectrum's figure."""

from pathlib import Path

import numpy as np
import pytest
from figure_cases import small_run

from upliftcli.analysis import run as analysis
from upliftcli.deck.load import load_deck
from upliftcli.figures import sets
from upliftcli.units import STANDARD_GRAVITY

INPUTS = Path(__file__).resolve().parents[1] / "inputs"


def test_figures_of_a_run_with_a_record():
    deck, results = small_run()
    specs = sets.analysis_figures(deck, results)
    assert list(specs) == ["profiles", "modes", "spectrum", "histories_exact", "moment_rotation_exact",
                           "energy_exact"]
    label = sets.motion_label(deck)
    assert label == f"record {deck.ground_motion.name}"
    for name in ("profiles", "histories_exact", "energy_exact"):
        assert deck.title in specs[name].title and label in specs[name].title
    marks = {line.label.split(" =")[0]: line.value for line in specs["spectrum"].panels[0].lines}
    assert marks["T_1"] == pytest.approx(deck.system.modes.periods[0])
    t1bar = next(r.intermediates["T1bar"] for r in results if "T1bar" in r.intermediates)
    assert marks["T1bar"] == pytest.approx(t1bar)
    assert len({(line.style, line.color) for line in specs["spectrum"].panels[0].lines}) == 2
    simplified = [r for r in results if r.engine == "simplified"]
    assert list(sets.analysis_figures(deck, simplified)) == ["profiles", "modes", "spectrum"]


def test_design_spectrum_figure_and_title():
    deck = load_deck(INPUTS / "ten_story_asce7.toml")
    results = analysis.run(deck)
    spec = sets.spectrum_figure(deck, results)
    (panel,) = spec.panels
    (series,) = panel.series
    xi = float(deck.system.building.damping[0])
    np.testing.assert_allclose(series.y, deck.ground_motion.sa(series.x, xi) / STANDARD_GRAVITY)
    assert deck.ground_motion.name in spec.title and sets.motion_label(deck).startswith("design spectrum ASCE 7-22")
    assert panel.lines[0].value == pytest.approx(deck.system.modes.periods[0])


def test_suite_deck_draws_the_suite():
    deck = load_deck(INPUTS / "ten_story_asce7_suite.toml", ['analysis.engine=["simplified"]'])
    spec = sets.spectrum_figure(deck)
    suite = deck.ground_motion
    assert len(spec.panels[0].series) == suite.count + 2
    assert sets.motion_label(deck) == f"suite of {suite.count} records, target {suite.target.name}"


def fake_suite(scales=(0.6, 1.0, 1.7)):
    """A SuiteResult of the small run's exact uplift result under three scaled 'records', with
    the simplified engine on the 'target' beside it."""
    from dataclasses import replace

    from upliftcli.engines.suite_result import SuiteRecord, suite_result

    _, results = small_run()
    exact = next(r for r in results if r.engine == "exact" and r.support == "uplift")
    simplified = next(r for r in results if r.engine == "simplified" and r.support == "uplift")
    records = [replace(exact, peaks={k: v * s for k, v in exact.peaks.items()},
                       histories=dict(exact.histories)) for s in scales]
    names = [SuiteRecord(f"record {k}", f"r{k}.txt", s) for k, s in enumerate(scales)]
    return suite_result(records, names, "mean", rule="asce7-22", simplified=simplified), simplified


def test_profiles_of_a_suite_result():
    deck, _ = small_run()
    suite, simplified = fake_suite()
    spec = sets.profiles(deck, [suite])
    (shear,) = [p for p in spec.panels if p.title == "peak story shear"]
    factor = 1e-6 if shear.xlabel.endswith("[MN]") else 1e-3
    thin, thick, dashed = shear.series[:3], shear.series[3], shear.series[4]
    for record, line in zip(suite.record_results, thin, strict=True):
        np.testing.assert_allclose(line.x[::2], factor * record.peaks["shear"])
    # the thick line is the suite's design statistic as the suite result computes it
    np.testing.assert_allclose(thick.x[::2], factor * suite.peaks["shear"], rtol=1e-12)
    assert thick.label.endswith("mean of 3 records")
    np.testing.assert_allclose(dashed.x[::2], factor * simplified.peaks["shear"])
    assert dashed.style == "--" and "target spectrum" in dashed.label


def test_results_documents_never_hold_histories():
    """Histories live beside the peaks (AnalysisResult.histories), never in the documents."""
    from upliftcli.output import result_to_dict

    suite, _ = fake_suite()
    assert all(r.histories for r in suite.record_results) and not suite.histories
    document = result_to_dict(suite)
    assert all("histories" not in r["result"]["details"] for r in document["suite"]["records"])
