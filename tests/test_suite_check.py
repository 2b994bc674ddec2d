"""The exact answer for a design spectrum (suite_check.py): the check suite cached by its key, the
exact suite mean beside the simplified value, and the ratio split into the suite's standing against
the target and the procedure's own error."""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import invoke

from upliftcli import analysis, suite_check
from upliftcli.accuracy import CHECKED
from upliftcli.deck import load_deck
from upliftcli.motion.design_spectra import ASCE7Spectrum

ROOT = Path(__file__).resolve().parents[1]
DESIGN = ROOT / "inputs" / "ten_story_asce7.toml"


def test_cache_folder(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert suite_check.cache_dir() == tmp_path / "uplift"
    monkeypatch.delenv("XDG_CACHE_HOME")
    if sys.platform.startswith("linux"):
        assert suite_check.cache_dir() == Path.home() / ".cache" / "uplift"


def test_key_follows_the_target_and_the_generator(monkeypatch):
    one, same, other = ASCE7Spectrum(1.0, 0.6, 8.0), ASCE7Spectrum(1.0, 0.6, 8.0), ASCE7Spectrum(1.0, 0.5, 8.0)
    key = suite_check.suite_key(one, (0.05, 5.0))
    assert key == suite_check.suite_key(same, (0.05, 5.0)) != suite_check.suite_key(other, (0.05, 5.0))
    assert key != suite_check.suite_key(one, (0.05, 4.0))
    monkeypatch.setattr("upliftcli.motion.generate.GENERATOR_VERSION", "another")
    assert key != suite_check.suite_key(one, (0.05, 5.0))


def test_check_suite_is_generated_once_and_cached_atomically(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(suite_check, "CHECK_COUNT", 2)  # two records keep this test short
    spectrum = ASCE7Spectrum(0.8, 0.4, 8.0)
    notes = []
    first, info = suite_check.check_suite(spectrum, notes.append)
    assert len(notes) == 1 and "generating the check suite (2 records" in notes[0]
    folder = tmp_path / "uplift" / "check-suites"
    assert [p.name for p in folder.iterdir()] == [Path(info["cache"]).name]  # no temporary file left
    again, _ = suite_check.check_suite(spectrum, notes.append)
    assert len(notes) == 1  # read from the cache
    for a, b in zip(first.motions(), again.motions(), strict=True):
        np.testing.assert_array_equal(a.acceleration, b.acceleration)
    assert first.count == 2 and first.made == ("artificial",) * 2 and info["seed"] == suite_check.CHECK_SEED
    ratio = first.mean_ratio()  # matched to 100 % of the spectrum ("mean" rule), each within -10/+30 %
    assert ratio.min() >= 0.9 and ratio.max() <= 1.3


@pytest.fixture(scope="module")
def checked():
    deck = load_deck(DESIGN)
    results = analysis.run(deck)
    suite_check.check_suite_accuracy(deck, results)
    return results


def test_simplified_results_get_the_exact_suite_mean(checked):
    for result in checked:
        check = result.details["accuracy"]
        assert check["reference"] == "exact-suite" and check["support"] == result.support
        assert (check["suite"]["source"], check["suite"]["count"], check["suite"]["statistic"]) == ("generated", 11,
                                                                                                      "mean")
        for name in CHECKED:
            assert check["ratio"][name] == pytest.approx(check["simplified"][name] / check["exact"][name])
            # the ratio is the product of its two factors
            assert check["ratio"][name] == pytest.approx(check["spectrum_ratio"][name] * check["procedure_ratio"][name],
                                                         rel=1e-12)


def test_plain_response_spectrum_analysis_has_no_procedure_error(checked):
    # rigid base: modal response spectrum analysis (CQC) against the exact linear response, record by
    # record: within a few per cent, while the records' standing against the target is its own factor
    rigid = next(r for r in checked if r.support == "rigid").details["accuracy"]
    for name in CHECKED:
        assert 0.95 <= rigid["procedure_ratio"][name] <= 1.05
        assert 0.85 <= rigid["spectrum_ratio"][name] <= 1.15


def test_the_deck_suite_serves_as_the_check(tmp_path):
    deck = load_deck(ROOT / "inputs" / "ten_story_asce7_suite.toml", ["analysis.engine=\"simplified\"",
                                                                       "analysis.supports=\"rigid\""])
    (result,) = analysis.run(deck)
    suite_check.check_suite_accuracy(deck, [result])
    check = result.details["accuracy"]
    assert check["suite"]["source"] == "deck" and check["suite"]["count"] == 11
    # the records stand 12-18 % above the (MCE_R) target: the ratio shows it, the procedure does not
    assert check["spectrum_ratio"]["base_shear"] < 0.92 and 0.95 <= check["procedure_ratio"]["base_shear"] <= 1.05


def test_no_check_skips_it():
    result = invoke("analyze", DESIGN, "--no-check", "--support", "rigid", "--format", "json")
    assert result.exit_code == 0 and '"accuracy"' not in result.stdout
    result = invoke("analyze", DESIGN, "--support", "rigid")
    assert result.exit_code == 0 and "Accuracy check split" in result.stdout


def test_a_record_deck_is_left_to_the_record_check(example_deck):
    results = analysis.run(replace(example_deck))
    suite_check.check_suite_accuracy(example_deck, results)
    assert all("accuracy" not in r.details for r in results)
