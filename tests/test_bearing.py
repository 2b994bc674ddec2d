"""The bearing capacity of the two-element and Winkler foundations (model/bearing.py, docs/deck.md,
docs/theory.md section 14): the three ways to give it, Q_y of each element, M_c and V_c of the
system, the refusals (half-space, FS_v <= 1), the engines that model it."""

import math
import re
from pathlib import Path

import numpy as np
import pytest

from upliftcli.analysis import run as analysis
from upliftcli.api import analyze
from upliftcli.deck.load import load_deck
from upliftcli.errors import InputError
from upliftcli.model.foundations import TwoElement, Winkler
from upliftcli.model.rocking_capacity import winkler_moment_capacity
from upliftcli.motion.records import read_record

ROOT = Path(__file__).resolve().parent.parent
TWO = ROOT / "inputs" / "ten_story_elcentro.toml"
WINKLER = ROOT / "inputs" / "ten_story_winkler.toml"
HALFSPACE = ROOT / "inputs" / "frame_halfspace.toml"


def deck(path, *overrides):
    return load_deck(path, list(overrides), load_ground_motion=False)


def test_three_ways_give_one_capacity_two_elements():
    """Q_y = FS_v W/2 = q_c L b: a safety factor, a pressure with the mat length and the force
    itself give the same elements and M_c = W b min(1, FS_v - 1)."""
    by_factor = deck(TWO, "foundation.safety_factor=1.6").system
    weight, b = by_factor.weight, by_factor.half_width
    q_y = 1.6 * weight / 2.0
    by_force = deck(TWO, f"foundation.element_capacity={q_y!r}").system
    length = 25.0
    by_pressure = deck(TWO, f"foundation.bearing_pressure={q_y / (length * b)!r}",
                       f"foundation.mat_length={length}").system
    for system in (by_factor, by_force, by_pressure):
        elements = system.foundation.contact_elements(b)
        assert np.allclose(elements.capacity, [q_y, q_y], rtol=1e-14)
        assert system.critical_base_moment == pytest.approx(0.6 * weight * b, rel=1e-14)
        assert system.critical_base_shear == pytest.approx(0.6 * weight * b / system.effective_height, rel=1e-14)
        assert system.tipping_moment == weight * b
    assert deck(TWO, "foundation.safety_factor=2.5").system.critical_base_moment == pytest.approx(weight * b)


def test_three_ways_give_one_capacity_winkler():
    by_factor = deck(WINKLER, "foundation.safety_factor=2.0").system
    weight, b = by_factor.weight, by_factor.half_width
    line = 2.0 * weight / (2.0 * b)
    by_line = deck(WINKLER, f"foundation.line_capacity={line!r}").system
    by_pressure = deck(WINKLER, f"foundation.bearing_pressure={line / 30.0!r}", "foundation.mat_length=30").system
    for system in (by_factor, by_line, by_pressure):
        elements = system.foundation.contact_elements(b)
        assert elements.capacity.size == 20
        assert np.allclose(elements.capacity, line * 2.0 * b / 20, rtol=1e-14)
        # ASCE 41-17 8.4: (P B/2)(1 - q/q_c) with q/q_c = 1/FS_v
        assert system.critical_base_moment == pytest.approx(weight * b * 0.5, rel=1e-14)
        assert system.critical_base_moment == pytest.approx(winkler_moment_capacity(b, line, weight), rel=1e-14)


def test_without_a_capacity_nothing_changes():
    system = deck(TWO).system
    assert system.foundation.capacity is None
    assert system.foundation.contact_elements(system.half_width).capacity is None
    assert system.critical_base_moment == system.total_mass * system.gravity * system.half_width
    assert deck(HALFSPACE).system.critical_base_moment == deck(HALFSPACE).system.tipping_moment


@pytest.mark.parametrize(("overrides", "field", "words"), [
    (["foundation.bearing_pressure=2e5"], "foundation.mat_length", "mat length L"),
    (["foundation.safety_factor=1.0"], "foundation.safety_factor", "> 1"),
    (["foundation.element_capacity=1e6"], "foundation.element_capacity", "FS_v = 0.05"),
    (["foundation.line_capacity=1e6"], "foundation.line_capacity", "belongs to type 'winkler'"),
])
def test_bad_capacities_name_the_field(overrides, field, words):
    with pytest.raises(InputError) as info:
        deck(TWO, *overrides)
    assert info.value.location == field
    assert words in str(info.value)
    assert "\n" not in str(info.value)


def test_two_ways_in_one_deck_are_refused(tmp_path):
    text = TWO.read_text().replace("[foundation]\n", "[foundation]\nsafety_factor = 1.5\nelement_capacity = 3e7\n")
    path = tmp_path / "deck.toml"
    path.write_text(text)
    with pytest.raises(InputError, match=re.escape("only one of foundation.element_capacity, "
                                                   "foundation.bearing_pressure, foundation.safety_factor")) as info:
        load_deck(path, load_ground_motion=False)
    assert info.value.source == str(path)


