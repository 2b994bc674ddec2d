"""The exact answer for a design spectrum (analysis/suite_check.py): the check suite cached by its key, the
exact suite mean beside the simplified value, and the ratio split into the suite's standing against
the target and the procedure's own error."""

from __future__ import annotations

import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import invoke

from upliftcli.analysis import run as analysis
from upliftcli.analysis import suite_check
from upliftcli.analysis.accuracy import Check
from upliftcli.deck.load import load_deck
from upliftcli.engines.quantities import COMPARED
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
    return results, suite_check.check_suite_accuracy(deck, results)


def test_simplified_results_get_the_exact_suite_mean(checked):
    results, checks = checked
    assert [c.support for c in checks] == [r.support for r in results]
    for result, check in zip(results, checks, strict=True):
        assert isinstance(check, Check) and check.error is None
        assert check.reference == "exact engine on a spectrum-compatible suite (11 artificial records, seed 2024, mean)"
        assert (check.suite["source"], check.suite["count"], check.suite["statistic"]) == ("generated", 11, "mean")
        assert check.comparisons[0].simplified == result.base_shear  # the result itself, not changed
        assert "accuracy" not in result.details
        names = [c.name for c in check.comparisons]
        assert names == [name for name in COMPARED if result.support in COMPARED[name].supports]
        for c in check.comparisons:
            assert c.ratio == pytest.approx(c.simplified / c.exact)
            # the ratio is the product of its two factors
            assert c.ratio == pytest.approx(check.spectrum_ratio[c.name] * check.procedure_ratio[c.name], rel=1e-12)
        document = check.to_dict()  # the JSON `accuracy` object: the record check's keys and the split
        assert {"support", "reference", "band", "motion_band", "simplified", "exact", "ratio", "out_of_band",
                "warnings", "suite", "spectrum_ratio", "procedure_ratio"} <= set(document)
        assert document["procedure_ratio"] == dict(check.procedure_ratio)


def test_plain_response_spectrum_analysis_has_no_procedure_error(checked):
    # rigid base: modal response spectrum analysis (CQC) against the exact linear response, record by
    # record: within a few per cent, while the records' standing against the target is its own factor
    _, checks = checked
    rigid = next(c for c in checks if c.support == "rigid")
    for name in ("base_shear", "base_moment", "drift_ratio", "roof_displacement"):
        assert 0.95 <= rigid.procedure_ratio[name] <= 1.05
        assert 0.85 <= rigid.spectrum_ratio[name] <= 1.15


def test_the_deck_suite_serves_as_the_check(tmp_path):
    deck = load_deck(ROOT / "inputs" / "ten_story_asce7_suite.toml", ["analysis.engine=\"simplified\"",
                                                                       "analysis.supports=\"rigid\""])
    (result,) = analysis.run(deck)
    (check,) = suite_check.check_suite_accuracy(deck, [result])
    assert check.suite["source"] == "deck" and check.suite["count"] == 11
    assert check.reference.startswith("exact engine on a spectrum-compatible suite (the deck's 11 records")
    # the records stand 12-18 % above the (MCE_R) target: the ratio shows it, the procedure does not
    assert check.spectrum_ratio["base_shear"] < 0.92 and 0.95 <= check.procedure_ratio["base_shear"] <= 1.05


def test_no_check_skips_it():
    result = invoke("analyze", DESIGN, "--no-check", "--support", "rigid", "--format", "json")
    assert result.exit_code == 0 and '"accuracy"' not in result.stdout
    result = invoke("analyze", DESIGN, "--support", "rigid")
    assert result.exit_code == 0 and "Accuracy check split" in result.stdout
    assert "against the exact engine on a spectrum-compatible suite" in " ".join(result.stdout.split())
    assert "V_b [kN]" in result.stdout  # display units
    us = invoke("analyze", DESIGN, "--support", "rigid", "--units", "us")
    assert "V_b [kip]" in us.stdout and "Accuracy check split" in us.stdout
    document = json.loads(invoke("analyze", DESIGN, "--support", "rigid", "--format", "json").stdout)
    assert document["accuracy"]["suite"]["source"] == "generated"
    assert set(document["accuracy"]["spectrum_ratio"]) == set(document["accuracy"]["ratio"])


def test_a_record_deck_is_left_to_the_record_check(example_deck):
    results = analysis.run(replace(example_deck))
    assert suite_check.check_suite_accuracy(example_deck, results) == []
    assert [c.reference for c in suite_check.check_deck(example_deck, results)] == ["exact engine, all 10 modes"] * 3


def test_the_report_shows_the_check_and_its_split(checked):
    from upliftcli.report.build import build_report
    from upliftcli.report.document import Table
    from upliftcli.report.provenance import provenance

    results, checks = checked
    deck = load_deck(DESIGN)
    report, _ = build_report(deck, results, DESIGN.read_text(), [], provenance(deck, ["test"]), checks=checks)
    tables = {block.id: block for section in report.sections for block in section.blocks if isinstance(block, Table)}
    assert "exact engine on a spectrum-compatible suite (11 artificial records" in tables["table-accuracy"].note
    split = tables["table-accuracy-split"]
    assert len(split.rows) == len(tables["table-accuracy"].rows) == sum(len(c.comparisons) for c in checks)
    first = checks[0].comparisons[0]
    assert split.rows[0][:2] == [checks[0].support, COMPARED[first.name].meaning]
    assert float(split.rows[0][4]) == pytest.approx(checks[0].procedure_ratio[first.name], rel=1e-3)


def test_the_cache_is_not_written_through_a_symlink(tmp_path):
    outside = tmp_path / "outside.npz"
    outside.write_bytes(b"keep")
    path = tmp_path / "check-suites" / "key.npz"
    path.parent.mkdir()
    path.symlink_to(outside)
    suite_check._store(path, np.zeros((2, 3)), np.ones(2))  # not kept, no error
    assert outside.read_bytes() == b"keep" and path.is_symlink()
