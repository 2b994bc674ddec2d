"""Suites as data: reading, factors applied, and every bad-input message."""

from __future__ import annotations

import dataclasses
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from upliftcli.errors import InputError
from upliftcli.motion.code_rules import RULES
from upliftcli.motion.design_spectra import ASCE7Spectrum, TabulatedSpectrum
from upliftcli.motion.records import read_record
from upliftcli.motion.suites import build_suite, read_records, suite_entries

ROOT = Path(__file__).resolve().parents[1]
ELCENTRO = ROOT / "records" / "elcentro_1940_ns_chopra.txt"
TARGET = ASCE7Spectrum(1.0, 0.6, 8.0)


@pytest.fixture(scope="module")
def record():
    return read_record(ELCENTRO)


def test_suite_is_frozen_and_applies_its_factors(record):
    suite = build_suite([record, replace(record, acceleration=2 * record.acceleration)], TARGET, (0.2, 2.0),
                        RULES["mean"], "amplitude", suite_factor=True)
    with pytest.raises(dataclasses.FrozenInstanceError):
        suite.scaling = "none"  # type: ignore[misc]
    assert suite.factors[0] == suite.factors[1]
    motions = suite.motions()
    np.testing.assert_allclose(motions[1].acceleration, 2 * suite.factors[0] * record.acceleration)
    assert motions[0].scale == pytest.approx(suite.factors[0])
    assert suite.mean_ratio().min() == pytest.approx(1.005, rel=1e-9)  # "mean": 100 %, aimed 0.5 % above
    assert suite.count == 2 and suite.statistic == "mean" and suite.sources == (str(ELCENTRO),) * 2


def test_check_spectra_computed_once_read_only_and_equal_to_explicit_periods(record):
    suite = build_suite([record, replace(record, acceleration=2 * record.acceleration)], TARGET, (0.2, 2.0),
                        RULES["mean"], "amplitude")
    spectra = suite.spectra()
    assert suite.spectra() is spectra and not spectra.flags.writeable
    np.testing.assert_array_equal(spectra, suite.spectra(suite.periods.copy()))
    rescaled = replace(suite, factors=(1.0, 1.0))  # a new suite: its own spectra
    np.testing.assert_allclose(rescaled.spectra()[1], 2.0 * rescaled.spectra()[0], rtol=1e-12)


def test_record_too_short_for_the_period_range(record):
    with pytest.raises(InputError, match=r"elcentro_1940_ns_chopra\.txt: duration: a record of at least 4 x the "
                                         r"upper period 8 s = 32 s for the period range, got 31\.18 s"):
        build_suite([record], TARGET, (0.2, 8.0), RULES["asce7-22"])


def test_the_documented_limits_of_a_suite_are_checked_before_its_spectra(record, monkeypatch):
    """A period range of [1e-6, 2e-6] s ran past 300 s: the lower period is refused below the
    record's spectrum range, and the sub-steps of the suite's check spectra are bounded, before
    any spectrum is computed (counted, not timed)."""
    from upliftcli.motion import suites

    computed = []
    monkeypatch.setattr(suites, "response_spectrum", lambda *args, **kwargs: computed.append(args))
    with pytest.raises(InputError, match=r"^suite: period_range: periods of at least 8e-06 s or 0 \(limit for the "
                                         r"record's dt = 0.02 s .*got 1e-06 s \(record .*elcentro"):
        build_suite([record], TARGET, (1e-6, 2e-6), RULES["mean"], "amplitude")
    with pytest.raises(InputError, match=r"^suite: period_range: at most 100,000,000 oscillator sub-steps for the "
                                         r"spectra of the suite"):
        build_suite([record] * 3, TARGET, (1e-5, 2e-5), RULES["mean"], "amplitude")
    assert computed == []


def test_an_all_zero_record_is_not_scaled(record):
    """An all-zero record in a scaled suite gave the factor nan with exit 0."""
    zero = replace(record, acceleration=np.zeros_like(record.acceleration), source="zero.txt")
    for scaling, expected in (("amplitude", "a record with non-zero accelerations to be scaled"),
                              ("match", "acceleration: a record with motion to match")):  # check_record (issue 24)
        with pytest.raises(InputError, match=rf"^zero.txt: {expected}"):
            build_suite([record, zero], TARGET, (0.2, 2.0), RULES["mean"], scaling)
    assert build_suite([record, zero], TARGET, (0.2, 2.0), RULES["mean"], "none").factors == (1.0, 1.0)


def _degenerate(record, values) -> object:
    """The record with these accelerations [m/s^2] (its length and step kept), named degenerate.txt."""
    return replace(record, acceleration=np.asarray(values, dtype=float), source="degenerate.txt")


