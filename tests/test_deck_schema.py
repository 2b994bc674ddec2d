"""deck_schema: every error of a deck in one pass, the deck's unit system, the plausible ranges
(warnings) and the deck in bare SI (the resolved deck)."""

import re
from pathlib import Path

import pytest

from upliftcli.deck import schema as deck_schema
from upliftcli.deck.practice import plausibility
from upliftcli.deck.schema import si_mapping, validate
from upliftcli.errors import InputError, InputErrors

ROOT = Path(__file__).resolve().parent.parent

FOUR_MISTAKES = {
    "building": {"stories": 10, "floor_mas": 350e3, "story_height": "3.5 furlongs", "period": -1},
    "foundation": {"slenderness": 6, "damping_ratio": True},
    "ground_motion": {"design_spectrum": {"type": "asce7", "sds": 1e300, "sd1": 0.6, "tl": 8.0}},
}


def test_every_error_is_found_in_one_pass():
    with pytest.raises(InputErrors) as info:
        validate(FOUR_MISTAKES, "deck.toml")
    assert [e.location for e in info.value.errors] == [
        "building.floor_mas", "building.story_height", "building.period", "foundation.damping_ratio",
        "ground_motion.design_spectrum.sds"]
    text = str(info.value).splitlines()
    assert len(text) == 5 and all(line.startswith("deck.toml: ") for line in text)
    assert "did you mean 'floor_mass'" in text[0] and "'3.5 furlongs'" in text[1]
    assert text[4].endswith("of magnitude 1e-30 to 1e+30 [g], got 1e+300")


def test_check_bands_that_do_not_hold_1_are_refused_in_one_pass():
    """A check band bounds the ratio simplified / exact, so it holds 1: [1.1, 1.5] was refused by
    deck/load.py after the schema, as the first of the two only, and [1.5, 1.1] in the generic words
    of a pair; both fields are now checked by their declared check (deck/fields.py band-around-one)."""
    raw = {"analysis": {"check_band": [1.1, 1.5], "check_band_motion": [2.0, 0.5]}}
    with pytest.raises(InputErrors) as info:
        validate(raw, "deck.toml")
    assert str(info.value).splitlines() == [
        "deck.toml: analysis.check_band: [low, high] with 0 <= low < 1 < high (ratios simplified / exact), got "
        "[1.1, 1.5]",
        "deck.toml: analysis.check_band_motion: [low, high] with 0 <= low < 1 < high (ratios simplified / exact), "
        "got [2.0, 0.5]"]


def test_errors_of_nested_values_name_set_when_they_came_from_it():
    raw = {"ground_motion": {"suite": [{"file": "a.txt", "dt": True}, {"file": "b.txt", "dt": "x", "scale": False}],
                             "design_spectrum": {"type": "asce7", "sds": True, "sd1": 0.6, "tl": 8.0}}}
    with pytest.raises(InputErrors) as info:
        validate(raw, "deck.toml", frozenset({"ground_motion.suite"}))
    assert [(e.source, e.location) for e in info.value.errors] == [
        ("--set", "ground_motion.suite[0].dt"), ("--set", "ground_motion.suite[1].dt"),
        ("--set", "ground_motion.suite[1].scale"), ("deck.toml", "ground_motion.design_spectrum.sds")]


def test_one_error_stays_a_plain_input_error():
    with pytest.raises(InputError) as info:
        validate({"building": {"period": 0}}, "deck.toml")
    assert not isinstance(info.value, InputErrors) and info.value.location == "building.period"


def test_a_us_deck_is_read_in_us_units():
    values = validate({"units": "us", "building": {"story_height": 10, "floor_mass": "350 t"},
                       "foundation": {"b": 20, "c_f": 1.0}, "criteria": {"drift": 1.0, "base_moment": 1.0}},
                      "deck.toml")
    assert values["building"] == {"story_height": pytest.approx(3.048, rel=1e-15), "floor_mass": 350e3}
    assert values["foundation"]["b"] == pytest.approx(6.096)
    assert values["foundation"]["c_f"] == pytest.approx(175126.8352)
    assert values["criteria"] == {"drift": 0.0254, "base_moment": pytest.approx(4448.2216152605 * 0.3048)}
    with pytest.raises(InputError, match=r"^deck.toml: units: one of si, us, got 'imperial'"):
        validate({"units": "imperial"}, "deck.toml")


def test_plausibility_names_the_deck_and_the_field():
    raw = {"building": {"floor_mass": 300, "story_height": 3200, "period": 1.0},
           "criteria": {"drift_ratio": 2},
           "ground_motion": {"design_spectrum": {"type": "asce7", "sds": 50, "sd1": 0.6, "tl": 8}}}
    warnings = plausibility(validate(raw, "a.toml"), "a.toml", frozenset({"criteria.drift_ratio"}))
    assert warnings == [
        "a.toml: building.floor_mass: 300 kg is far outside building practice (1000 to 1e+08 kg): a unit mistake? "
        "(the analysis goes on)",
        "a.toml: building.story_height: 3200 m is far outside building practice (1.5 to 30 m): a unit mistake? "
        "(the analysis goes on)",
        "a.toml (--set): criteria.drift_ratio: 2 is far outside building practice (0.0001 to 0.1): a unit mistake? "
        "(the analysis goes on)",
        "a.toml: ground_motion.design_spectrum.sds: 50 g is far outside building practice (0.01 to 5 g): a unit "
        "mistake? (the analysis goes on)"]


