"""Issue 37, units: a deck's `units` sets the display units (--units overrides it); every label is in
the unit its numbers are in (a US deck's sweep: terminal, JSON, figure axis); --units us writes the
JSON and CSV in US units with unit-tagged columns (SI without it); the report's resolved inputs in
the display units. Hand conversions: 1 ft = 0.3048 m, 1 in = 0.0254 m, 1 kip = 4448.2216152605 N."""

import csv
import io
import json
import re
from pathlib import Path

import pytest
from cli_helpers import invoke

from upliftcli.deck.load import load_deck
from upliftcli.report.inputs import inputs_section
from upliftcli.sweep import figures
from upliftcli.sweep.plan import plan_sweep

ROOT = Path(__file__).resolve().parent.parent
US_DECK = ROOT / "inputs" / "ten_story_elcentro_us.toml"
SI_DECK = ROOT / "inputs" / "ten_story_elcentro.toml"
FOOT, INCH, KIP = 0.3048, 0.0254, 4448.2216152605
BAR = r"\s*[│|]\s*"
VARY = ["--vary", "building.story_height=10,13"]


def read_csv(path: Path) -> list[dict]:
    """A result CSV without its '#' provenance lines."""
    text = "".join(line for line in path.read_text().splitlines(keepends=True) if not line.startswith("#"))
    return list(csv.DictReader(io.StringIO(text)))


