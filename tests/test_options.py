"""engines/options.py: one declaration per option, the same check from a deck, --set or Python."""

from __future__ import annotations

from pathlib import Path

import pytest

from upliftcli.deck import schema as deck_schema
from upliftcli.deck.load import load_deck
from upliftcli.engines.options import ExactOptions, SimplifiedOptions, deck_fields
from upliftcli.errors import InputError

EXAMPLE = Path(__file__).resolve().parents[1] / "inputs" / "ten_story_elcentro.toml"


def test_the_deck_tables_are_the_declared_options():
    assert deck_schema.TABLES["analysis.exact"] == deck_fields(ExactOptions)
    for name, field in deck_fields(SimplifiedOptions).items():
        assert deck_schema.TABLES["analysis"][name] is field


def test_defaults_come_from_the_declarations():
    for cls in (ExactOptions, SimplifiedOptions):
        options = cls()
        for name, field in deck_fields(cls).items():
            assert getattr(options, name) == field.default


def test_one_rule_for_a_deck_an_override_and_python():
    """steps_per_period >= 2: the schema used to accept 1 and the engine then refused it with
    a message naming neither the deck nor --set."""
    with pytest.raises(InputError) as info:
        load_deck(EXAMPLE, ["analysis.exact.steps_per_period=1"], load_ground_motion=False)
    assert str(info.value) == "--set: analysis.exact.steps_per_period: an integer >= 2, got 1"
    with pytest.raises(InputError, match=r"ExactOptions: analysis.exact.steps_per_period: an integer >= 2"):
        ExactOptions(steps_per_period=1)
    with pytest.raises(InputError, match="one of srss, cqc, got 'abs'"):
        SimplifiedOptions(combination="abs")
    with pytest.raises(InputError, match="time_step: a number > 0 "):
        ExactOptions(time_step=-1.0)
    assert load_deck(EXAMPLE, ["analysis.exact.steps_per_period=2"],
                     load_ground_motion=False).analysis.exact.steps_per_period == 2
