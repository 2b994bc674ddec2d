"""Design spectra at their corner periods against hand values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from upliftcli.errors import InputError
from upliftcli.motion.design_spectra import (
    ASCE7Spectrum,
    EC8Spectrum,
    TabulatedSpectrum,
    asce_damping_coefficient,
    ec8_damping_correction,
    from_mapping,
)

G = 9.80665


def test_asce7_corner_values_at_5_percent():
    spectrum = ASCE7Spectrum(sds=1.0, sd1=0.6, tl=8.0)
    # T0 = 0.2 * 0.6 / 1.0 = 0.12 s, TS = 0.6 s
    assert (spectrum.t0, spectrum.ts) == pytest.approx((0.12, 0.6))
    periods = [0.0, 0.06, 0.12, 0.6, 1.0, 2.0, 8.0, 10.0]
    hand = [0.4, 0.7, 1.0, 1.0, 0.6, 0.3, 0.075, 0.6 * 8.0 / 100.0]
    np.testing.assert_allclose(spectrum.sa(periods, 0.05) / G, hand, rtol=1e-12)
    assert spectrum.sa(1.0, 0.05).shape == ()


def test_asce_damping_coefficient_against_asce7_table():
    # ASCE 7 Table 18.7-2 (damping coefficient B): 2 % 0.8, 5 % 1.0, 10 % 1.2, 20 % 1.5, 30 % 1.8
    np.testing.assert_allclose(asce_damping_coefficient([0.02, 0.05, 0.10, 0.20, 0.30]),
                               [0.8, 1.0, 1.2, 1.5, 1.8], rtol=0.025)
    spectrum = ASCE7Spectrum(sds=1.0, sd1=0.6, tl=8.0)
    b = 4 / (5.6 - math.log(10.0)) / (4 / (5.6 - math.log(5.0)))
    np.testing.assert_allclose(spectrum.sa([0.0, 0.12, 0.6, 2.0, 10.0], 0.10) / G,
                               [0.4, 1.0 / b, 1.0 / b, 0.3 / b, 0.048 / b], rtol=1e-12)


def test_ec8_type1_ground_b_corners():
    spectrum = EC8Spectrum(ag=0.3, ground_type="B", spectrum_type=1)  # S 1.2, TB 0.15, TC 0.5, TD 2.0
    periods = [0.0, 0.075, 0.15, 0.5, 1.0, 2.0, 4.0]
    hand = [0.36, 0.63, 0.9, 0.9, 0.45, 0.225, 0.05625]
    np.testing.assert_allclose(spectrum.sa(periods, 0.05) / G, hand, rtol=1e-12)


def test_ec8_type2_ground_d_and_damping_correction():
    spectrum = EC8Spectrum(ag=0.1, ground_type="d", spectrum_type=2, importance=1.2)  # S 1.8, TB .1, TC .3, TD 1.2
    ag_s = 0.1 * 1.2 * 1.8
    eta = math.sqrt(10 / (5 + 10))
    hand = [ag_s, ag_s * 2.5 * eta, ag_s * 2.5 * eta * 0.3 / 0.6, ag_s * 2.5 * eta * 0.3 * 1.2 / 9.0]
    np.testing.assert_allclose(spectrum.sa([0.0, 0.2, 0.6, 3.0], 0.10) / G, hand, rtol=1e-12)
    assert float(ec8_damping_correction(0.5)) == 0.55  # lower bound
    assert float(ec8_damping_correction(0.05)) == 1.0
    with pytest.raises(InputError, match="period: periods within 0 to 4 s"):
        spectrum.sa([5.0], 0.05)


def test_tabulated_spectrum_interpolation_damping_and_range():
    table = TabulatedSpectrum([0.1, 0.5, 2.0], [0.5, 1.0, 0.25], damping=0.05)
    np.testing.assert_allclose(table.sa([0.1, 0.3, 1.25], 0.05) / G, [0.5, 0.75, 0.625])
    np.testing.assert_allclose(table.sa([0.5], 0.02) / G, [math.sqrt(10 / 7)])
    asce = TabulatedSpectrum([0.1, 0.5, 2.0], [0.5, 1.0, 0.25], damping=0.05, damping_correction="asce", units="m/s2")
    np.testing.assert_allclose(asce.sa([0.5], 0.10), asce_damping_coefficient(0.05) / asce_damping_coefficient(0.10))
    assert table.period_range == (0.1, 2.0)
    with pytest.raises(InputError, match="period: periods within 0.1 to 2 s"):
        table.sa([0.05], 0.05)
    with pytest.raises(InputError, match="periods"):
        TabulatedSpectrum([0.5, 0.1], [1.0, 2.0], damping=0.05)


def test_from_mapping_builds_each_type(tmp_path):
    deck = tmp_path / "deck.toml"
    asce = from_mapping({"type": "asce7", "sds": 1.0, "sd1": 0.6, "tl": 8.0}, str(deck))
    assert isinstance(asce, ASCE7Spectrum)
    ec8 = from_mapping({"type": "ec8", "ag": 0.3, "ground_type": "B", "spectrum_type": 1}, str(deck))
    assert float(ec8.sa(0.3, 0.05)) / G == pytest.approx(0.9)
    (tmp_path / "sa.csv").write_text("period_s,sa_g\n0.0,0.4\n1.0,1.0\n3.0,0.2\n")
    table = from_mapping({"type": "table", "file": "sa.csv", "damping": 0.05}, str(deck))
    assert float(table.sa(2.0, 0.05)) / G == pytest.approx(0.6)
    inline = from_mapping({"type": "table", "periods": [0, 1], "sa": [0.2, 0.4], "damping": 0.02}, str(deck))
    assert float(inline.sa(0.5, 0.02)) / G == pytest.approx(0.3)


@pytest.mark.parametrize("mapping, message", [
    ({"type": "asce7", "sds": 1.0, "sd1": 0.6}, r"spectrum\.tl: a value"),
    ({"type": "asce7", "sds": 1.0, "sd1": 0.6, "tl": 8.0, "sdz": 1}, r"spectrum\.sdz: a key of a asce7"),
    ({"type": "asce7", "sds": -1.0, "sd1": 0.6, "tl": 8.0}, r"spectrum\.sds: a number > 0 \[g\]"),
    ({"type": "ec8", "ag": 0.3, "ground_type": "S1"}, r"spectrum\.ground_type"),
    ({"type": "ec8", "ag": 0.3, "ground_type": "B", "spectrum_type": 3}, r"spectrum\.spectrum_type"),
    ({"type": "table", "damping": 0.05}, r"spectrum\.file: either"),
    ({"type": "nehrp"}, r"spectrum\.type: one of"),
])
def test_from_mapping_errors_name_the_field(mapping, message):
    with pytest.raises(InputError, match=rf"deck\.toml: {message}"):
        from_mapping(mapping, "deck.toml")


def test_table_file_errors_name_the_line(tmp_path):
    (tmp_path / "bad.csv").write_text("T,Sa\n0.1,0.5\n0.2,abc\n")
    with pytest.raises(InputError, match=r"bad\.csv: line 3"):
        from_mapping({"type": "table", "file": "bad.csv", "damping": 0.05}, str(tmp_path / "deck.toml"))
