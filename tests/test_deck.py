"""Deck loading: formats, derived quantities, --set overrides, and one clear error per bad input."""

import math
import re
from pathlib import Path

import numpy as np
import pytest

from upliftcli.deck import schema as deck_schema
from upliftcli.deck.load import build_deck, load_deck
from upliftcli.errors import InputError
from upliftcli.model.foundations import HalfSpace, TwoElement, Winkler

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"

BASE = """
[building]
stories = 4
floor_mass = 2.0e5
story_height = 3.0
story_stiffness = 4.0e8

[foundation]
b = 5.0
k_f = 1.0e9
c_f = 1.0e7
"""


def write(tmp_path, text, name="deck.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def load(tmp_path, text, overrides=(), ground_motion=False):
    return load_deck(write(tmp_path, text), overrides, load_ground_motion=ground_motion)


# ----------------------------------------------------------------------------- the example

def test_example_deck_is_the_papers_system():
    deck = load_deck(EXAMPLE)
    system = deck.system
    modes = system.modes
    assert modes.periods[0] == pytest.approx(0.5)
    assert system.effective_height / system.half_width == pytest.approx(10.0)
    w_v = math.sqrt(2 * system.foundation.stiffness / system.total_mass)
    assert w_v / modes.omega[0] == pytest.approx(8.0)
    assert system.foundation.damping / (system.total_mass * w_v) == pytest.approx(0.4)
    assert np.all(modes.damping == 0.05)
    assert deck.analysis.supports == ["rigid", "bonded", "uplift"]
    assert deck.analysis.engines == ["simplified"]
    assert deck.ground_motion.dt == pytest.approx(0.02)
    assert deck.ground_motion.pga == pytest.approx(0.31882 * 9.80665, rel=1e-6)
    # the spectrum object is the record's: 5 % S_a(0.5 s) = 0.916 g (records/README)
    assert deck.spectrum.sa(np.array([0.5]), 0.05)[0] / 9.80665 == pytest.approx(0.916, rel=0.005)
    assert deck.criteria == {"drift_ratio": 0.02}


# ----------------------------------------------------------------------------- building forms

def test_uniform_with_stiffness(tmp_path):
    deck = load(tmp_path, BASE)
    b = deck.system.building
    assert b.n_stories == 4
    np.testing.assert_allclose(b.heights, [3, 6, 9, 12])
    np.testing.assert_allclose(b.story_stiffness, 4e8)
    assert isinstance(deck.system.foundation, TwoElement)


def test_per_story_arrays_and_period_scaling(tmp_path):
    text = BASE.replace("stories = 4\nfloor_mass = 2.0e5\nstory_height = 3.0\nstory_stiffness = 4.0e8",
                        "masses = [3e5, 2e5, 2e5, 1e5]\nstory_heights = [4.0, 3.0, 3.0, 3.0]\n"
                        "story_stiffnesses = [8e8, 6e8, 4e8, 2e8]\nperiod = 0.8\ndamping = [0.05, 0.03, 0.03, 0.02]")
    deck = load(tmp_path, text)
    b = deck.system.building
    assert deck.system.modes.periods[0] == pytest.approx(0.8)
    ratios = b.story_stiffness / b.story_stiffness[0]
    np.testing.assert_allclose(ratios, [1, 0.75, 0.5, 0.25])
    np.testing.assert_allclose(b.damping, [0.05, 0.03, 0.03, 0.02])


def test_stiffness_matrix_frame(tmp_path):
    k = np.array([[2, -1, 0], [-1, 2, -1], [0, -1, 1]]) * 5e8
    rows = ", ".join("[" + ", ".join(repr(float(v)) for v in row) + "]" for row in k)
    text = f"[building]\nmasses = [1e5, 1e5, 1e5]\nstory_heights = [3.0, 3.0, 3.0]\nstiffness_matrix = [{rows}]\n" \
           "[foundation]\nb = 5.0\nk_f = 1e9\n"
    deck = load(tmp_path, text)
    np.testing.assert_allclose(deck.system.building.stiffness, k)
    assert deck.system.building.story_stiffness is None


def test_winkler_and_halfspace(tmp_path):
    text = BASE.replace("k_f = 1.0e9\nc_f = 1.0e7", 'type = "winkler"\nk_w = 2e8\nc_w = 1e6\nelements = 10')
    deck = load(tmp_path, text)
    assert deck.system.foundation == Winkler(2e8, 1e6, 10)
    text = BASE.replace("k_f = 1.0e9\nc_f = 1.0e7",
                        'type = "halfspace"\nshear_wave_velocity = 200.0\ndensity = 1800.0\npoisson_ratio = 0.3')
    deck = load(tmp_path, text)
    f = deck.system.foundation
    assert isinstance(f, HalfSpace)
    assert f.shear_modulus == pytest.approx(1800.0 * 200.0**2)
    assert f.half_length == 5.0  # default: square mat


def test_modes_from_mass_participation(tmp_path):
    deck = load_deck(EXAMPLE, ["analysis.mass_participation=0.95"], load_ground_motion=False)
    assert deck.analysis.n_modes == 3  # 0.848, 0.939, 0.970
    assert deck.analysis.simplified.n_modes == 3
    assert deck.analysis.exact.n_modes == 3
    deck = load_deck(EXAMPLE, load_ground_motion=False)
    assert deck.analysis.n_modes == 10 and deck.analysis.exact.n_modes is None


# ----------------------------------------------------------------------------- overrides

def test_set_overrides_by_dotted_path():
    deck = load_deck(EXAMPLE, ["building.period=1.2", "foundation.b=4", "analysis.combination=cqc",
                               'analysis.supports=["uplift"]'], load_ground_motion=False)
    assert deck.system.modes.periods[0] == pytest.approx(1.2)
    assert deck.system.half_width == 4.0  # replaces slenderness = 10
    assert "slenderness" not in deck.raw["foundation"]
    assert deck.analysis.simplified.combination == "cqc"
    assert deck.analysis.supports == ["uplift"]


def test_set_k_f_replaces_ratio(tmp_path):
    deck = load_deck(EXAMPLE, ["foundation.k_f=2e9"], load_ground_motion=False)
    assert deck.system.foundation.stiffness == 2e9
    w_v = math.sqrt(2 * 2e9 / deck.system.total_mass)
    assert deck.system.foundation.damping == pytest.approx(0.4 * deck.system.total_mass * w_v)


def test_bad_override_value_is_reported_against_set():
    with pytest.raises(InputError) as info:
        load_deck(EXAMPLE, ["foundation.b=-1"], load_ground_motion=False)
    assert str(info.value).startswith("--set: foundation.b:")


# ----------------------------------------------------------------------------- bad input

BAD_CASES = [
    # (replace this, with that, location, words in the message)
    ("floor_mass = 2.0e5", "flor_mass = 2.0e5", "building.flor_mass", "did you mean 'floor_mass'"),
    ("floor_mass = 2.0e5", "", "building.floor_mass", "missing"),
    ("floor_mass = 2.0e5", "floor_mass = -2.0e5", "building.floor_mass", "> 0 [kg]"),
    ("floor_mass = 2.0e5", "floor_mass = 0", "building.floor_mass", "> 0 [kg]"),
    ("story_stiffness = 4.0e8", "story_stiffness = -1.0", "building.story_stiffness", "> 0 [N/m]"),
    ("story_stiffness = 4.0e8", "", "building.story_stiffness", "missing"),
    ("story_height = 3.0", "story_height = 0.0", "building.story_height", "> 0 [m]"),
    ("story_height = 3.0", 'story_height = "tall"', "building.story_height", "a number"),
    ("story_stiffness = 4.0e8", "story_stiffness = 4.0e8\ndamping = 1.0", "building.damping", "in [0, 1)"),
    ("story_stiffness = 4.0e8", "story_stiffness = 4.0e8\ndamping = -0.1", "building.damping", "in [0, 1)"),
    ("story_stiffness = 4.0e8", "story_stiffness = 4.0e8\ndamping = [0.05, 0.05]", "building.damping", "4 values"),
    ("b = 5.0", "b = 0.0", "foundation.b", "> 0 [m]"),
    ("b = 5.0", "b = -5.0", "foundation.b", "> 0 [m]"),
    ("b = 5.0", "", "foundation.b", "missing"),
    ("b = 5.0", "b = 5.0\nslenderness = 4", "foundation.slenderness", "only one of"),
    ("k_f = 1.0e9", "k_w = 1.0e9", "foundation.k_w", "belongs to type 'winkler'"),
    ("k_f = 1.0e9", "", "foundation.k_f", "missing"),
    ("c_f = 1.0e7", "c_f = -1.0e7", "foundation.c_f", ">= 0"),
    ("[foundation]", "[fundation]", "fundation", "did you mean 'foundation'"),
    ("stories = 4", "stories = 4.5", "building.stories", "an integer"),
]


@pytest.mark.parametrize("old, new, location, words", BAD_CASES)
def test_bad_input_one_clear_error(tmp_path, old, new, location, words):
    assert old in BASE
    with pytest.raises(InputError) as info:
        load(tmp_path, BASE.replace(old, new, 1))
    error = info.value
    assert error.source == str(tmp_path / "deck.toml")
    assert error.location == location
    assert words in str(error)
    assert "\n" not in str(error)


def test_malformed_toml_names_the_line(tmp_path):
    with pytest.raises(InputError) as info:
        load(tmp_path, BASE.replace("b = 5.0", "b = = 5.0"))
    assert re.search(r"line \d+", info.value.location)
    assert "valid TOML" in str(info.value)


def test_missing_deck_file(tmp_path):
    with pytest.raises(InputError, match="file not found"):
        load_deck(tmp_path / "nope.toml")


def test_stiffness_matrix_must_be_positive_definite(tmp_path):
    text = "[building]\nmasses = [1e5, 1e5]\nstory_heights = [3.0, 3.0]\n" \
           "stiffness_matrix = [[1e8, 2e8], [2e8, 1e8]]\n[foundation]\nb = 5.0\nk_f = 1e9\n"
    with pytest.raises(InputError, match="positive-definite"):
        load(tmp_path, text)


def test_unreadable_record_is_an_input_error(tmp_path):
    bad = tmp_path / "broken.txt"
    bad.write_text("# dt = 0.02\n0.1 0.2\nabc\n")
    text = BASE + '[ground_motion]\nrecord = "broken.txt"\nunits = "g"\n'
    with pytest.raises(InputError) as info:
        load(tmp_path, text, ground_motion=True)
    assert "broken.txt" in info.value.source
    text = BASE + '[ground_motion]\nrecord = "missing.txt"\nunits = "g"\n'
    with pytest.raises(InputError, match="not found"):
        load(tmp_path, text, ground_motion=True)


def test_missing_ground_motion_only_matters_for_analysis(tmp_path):
    load(tmp_path, BASE)  # modes: fine
    with pytest.raises(InputError) as info:
        load(tmp_path, BASE, ground_motion=True)
    assert info.value.location == "ground_motion"


def test_unknown_criterion_and_analysis_option(tmp_path):
    with pytest.raises(InputError, match="did you mean 'drift_ratio'"):
        load(tmp_path, BASE + "[criteria]\ndrift_ration = 0.01\n")
    with pytest.raises(InputError, match="one of srss, cqc"):
        load(tmp_path, BASE + '[analysis]\ncombination = "abs"\n')
    with pytest.raises(InputError, match="at most 4 modes"):
        load(tmp_path, BASE + "[analysis]\nmodes = 5\n")


# ----------------------------------------------------------------------------- schema and docs

def test_exact_options_cover_the_engine_contract():
    from dataclasses import fields

    from upliftcli.engines.options import ExactOptions

    assert set(deck_schema.TABLES["analysis.exact"]) <= {f.name for f in fields(ExactOptions)}


def test_reference_page_documents_every_field_with_its_unit():
    text = (ROOT / "docs" / "deck.md").read_text()
    sections = re.split(r"^## ", text, flags=re.M)
    for table, fields in deck_schema.TABLES.items():
        if not table:
            continue
        section = next(s for s in sections if s.startswith(f"`[{table}]`"))
        for name, field in fields.items():
            row = next((line for line in section.splitlines() if line.startswith(f"| `{name}` |")), None)
            assert row is not None, f"{table}.{name} is not documented"
            assert f"| {field.unit} |" in row, f"{table}.{name}: unit {field.unit} not in {row}"


def test_set_foundation_type_drops_the_other_types_fields():
    deck = load_deck(EXAMPLE, ['foundation.type="winkler"', "foundation.k_w=5e8"], load_ground_motion=False)
    assert isinstance(deck.system.foundation, Winkler)
    assert "frequency_ratio" not in deck.raw["foundation"]


def test_design_spectrum_ground_motion():
    deck = load_deck(ROOT / "inputs" / "ten_story_asce7.toml")
    assert deck.ground_motion is deck.spectrum
    # ASCE 7-22 11.4.5.2: S_a = S_D1 / T between T_S and T_L, at 5 % damping
    assert deck.spectrum.sa(np.array([1.0]), 0.05)[0] == pytest.approx(0.6 * 9.80665, rel=1e-9)
    with pytest.raises(InputError) as info:
        load_deck(ROOT / "inputs" / "ten_story_asce7.toml", ["ground_motion.design_spectrum.sds=-1"])
    assert info.value.source == "--set" and info.value.location == "ground_motion.design_spectrum.sds"
    # --set of a record replaces the design spectrum (alternatives)
    deck = load_deck(ROOT / "inputs" / "ten_story_asce7.toml",
                     ['ground_motion.record="../records/elcentro_1940_ns_chopra.txt"', 'ground_motion.units="g"'])
    assert deck.ground_motion.dt == pytest.approx(0.02)


def test_record_and_design_spectrum_together_is_an_error(tmp_path):
    text = BASE + '[ground_motion]\nscale = 2.0\ndesign_spectrum = { type = "asce7", sds = 1.0, sd1 = 0.6, tl = 8.0 }\n'
    with pytest.raises(InputError, match="no record fields"):
        load(tmp_path, text, ground_motion=True)


def test_build_deck_from_a_mapping_for_sweeps():
    """Sweeps build decks from the parsed mapping and (path, value) pairs, without re-reading the file."""
    import tomllib

    raw = tomllib.loads(EXAMPLE.read_text())
    deck = build_deck(raw, str(EXAMPLE), [("building.period", 2.0)], load_ground_motion=False)
    assert deck.system.modes.periods[0] == pytest.approx(2.0)
    assert raw["building"]["period"] == 0.5  # the caller's mapping is not modified
    assert deck.raw["building"]["period"] == 2.0


# ----------------------------------------------------------------------------- nonsense refused (issue 13)

def _deck_with_record(tmp_path, name="deck.toml"):
    text = EXAMPLE.read_text().replace("../records/elcentro_1940_ns_chopra.txt", str(RECORD))
    path = tmp_path / name
    path.write_text(text)
    return path


def test_a_byte_order_mark_is_accepted(tmp_path):
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + _deck_with_record(tmp_path).read_bytes())
    assert load_deck(path).system.building.n_stories == 10


