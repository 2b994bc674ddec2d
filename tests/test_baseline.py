"""Baseline correction: the record ends at rest, polynomials are removed exactly, integrals are the records' ones."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from upliftcli.motion.baseline import baseline_correct, correction_basis
from upliftcli.motion.records import ground_displacement, ground_velocity, read_record

ELCENTRO = Path(__file__).resolve().parents[1] / "records" / "elcentro_1940_ns_chopra.txt"



def test_the_record_integrals_work_on_columns_and_are_exact_for_a_ramp():
    """The correction integrates its basis as columns: each column as alone, and a(t) = t
    (piecewise linear, so exact) gives v = t^2/2 and d = t^3/6."""
    rng = np.random.default_rng(3)
    values = rng.normal(size=(500, 3))
    velocity, displacement = ground_velocity(values, 0.01), ground_displacement(values, 0.01)
    t = np.arange(500) * 0.01
    np.testing.assert_allclose(ground_velocity(t, 0.01), t**2 / 2, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(ground_displacement(t, 0.01), t**3 / 6, rtol=1e-12, atol=1e-15)
    for k in range(3):
        np.testing.assert_allclose(velocity[:, k], ground_velocity(values[:, k], 0.01), rtol=0, atol=1e-14)
        np.testing.assert_allclose(displacement[:, k], ground_displacement(values[:, k], 0.01), rtol=0, atol=1e-14)


def test_corrected_record_ends_at_rest():
    record = read_record(ELCENTRO)
    drifting = record.acceleration + 0.01  # a constant offset: v grows by 0.31 m/s, d by 4.9 m
    corrected = baseline_correct(drifting, record.dt)
    scale_v = np.abs(ground_velocity(record.acceleration, record.dt)).max()
    scale_d = np.abs(ground_displacement(record.acceleration, record.dt)).max()
    assert abs(ground_velocity(corrected, record.dt)[-1]) < 1e-12 * scale_v
    assert abs(ground_displacement(corrected, record.dt)[-1]) < 1e-12 * scale_d
    assert abs(ground_displacement(drifting, record.dt)[-1]) > 4.0


def test_polynomial_trends_are_removed_exactly():
    # the correction is a projection: adding any polynomial s (1 - s) q(s), q of degree <= 4,
    # does not change the result
    record = read_record(ELCENTRO)
    s = record.time / record.time[-1]
    trend = s * (1 - s) * (0.3 - 0.2 * s + 0.5 * s**2 - 0.1 * s**3 + 0.05 * s**4)
    np.testing.assert_allclose(baseline_correct(record.acceleration + trend, record.dt),
                               baseline_correct(record.acceleration, record.dt), rtol=0, atol=1e-10)


def test_first_and_last_samples_are_kept():
    # the correcting polynomial vanishes at both ends: no offset where the record is quiet
    record = read_record(ELCENTRO)
    drifting = record.acceleration + 0.01
    corrected = baseline_correct(drifting, record.dt)
    assert corrected[0] == drifting[0] and corrected[-1] == drifting[-1]
    basis = correction_basis(record.npts, record.dt)
    assert basis.shape == (record.npts, 5)
    np.testing.assert_array_equal(basis[[0, -1]], 0.0)
