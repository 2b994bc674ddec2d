"""The one value checker: magnitudes, integer limits, choices of command-line options."""

import pytest

from upliftcli.deck.fields import Field, check_value, parse_choices, shown
from upliftcli.errors import InputError


def checked(field, value):
    messages = []

    def error(expected):
        messages.append(expected)
        raise ValueError(expected)

    try:
        return check_value(field, value, error)
    except ValueError:
        return messages[0]


def test_numbers_outside_the_supported_magnitudes_are_refused():
    length = Field("number", "m", "a length", "positive")
    assert checked(length, 1e30) == 1e30 and checked(length, 1e-30) == 1e-30
    assert checked(length, 1e308) == "a number > 0 of magnitude 1e-30 to 1e+30 [m], got 1e+308"
    assert checked(length, 1e-300).startswith("a number > 0 of magnitude")
    assert checked(Field("number", "kg", "mass", "nonnegative"), 0.0) == 0.0  # zero stays allowed
    assert checked(Field("pair", "s", "window"), [0, 1e308]).startswith("[start, end] of magnitude")
    assert checked(Field("numbers", "kg", "masses", "positive"), [1.0, 1e31]).startswith("every entry a number")
    assert checked(Field("matrix", "N/m", "K"), [[1e40]]).startswith("a square array of arrays of numbers of magn")


def test_a_pair_takes_the_check_of_its_field():
    """band-around-one (analysis.check_band: the ratio simplified / exact is 1 for an exact
    estimate): [low, high] with low < 1 < high, said in those words, as a plain pair's order is."""
    band = Field("pair", "-", "a band of ratios", "band-around-one")
    assert checked(band, [0.8, 1.25]) == (0.8, 1.25) and checked(band, [0, 2]) == (0.0, 2.0)
    for bad in ([1.1, 1.5], [0.5, 0.9], [0.5, 1], [1.25, 0.8], [0.9], 0.9):
        assert checked(band, bad) == f"[low, high] with 0 <= low < 1 < high (ratios simplified / exact), got {bad}"
    assert checked(Field("pair", "s", "window"), [1.1, 1.5]) == (1.1, 1.5)  # a plain pair: any order-true pair
    assert checked(Field("pair", "s", "window"), [2, 1]) == "[start, end] with 0 <= start < end [s], got [2, 1]"


def test_integers_are_bounded():
    assert checked(Field("integer", "-", "stories", "stories"), 500) == 500
    assert checked(Field("integer", "-", "stories", "stories"), 2**63 - 1) == \
        "an integer from 1 to 500, got 9223372036854775807"
    assert checked(Field("integer", "-", "n", "count"), 10**7) == "an integer >= 1 and at most 1,000,000, got 10000000"


def test_long_values_are_shown_cut():
    nested: list = []
    for _ in range(60):
        nested = [nested]
    text = shown(nested)
    assert len(text) <= 80 and "..." in text


def test_parse_choices_matches_exactly_and_hints_the_case():
    assert parse_choices(["exact,simplified", "all"], ("simplified", "exact"), "--engine") == ["exact", "simplified"]
    with pytest.raises(InputError, match=r"^--engine: EXACT: one of simplified, exact or all \(names are lower case: "
                                         r"'exact'\)$"):
        parse_choices(["EXACT"], ("simplified", "exact"), "--engine")
    with pytest.raises(InputError, match="did you mean 'exact'"):
        parse_choices(["exakt"], ("simplified", "exact"), "--engine")


# ----------------------------------------------------------------------------- types, units, systems

MASS = Field("number", "kg", "floor mass", "positive", plausible=(1e3, 1e8))
HEIGHT = Field("number", "m", "story height", "positive")


@pytest.mark.parametrize("value", [True, False, "x", [[1.0]], [1.0], {"a": 1}, "1_000 kg", "5%", "inf kg"])
def test_what_is_not_a_number_is_refused(value):
    import datetime

    assert isinstance(checked(MASS, value), str)
    assert isinstance(checked(MASS, datetime.date(1979, 5, 27)), str)