def test_deeply_nested_toml_is_one_error(tmp_path):
    path = tmp_path / "deep.toml"
    path.write_text("a = " + "[" * 5000 + "]" * 5000 + "\n")
    with pytest.raises(InputError, match=r"deep.toml: valid TOML \(arrays or tables nested too deeply: "
                                         r"at most 32 levels\)$"):
        load_deck(path)
    with pytest.raises(InputError, match=r"^--set: building.period: a number > 0 \[s\] or a text 'number unit' "
                                         r".*, got '\[\[\["):
        load_deck(EXAMPLE, ["building.period=" + "[" * 5000 + "]" * 5000])


@pytest.mark.parametrize(("override", "message"), [
    ("building.period=1e308", "--set: building.period: a number > 0 of magnitude 1e-30 to 1e+30 [s], got 1e+308"),
    ("foundation.b=1e308", "--set: foundation.b: a number > 0 of magnitude"),
    ("building.story_height=1e-300", "--set: building.story_height: a number > 0 of magnitude"),
    ("ground_motion.window=[0, 1e308]", "--set: ground_motion.window: [start, end] of magnitude"),
    ("building.stories=1000000", "--set: building.stories: an integer from 1 to 500, got 1000000"),
    ("building.stories=9223372036854775807", "--set: building.stories: an integer from 1 to 500"),
    ("ground_motion.scale=1e308", "--set: ground_motion.scale: a number > 0 of magnitude"),
    ("ground_motion.scale=1e30", "--set: ground_motion.scale: accelerations of magnitude at most 1e+30 m/s^2"),
    ("analysis.gravity=1e308", "--set: analysis.gravity: a number > 0 of magnitude"),
])
def test_values_the_schema_accepted_before_are_refused_on_one_line(override, message):
    with pytest.raises(InputError) as info:
        load_deck(EXAMPLE, [override])
    assert str(info.value).startswith(message) and "\n" not in str(info.value)


