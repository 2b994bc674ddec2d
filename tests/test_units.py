"""units.py: the unit symbols checked against independent definitions (NIST SP 811, Appendix B),
the parser of unit texts, the US customary unit of each quantity and the acceleration aliases."""

import pytest

from upliftcli.units import (
    ACCELERATION_ALIASES,
    ACCELERATION_UNITS,
    KIND_OF_UNIT,
    QUANTITY_KINDS,
    acceleration_unit,
    conversion,
    parse_unit,
    split_quantity,
    system_unit,
)

# NIST SP 811 (2008), Appendix B.8/B.9, the exact or reference values
FOOT = 0.3048  # m, exact
INCH = 0.0254  # m, exact
POUND_FORCE = 4.4482216152605  # N, exact (lbm x g_n)
KIP = 4448.2216152605  # N
PSI = 6894.757293168  # Pa (NIST: 6.894 757 E+03)
POUND_PER_CUBIC_FOOT = 16.01846337  # kg/m^3 (NIST: 1.601 846 E+01)
SLUG = 14.59390294  # kg (NIST: 1.459 390 E+01)


@pytest.mark.parametrize(("unit", "si_unit", "expected"), [
    ("ft", "m", FOOT),
    ("in", "m", INCH),
    ("kip", "N", KIP),
    ("lbf", "N", POUND_FORCE),
    ("kip s2/in", "kg", KIP / INCH),  # 175,126.8 kg
    ("kip/in", "N/m", KIP / INCH),
    ("kip s/in", "N s/m", KIP / INCH),
    ("kip ft", "N m", KIP * FOOT),
    ("kip-ft", "N m", KIP * FOOT),
    ("kip s2 in", "kg m^2", KIP * INCH),
    ("kip/in2", "N/m^2", KIP / INCH**2),
    ("psi", "Pa", PSI),
    ("ksi", "Pa", 1000 * PSI),
    ("ksf", "Pa", KIP / FOOT**2),
    ("pcf", "kg/m^3", POUND_PER_CUBIC_FOOT),
    ("slug", "kg", SLUG),
    ("ft/s", "m/s", FOOT),
    ("in/s2", "m/s^2", INCH),
    ("g", "m/s^2", 9.80665),
    ("gal", "m/s^2", 0.01),
    ("m/s/s", "m/s^2", 1.0),
    ("t", "kg", 1000.0),
    ("kN m", "N m", 1000.0),
    ("MPa", "Pa", 1e6),
])
def test_conversions_agree_with_the_definitions(unit, si_unit, expected):
    assert conversion(unit, si_unit) == pytest.approx(expected, rel=1e-9)


def test_exact_definitions_are_exact():
    assert conversion("ft", "m") == 0.3048 and conversion("in", "m") == 0.0254
    assert conversion("kip", "N") == 4448.2216152605
    assert conversion("m", "ft") == pytest.approx(1 / 0.3048, rel=1e-15)
    assert conversion("lbf", "N") == pytest.approx(0.45359237 * 9.80665, rel=1e-15)


def test_units_of_another_dimension_or_unknown_are_refused():
    with pytest.raises(ValueError, match="dimension"):
        conversion("kg", "m")
    with pytest.raises(ValueError, match="'furlong' is not one"):
        parse_unit("furlong")
    for text in ("", "m/", "/s", "kip s2 / / in"):
        with pytest.raises(ValueError):
            parse_unit(text)
    assert parse_unit("s^-2") == (1.0, (0, 0, -2)) and parse_unit("m**2") == (1.0, (0, 2, 0))


def test_a_quantity_text_is_a_plain_number_and_a_unit():
    assert split_quantity("11.5 ft") == (11.5, "ft")
    assert split_quantity(" 2.0 kip s2/in ") == (2.0, "kip s2/in")
    assert split_quantity("12") == (12.0, "") and split_quantity("-1e3 N") == (-1000.0, "N")
    for text in ("1_000 kg", "ft 11", "inf m", "nan", "", "5%x"):
        assert split_quantity(text) is None or split_quantity(text)[1] != "", text
    assert split_quantity("1_000 kg") is None and split_quantity("inf m") is None


def test_every_quantity_kind_has_convertible_si_and_us_units():
    for kind, (si, us) in QUANTITY_KINDS.items():
        assert parse_unit(si)[1] == parse_unit(us)[1], kind
        assert system_unit(kind, "si") == si and system_unit(kind, "us") == us
    assert KIND_OF_UNIT["m"] == "length" and system_unit("displacement", "us") == "in"


def test_acceleration_aliases_map_to_the_canonical_units():
    assert set(ACCELERATION_ALIASES.values()) == set(ACCELERATION_UNITS)
    assert acceleration_unit("Gal") == "cm/s2" and acceleration_unit("in/sec^2") == "in/s2"
    assert acceleration_unit("m / s**2") == "m/s2" and acceleration_unit("furlong") is None
    assert acceleration_unit(1.0) is None
    for alias, canonical in ACCELERATION_ALIASES.items():  # each alias is the unit it names
        if alias not in ("mps2",):
            assert conversion(alias.replace("**", "^"), "m/s^2") == pytest.approx(ACCELERATION_UNITS[canonical])


def test_the_aliases_are_documented_in_one_table():
    from pathlib import Path

    text = (Path(__file__).resolve().parent.parent / "docs" / "deck.md").read_text()
    for alias, canonical in ACCELERATION_ALIASES.items():
        row = next(line for line in text.splitlines() if line.startswith(f"| `{canonical}` |"))
        assert alias == canonical or f"`{alias}`" in row, alias