@pytest.mark.parametrize(("value", "shown"), [
    (1.0000001, "1.0000001"), (1.05, "1.05"), (1.19999, "1.19999"), (0.123456789, "0.123456789"), (300.0, "300"),
    (1e-7, "1e-07"), (123456.7, "123456.7"), (1000.0001, "1000.0001")])
def test_a_warning_shows_the_value_as_given(value, shown):
    """The safety-factor warning printed 1.0000001 as '1': the value is shown to 4 digits when that
    is the value, else by its shortest text that reads back as it."""
    from upliftcli.deck.practice import given

    assert given(value) == shown and float(given(value)) == value
    raw = {"foundation": {"type": "two-element", "slenderness": 5.0, "frequency_ratio": 8, "damping_ratio": 0.1,
                          "safety_factor": 1.0000001}}
    warning, = plausibility(validate(raw, "a.toml"), "a.toml")
    assert warning.startswith("a.toml: foundation.safety_factor: 1.0000001 is far outside building practice (1.2 to "
                              "100)"), warning


def test_every_example_deck_is_plausible():
    from upliftcli.deck.load import read_toml

    for path in sorted((ROOT / "inputs").glob("*.toml")):
        assert plausibility(validate(read_toml(path), str(path)), str(path)) == [], path.name


def test_the_documented_ranges_are_the_declared_ones():
    from upliftcli.motion.spectrum_fields import SPECTRUM_FIELDS

    text = (ROOT / "docs" / "deck.md").read_text()
    section = text.split("## Plausible ranges", 1)[1].split("\n## ", 1)[0]
    documented = {m.group(1): (float(m.group(2)), float(m.group(3)), m.group(4))
                  for m in re.finditer(r"^\| `([\w.]+)` \| ([\d.e+-]+) \| ([\d.e+-]+) \| (\S+) \|$", section, re.M)}
    declared = {deck_schema.dotted(table, name): (*field.plausible, field.unit)
                for table, fields in deck_schema.TABLES.items() for name, field in fields.items() if field.plausible}
    declared |= {f"ground_motion.design_spectrum.{key}": (*field.plausible, field.unit)
                 for key, field in SPECTRUM_FIELDS.items() if field.plausible}
    assert documented == declared


def test_the_deck_in_bare_si():
    raw = {"title": "t", "units": "us", "building": {"stories": 2, "story_height": 10, "period": 1},
           "ground_motion": {"window": ["1 s", 5], "suite": [{"file": "a.txt", "dt": "10 ms"}, "b.txt"],
                             "design_spectrum": {"type": "asce7", "sds": "9.80665 m/s2", "sd1": 0.6, "tl": 8}}}
    resolved = si_mapping(raw, validate(raw, "deck.toml"))
    assert "units" not in resolved and resolved["title"] == "t"
    assert resolved["building"] == {"stories": 2, "story_height": pytest.approx(3.048), "period": 1}
    assert resolved["ground_motion"]["window"] == [1.0, 5.0]
    assert resolved["ground_motion"]["suite"] == [{"file": "a.txt", "dt": 0.01}, "b.txt"]
    assert resolved["ground_motion"]["design_spectrum"]["sds"] == 1.0
    assert raw["building"]["story_height"] == 10  # the deck as given is kept
    si = {"building": {"stories": 2, "story_height": 3, "floor_mass": 1e5}, "ground_motion": {"window": [0, 5]}}
    assert si_mapping(si, validate(si, "deck.toml")) == si  # bare SI comes back as it was


def test_every_numeric_field_has_a_quantity_or_none():
    """A unit without a quantity kind would be read as SI in a US deck: every number field of the
    deck is dimensionless or of a kind of units.QUANTITY_KINDS."""
    from upliftcli.deck.fields import NUMERIC
    from upliftcli.motion.spectrum_fields import SPECTRUM_FIELDS

    fields = [(deck_schema.dotted(table, name), field) for table, fields in deck_schema.TABLES.items()
              for name, field in fields.items()] + list(SPECTRUM_FIELDS.items())
    for path, field in fields:
        if field.kind in NUMERIC and field.unit != "-":
            assert field.quantity_kind is not None or path == "sa", path


def test_the_units_table_of_the_docs_is_the_declared_one():
    """docs/deck.md, Units: each quantity's SI and US unit (units.QUANTITY_KINDS) and the fields
    of that quantity; every dimensional number field of the deck is listed once."""
    from upliftcli.deck.fields import NUMERIC
    from upliftcli.motion.spectrum_fields import SPECTRUM_FIELDS
    from upliftcli.units import QUANTITY_KINDS

    text = (ROOT / "docs" / "deck.md").read_text()
    section = text.split("\n## Units", 1)[1].split("\n## ", 1)[0]
    listed = {}
    for match in re.finditer(r"^\| ([a-z ]+) \| (.+?) \| ([^|]+?) \| (.+?) \|$", section, re.M):
        kind, cells, si, us = match.groups()
        if kind not in QUANTITY_KINDS:
            continue
        assert (si, us.split(" (")[0]) == QUANTITY_KINDS[kind], kind
        for name in re.findall(r"`([\w.()]+)`", cells):
            for expanded in ([name.replace("(s)", ""), name.replace("(s)", "s")] if "(s)" in name else
                             [name.replace("(es)", ""), name.replace("(es)", "es")] if "(es)" in name else [name]):
                listed[expanded.rsplit(".", 1)[-1]] = kind
    declared = {name: field.quantity_kind for fields in deck_schema.TABLES.values() for name, field in fields.items()
                if field.kind in NUMERIC and field.unit != "-"}
    declared |= {name: field.quantity_kind for name, field in SPECTRUM_FIELDS.items()
                 if field.kind in NUMERIC and field.quantity_kind}
    assert listed == declared