def test_the_half_space_refuses_a_capacity():
    with pytest.raises(InputError, match="no bearing capacity for the half-space") as info:
        deck(HALFSPACE, "foundation.safety_factor=2")
    assert info.value.location == "foundation.safety_factor"


def test_a_set_capacity_replaces_the_other_way():
    loaded = deck(TWO, "foundation.element_capacity=3e7", "foundation.safety_factor=3")
    assert "element_capacity" not in loaded.raw["foundation"]
    assert loaded.system.foundation.capacity == pytest.approx(1.5 * loaded.system.weight)


@pytest.mark.parametrize("engine", ["exact", "approximate"])
def test_history_engines_model_a_capacity(engine):
    """The history engines model yielding in the uplift analysis (docs/theory.md section 14,
    tests/test_yielding.py); the linear references (rigid, bonded) run as without a capacity."""
    loaded = load_deck(TWO, ["foundation.safety_factor=1.5"])
    result = analysis.run_one(loaded, engine, "uplift")
    assert any(result.details["yielding"]["yielded"]) and result.details["yielding"]["plastic_work"] > 0.0
    elastic = load_deck(TWO)
    bonded = analysis.run_one(loaded, engine, "bonded")
    assert bonded.base_shear == analysis.run_one(elastic, engine, "bonded").base_shear
    assert "yielding" not in bonded.details


def test_history_engines_take_a_system_built_in_code():
    system = deck(TWO).system
    yielding = type(system)(system.building, TwoElement(system.foundation.stiffness, system.foundation.damping,
                                                        0.8 * system.weight), system.half_width)
    record = read_record(ROOT / "records" / "elcentro_1940_ns_chopra.txt", units="g")
    result = analyze(yielding, record, "uplift", engine="exact")
    assert min(result.details["yielding"]["plastic_settlement"]) < 0.0
    assert analyze(yielding, record, "uplift", engine="simplified").critical_base_moment == pytest.approx(
        0.6 * system.weight * system.half_width)


def test_winkler_capacity_of_the_dataclass():
    foundation = Winkler(6e8, 1.5e7, 10, 2.0e6)
    assert foundation.total_capacity(6.0) == 2.4e7
    assert np.allclose(foundation.contact_elements(6.0).capacity, 2.0e6 * 1.2)
    assert foundation.moment_capacity(6.0, 1.2e7) == pytest.approx(1.2e7 * 6.0 * (1 - 1.2e7 / 2.4e7))
    assert math.isclose(Winkler(6e8, 1.5e7).moment_capacity(6.0, 1.2e7), 1.2e7 * 6.0)


@pytest.mark.parametrize("overrides", [["foundation.mat_length=30"],
                                       ["foundation.safety_factor=3", "foundation.mat_length=30"]])
def test_a_mat_length_without_bearing_pressure_is_refused(overrides):
    """mat_length only scales bearing_pressure (q_c L): alone, or beside a safety factor, nothing
    reads it, and it was ignored without a word."""
    with pytest.raises(InputError) as info:
        deck(TWO, *overrides)
    assert str(info.value) == ("--set: foundation.mat_length: only with foundation.bearing_pressure, which it scales "
                               "(q_c L); without it the mat length is not used (a capacity from safety_factor or the "
                               "foundation's own field needs no length)")


def test_a_set_capacity_replaces_a_pressure_with_its_mat_length(tmp_path):
    """--set safety_factor (or the foundation's own field) on a deck giving bearing_pressure and
    mat_length removes both: the length goes with the pressure it scales."""
    text = TWO.read_text().replace("[foundation]\n", "[foundation]\nbearing_pressure = 3e6\nmat_length = 30\n")
    path = tmp_path / "deck.toml"
    path.write_text(text)
    for override, capacity in (("foundation.safety_factor=3", None), ("foundation.element_capacity=3e7", 3e7)):
        loaded = load_deck(path, [override], load_ground_motion=False)
        assert "bearing_pressure" not in loaded.raw["foundation"] and "mat_length" not in loaded.raw["foundation"]
        assert loaded.system.foundation.capacity == pytest.approx(capacity or 1.5 * loaded.system.weight)
    kept = load_deck(path, ["foundation.mat_length=20"], load_ground_motion=False)
    assert kept.system.foundation.capacity == pytest.approx(3e6 * 20 * kept.system.half_width)


def test_a_safety_factor_near_one_warns():
    """FS_v just above 1 (the soil at its capacity under gravity alone) is accepted but outside
    practice: a warning naming the field and the range (fuzzing found FS_v = 1.0000001 giving
    M_b = 5e6 M_c in the simplified engine with no word under --no-check); FS_v = 1.5 is quiet."""
    near = load_deck(TWO, ["foundation.safety_factor=1.05"])
    assert any("foundation.safety_factor: 1.05 is far outside building practice (1.2 to 100)" in w
               for w in near.warnings), near.warnings
    assert not [w for w in load_deck(TWO, ["foundation.safety_factor=1.5"]).warnings if "safety_factor" in w]