def test_per_story_arrays_are_bounded_too(tmp_path):
    path = tmp_path / "tall.toml"
    path.write_text(BASE.replace("stories = 4\nfloor_mass = 2.0e5", "masses = [" + ", ".join(["2e5"] * 501) + "]"))
    with pytest.raises(InputError, match=r"tall.toml: building.masses: at most 500 stories \(limit of the tool\), "
                                         r"got 501"):
        load_deck(path, load_ground_motion=False)


def test_a_building_without_finite_modes_names_the_field():
    # masses 60 orders of magnitude apart: the eigenproblem loses positive definiteness in double precision
    with pytest.raises(InputError, match=r"ten_story_elcentro.toml: building.period: a value giving finite positive "
                                         r"frequencies and effective heights"):
        load_deck(EXAMPLE, ["building.stories=3", "building.masses=[1e30, 1e-30, 1e30]",
                            "building.story_stiffness=1e-30"], load_ground_motion=False)


def test_record_fields_of_the_deck_are_blamed_on_the_deck_not_the_record(tmp_path):
    path = _deck_with_record(tmp_path)
    for override, location in (("ground_motion.dt=0.01", "ground_motion.dt"),
                               ('ground_motion.units="furlong"', "ground_motion.units"),
                               ("ground_motion.window=[40, 50]", "ground_motion.window")):
        with pytest.raises(InputError) as info:
            load_deck(path, [override])
        assert (info.value.source, info.value.location) == ("--set", location), str(info.value)
    bad = tmp_path / "bad.toml"
    bad.write_text(path.read_text().replace('units = "g"', 'units = "furlong"'))
    with pytest.raises(InputError, match=r"bad.toml: ground_motion.units: acceleration units g, m/s2, cm/s2 or in/s2"):
        load_deck(bad)


