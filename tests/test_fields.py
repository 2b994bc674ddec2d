"""The one value checker: magnitudes, integer limits, choices of command-line options."""

import pytest

from upliftcli.errors import InputError
from upliftcli.fields import Field, check_value, parse_choices, shown


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
