"""Selection of recorded motions: the fits and misfits in closed form, the per-event cap, the
factor limits (a candidate beyond them passed over, never clipped; the factor a record is
written with, its fit times the suite's common multiplier, within them), each error naming its
option."""

from __future__ import annotations

import numpy as np
import pytest

from upliftcli.errors import InputError
from upliftcli.motion.scaling import amplitude_factors
from upliftcli.motion.selection import CRITERION, candidate_spectra, check_factors, fits, select

TARGET = np.array([1.0, 2.0, 4.0, 2.0, 1.0])


def test_fits_and_misfits_in_closed_form():
    # proportional spectra: the fit is the ratio, the misfit 0; a shape off by exp(+-0.1): RMS 0.1
    shape = np.exp(np.array([0.1, -0.1, 0.1, -0.1, 0.0]) * np.sqrt(5 / 4))
    spectra = np.vstack((0.5 * TARGET, 2.0 * TARGET, 0.25 * TARGET * shape))
    factors, misfits = fits(spectra, TARGET)
    np.testing.assert_allclose(factors, [2.0, 0.5, 4.0], rtol=1e-12)
    np.testing.assert_allclose(misfits, [0.0, 0.0, 0.1], atol=1e-12)
    # a fit is never clipped: the misfit is the shape's alone, whatever the factor
    factors, misfits = fits(0.1 * TARGET * shape, TARGET)
    assert factors[0] == pytest.approx(10.0) and misfits[0] == pytest.approx(0.1)


def test_best_first_and_at_most_per_event():
    spectra = np.vstack([TARGET * np.exp(0.05 * k * np.array([1, -1, 1, -1, 0])) for k in range(6)])
    events = ["A", "A", "A", "B", "B", "C"]
    choice = select(spectra, TARGET, events, 4, per_event=2)
    assert choice.indices == (0, 1, 3, 4)  # the third of A is skipped for B's
    assert list(choice.misfits) == sorted(choice.misfits)
    with pytest.raises(InputError, match=r"--count: at most 5 records from 3 earthquakes with --per-event 2 "
                                          r"\(6 usable candidates\), got --count 6"):
        select(spectra, TARGET, events, 6, per_event=2)


def test_factor_limits_name_their_option():
    check_factors([0.5, 3.9], (0.25, 4.0), 0.9)
    with pytest.raises(InputError, match=r"--factor-max: .* the chosen records need up to 4\.5"):
        check_factors([0.5, 4.5], (0.25, 4.0), 0.9)
    with pytest.raises(InputError, match=r"--factor-min: .* the chosen records need 0\.2"):
        check_factors([0.2, 1.0], (0.25, 4.0), 0.9)


def _shaped(level: float, k: int) -> np.ndarray:
    """A candidate of `level` x the target with a shape misfit growing with k (0.02 k)."""
    return level * TARGET * np.exp(0.02 * k * np.array([1.0, -1.0, 1.0, -1.0, 0.0]))


def test_a_candidate_beyond_the_limits_is_passed_over_not_clipped():
    """The best-shaped candidate needs a factor of 5 (beyond 4): it was clipped to 4, ranked by
    the misfit at 4, chosen, and then written with 5 (`--factor-max 4` refused 4.1, `5` then 6.24)."""
    spectra = np.vstack([_shaped(0.2, 0)] + [_shaped(0.5, k) for k in range(1, 5)])
    choice = select(spectra, TARGET, list("ABCDE"), 3, per_event=1, criterion=1.0)
    assert choice.indices == (1, 2, 3)
    assert max(choice.factors) <= 4.0
    wide = select(spectra, TARGET, list("ABCDE"), 3, (0.25, 6.0), per_event=1, criterion=1.0)
    assert wide.indices[0] == 0 and max(wide.factors) <= 6.0


def test_the_written_factors_are_the_fits_times_the_common_multiplier_within_the_limits():
    """A record whose fit is within the limits but whose fit x the suite's common multiplier is
    not is replaced: the choice is made again without it."""
    rng = np.random.default_rng(7)
    spectra = np.vstack([TARGET * rng.uniform(0.26, 0.5) * np.exp(rng.normal(0.0, 0.15, TARGET.size))
                         for _ in range(30)])
    events = [f"E{k // 2}" for k in range(30)]
    for high in (3.0, 3.5, 4.0, 5.0):
        choice = select(spectra, TARGET, events, 7, (0.25, high), per_event=2)
        written = amplitude_factors(spectra[list(choice.indices)], TARGET, CRITERION)
        np.testing.assert_allclose(choice.factors, written, rtol=1e-12)
        assert max(choice.factors) <= high * (1 + 1e-9), high
        ratios = np.asarray(choice.factors) / np.asarray(choice.fits)
        np.testing.assert_allclose(ratios, ratios[0], rtol=1e-12)  # one common multiplier


def test_too_few_within_the_limits_names_the_factor_limit():
    spectra = np.vstack([_shaped(0.1, k) for k in range(4)] + [_shaped(0.5, 5)])
    with pytest.raises(InputError, match=r"--factor-max: scale factors within 0\.25-4 .* only 1 of 5 candidates fit "
                                          r"the target within them, too few for --count 3 with --per-event 3 "
                                          r"\(their own fits span 2 to 10; widen --factor-max"):
        select(spectra, TARGET, list("ABCDE"), 3)
    with pytest.raises(InputError, match=r"--factor-min: .* only 0 of 2 candidates .* widen --factor-min or give "
                                          r"weaker records"):
        select(np.vstack([_shaped(10.0, 0), _shaped(20.0, 1)]), TARGET, list("AB"), 2)


def test_candidate_spectra_limit_the_pool_not_a_suite(monkeypatch):
    """The candidates' spectra are bounded by MAX_SELECTION_WORK for the pool (the suite's own
    limit is checked on the records chosen): the FEMA P695 near-field set (56 records) was refused
    as if it were one suite, the message blaming the deck's period_range."""
    from upliftcli.motion.records import Record
    from upliftcli.runtime import limits

    records = [Record(f"r{k}", 0.01, np.sin(np.arange(1000) * 0.1 * (k + 1)), source=f"r{k}.txt") for k in range(3)]
    periods = np.array([0.2, 0.5, 1.0])
    spectra = candidate_spectra(records, periods, 0.05, "folder")
    assert spectra.shape == (3, 3) and np.all(spectra > 0)
    monkeypatch.setattr(limits, "MAX_SELECTION_WORK", 8_000)
    with pytest.raises(InputError, match=r"--from: folder: at most 8,000 oscillator sub-steps for the candidates' "
                                          r"spectra, got 9,000 \(3 records, 3 periods from 0\.2 s\): fewer "
                                          r"candidates"):
        candidate_spectra(records, periods, 0.05, "folder")
    coarse = [Record("coarse", 0.5, np.ones(100), source="coarse.txt")]
    with pytest.raises(InputError, match=r"--from: folder: periods of at least .* \(record coarse\.txt\)"):
        candidate_spectra(coarse, np.array([1e-4, 1.0]), 0.05, "folder")
