"""--set overrides (deck/overrides.py): values read as TOML, paths checked against the schema,
alternatives replaced."""

import pytest

from upliftcli.deck.overrides import apply_overrides, parse_override
from upliftcli.errors import InputError


def test_parse_override_values():
    assert parse_override("building.period=0.5") == ("building.period", 0.5)
    assert parse_override("building.stories=3") == ("building.stories", 3)
    assert parse_override("analysis.combination=cqc") == ("analysis.combination", "cqc")
    assert parse_override('analysis.engine=["simplified", "exact"]')[1] == ["simplified", "exact"]
    assert parse_override("ground_motion.design_spectrum.sds=1.0") == ("ground_motion.design_spectrum.sds", 1.0)


@pytest.mark.parametrize("text, location, words", [
    ("building.perod=0.5", "building.perod", "did you mean 'building.period'"),
    ("building.period", "building.period", "PATH=VALUE"),
    ("nothing.here=1", "nothing.here", "a known deck field"),
])
def test_bad_override_names_set_and_path(text, location, words):
    with pytest.raises(InputError) as info:
        parse_override(text)
    assert info.value.source == "--set"
    assert info.value.location == location
    assert words in str(info.value)


def test_a_newline_inside_a_set_value_is_refused():
    with pytest.raises(InputError, match=r"^--set: building.period: a value on one line"):
        parse_override("building.period=0.5\nx=1")


def test_an_override_replaces_its_alternatives():
    raw = {"foundation": {"type": "two-element", "b": 2.0, "frequency_ratio": 5.0, "damping_ratio": 0.1}}
    result, paths = apply_overrides(raw, [("foundation.slenderness", 0.1)])
    assert result["foundation"] == {"type": "two-element", "slenderness": 0.1, "frequency_ratio": 5.0,
                                    "damping_ratio": 0.1}
    assert paths == frozenset({"foundation.slenderness"})
    assert raw["foundation"]["b"] == 2.0  # the input is not changed


def test_a_key_of_an_overridden_table_is_named_as_set():
    from upliftcli.deck.overrides import set_by_override

    overridden = frozenset({"ground_motion.design_spectrum", "ground_motion.suite"})
    assert set_by_override("ground_motion.design_spectrum.sds", overridden)
    assert set_by_override("ground_motion.suite[1].file", overridden)
    assert not set_by_override("ground_motion.design_spectrum_x", overridden)
    assert not set_by_override("building.period", overridden)


def test_a_bad_design_spectrum_given_by_set_names_set():
    from pathlib import Path

    from upliftcli.deck.load import load_deck

    deck = Path(__file__).resolve().parents[1] / "inputs" / "ten_story_asce7.toml"
    with pytest.raises(InputError, match=r"^--set: ground_motion\.design_spectrum\.sds: a number > 0 \[g\]"):
        load_deck(deck, ['ground_motion.design_spectrum={type="asce7", sds=-1.0, sd1=0.6, tl=8}'])


def test_override_header_units_goes_with_the_record_fields():
    from upliftcli.deck.overrides import apply_overrides

    raw = {"ground_motion": {"record": "r.txt", "units": "gal", "override_header_units": True}}
    result, _ = apply_overrides(raw, [("ground_motion.design_spectrum", {"type": "asce7"})])
    assert result["ground_motion"] == {"design_spectrum": {"type": "asce7"}}
