"""Every mistake of a deck in one run (deck/load.build_deck, deck/failed.py): the schema's, the
foundation's fields of another type, the building's, the ground motion's and the criteria's, each
message as it was when it came alone, in the order the runs that found them one after another
gave; a mistake that makes the others meaningless (an unknown unit system, a field that is not a
number, an unknown foundation type) reported alone."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from cli_helpers import invoke

from upliftcli.deck.load import load_deck
from upliftcli.errors import InputError, lines

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"

#: wrong types, a value out of range, an unknown field and two fields of another foundation type
SEVEN_MISTAKES = """title = "seven mistakes"

[building]
stories = 10
floor_mass = "heavy"
story_height = 3.5
period = 0.5
damping = 1.5

[foundation]
type = "two-element"
slenderness = 10
frequncy_ratio = 8
frequency_ratio = 8
damping_ratio = 0.4
k_w = 6.0e8
elements = 20

[ground_motion]
record = "elcentro_1940_ns_chopra.txt"
units = "g"

[analysis]
combination = "abs"

[criteria]
drift_ratio = -0.02
"""
#: what the deck was told over three runs before (5 lines, then 1, then 1), word for word
THREE_RUNS = [
    "error: bad.toml: building.floor_mass: a number > 0 [kg] or a text 'number unit' with a unit of mass "
    "(docs/deck.md, Units), got 'heavy'",
    "error: bad.toml: building.damping: a number in [0, 1), got 1.5",
    "error: bad.toml: foundation.frequncy_ratio: a known field of [foundation] (did you mean 'frequency_ratio'?); "
    "unknown key 'frequncy_ratio'",
    "error: bad.toml: analysis.combination: one of srss, cqc, got 'abs'",
    "error: bad.toml: criteria.drift_ratio: a number > 0, got -0.02",
    "error: bad.toml: foundation.k_w: no k_w for foundation type 'two-element' (it belongs to type 'winkler')",
    "error: bad.toml: foundation.elements: no elements for foundation type 'two-element' (it belongs to type "
    "'winkler')",
]


def _analyze(folder: Path, text: str) -> list[str]:
    """`uplift analyze bad.toml` in `folder` (beside a copy of the El Centro record): its stderr lines."""
    shutil.copy(RECORD, folder / RECORD.name)
    (folder / "bad.toml").write_text(text)
    done = invoke("analyze", folder / "bad.toml")
    assert done.exit_code == 2, done.output
    return [line.replace(str(folder / "bad.toml"), "bad.toml") for line in done.stderr.splitlines()]


def test_seven_mistakes_are_reported_in_one_run(tmp_path):
    assert _analyze(tmp_path, SEVEN_MISTAKES) == THREE_RUNS
    fixed = (SEVEN_MISTAKES.replace('floor_mass = "heavy"', "floor_mass = 350e3").replace("damping = 1.5", "")
             .replace("frequncy_ratio = 8\n", "").replace('"abs"', '"srss"').replace("-0.02", "0.02"))
    assert _analyze(tmp_path, fixed) == THREE_RUNS[5:]  # the two fields of another type, together


def _errors(folder: Path, deck: dict[str, str]) -> list[str]:
    """The error lines of a deck given as its tables' text, read beside the El Centro record."""
    shutil.copy(RECORD, folder / RECORD.name)
    path = folder / "deck.toml"
    path.write_text("".join(f"[{table}]\n{body}\n" for table, body in deck.items()))
    with pytest.raises(InputError) as info:
        load_deck(path)
    return lines(info.value)


BASE = {
    "building": "stories = 3\nfloor_mass = 2e5\nstory_height = 3.0\nperiod = 0.4",
    "foundation": "b = 3.0\nk_f = 5e8\nc_f = 4e6",
    "ground_motion": 'record = "elcentro_1940_ns_chopra.txt"\nunits = "g"',
    "analysis": 'engine = "simplified"',
    "criteria": "drift_ratio = 0.02",
}
#: mistakes found by the checks after the schema's, each independent of the others: (table, text
#: replaced, its replacement)
LATER_MISTAKES = [
    ("building", "floor_mass = 2e5\nstory_height = 3.0", "masses = [2e5, 2e5]\nstory_heights = [3.0, 3.0, 3.0, 3.0]"),
    ("foundation", "c_f = 4e6", "c_f = 4e6\nk_w = 1e8\nc_w = 1e6"),
    ("criteria", "drift_ratio = 0.02", 'drift_ratio = 0.02\nrotation = 0.01\nsettlement = 0.01\n[criteria.sources]\n'
                                       'base_shear = "a table"'),
]


def _with(mistakes) -> dict[str, str]:
    deck = dict(BASE)
    for table, old, new in mistakes:
        deck[table] = deck[table].replace(old, new)
    return deck


def test_the_mistakes_of_the_later_checks_come_together_each_as_alone(tmp_path):
    """Per-story arrays of the wrong lengths, two fields of another foundation type, two rocking
    limits without the exact engine and the source of a limit not set: each table's mistakes were
    reported one at a time, one table a run."""
    alone = [_errors(tmp_path, _with([mistake])) for mistake in LATER_MISTAKES]
    assert [len(found) for found in alone] == [2, 2, 3]
    assert _errors(tmp_path, _with(LATER_MISTAKES)) == [line for found in alone for line in found]


def test_the_building_and_the_criteria_come_with_the_schemas_mistakes(tmp_path):
    deck = _with([LATER_MISTAKES[0], ("analysis", '"simplified"', '"simplified"\ncombination = "abs"')])
    assert _errors(tmp_path, deck) == [
        f"{tmp_path / 'deck.toml'}: analysis.combination: one of srss, cqc, got 'abs'",
        *_errors(tmp_path, _with(LATER_MISTAKES[:1]))]
    missing = dict(BASE, building="stories = 3\nperiod = 0.4", criteria="[criteria.sources]\ndrift_ratio = \"x\"")
    assert [line.split(": ")[1] for line in _errors(tmp_path, missing)] == [
        "building.floor_mass", "building.story_height", "criteria.sources.drift_ratio"]


@pytest.mark.parametrize(("table", "old", "new", "only"), [
    ("building", "floor_mass = 2e5", 'floor_mass = "heavy"', "building.floor_mass"),  # not also "missing"
    ("foundation", "b = 3.0", 'type = "winklr"\nb = 3.0', "foundation.type"),  # k_f: of no type known
    ("ground_motion", 'units = "g"', 'units = "furlongs"', "ground_motion.units"),
])
def test_a_mistake_that_makes_the_others_meaningless_comes_alone(tmp_path, table, old, new, only):
    deck = _with([(table, old, new)])
    deck["foundation"] += "\nk_w = 1e8" if table == "foundation" else ""
    assert [line.split(": ")[1] for line in _errors(tmp_path, deck)] == [only]


def test_an_unknown_unit_system_is_reported_alone(tmp_path):
    """The deck's numbers are read in its system: with none known, the building's checks would judge
    numbers read in the wrong units."""
    shutil.copy(RECORD, tmp_path / RECORD.name)
    path = tmp_path / "deck.toml"
    text = "".join(f"[{table}]\n{body}\n" for table, body in _with(LATER_MISTAKES[:1]).items())
    path.write_text('units = "metric"\n' + text)
    with pytest.raises(InputError) as info:
        load_deck(path)
    assert [line.split(": ")[1] for line in lines(info.value)] == ["units"]
