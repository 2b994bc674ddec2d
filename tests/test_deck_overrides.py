"""--set overrides (deck_overrides.py): values read as TOML, paths checked against the schema,
alternatives replaced."""

import pytest

from upliftcli.deck_overrides import apply_overrides, parse_override
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
