"""Design spectra at their corner periods against hand values."""

from __future__ import annotations

import datetime
import math

import numpy as np
import pytest

from upliftcli.errors import InputError
from upliftcli.motion.design_spectra import (
    USGS_PERIODS,
    ASCE7MultiPeriodSpectrum,
    ASCE7Spectrum,
    EC8Spectrum,
    TabulatedSpectrum,
    asce_damping_coefficient,
    ec8_damping_correction,
    from_mapping,
    procedure_warning,
    spectrum_warnings,
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
    # beyond the 4 s of EN 1998-1 3.2.2.2 Eq. 3.5 is continued: constant spectral displacement
    sd = spectrum.sa([4.0, 6.0, 10.0], 0.10) * (np.array([4.0, 6.0, 10.0]) / (2 * math.pi)) ** 2
    np.testing.assert_allclose(sd, ag_s * G * 2.5 * eta * 0.3 * 1.2 / (4 * math.pi**2), rtol=1e-12)


def test_tabulated_spectrum_interpolation_damping_and_range():
    table = TabulatedSpectrum([0.1, 0.5, 2.0], [0.5, 1.0, 0.25], damping=0.05)
    np.testing.assert_allclose(table.sa([0.1, 0.3, 1.25], 0.05) / G, [0.5, 0.75, 0.625])
    np.testing.assert_allclose(table.sa([0.5], 0.02) / G, [math.sqrt(10 / 7)])
    asce = TabulatedSpectrum([0.1, 0.5, 2.0], [0.5, 1.0, 0.25], damping=0.05, damping_correction="asce", units="m/s2")
    np.testing.assert_allclose(asce.sa([0.5], 0.10), asce_damping_coefficient(0.05) / asce_damping_coefficient(0.10))
    assert table.period_range == (0.1, 2.0)
    with pytest.raises(InputError, match=r"period: periods within 0\.1 to 2 s"):
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
    ({"type": "asce7", "sds": 1.0, "sd1": 0.6, "tl": 8.0, "sdz": 1},
     r"spectrum\.sdz: a key of a spectrum of type .asce7."),
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


# ----------------------------------------------------------------------------- ASCE 7-22 multi-period

#: an illustrative multi-period design spectrum [g] at the 22 USGS periods
MULTI = [0.40, 0.40, 0.40, 0.42, 0.52, 0.66, 0.78, 0.92, 1.00, 1.04, 1.06, 1.05, 1.00, 0.85, 0.70, 0.52,
         0.41, 0.27, 0.19, 0.14, 0.075, 0.045]


def test_usgs_periods_are_the_22_of_the_design_service():
    assert len(USGS_PERIODS) == 22 and USGS_PERIODS[0] == 0.0 and USGS_PERIODS[-1] == 10.0
    assert USGS_PERIODS[:6] == (0.0, 0.01, 0.02, 0.03, 0.05, 0.075) and 0.75 in USGS_PERIODS and 7.5 in USGS_PERIODS


def test_multiperiod_ordinates_interpolation_and_range():
    spectrum = ASCE7MultiPeriodSpectrum(MULTI)
    np.testing.assert_allclose(spectrum.sa(list(USGS_PERIODS), 0.05) / G, MULTI, rtol=1e-12)
    # linear in T between ordinates: halfway between 1 s (0.70) and 1.5 s (0.52)
    assert float(spectrum.sa(1.25, 0.05)) / G == pytest.approx(0.61, rel=1e-12)
    assert spectrum.period_range == (0.0, 10.0)
    with pytest.raises(InputError, match=r"period: periods within 0 to 10 s .* got 12 s"):
        spectrum.sa([12.0], 0.05)


def test_multiperiod_sds_sd1_from_asce7_22_21_4_and_damping_ramp():
    spectrum = ASCE7MultiPeriodSpectrum(MULTI)
    # S_DS = 0.9 max S_a(0.2-5 s) = 0.9 x 1.06; S_D1 = max(0.9 max T S_a(1-5 s), S_a(1 s)) = 0.9 x 2 x 0.41
    assert spectrum.sds == pytest.approx(0.954) and spectrum.sd1 == pytest.approx(0.738)
    t0 = 0.2 * 0.738 / 0.954
    assert spectrum.t0 == pytest.approx(t0)
    b = float(asce_damping_coefficient(0.15) / asce_damping_coefficient(0.05))
    ratio = spectrum.sa([0.0, 0.5 * t0, t0, 0.5, 3.0], 0.15) / spectrum.sa([0.0, 0.5 * t0, t0, 0.5, 3.0], 0.05)
    np.testing.assert_allclose(ratio, [1.0, 0.5 * (1 + 1 / b), 1 / b, 1 / b, 1 / b], rtol=1e-12)
    given = ASCE7MultiPeriodSpectrum(MULTI, sds=1.0, sd1=0.6)
    assert given.t0 == pytest.approx(0.12)


def test_multiperiod_from_mapping_and_errors(tmp_path):
    deck = str(tmp_path / "deck.toml")
    spectrum = from_mapping({"type": "asce7-multiperiod", "sa": MULTI}, deck)
    assert isinstance(spectrum, ASCE7MultiPeriodSpectrum)
    rows = "".join(f"{t},{v}\n" for t, v in zip(USGS_PERIODS, MULTI, strict=True))
    (tmp_path / "usgs.csv").write_text("T,Sa\n" + rows)
    from_file = from_mapping({"type": "asce7-multiperiod", "file": "usgs.csv", "sds": 1.0, "sd1": 0.7}, deck)
    np.testing.assert_allclose(from_file.ordinates, MULTI)
    with pytest.raises(InputError, match=r"deck\.toml: spectrum\.sa: the 22 ordinates"):
        from_mapping({"type": "asce7-multiperiod", "sa": MULTI[:-1]}, deck)
    with pytest.raises(InputError, match=r"spectrum\.periods: the 22 periods"):
        from_mapping({"type": "asce7-multiperiod", "periods": list(range(22)), "sa": MULTI}, deck)
    with pytest.raises(InputError, match=r"spectrum\.sa: the 22 ordinates"):
        from_mapping({"type": "asce7-multiperiod"}, deck)


def test_two_period_spectrum_warns_for_modal_and_response_history_procedures():
    two = ASCE7Spectrum(1.0, 0.6, 8.0)
    assert procedure_warning(two, "elf") is None
    for procedure in ("modal", "response-history"):
        message = procedure_warning(two, procedure)
        assert message.startswith("ASCE 7-22 11.4.5 permits the two-period design spectrum")
        assert "asce7-multiperiod" in message
    assert procedure_warning(ASCE7MultiPeriodSpectrum(MULTI), "modal") is None
    assert procedure_warning(EC8Spectrum(0.3, "B"), "response-history") is None


def test_ec8_beyond_four_seconds_is_reported():
    spectrum = EC8Spectrum(0.3, "B")
    assert spectrum_warnings(spectrum, [1.0, 4.0]) == []
    (message,) = spectrum_warnings(spectrum, [2.0, 5.5])
    assert "up to 4 s" in message and "T = 5.5 s" in message


def test_table_damping_correction_default_is_given_by_the_caller():
    table = {"type": "table", "periods": [0.0, 1.0], "sa": [0.4, 1.0], "damping": 0.05}
    assert from_mapping(table, "deck.toml").damping_correction == "ec8"
    assert from_mapping(table, "deck.toml", default_correction="asce").damping_correction == "asce"
    explicit = from_mapping({**table, "damping_correction": "ec8"}, "d", default_correction="asce")
    assert explicit.damping_correction == "ec8"


def test_deck_reference_documents_every_key_of_every_spectrum_type():
    """docs/deck.md names each design_spectrum type and each of its keys (design_spectra._KEYS)."""
    from pathlib import Path

    from upliftcli.motion.design_spectra import _KEYS

    text = (Path(__file__).resolve().parents[1] / "docs" / "deck.md").read_text()
    section = text[text.index("`design_spectrum` (read by"):text.index("### Record suites")]
    rows = {line.split("|")[1].strip(): line for line in section.splitlines() if line.startswith('| `"')}
    for kind, (required, optional) in _KEYS.items():
        row = rows[f'`"{kind}"`']
        for key in (required | optional) - {"type"}:
            assert f"`{key}`" in row, (kind, key)
        for key in required - {"type"}:
            assert f"**`{key}`**" in row, (kind, key)


def test_table_alone_takes_the_correction_of_the_statistics_it_names(tmp_path):
    from upliftcli.deck.load import build_deck
    from upliftcli.provenance.record import of_deck

    table = {"type": "table", "periods": [0.0, 1.0, 4.0], "sa": [0.4, 1.0, 0.2], "damping": 0.05}
    raw = {"building": {"stories": 2, "floor_mass": 1e5, "story_height": 3.0, "period": 0.3},
           "foundation": {"b": 3.0, "k_f": 1e9}, "ground_motion": {"design_spectrum": table}}
    plain = build_deck(raw, str(tmp_path / "d.toml"))
    asce = build_deck(raw, str(tmp_path / "d.toml"), [("ground_motion.statistics", "asce7-22")])
    assert plain.spectrum.damping_correction == "ec8" and asce.spectrum.damping_correction == "asce"
    expected = asce_damping_coefficient(0.05) / asce_damping_coefficient(0.02)  # B(5 %)/B(2 %)
    assert float(asce.spectrum.sa(np.array([1.0]), 0.02)[0]) == pytest.approx(G * expected, rel=1e-12)
    assert float(plain.spectrum.sa(np.array([1.0]), 0.02)[0]) == pytest.approx(G * math.sqrt(10 / 7) / 1.0, rel=1e-12)
    entry = of_deck(asce)["spectrum"]
    assert entry["damping_correction"] == "asce" and entry["damping"] == 0.05 and entry["period_range"] == [0.0, 4.0]


def test_a_missing_table_file_names_the_field_and_the_folder(tmp_path):
    deck = tmp_path / "deck.toml"
    with pytest.raises(InputError) as info:
        from_mapping({"type": "table", "file": "sa.csv", "damping": 0.05}, str(deck), "ground_motion.design_spectrum")
    assert info.value.location == "ground_motion.design_spectrum.file"
    assert info.value.expected == (f"an existing spectrum table, not found: 'sa.csv' (relative to the deck's folder "
                                   f"'{tmp_path}': '{tmp_path / 'sa.csv'}')")


def test_the_damping_correction_is_read_whatever_its_case(tmp_path):
    """"ASCE" or "asce": the deck's choice and the one of a table built in code agree."""
    table = {"type": "table", "periods": [0.0, 4.0], "sa": [1.0, 1.0], "damping": 0.05, "damping_correction": "ASCE"}
    assert from_mapping(table, str(tmp_path / "deck.toml")).damping_correction == "asce"


# ----------------------------------------------------------------------------- keys through the field checker

@pytest.mark.parametrize(("mapping", "message"), [
    ({"type": "asce7", "sds": True, "sd1": 0.6, "tl": 8.0}, r"spectrum\.sds: a number > 0 \[g\], got True$"),
    ({"type": "asce7", "sds": 1e300, "sd1": 0.6, "tl": 8.0}, r"spectrum\.sds: a number > 0 of magnitude 1e-30 to "
                                                           r"1e\+30 \[g\], got 1e\+300$"),
    ({"type": "asce7", "sds": "1.0", "sd1": 0.6, "tl": 8.0}, r"spectrum\.sds: a number > 0 \[g\] or a text"),
    ({"type": "asce7", "sds": [[1.0]], "sd1": 0.6, "tl": 8.0}, r"spectrum\.sds: a number > 0 \[g\], got \[\[1\.0\]\]"),
    ({"type": "ec8", "ag": 0.3, "ground_type": "B", "importance": False}, r"spectrum\.importance: a number > 0"),
    ({"type": "ec8", "ag": 0.3, "ground_type": "B", "spectrum_type": 3}, r"spectrum\.spectrum_type: an integer 1 or 2"),
    ({"type": "table", "periods": [0, 1, 8], "sa": [1, 1, 1], "damping": "5%"},
     r"spectrum\.damping: a number in \(0, 1\) \(0\.05 = 5 %\) \(a bare number: this field takes no unit\), "
     r"got '5%'$"),
    ({"type": "table", "periods": [0, 1, 8], "sa": [1, True, 1], "damping": 0.05}, r"spectrum\.sa: every entry a"),
    ({"type": "table", "periods": [0, 1, 8], "sa": [1, 1, 1], "damping": 0.05, "name": datetime.date(1979, 5, 27)},
     r"spectrum\.name: a string, got datetime\.date\(1979, 5, 27\)$"),
    ({"type": "asce7-multiperiod", "sa": [0.5] * 22, "name": 3}, r"spectrum\.name: a string, got 3$"),
    ({"type": "table", "periods": [0, 8], "sa": [1, 1], "damping": 0.05, "units": "furlong"},
     r"spectrum\.units: acceleration units g, m/s2, cm/s2 or in/s2"),
])
def test_every_key_goes_through_the_field_checker(tmp_path, mapping, message):
    deck = str(tmp_path / "deck.toml")
    with pytest.raises(InputError, match=message) as info:
        from_mapping(mapping, deck)
    assert info.value.source == deck and "\n" not in str(info.value)


def test_all_the_bad_keys_of_a_spectrum_are_reported_together(tmp_path):
    from upliftcli.errors import InputErrors

    with pytest.raises(InputErrors) as info:
        from_mapping({"type": "asce7", "sds": True, "sd1": "x", "tll": 8}, str(tmp_path / "deck.toml"),
                     "ground_motion.design_spectrum")
    assert [e.location for e in info.value.errors] == [
        "ground_motion.design_spectrum.sds", "ground_motion.design_spectrum.sd1", "ground_motion.design_spectrum.tll",
        "ground_motion.design_spectrum.tl"]
    assert "did you mean 'tl'" in info.value.errors[2].expected


def test_keys_of_a_spectrum_read_from_a_file_are_blamed_on_the_deck_naming_the_file(tmp_path):
    (tmp_path / "usgs.csv").write_text("".join(f"{t},0.5\n" for t in USGS_PERIODS))
    deck = str(tmp_path / "deck.toml")
    with pytest.raises(InputError) as info:
        from_mapping({"type": "asce7-multiperiod", "file": "usgs.csv", "sds": -1}, deck,
                     "ground_motion.design_spectrum")
    assert str(info.value) == (f"{deck}: ground_motion.design_spectrum.sds: a number > 0 [g], got -1 (spectrum read "
                               "from 'usgs.csv')")
    (tmp_path / "table.csv").write_text("period_s,sa_g\n0,0.4\n1,-0.5\n8,0.1\n")
    with pytest.raises(InputError) as info:  # what the file holds: the deck's field, naming the file
        from_mapping({"type": "table", "file": "table.csv", "damping": 0.05}, deck, "ground_motion.design_spectrum")
    assert (info.value.source, info.value.location) == (deck, "ground_motion.design_spectrum.file")
    assert "spectral accelerations >= 0" in info.value.expected and "table.csv" in info.value.expected
    (tmp_path / "bad.csv").write_text("0,0.4\n1,x\n")
    with pytest.raises(InputError, match=r"bad\.csv: line 2: two numbers"):  # a fault of the file: the file's line
        from_mapping({"type": "table", "file": "bad.csv", "damping": 0.05}, deck, "ground_motion.design_spectrum")


def test_a_spectrum_key_may_carry_its_unit():
    spectrum = from_mapping({"type": "asce7", "sds": "9.80665 m/s2", "sd1": "0.6 g", "tl": "8000 ms"}, "deck.toml")
    assert (spectrum.sds, spectrum.sd1, spectrum.tl) == (1.0, 0.6, 8.0)