def test_a_symlinked_deck_reads_its_record_next_to_its_target(tmp_path):
    link = tmp_path / "elsewhere" / "link.toml"
    link.parent.mkdir()
    link.symlink_to(EXAMPLE)  # the record path ../records/... is relative to inputs/, not to elsewhere/
    deck = load_deck(link)
    assert Path(deck.ground_motion.source).resolve() == RECORD.resolve()


def test_blame_prefers_set_then_the_deck():
    deck = load_deck(EXAMPLE, ["foundation.damping_ratio=0.3"])
    assert deck.blame("foundation.frequency_ratio", "foundation.damping_ratio") == ("--set", "foundation.damping_ratio")
    assert deck.blame("foundation.k_f", "foundation.frequency_ratio") == (str(EXAMPLE), "foundation.frequency_ratio")
    assert deck.blame("foundation.k_f") == (str(EXAMPLE), "foundation.k_f")


def test_a_missing_record_names_the_deck_field_and_the_folder(deck_dir):
    deck = deck_dir / "inputs" / "deck.toml"
    folder = deck.parent.resolve()
    expected = (f"an existing record file, not found: 'nothere.txt' (relative to the deck's folder '{folder}': "
                f"'{folder / 'nothere.txt'}')")
    with pytest.raises(InputError) as info:
        load_deck(deck, ['ground_motion.record="nothere.txt"'])
    assert (info.value.source, info.value.location, info.value.expected) == ("--set", "ground_motion.record", expected)
    deck.write_text(deck.read_text().replace("../records/elcentro_1940_ns_chopra.txt", "nothere.txt"))
    with pytest.raises(InputError) as info:
        load_deck(deck)
    assert (info.value.source, info.value.location, info.value.expected) == (str(deck), "ground_motion.record",
                                                                             expected)
    absolute = deck_dir / "gone.txt"
    with pytest.raises(InputError, match=f"ground_motion.record: an existing record file, not found: '{absolute}'$"):
        load_deck(deck, [f'ground_motion.record="{absolute}"'])


