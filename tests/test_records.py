"""Tests of motion/records.py: read_record's units, scale, time window and bad input, and the
record measures (the formats: test_readers.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_readers import VALUES, write  # a small record and a file writer, shared

from upliftcli.errors import InputError
from upliftcli.motion.records import (
    arias_intensity,
    bundled_records_dir,
    ground_displacement,
    ground_velocity,
    read_record,
)
from upliftcli.units import STANDARD_GRAVITY

G = STANDARD_GRAVITY


def test_scale_units_and_window(tmp_path):
    path = write(tmp_path, "rec.csv", "t,a\n" + "\n".join(f"{i * 0.1:.1f},{v}" for i, v in enumerate(VALUES)))
    record = read_record(path, units="m/s2", scale=2.0, window=(0.2, 0.5))
    np.testing.assert_allclose(record.acceleration, 2.0 * VALUES[2:6])
    assert record.scale == 2.0 and record.time[0] == 0.0
    with pytest.raises(InputError, match="window"):
        read_record(path, units="g", window=(0.5, 0.2))
    with pytest.raises(InputError, match="units: acceleration units one of"):
        read_record(path, units="furlong/s2")
    with pytest.raises(InputError, match=r"dt = 0\.1 s as in the file"):
        read_record(path, units="g", dt=0.02)


def test_empty_and_missing_files(tmp_path):
    with pytest.raises(InputError, match=r"empty\.txt: acceleration values \(the file is empty\)"):
        read_record(write(tmp_path, "empty.txt", "\n  \n"), dt=0.01, units="g")
    with pytest.raises(InputError, match="file not found"):
        read_record(tmp_path / "nope.AT2")
    with pytest.raises(InputError, match=r"headeronly\.txt: acceleration values after the header"):
        read_record(write(tmp_path, "headeronly.txt", "# dt = 0.01\n# units: g\n"))
    with pytest.raises(InputError, match="format: one of"):
        read_record(tmp_path / "nope.AT2", format="mseed")


def test_integrals_are_exact_for_piecewise_linear_acceleration():
    dt, a0, slope = 0.01, 1.5, -2.0
    t = np.arange(301) * dt
    acceleration = a0 + slope * t
    np.testing.assert_allclose(ground_velocity(acceleration, dt), a0 * t + slope * t**2 / 2, atol=1e-12)
    np.testing.assert_allclose(ground_displacement(acceleration, dt), a0 * t**2 / 2 + slope * t**3 / 6, atol=1e-12)
    duration = t[-1]
    exact = (a0 + slope * duration) ** 3 - a0**3
    assert arias_intensity(acceleration, dt) == pytest.approx(math.pi / (2 * G) * exact / (3 * slope), rel=1e-12)


def test_elcentro_peak_ground_velocity():
    record = read_record(bundled_records_dir() / "elcentro_1940_ns_chopra.txt")
    pgv = np.max(np.abs(ground_velocity(record.acceleration, record.dt)))
    assert pgv == pytest.approx(0.36, abs=0.005)  # "about 36 cm/s" (records/README.md)


def test_one_sample_is_refused(tmp_path):
    with pytest.raises(InputError, match="at least two acceleration samples, found 1"):
        read_record(write(tmp_path, "one.txt", "# dt = 0.01\n# units: g\n0.05\n"))


def test_values_that_overflow_after_units_and_scale_are_refused(tmp_path):
    with pytest.raises(InputError, match=r"big.txt: accelerations of magnitude at most 1e\+30 m/s\^2 .* got inf"):
        read_record(write(tmp_path, "big.txt", "# dt = 0.01\n# units: g\n1e308\n0.1\n"))
    with pytest.raises(InputError, match=r": scale: accelerations of magnitude at most") as info:
        read_record(write(tmp_path, "ok.txt", "# dt = 0.01\n# units: g\n1\n0.1\n"), scale=1e30)
    assert info.value.location == "scale"


def test_record_time_step_is_bounded(tmp_path):
    with pytest.raises(InputError, match=r"line 1: a time step dt: a number > 0 and at most 10 \[s\], got 1e\+300"):
        read_record(write(tmp_path, "dt.txt", "# dt = 1e300\n# units: g\n0.1\n0.1\n"))


def test_a_window_ending_far_past_the_record_keeps_the_rest(tmp_path):
    path = write(tmp_path, "w.txt", "# dt = 0.01\n# units: g\n1 2 3 4 5\n")
    assert read_record(path, window=(0.02, 1e30)).acceleration.size == 3


def test_units_that_contradict_the_header_are_refused_unless_overridden(tmp_path):
    path = write(tmp_path, "r.txt", "# dt = 0.01\n# units: g\n0.1\n-0.2\n0.3\n")
    with pytest.raises(InputError) as info:
        read_record(path, units="gal")
    assert info.value.location == "units"
    assert "declares, g, got 'gal' (a factor of 0.00102 on every value" in info.value.expected
    assert "override_header_units = true" in info.value.expected
    record = read_record(path, units="cm/s2", override_header_units=True)
    assert record.units == "cm/s2" and record.pga == pytest.approx(0.003)
    assert read_record(path, units="G").pga == pytest.approx(0.3 * STANDARD_GRAVITY)  # the same units: fine
    plain = write(tmp_path, "plain.txt", "# dt = 0.01\n0.1\n-0.2\n0.3\n")  # no units in the header
    assert read_record(plain, units="gal").pga == pytest.approx(0.003)


def test_a_boolean_is_no_time_step_nor_scale(tmp_path):
    path = write(tmp_path, "r.txt", "0.1\n-0.2\n0.3\n")
    with pytest.raises(InputError, match=r"dt: a time step dt: a number > 0 and at most 10 \[s\], got True"):
        read_record(path, units="g", dt=True)
    with pytest.raises(InputError, match="scale: a finite non-zero scale factor, got True"):
        read_record(path, units="g", dt=0.01, scale=True)
