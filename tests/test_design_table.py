"""The [design] table (model/design.py, deck/design.py): ASCE 7-22 Table 12.12-1 and Table 1.5-2 row by
row, the deck's values and its one-line errors (docs/deck.md, [design])."""

from __future__ import annotations

import pytest

from upliftcli.deck.load import build_deck
from upliftcli.errors import InputError, lines
from upliftcli.model.design import Design, allowable_drift_ratio, importance_factor

#: ASCE 7-22 Table 12.12-1, typed from the standard: row -> Delta_a/h_sx for risk category I, II, III, IV
TABLE_12_12_1 = {
    "low-rise-drift-tolerant": (0.025, 0.025, 0.020, 0.015),
    "masonry-cantilever-shear-wall": (0.010, 0.010, 0.010, 0.010),
    "other-masonry-shear-wall": (0.007, 0.007, 0.007, 0.007),
    "all-other": (0.020, 0.020, 0.015, 0.010),
}


@pytest.mark.parametrize("structure", list(TABLE_12_12_1))
@pytest.mark.parametrize("column", range(4))
def test_the_allowable_drift_is_table_12_12_1s(structure, column):
    risk = ("I", "II", "III", "IV")[column]
    assert allowable_drift_ratio(structure, risk, 3) == TABLE_12_12_1[structure][column]


def test_a_one_story_drift_tolerant_structure_has_no_limit_but_the_other_rows_do():
    """Footnote c of Table 12.12-1: no drift limit for a single-story structure of the first row."""
    assert allowable_drift_ratio("low-rise-drift-tolerant", "II", 1) is None
    assert allowable_drift_ratio("all-other", "II", 1) == 0.020


@pytest.mark.parametrize(("risk", "ie"), [("I", 1.0), ("II", 1.0), ("III", 1.25), ("IV", 1.5)])
def test_the_importance_factor_is_table_1_5_2s(risk, ie):
    assert importance_factor(risk) == ie


def deck(**design) -> dict:
    """A three-story deck on an ASCE 7-22 design spectrum with the [design] fields given."""
    return {
        "building": {"stories": 3, "floor_mass": 1.0e5, "story_height": 3.5, "period": 0.4},
        "foundation": {"type": "two-element", "b": 10.0, "frequency_ratio": 4.0},
        "ground_motion": {"design_spectrum": {"type": "asce7", "sds": 1.0, "sd1": 0.6, "tl": 8.0}},
        "analysis": {"engine": "simplified", "supports": ["rigid"]},
        **({"design": design} if design else {}),
    }


def test_a_deck_without_design_has_none_and_one_with_it_has_its_values():
    assert build_deck(deck(), "d.toml").design is None
    design = build_deck(deck(R=8, Cd=5.5, Omega0=3, risk_category="III"), "d.toml").design
    assert design == Design(R=8.0, Cd=5.5, Ie=1.25, risk_category="III", structure="all-other", Omega0=3.0)
    assert design.force_factor == 1.25 / 8 and design.drift_factor == 5.5 / 8
    assert design.allowable_drift_ratio(3) == 0.015


BAD = [
    ({"Cd": 5.5, "risk_category": "II"}, "d.toml: design.R: a value with design.Cd (the linear procedure of ASCE "
     "7-22 12.9.1.2 needs R and C_d; a chapter 16 deck may give neither)"),
    ({"R": 8, "risk_category": "II"}, "d.toml: design.Cd: a value with design.R"),
    ({"R": 8, "Cd": 5.5}, "d.toml: design.risk_category: a value in a [design] table (it sets I_e and the allowable "
     "drift)"),
    ({"R": 0.5, "Cd": 5.5, "risk_category": "II"}, "d.toml: design.R: a number >= 1, got 0.5"),
    ({"R": 8, "Cd": 5.5, "risk_category": "V"}, "d.toml: design.risk_category: one of I, II, III, IV, got 'V'"),
    ({"R": 8, "Cd": 5.5, "risk_category": "II", "Ie": 1.1}, "d.toml: design.Ie: a number 1.0, 1.25 or 1.5 "
     "(ASCE 7-22 Table 1.5-2), got 1.1"),
    ({"R": 8, "Cd": 5.5, "risk_category": "II", "Ie": 1.5}, "d.toml: design.Ie: 1.0, the importance factor of risk "
     "category II (ASCE 7-22 11.5.1, Table 1.5-2), got 1.5"),
    ({"R": 8, "Cd": 5.5, "risk_category": "II", "structure": "masonry"}, "d.toml: design.structure: one of "
     "low-rise-drift-tolerant, masonry-cantilever-shear-wall, other-masonry-shear-wall, all-other, got 'masonry'"),
    ({"R": 8, "Cd": 5.5, "risk_category": "II", "Rr": 3}, "d.toml: design.Rr: a known field of [design]"),
]


@pytest.mark.parametrize(("design", "message"), BAD)
def test_a_bad_design_field_is_one_line_naming_the_file_and_the_field(design, message):
    with pytest.raises(InputError) as caught:
        build_deck(deck(**design), "d.toml")
    (line,) = lines(caught.value)
    assert line.startswith(message)


def test_the_low_rise_row_on_more_than_four_stories_is_refused():
    mapping = deck(R=8, Cd=5.5, risk_category="II", structure="low-rise-drift-tolerant")
    mapping["building"]["stories"] = 5
    with pytest.raises(InputError, match=r"^d\.toml: design\.structure: a row of ASCE 7-22 Table 12\.12-1 that fits "
                       r"the building: low-rise-drift-tolerant holds 4 stories or less, the building has 5$"):
        build_deck(mapping, "d.toml")
    mapping["building"]["stories"] = 4
    assert build_deck(mapping, "d.toml").design.allowable_drift_ratio(4) == 0.025


def test_values_outside_table_12_2_1s_range_are_warnings_naming_the_field():
    warnings = build_deck(deck(R=9, Cd=7, Omega0=3.5, risk_category="II"), "d.toml").warnings
    assert [w.split(":")[1].strip() for w in warnings] == ["design.R", "design.Cd", "design.Omega0"]


def test_a_chapter_16_deck_may_give_the_risk_category_and_the_structure_alone():
    """Chapter 16 uses no R, C_d or Omega_0: a [design] table with the risk category and the row of Table
    12.12-1 alone is a Design without them (Design.linear false)."""
    design = build_deck(deck(risk_category="IV", structure="other-masonry-shear-wall"), "d.toml").design
    assert design == Design(R=None, Cd=None, Ie=1.5, risk_category="IV", structure="other-masonry-shear-wall")
    assert not design.linear and design.allowable_drift_ratio(3) == 0.007
    assert design.to_dict() == {"Ie": 1.5, "risk_category": "IV", "structure": "other-masonry-shear-wall"}