# ----------------------------------------------------------------------------- units, attribution, warnings

US_EXAMPLE = ROOT / "inputs" / "ten_story_elcentro_us.toml"


def test_the_us_deck_builds_the_si_decks_system():
    si, us = load_deck(EXAMPLE), load_deck(US_EXAMPLE)
    np.testing.assert_allclose(us.system.building.masses, si.system.building.masses, rtol=1e-15)
    np.testing.assert_allclose(us.system.building.heights, si.system.building.heights, rtol=1e-15)
    np.testing.assert_allclose(us.system.building.stiffness, si.system.building.stiffness, rtol=1e-14)
    assert us.system.half_width == pytest.approx(si.system.half_width, rel=1e-15)
    assert us.system.foundation.stiffness == pytest.approx(si.system.foundation.stiffness, rel=1e-14)
    assert us.system.foundation.damping == pytest.approx(si.system.foundation.damping, rel=1e-14)
    assert us.resolved["building"]["floor_mass"] == pytest.approx(350e3, rel=1e-15) and "units" not in us.resolved


def test_set_values_are_read_in_the_decks_units():
    us = load_deck(US_EXAMPLE, ["building.story_height=12"], load_ground_motion=False)
    assert us.system.building.heights[0] == pytest.approx(12 * 0.3048, rel=1e-15)
    with_unit = load_deck(US_EXAMPLE, ['building.story_height="3.6 m"'], load_ground_motion=False)
    assert with_unit.system.building.heights[0] == 3.6
    bare_text = load_deck(EXAMPLE, ["building.story_height=12 ft"], load_ground_motion=False)  # not TOML: a text
    assert bare_text.system.building.heights[0] == pytest.approx(3.6576, rel=1e-15)


