"""Matching keeps a record's character (issue 36, item 3): on a near-field-like record made here
(weak P-wave motion, then a velocity pulse with strong shaking, then a coda), D5-95 grows by at
most 1.25x and at most 2 % of the Arias intensity is added before the original's t_5, by the
net measure (the matched record's normalised Husid curve at the original's t_5)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from upliftcli.motion.baseline import baseline_correct
from upliftcli.motion.character import keep_shares
from upliftcli.motion.code_rules import RULES
from upliftcli.motion.code_spectra import ASCE7Spectrum
from upliftcli.motion.matching import match_record, settings_for
from upliftcli.motion.measures import arias_times, character_change, husid_at, peak_motion
from upliftcli.motion.records import Record

DT = 0.01


def pulse_record() -> np.ndarray:
    """20 s: weak noise from 1 s, a one-cycle acceleration pulse of period 1.5 s (a forward
    directivity velocity pulse) with strong noise from 4 s, an exponential coda."""
    rng = np.random.default_rng(7)
    t = np.arange(2001) * DT
    envelope = np.where(t < 1.0, 0.0, np.where(t < 4.0, 0.08, np.exp(-np.maximum(t - 6.0, 0.0) / 1.5)))
    noise = rng.standard_normal(t.size) * envelope * 1.5
    pulse = np.where((t >= 4.0) & (t < 5.5), 6.0 * np.sin(2.0 * math.pi * (t - 4.0) / 1.5), 0.0)
    taper = np.minimum(1.0, np.minimum(t, t[-1] - t) / 0.5)
    return baseline_correct((noise + pulse) * taper, DT)


def test_a_matched_pulse_record_keeps_its_duration_and_onset():
    original = pulse_record()
    record = Record("pulse", DT, original, source="pulse (made in the test)", units="m/s2")
    result = match_record(record, ASCE7Spectrum(1.0, 0.6, 8.0), (0.2, 2.0), settings_for(RULES["asce7-22"]))
    change = character_change(original, result.acceleration, DT)
    assert change.d5_95_ratio <= 1.25
    assert change.early_gain <= 0.02
    assert 0.2 < change.pgv_ratio < 5.0 and 0.2 < change.pgd_ratio < 5.0


def test_keep_shares_returns_the_weak_start_its_five_percent():
    """A record whose strong part was lowered to 0.7 (as wavelets that lower it do): its unchanged start
    then holds far more than 5 % of the intensity; keep_shares brings the Husid curve at the
    original's t_5 back to 5 % and at its t_95 back to 95 %, leaving the strong part alone."""
    original = pulse_record()
    t5, t95 = arias_times(original, DT)
    t = np.arange(original.size) * DT
    lowered = np.where((t > t5) & (t < t95), 0.7 * original, original)
    assert husid_at(lowered, DT, t5) > 0.08
    kept = keep_shares(lowered, original, DT)
    assert husid_at(kept, DT, t5) == pytest.approx(0.05, abs=0.003)
    assert husid_at(kept, DT, t95) == pytest.approx(0.95, abs=0.003)
    middle = (t > t5 + 0.5) & (t < t95 - 0.5)
    np.testing.assert_allclose(kept[middle], lowered[middle], atol=0.01 * np.abs(lowered).max())
    # a record with its own shares is kept (to the sample-level rounding of t_5, t_95)
    np.testing.assert_allclose(keep_shares(original, original, DT), original, atol=0.01 * np.abs(original).max())


def test_character_change_of_a_scaled_record_is_none():
    original = pulse_record()
    change = character_change(original, 1.7 * original, DT)
    assert change.d5_95_ratio == pytest.approx(1.0) and change.early_gain == pytest.approx(0.0, abs=1e-12)
    assert change.pgv_ratio == pytest.approx(1.0) and change.pgd_ratio == pytest.approx(1.0)
    assert peak_motion(2.0 * original, DT)[0] == pytest.approx(2.0 * peak_motion(original, DT)[0])