def _spike(n: int, at: int) -> np.ndarray:
    values = np.zeros(n)
    values[at] = 3.0
    return values


@pytest.mark.parametrize(("values", "expected"), [
    (lambda n: np.full(n, 0.0981), r"every sample is 0\.0981 m/s\^2: a constant acceleration"),
    (lambda n: _spike(n, 0), r"D5-95\) lasts 0\.0\d+ s from t = 0\.\d+ s, less than the lower period 0\.2 s"),
    (lambda n: _spike(n, n // 2), r"lasts 0\.0\d+ s from t = [\d.]+ s, less than the lower period 0\.2 s: a single"),
    (lambda n: _spike(n, n - 1), r"lasts 0\.0\d+ s .*: a single pulse, not a ground motion"),
    (lambda n: 1e-300 * (-1.0) ** np.arange(n), r"its Arias intensity is 0 in double precision \(peak 1e-300"),
], ids=["constant", "first sample", "one sample", "last sample", "1e-300"])
def test_a_record_with_no_ground_shaking_is_refused_before_matching(record, monkeypatch, values, expected):
    """Issue 38, T9: a constant record ended in a LinAlgError deep in the wavelet iteration; a
    single non-zero sample in a singular system (or a record matched from nothing but wavelets);
    values whose squares underflow in a factor of inf. Each is now one line naming the record,
    before any spectrum is computed."""
    from upliftcli.motion import suites

    computed = []
    monkeypatch.setattr(suites, "match_record", lambda *args, **kwargs: computed.append(args))
    degenerate = _degenerate(record, values(record.npts))
    with pytest.raises(InputError, match=r"^degenerate.txt: acceleration: a record with motion to match \(.*"
                                         + expected):
        build_suite([record, degenerate], TARGET, (0.2, 2.0), RULES["asce7-22"], "match")
    assert computed == []


def test_a_record_whose_spectrum_is_zero_is_not_scaled(record):
    """Accelerations of 5e-324 m/s^2 (the smallest double) give S_a = 0: their amplitude factor
    was 1/0 (a ZeroDivisionError under `record scale`); now one line naming the record."""
    tiny = _degenerate(record, 5e-324 * (-1.0) ** np.arange(record.npts))
    with pytest.raises(InputError, match=r"^degenerate.txt: acceleration: a record with a response spectrum > 0 "
                                         r"over the period range to be scaled, got S_a = 0 m/s\^2 at 0\.2 s"):
        build_suite([record, tiny], TARGET, (0.2, 2.0), RULES["mean"], "amplitude")


def test_record_too_coarse_to_be_matched(record):
    with pytest.raises(InputError, match=r"dt: a time step of at most 0\.0125 s .* to be matched, got 0\.02 s"):
        build_suite([record], TARGET, (0.05, 2.0), RULES["asce7-22"], "match")
    build_suite([record], TARGET, (0.05, 2.0), RULES["asce7-22"], "amplitude")  # scaling needs no fine step


def test_target_that_does_not_cover_the_range(record):
    table = TabulatedSpectrum([0.0, 0.5, 2.0], [0.4, 1.0, 0.3], damping=0.05)
    with pytest.raises(InputError, match=r"suite: period_range: a period range within the target's 0-2 s .* "
                                         r"got 0\.2-2\.4 s"):
        build_suite([record], table, (0.2, 2.4), RULES["mean"])


def test_too_few_records_warns_naming_the_rule(record):
    ec8 = build_suite([record] * 3, TARGET, (0.2, 2.0), RULES["ec8"], "amplitude")
    assert ("EN 1998-1 3.2.3.1 / 4.3.3.4.3: with fewer than 7 records the design value is the maximum of the "
            "responses, not the mean (3 records)") in ec8.warnings
    assert ec8.statistic == "max"
    asce = build_suite([record], TARGET, (0.2, 2.0), RULES["asce7-22"], "none")
    assert "ASCE 7-22 16.2 asks for at least 11 records; the suite has 1" in asce.warnings
    assert any("the mean S_a/target is" in w and "below 0.9" in w for w in asce.warnings)


def test_bad_arguments(record):
    with pytest.raises(InputError, match="suite: suite: at least one record"):
        build_suite([], TARGET, (0.2, 2.0), RULES["mean"])
    with pytest.raises(InputError, match="scaling: one of none, amplitude, match"):
        build_suite([record], TARGET, (0.2, 2.0), RULES["mean"], "spectral")
    with pytest.raises(InputError, match="period_range: 0 < lower < upper"):
        build_suite([record], TARGET, (2.0, 0.2), RULES["mean"])


def test_entries_from_a_folder_and_a_list(tmp_path):
    folder = tmp_path / "suite"
    folder.mkdir()
    for name in ("b.txt", "a.txt"):
        (folder / name).write_bytes(ELCENTRO.read_bytes())
    (folder / "README.md").write_text("not a record")
    (folder / "manifest.json").write_text("{}")
    deck = str(tmp_path / "deck.toml")
    entries = suite_entries("suite", deck)
    assert [path.name for path, _ in entries] == ["a.txt", "b.txt"]
    assert len(read_records(entries)) == 2
    entries = suite_entries(["suite/a.txt", {"file": "suite/b.txt", "units": "g", "scale": 2.0}], deck)
    records = read_records(entries)
    np.testing.assert_allclose(records[1].acceleration, 2 * records[0].acceleration)
    with pytest.raises(InputError, match=r"deck\.toml: ground_motion\.suite: a folder of records .* not found"):
        suite_entries("missing", deck)
    with pytest.raises(InputError, match=r"ground_motion\.suite\[1\]\.unit: a key of a suite record"):
        suite_entries(["suite/a.txt", {"file": "suite/b.txt", "unit": "g"}], deck)
    with pytest.raises(InputError, match=r"ground_motion\.suite\[0\]\.file: the path of a record file"):
        suite_entries([{"units": "g"}], deck)
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match=r"ground_motion\.suite: record files"):
        suite_entries("empty", deck)


# ----------------------------------------------------------------------------- entries through the field checker

def test_suite_entries_go_through_the_field_checker(tmp_path):
    from upliftcli.errors import InputErrors
    from upliftcli.motion.suites import suite_entries

    deck = str(tmp_path / "deck.toml")
    with pytest.raises(InputError, match=r"deck\.toml: ground_motion\.suite\[0\]\.dt: a number > 0 and at most 10 "
                                         r"\[s\], got True$"):
        suite_entries([{"file": "a.txt", "dt": True}], deck)  # was read as dt = 1 s: a base shear 88x too large
    with pytest.raises(InputErrors) as info:
        suite_entries([{"file": "a.txt", "dt": "x", "scale": 0, "units": "furlong", "formats": "at2"}], deck)
    assert [e.location for e in info.value.errors] == [f"ground_motion.suite[0].{key}" for key in
                                                       ("dt", "scale", "units", "formats")]
    with pytest.raises(InputError, match=r"suite\[1\]\.file: the path of a record file"):
        suite_entries(["a.txt", {"dt": 0.01}], deck)
    with pytest.raises(InputError, match=r"suite\[0\]: a file path or a table"):
        suite_entries([3], deck)
    (path, options), = suite_entries([{"file": "a.txt", "dt": "10 ms", "units": "gal"}], deck)
    assert path == tmp_path / "a.txt" and options == {"dt": 0.01, "units": "gal"}
def test_a_suite_holds_at_most_the_documented_number_of_records(tmp_path):
    from upliftcli.runtime.limits import MAX_SUITE_RECORDS

    deck = str(tmp_path / "deck.toml")
    with pytest.raises(InputError, match=r"ground_motion.suite: at most 1,000 records \(limit of the tool\), got 1,0"):
        suite_entries(["r.txt"] * (MAX_SUITE_RECORDS + 1), deck)
    for k in range(3):
        (tmp_path / f"r{k}.txt").write_text("x")
    assert len(suite_entries(".", deck)) == 3


@pytest.mark.skipif(not hasattr(__import__("os"), "mkfifo"), reason="named pipes are POSIX")
def test_a_fifo_among_the_records_of_a_suite_folder_is_refused_by_name(tmp_path):
    """Issue 38: a FIFO named as a record in a suite folder was passed over without a word. It is
    now one line naming it (never opened: it would block); other names are still passed over."""
    import os
    import shutil

    folder = tmp_path / "suite"
    folder.mkdir()
    shutil.copy(ELCENTRO, folder / "a.txt")
    os.mkfifo(folder / "notes.md")  # not named as a record: passed over, as before
    assert [path.name for path, _ in suite_entries("suite", str(tmp_path / "deck.toml"))] == ["a.txt"]
    os.mkfifo(folder / "b.txt")
    with pytest.raises(InputError) as info:
        suite_entries("suite", str(tmp_path / "deck.toml"))
    assert str(info.value) == (f"{tmp_path / 'deck.toml'}: ground_motion.suite: regular record files in "
                               f"'{folder}': 'b.txt' is a named pipe (FIFO) (move it out of the folder, or list "
                               "the records in the deck)")