def test_a_half_space_with_a_negative_rocking_stiffness_names_its_half_length():
    """half_length = 1e30 was reported as 'analysis.exact.n_modes: math domain error'."""
    with pytest.raises(InputError) as info:
        load_deck(ROOT / "inputs" / "frame_halfspace.toml", ["foundation.half_length=1e30"], load_ground_motion=False)
    assert (info.value.source, info.value.location) == ("--set", "foundation.half_length")
    assert info.value.expected.startswith("a foundation giving a finite rocking stiffness K_theta > 0 at the "
                                          "fixed-base w_1") and "2e+30 m long" in info.value.expected
    assert load_deck(ROOT / "inputs" / "frame_halfspace.toml", ["foundation.half_length=1e3"],
                     load_ground_motion=False).system.foundation.half_length == 1e3  # L/B = 143: fine


def test_the_decks_warnings_name_the_field():
    deck = load_deck(EXAMPLE, ["building.floor_mass=300", "criteria.drift_ratio=2"], load_ground_motion=False)
    assert [w.split(":")[1].strip() for w in deck.warnings] == ["building.floor_mass", "criteria.drift_ratio"]
    assert load_deck(EXAMPLE, load_ground_motion=False).warnings == ()


def test_record_units_contradicting_the_header_name_the_deck_field():
    with pytest.raises(InputError) as info:
        load_deck(EXAMPLE, ["ground_motion.units=cm/s2"])
    assert (info.value.source, info.value.location) == ("--set", "ground_motion.units")
    assert "declares, g, got 'cm/s2'" in info.value.expected
    meant = load_deck(EXAMPLE, ["ground_motion.units=cm/s2", "ground_motion.override_header_units=true"])
    assert meant.ground_motion.units == "cm/s2"
    assert meant.ground_motion.pga == pytest.approx(load_deck(EXAMPLE).ground_motion.pga / 980.665)


def test_the_building_and_the_ground_motion_are_checked_together(tmp_path):
    from upliftcli.errors import InputErrors

    deck = tmp_path / "missing.toml"
    deck.write_text('[building]\nstories = 10\nfloor_mass = 350e3\nstory_height = 3.5\n[foundation]\nslenderness = 6\n'
                    '[ground_motion]\nrecord = "nowhere.txt"\n')
    with pytest.raises(InputErrors) as info:
        load_deck(deck)
    assert [e.location for e in info.value.errors] == ["building.story_stiffness", "ground_motion.record"]
    fixed = deck.read_text().replace("story_height = 3.5\n", "story_height = 3.5\nperiod = 1.0\n")
    deck.write_text(fixed)
    with pytest.raises(InputErrors) as info:  # the foundation's missing k_f with the record
        load_deck(deck)
    assert [e.location for e in info.value.errors] == ["foundation.k_f", "ground_motion.record"]