def test_a_number_may_carry_a_unit_of_its_quantity():
    assert checked(HEIGHT, "11.5 ft") == pytest.approx(11.5 * 0.3048, rel=1e-15)
    assert checked(MASS, "2.0 kip s2/in") == pytest.approx(2.0 * 4448.2216152605 / 0.0254, rel=1e-15)
    assert checked(Field("number", "N/m", "k_f", "positive"), "5000 kip/in") == pytest.approx(5000 * 175126.835246)
    assert checked(Field("numbers", "kg", "masses", "positive"), ["350 t", 3e5]) == [350e3, 3e5]
    assert checked(Field("pair", "s", "window"), ["0.5 s", "2000 ms"]) == (0.5, 2.0)
    assert checked(Field("number", "g", "S_DS", "positive"), "0.98066500 m/s2") == pytest.approx(0.1, rel=1e-12)
    assert checked(HEIGHT, "3 kg") == ("a number > 0 [m] or a text 'number unit' with a unit of length "
                                       "(docs/deck.md, Units), got '3 kg'")
    assert checked(HEIGHT, "-3 ft").startswith("a number > 0")  # the range checked after the conversion
    assert checked(HEIGHT, "1e40 in").startswith("a number > 0 of magnitude")


def test_a_dimensionless_field_takes_no_unit_text():
    damping = Field("number", "-", "damping ratio", "damping-ratio")
    assert checked(damping, "5%") == ("a number in (0, 1) (0.05 = 5 %) (a bare number: this field takes no unit), "
                                      "got '5%'")
    assert checked(damping, "0.05").startswith("a number in (0, 1)")
    assert checked(damping, 0.05) == 0.05


def test_bare_numbers_are_read_in_the_decks_unit_system():
    def us(field, value):
        return check_value(field, value, lambda expected: pytest.fail(expected), "us")

    assert us(HEIGHT, 12) == pytest.approx(3.6576, rel=1e-15)  # ft
    assert us(Field("number", "m", "drift", "positive", quantity="displacement"), 1.0) == 0.0254  # in
    assert us(MASS, 2.0) == pytest.approx(350253.67, rel=1e-7)  # kip s2/in
    assert us(Field("number", "s", "period", "positive"), 0.5) == 0.5
    assert us(Field("number", "-", "ratio", "positive"), 8) == 8.0
    assert us(Field("matrix", "N/m", "K"), [[1.0]]) == [[pytest.approx(175126.835246)]]
    assert us(HEIGHT, "3.5 m") == 3.5  # a text with its unit wins
    bare = check_value(HEIGHT, 3.5, lambda expected: pytest.fail(expected))
    assert bare == 3.5 and type(bare) is float  # SI bare numbers unchanged, bit for bit


def test_check_mapping_gathers_every_error():
    from upliftcli.deck.fields import check_mapping
    from upliftcli.errors import InputError, InputErrors

    def error_for(path):
        def error(expected):
            raise InputError("deck.toml", path, expected)
        return error

    fields = {"sds": Field("number", "g", "S_DS", "positive"), "name": Field("string", "-", "label")}
    assert check_mapping(fields, {"sds": "0.4 g", "name": "x"}, "t", error_for) == {"sds": 0.4, "name": "x"}
    with pytest.raises(InputErrors) as info:
        check_mapping(fields, {"sds": True, "name": 3, "sdss": 1}, "t", error_for)
    assert [(e.location, e.expected[:12]) for e in info.value.errors] == [
        ("t.sds", "a number > 0"), ("t.name", "a string, go"), ("t.sdss", "a known key:")]
    assert "did you mean 'sds'" in str(info.value).splitlines()[2]
    with pytest.raises(InputError) as one:
        check_mapping(fields, {"sds": -1}, "t", error_for)
    assert not isinstance(one.value, InputErrors)


def test_implausible_values_are_named_with_the_range():
    from upliftcli.deck.practice import implausible

    assert implausible(MASS, 350e3) is None and implausible(HEIGHT, 1e9) is None  # no range declared
    assert implausible(MASS, 300.0) == ("300 kg is far outside building practice (1000 to 1e+08 kg): a unit "
                                        "mistake? (the analysis goes on)")
    masses = Field("numbers", "kg", "masses", "positive", plausible=(1e3, 1e8))
    assert implausible(masses, [350e3, 2e9]).startswith("2e+09 kg")


def test_implausible_values_of_a_us_deck_are_shown_in_its_units_too():
    from upliftcli.deck.practice import implausible

    height = Field("number", "m", "story height", "positive", plausible=(1.5, 30.0))
    assert implausible(height, 91.44, "us") == ("91.44 m = 300 ft is far outside building practice (1.5 to 30 m = "
                                                "4.921 to 98.43 ft): a unit mistake? (the analysis goes on)")