def test_a_us_decks_sweep_labels_its_varied_field_in_ft(tmp_path):
    """The reproducer of issue 37: story_height 10, 13 (ft, the deck's units) shown as ft, not as m."""
    result = invoke("sweep", US_DECK, *VARY, "--units", "us", "--support", "uplift", "--engine", "simplified",
                    "--out", tmp_path, "--workers", "1",
                    env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    assert re.search(rf"building\.story_height{BAR}ft{BAR}2{BAR}list{BAR}10{BAR}13", result.stdout)
    assert "building.story_height [ft]" in result.stdout and "[m]" not in result.stdout
    document = json.loads((tmp_path / "ten_story_elcentro_us.story_height.sweep.json").read_text())
    assert document["varied"] == [{"path": "building.story_height", "unit": "ft", "spacing": "list",
                                   "values": [10, 13]}]
    assert document["units"]["building.story_height"] == "ft"
    assert sorted(row["building.story_height"] for row in document["rows"]) == [10, 13]


def test_a_us_decks_sweep_in_si_display_converts_its_values(tmp_path):
    """The same sweep shown in SI (--units si): 10 ft = 3.048 m; k_f 1000 kip/in = 175127 kN/m."""
    result = invoke("sweep", US_DECK, *VARY, "--vary", "foundation.k_f=1000,2000", "--units", "si", "--support",
                    "uplift", "--engine", "simplified", "--out", tmp_path, "--workers", "1", env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    assert re.search(rf"building\.story_height{BAR}m{BAR}2{BAR}list{BAR}3\.048{BAR}3\.9624", result.stdout)
    kn_per_m = 1000 * KIP / INCH / 1000
    assert f"{kn_per_m:.0f}" == "175127"
    assert re.search(rf"foundation\.k_f{BAR}kN/m{BAR}2{BAR}list{BAR}175127{BAR}350254", result.stdout)


def test_a_us_decks_display_units_are_us_without_the_option(tmp_path):
    """No --units: the deck's units = "us" sets kip, ft ... (sweep and analyze alike); --units si overrides."""
    sweep = invoke("sweep", US_DECK, *VARY, "--support", "uplift", "--engine", "simplified", "--out", tmp_path,
                   "--workers", "1", env={"COLUMNS": "200"})
    assert sweep.exit_code == 0 and "building.story_height [ft]" in sweep.stdout
    analyze = invoke("analyze", US_DECK, "--no-check", env={"COLUMNS": "200"})
    assert "shear [kip]" in analyze.stdout and "[kN]" not in analyze.stdout
    si = invoke("analyze", US_DECK, "--no-check", "--units", "si", env={"COLUMNS": "200"})
    assert "shear [kN]" in si.stdout and "[kip]" not in si.stdout
    assert "V_b [kN]" in invoke("analyze", SI_DECK, "--no-check", env={"COLUMNS": "200"}).stdout


def test_the_sweep_figure_axis_is_in_the_unit_of_its_numbers():
    """The figure of a US deck's sweep: the axis in ft with the values 10, 13 (or in m: 3.048, 3.9624)."""
    plan = plan_sweep(US_DECK, vary_texts=["building.story_height=10,13"], engines=["simplified"],
                      supports=["rigid"])
    rows = [{"status": "ok", "engine": "simplified", "support": "rigid", "building.story_height": h,
             "base_shear_coefficient": 0.1, "base_moment_coefficient": 0.1, "max_drift_ratio": 0.01,
             "critical_coefficient": 0.1} for h in (10, 13)]
    us = figures.sweep_figure(plan, rows, units="us")
    assert us.xlabel == "building.story_height [ft]"
    assert list(us.panels[0].series[0].x) == pytest.approx([10, 13])
    si = figures.sweep_figure(plan, rows, units="si")
    assert si.xlabel == "building.story_height [m]"
    assert list(si.panels[0].series[0].x) == pytest.approx([10 * FOOT, 13 * FOOT])
    nominal = [line for line in si.panels[0].lines if line.axis == "x"]  # the deck's own story height
    assert nominal[0].value == pytest.approx(3.5) and nominal[0].label == "deck: building.story_height = 3.5 m"
    assert next(line for line in us.panels[0].lines if line.axis == "x").value == pytest.approx(3.5 / FOOT)


def test_analyze_files_in_us_units_under_the_option(tmp_path):
    """--units us: the CSV columns tagged with US units (shear_kip, elevation_ft, displacement_in), the
    values hand-converted from the SI files; the JSON's units entry and values alike."""
    si_out, us_out = tmp_path / "si", tmp_path / "us"
    common = ["analyze", SI_DECK, "--engine", "simplified", "--support", "uplift", "--no-check"]
    assert invoke(*common, "--out", si_out).exit_code == 0
    assert invoke(*common, "--out", us_out, "--units", "us").exit_code == 0
    si, us = read_csv(si_out / "ten_story_elcentro.csv"), read_csv(us_out / "ten_story_elcentro.csv")
    assert list(us[0]) == ["engine", "support", "story", "elevation_ft", "displacement_in", "drift_in",
                           "drift_ratio", "shear_kip", "moment_kipft", "floor_acceleration_in_s2"]
    for a, b in zip(si, us, strict=True):
        assert float(b["elevation_ft"]) == pytest.approx(float(a["elevation_m"]) / FOOT, rel=1e-12)
        assert float(b["displacement_in"]) == pytest.approx(float(a["displacement_m"]) / INCH, rel=1e-12)
        assert float(b["shear_kip"]) == pytest.approx(float(a["shear_N"]) / KIP, rel=1e-12)
        assert float(b["moment_kipft"]) == pytest.approx(float(a["moment_Nm"]) / (KIP * FOOT), rel=1e-12)
        assert float(b["floor_acceleration_in_s2"]) == pytest.approx(float(a["floor_acceleration_m_s2"]) / INCH,
                                                                     rel=1e-12)
        assert b["drift_ratio"] == a["drift_ratio"]
    elements = read_csv(us_out / "ten_story_elcentro.elements.csv")
    assert list(elements[0])[3:] == ["position_ft", "reaction_kip"]
    one, other = (json.loads((out / "ten_story_elcentro.json").read_text()) for out in (si_out, us_out))
    assert one["units"]["base_shear"] == "N" and other["units"]["base_shear"] == "kip"
    assert other["units"]["effective_height"] == "ft" and other["units"]["intermediates"]["V_c"] == "kip"
    assert other["base_shear"] == pytest.approx(one["base_shear"] / KIP, rel=1e-12)
    assert other["effective_height"] == pytest.approx(one["effective_height"] / FOOT, rel=1e-12)
    assert other["stories"][0]["drift"] == pytest.approx(one["stories"][0]["drift"] / INCH, rel=1e-12)
    assert other["intermediates"]["V_c"] == pytest.approx(one["intermediates"]["V_c"] / KIP, rel=1e-12)
    assert other["base_shear_coefficient"] == one["base_shear_coefficient"]
    assert other["provenance"]["deck"] == one["provenance"]["deck"]  # what the run was: as it is


def test_sweep_tables_in_us_units_under_the_option(tmp_path):
    """--units us: a sweep's output columns renamed and converted (base_shear_kip, max_displacement_in),
    the varied field as given with its unit (N/m of an SI deck), the ratios unchanged; SI without it."""
    common = ["sweep", SI_DECK, "--vary", "foundation.k_f=1e8,1e9", "--engine", "simplified", "--support", "uplift",
              "--workers", "1", "--quiet"]
    assert invoke(*common, "--out", tmp_path / "si").exit_code == 0
    assert invoke(*common, "--out", tmp_path / "us", "--units", "us").exit_code == 0
    name = "ten_story_elcentro.k_f.sweep"
    si, us = read_csv(tmp_path / "si" / f"{name}.csv"), read_csv(tmp_path / "us" / f"{name}.csv")
    assert "base_shear_N" in si[0] and "base_shear_N" not in us[0]
    for a, b in zip(si, us, strict=True):
        assert b["foundation.k_f"] == a["foundation.k_f"]
        assert float(b["base_shear_kip"]) == pytest.approx(float(a["base_shear_N"]) / KIP, rel=1e-12)
        assert float(b["base_moment_kipft"]) == pytest.approx(float(a["base_moment_Nm"]) / (KIP * FOOT), rel=1e-12)
        assert float(b["max_displacement_in"]) == pytest.approx(float(a["max_displacement_m"]) / INCH, rel=1e-12)
        assert b["max_drift_ratio"] == a["max_drift_ratio"]
    document = json.loads((tmp_path / "us" / f"{name}.json").read_text())
    assert document["units"]["base_shear_kip"] == "kip" and document["units"]["foundation.k_f"] == "N/m"
    assert document["rows"][0]["V_c_kip"] == pytest.approx(float(si[0]["V_c_N"]) / KIP, rel=1e-12)


def test_modes_json_in_us_units_under_the_option():
    """`modes --format json --units us`: m_t in kip s^2/in, b and h_n* in ft; SI without the option."""
    si = json.loads(invoke("modes", SI_DECK, "--format", "json").stdout)
    us = json.loads(invoke("modes", SI_DECK, "--format", "json", "--units", "us").stdout)
    assert si["units"]["half_width"] == "m" and us["units"]["half_width"] == "ft"
    assert us["total_mass"] == pytest.approx(si["total_mass"] * INCH / KIP, rel=1e-12)
    assert us["units"]["total_mass"] == "kip s^2/in"
    assert us["modes"][0]["effective_height"] == pytest.approx(si["modes"][0]["effective_height"] / FOOT, rel=1e-12)
    assert us["modes"][0]["period"] == si["modes"][0]["period"]


def test_histories_csv_in_us_units_under_the_option(tmp_path):
    """--histories under --units us: shear in kip, displacements in in, accelerations in in/s^2."""
    common = ["analyze", SI_DECK, "--engine", "exact", "--support", "uplift", "--no-check", "--set",
              "ground_motion.window=[0, 2]"]
    assert invoke(*common, "--histories", tmp_path / "si.csv").exit_code == 0
    assert invoke(*common, "--histories", tmp_path / "us.csv", "--units", "us").exit_code == 0
    si, us = read_csv(tmp_path / "si.csv"), read_csv(tmp_path / "us.csv")
    last_si, last_us = si[-1], us[-1]
    assert last_us["time_s"] == last_si["time_s"] and last_us["theta_rad"] == last_si["theta_rad"]
    assert float(last_us["base_shear_kip"]) == pytest.approx(float(last_si["base_shear_N"]) / KIP, rel=1e-9)
    assert float(last_us["drift_1_in"]) == pytest.approx(float(last_si["drift_1_m"]) / INCH, rel=1e-9, abs=1e-12)
    assert float(last_us["ground_acceleration_in_s2"]) == pytest.approx(
        float(last_si["ground_acceleration_m_s2"]) / INCH, rel=1e-9, abs=1e-12)


def test_record_spectrum_csv_in_us_units_under_the_option():
    """`record spectrum --units us`: sd_in, psv_in_s, psa_in_s2 (psa_g as it is); SI without it."""
    record = ROOT / "records" / "elcentro_1940_ns_chopra.txt"
    si = read_text_csv(invoke("record", "spectrum", record, "--periods", "0.5,1").stdout)
    us = read_text_csv(invoke("record", "spectrum", record, "--periods", "0.5,1", "--units", "us").stdout)
    assert list(us[0]) == ["damping_ratio", "period_s", "sd_in", "psv_in_s", "psa_in_s2", "psa_g", "abs_acc_in_s2"]
    for a, b in zip(si, us, strict=True):
        assert float(b["sd_in"]) == pytest.approx(float(a["sd_m"]) / INCH, rel=1e-12)
        assert float(b["psa_in_s2"]) == pytest.approx(float(a["psa_m_s2"]) / INCH, rel=1e-12)
        assert b["psa_g"] == a["psa_g"] and b["period_s"] == a["period_s"]


def read_text_csv(text: str) -> list[dict]:
    return list(csv.DictReader(io.StringIO("".join(line + "\n" for line in text.splitlines()
                                                   if not line.startswith("#")))))


def test_a_us_decks_files_stay_si_without_the_option(tmp_path):
    """The deck's units set what a person reads; the files a script reads change only with --units."""
    assert invoke("analyze", US_DECK, "--no-check", "--out", tmp_path).exit_code == 0
    rows = read_csv(tmp_path / "ten_story_elcentro_us.csv")
    assert "shear_N" in rows[0] and float(rows[0]["elevation_m"]) == pytest.approx(3.5)
    assert json.loads((tmp_path / "ten_story_elcentro_us.json").read_text())["units"]["base_shear"] == "N"


def test_the_reports_resolved_inputs_are_in_the_display_units():
    """A US deck's report lists its resolved fields in kip s^2/in, ft, kip/in (not 271447 kg or
    10507610115 N/m); in SI display, as the engines read them."""
    deck = load_deck(US_DECK)
    rows = {row[0]: row[1:3] for row in _resolved_table(inputs_section(deck, "", [], "us")).rows}
    assert rows["building.story_height"] == ["11.483", "ft"]
    assert rows["building.floor_mass"] == ["1.9986", "kip s^2/in"]
    assert rows["foundation.k_f"] == ["100992", "kip/in"]
    assert rows["foundation.c_f"] == ["803.67", "kip s/in"]
    si = {row[0]: row[1:3] for row in _resolved_table(inputs_section(deck, "", [], "si")).rows}
    assert si["building.floor_mass"] == ["350000", "kg"]
    assert float(si["foundation.k_f"][0]) == pytest.approx(100991.5531326794 * KIP / INCH, rel=1e-4)
    assert si["foundation.k_f"][1] == "N/m"


def _resolved_table(section):
    """The table of the resolved deck of the inputs section."""
    return next(block for block in section.blocks if getattr(block, "id", "") == "table-resolved")
