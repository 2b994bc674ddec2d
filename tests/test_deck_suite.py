"""Record suites in the deck: fields, defaults, the period range rule, and every message naming its field."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from upliftcli.analysis import run as analysis
from upliftcli.deck.load import load_deck
from upliftcli.deck.suite import default_statistics, plan_from_deck, structure_period_range
from upliftcli.engines.registry import ENGINES
from upliftcli.engines.simplified import effective_properties
from upliftcli.errors import InputError
from upliftcli.motion.code_rules import RULES
from upliftcli.motion.design_spectra import ASCE7Spectrum, EC8Spectrum, TabulatedSpectrum
from upliftcli.motion.suites import Suite

ROOT = Path(__file__).resolve().parents[1]
ASCE_SUITE = ROOT / "inputs" / "ten_story_asce7_suite.toml"
EC8_SUITE = ROOT / "inputs" / "ten_story_ec8_suite.toml"


@pytest.fixture(scope="module")
def asce_deck():
    return load_deck(ASCE_SUITE)


def test_example_deck_holds_a_suite(asce_deck):
    suite = asce_deck.ground_motion
    assert isinstance(suite, Suite) and suite.count == 11 and suite.scaling == "none"
    assert asce_deck.spectrum is suite.target and suite.rule.name == "asce7-22"
    assert suite.factors == (1.0,) * 11 and suite.made == ("artificial",) * 11 and suite.matched
    assert suite.warnings == ("ASCE 7-22 16.2.2 asks for recorded ground motions, simulated ones only to supplement "
                              "them where not enough appropriate recorded motions are available: 11 of 11 records are "
                              "artificial (uplift record select chooses recorded motions)",)
    assert suite.mean_ratio().min() >= 1.1  # generated and matched to 110 % (records/.../manifest.json)
    # of the MCE_R spectrum: 1.5 x the deck's design-level ordinates (ASCE 7-22 16.2.1)
    assert suite.target.name.startswith("MCE_R = 1.5 x ASCE 7-22 multi-period")
    np.testing.assert_allclose(suite.target.sa(suite.periods, 0.05), 1.5 * suite.target.spectrum.sa(suite.periods,
                                                                                                    0.05))
    assert "T_90" in suite.period_note


def test_default_period_range_follows_asce7_22_on_the_structure(asce_deck):
    system = asce_deck.system
    t1 = float(system.modes.periods[0])
    t1bar = effective_properties(system)["T1bar"]
    cumulative = np.cumsum(system.modes.effective_mass) / system.building.masses.sum()
    t90 = float(system.modes.periods[np.argmax(cumulative >= 0.9)])
    assert t1 == pytest.approx(1.0) and t1bar > t1
    assert asce_deck.ground_motion.period_range == pytest.approx((min(0.2 * t1, t90), 2 * t1bar))
    (low, high), _ = structure_period_range(RULES["ec8"], system)
    assert (low, high) == pytest.approx((0.2 * t1, 2 * t1bar))


def test_ec8_deck_scales_each_record(tmp_path):
    deck = load_deck(EC8_SUITE)
    suite = deck.ground_motion
    assert suite.count == 12 and suite.rule.name == "ec8" and suite.statistic == "mean"
    assert suite.mean_ratio().min() == pytest.approx(0.9 * 1.005, rel=1e-9)  # 0.5 % margin at the check periods
    assert suite.made == ("recorded",) + ("artificial",) * 11  # from the manifest beside the files
    assert len(set(suite.factors)) == 12
    one = load_deck(EC8_SUITE, ["ground_motion.suite_factor=true"]).ground_motion
    assert len(set(one.factors)) == 1 and one.mean_ratio().min() == pytest.approx(0.9 * 1.005, rel=1e-9)


def test_overrides_of_the_suite_fields(asce_deck):
    deck = load_deck(ASCE_SUITE, ["ground_motion.period_range=[0.25, 2.0]", "ground_motion.scaling=\"amplitude\""])
    assert deck.ground_motion.period_range == (0.25, 2.0) and deck.ground_motion.scaling == "amplitude"
    # generated (matched) records keep the 110 % of ASCE 7-22 16.2.3.3 when amplitude-scaled
    assert deck.ground_motion.mean_ratio().min() == pytest.approx(1.1 * 1.005, rel=1e-9)
    with pytest.raises(InputError) as info:
        load_deck(ASCE_SUITE, ["ground_motion.period_range=[0.2, 12.0]"])
    assert (info.value.source, info.value.location) == ("--set", "ground_motion.period_range")
    assert "within the target's 0-10 s" in info.value.expected
    with pytest.raises(InputError, match=r"--set: ground_motion\.scaling: one of none, amplitude, match"):
        load_deck(ASCE_SUITE, ["ground_motion.scaling=\"spectral\""])
    with pytest.raises(InputError, match=r"--set: ground_motion\.statistics: one of asce7-22, ec8, mean"):
        load_deck(ASCE_SUITE, ["ground_motion.statistics=\"nehrp\""])
    with pytest.raises(InputError, match=r"--set: ground_motion\.suite: a folder \(string\) or a non-empty array"):
        load_deck(ASCE_SUITE, ["ground_motion.suite=3"])
    # a record replaces the suite and its target (alternatives)
    deck = load_deck(ASCE_SUITE, ['ground_motion.record="../records/elcentro_1940_ns_chopra.txt"'])
    assert deck.ground_motion.dt == pytest.approx(0.02) and "suite" not in deck.raw["ground_motion"]


def write(tmp_path, ground_motion: str) -> Path:
    text = ASCE_SUITE.read_text()
    head = text[: text.index("[ground_motion]")]
    path = tmp_path / "deck.toml"
    path.write_text(head + "[ground_motion]\n" + ground_motion)
    return path


def test_suite_field_errors_name_the_field(tmp_path):
    elcentro = str(ROOT / "records" / "elcentro_1940_ns_chopra.txt")
    with pytest.raises(InputError, match=r"deck\.toml: ground_motion\.design_spectrum: a design spectrum, the "
                                         r"target of ground_motion\.suite"):
        load_deck(write(tmp_path, f'suite = ["{elcentro}"]\n'))
    spectrum = 'design_spectrum = { type = "asce7", sds = 1.0, sd1 = 0.6, tl = 8.0 }\n'
    with pytest.raises(InputError, match=r"ground_motion\.scaling: a ground_motion\.suite to scale"):
        load_deck(write(tmp_path, spectrum + 'scaling = "amplitude"\n'))
    with pytest.raises(InputError, match=r"ground_motion\.design_spectrum: .* \(or no suite fields with a record\)"):
        load_deck(write(tmp_path, f'record = "{elcentro}"\nstatistics = "ec8"\n'))
    with pytest.raises(InputError, match=r"ground_motion\.period_range: \[lower, upper\] with 0 < lower"):
        load_deck(write(tmp_path, spectrum + f'suite = ["{elcentro}"]\nperiod_range = [0.0, 2.0]\n'))
    with pytest.raises(InputError, match=r"elcentro_1940_ns_chopra\.txt: duration: a record of at least 4 x"):
        load_deck(write(tmp_path, spectrum + f'suite = ["{elcentro}"]\nperiod_range = [0.2, 9.0]\n'))
    deck = load_deck(write(tmp_path, spectrum + f'suite = ["{elcentro}"]\n'))
    assert any(w.startswith("ASCE 7-22 11.4.5 permits the two-period") for w in deck.ground_motion.warnings)
    assert any("at least 11 records; the suite has 1" in w for w in deck.ground_motion.warnings)


def test_statistics_default_and_table_damping_correction(tmp_path):
    assert default_statistics(ASCE7Spectrum(1.0, 0.6, 8.0)) == "asce7-22"
    assert default_statistics(EC8Spectrum(0.3, "B")) == "ec8"
    assert default_statistics(TabulatedSpectrum([0, 1], [1, 1], 0.05)) == "mean"
    table = 'design_spectrum = { type = "table", periods = [0.0, 4.0], sa = [1.0, 1.0], damping = 0.05 }\n'
    assert load_deck(write(tmp_path, table)).spectrum.damping_correction == "ec8"
    deck = load_deck(write(tmp_path, table + 'statistics = "asce7-22"\n'))
    assert deck.spectrum.damping_correction == "asce"
    assert plan_from_deck(load_deck(write(tmp_path, table), load_ground_motion=False)).rule.name == "mean"


def test_history_engines_take_the_suite_the_simplified_engine_its_target(asce_deck):
    assert analysis.ground_motion_for(asce_deck, ENGINES["exact"]) is asce_deck.ground_motion
    assert analysis.ground_motion_for(asce_deck, ENGINES["simplified"]) is asce_deck.spectrum
    result = analysis.run_one(asce_deck, "simplified", "uplift")
    inter, system = result.intermediates, asce_deck.system
    # mode 1 reads the deck's target spectrum at T1bar, xi1bar: V_1 = m_1* S_a(T1bar, xi1bar) [26]
    sa = float(asce_deck.spectrum.sa([inter["T1bar"]], inter["xi1bar"])[0])
    assert inter["V1_bonded"] == pytest.approx(system.modes.effective_mass[0] * sa, rel=1e-12)


@pytest.mark.parametrize(("entry", "where"), [('"nothere.txt"', "ground_motion.suite[1]"),
                                             ('{ file = "nothere.txt", units = "g" }', "ground_motion.suite[1].file")])
def test_a_missing_suite_record_names_its_entry_and_the_folder(entry, where):
    first = '"../records/ten_story_asce7_suite/artificial_2024_01.txt"'
    with pytest.raises(InputError) as info:
        load_deck(ASCE_SUITE, [f"ground_motion.suite=[{first}, {entry}]"])
    folder = ASCE_SUITE.parent.resolve()
    assert info.value.source == "--set" and info.value.location == where
    assert info.value.expected == (f"an existing record file, not found: 'nothere.txt' (relative to the deck's "
                                   f"folder '{folder}': '{folder / 'nothere.txt'}')")


def test_a_deck_that_is_a_link_finds_its_suite_next_to_its_target(tmp_path):
    """A linked deck is read where it points: its suite folder (and record, and table) are
    resolved next to the target, as for a copy of the deck."""
    link = tmp_path / "linked.toml"
    link.symlink_to(ROOT / "inputs" / "ten_story_asce7_suite.toml")
    deck = load_deck(link)
    assert [r.name for r in deck.ground_motion.records] == [r.name for r in load_deck(
        ROOT / "inputs" / "ten_story_asce7_suite.toml").ground_motion.records]


def test_a_suite_entrys_option_that_does_not_suit_its_file_names_the_entry():
    record = "../records/ten_story_asce7_suite/artificial_2024_01.txt"
    deck = ROOT / "inputs" / "ten_story_ec8_suite.toml"
    with pytest.raises(InputError) as info:
        load_deck(deck, [f'ground_motion.suite=[{{file="{record}", units="gal"}}]'])
    assert (info.value.source, info.value.location) == ("--set", "ground_motion.suite[0].units")
    assert "declares, g, got 'gal'" in info.value.expected
    meant = load_deck(deck, [f'ground_motion.suite=[{{file="{record}", units="gal", override_header_units=true}}]'])
    assert meant.ground_motion.records[0].units == "cm/s2"
