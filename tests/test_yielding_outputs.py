"""The outputs of a building that yields (issue 35 item 3): the yielding stories' quantities
(engines/quantities.YIELDING) in the JSON, the CSV, the terminal, the report, the shear-drift
hysteresis figure, the sweep columns and a suite's statistics, each checked against the exact
engine's result object; and the elastic README example's JSON and CSV without a new key."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import numpy as np
import pytest
from rich.console import Console
from typer.testing import CliRunner

import upliftcli
from upliftcli.analysis import run as analysis
from upliftcli.cli import app
from upliftcli.cli.plotting import keep_histories
from upliftcli.cli.render import story_table as terminal_story_table
from upliftcli.cli.render import summary_table as terminal_summary
from upliftcli.deck.load import load_deck
from upliftcli.engines.suite_result import STATISTICS, SuiteRecord, suite_result
from upliftcli.figures import histories as fh
from upliftcli.figures.sets import analysis_figures
from upliftcli.output import result_to_dict, results_document, story_table, to_csv, to_json
from upliftcli.report.results import story_table as report_story_table
from upliftcli.report.results import summary_table as report_summary

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"
#: three stories of base-shear strength 0.15 W (ASCE 7-22 12.8.3 over the height), 5 % hardening, El Centro:
#: every story yields on the rigid base, some on the uplift support
DECK = f"""title = "Three yielding stories"
[building]
stories = 3
floor_mass = 350e3
story_height = 3.5
period = 0.5
damping = 0.05
strength_coefficient = 0.15
hardening_ratio = 0.05
[foundation]
type = "two-element"
slenderness = 10
frequency_ratio = 8
damping_ratio = 0.4
[ground_motion]
record = "{RECORD.as_posix()}"
units = "g"
[analysis]
engine = "exact"
supports = ["rigid", "uplift"]
"""
STORY_KEYS = {"ductility": "ductility", "residual_drift_ratio": "residual_drift_ratio",
              "hysteretic_energy": "hysteretic_energy", "yielded": "story_yielded"}
runner = CliRunner()


@pytest.fixture(scope="module")
def deck_path(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("yielding") / "three.toml"
    path.write_text(DECK)
    return path


@pytest.fixture(scope="module")
def results(deck_path):
    """The exact engine's rigid and uplift results of the deck, with their histories."""
    return analysis.run(keep_histories(load_deck(deck_path, [])))


def test_the_deck_yields_some_stories_and_not_others(results):
    """The premise of the tests below: every story yields on the rigid base; on the uplift support a story yields
    and one does not."""
    rigid, uplift = results
    assert rigid.building_yielded is True and rigid.peaks["yielded_stories"][0] == 3
    assert uplift.building_yielded is True and set(uplift.peaks["story_yielded"]) == {0.0, 1.0}


def test_the_json_carries_each_storys_yielding_and_the_buildings(results):
    """stories[i].ductility, residual_drift_ratio, hysteretic_energy and yielded (a boolean) are the result's
    values; building_yielded, yielded_stories and base_shear_strength beside the soil's `yielded` (absent
    here: no bearing capacity); the units listed; no instant of a yielding quantity (its peak has none)."""
    document = json.loads(to_json(list(results)))
    assert document["units"]["ductility"] == "-" and document["units"]["hysteretic_energy"] == "J"
    assert document["units"]["base_shear_strength"] == "N" and document["units"]["residual_drift_ratio"] == "-"
    for result, written in zip(results, document["results"], strict=True):
        for j, story in enumerate(written["stories"]):
            for key, name in STORY_KEYS.items():
                expected = result.peaks[name][j]
                assert story[key] == (bool(expected) if key == "yielded" else pytest.approx(expected, rel=1e-14))
            assert not {"ductility_time", "story_yielded_time", "story_yielded"} & set(story)
        assert written["building_yielded"] is True and "yielded" not in written
        assert written["yielded_stories"] == int(result.peaks["yielded_stories"][0])
        assert written["base_shear_strength"] == pytest.approx(result.peaks["base_shear_strength"][0], rel=1e-14)


def test_the_csv_story_table_has_the_columns_with_units(results):
    """The story table's columns ductility, residual_drift_ratio, hysteretic_energy_J and yielded (1/0)."""
    header, _ = story_table(list(results))
    assert header[-4:] == ["ductility", "residual_drift_ratio", "hysteretic_energy_J", "yielded"]
    table = list(csv.DictReader(io.StringIO(to_csv(list(results)))))
    uplift = results[1]
    mine = [row for row in table if row["support"] == "uplift"]
    for j, row in enumerate(mine):
        assert float(row["hysteretic_energy_J"]) == pytest.approx(uplift.peaks["hysteretic_energy"][j], rel=1e-14)
        assert float(row["ductility"]) == pytest.approx(uplift.peaks["ductility"][j], rel=1e-14)
        assert row["yielded"] == str(int(uplift.peaks["story_yielded"][j]))


def _text(table) -> str:
    console = Console(width=250, record=True, color_system=None)
    console.print(table)
    return console.export_text()


def test_the_terminal_shows_the_yielding_columns_and_the_buildings_verdict(results):
    """The story table: ductility, residual drift ratio [%], hysteretic energy [kJ], yielded yes/no; the summary:
    building yielded and V_y [kN]."""
    uplift = results[1]
    text = _text(terminal_story_table(uplift))
    assert "ductility" in text and "resid. drift ratio [%]" in text and "hyst. energy [kJ]" in text
    story_lines = [line for line in text.splitlines() if line.startswith("│")]
    assert [line.rstrip(" │").split()[-1] for line in story_lines] == [
        "yes" if flag else "no" for flag in uplift.peaks["story_yielded"][::-1]]
    assert f"{uplift.peaks['ductility'][0]:.5g}" in story_lines[-1]
    summary = _text(terminal_summary(list(results)))
    assert "building yielded" in summary and "V_y [kN]" in summary
    assert f"{uplift.peaks['base_shear_strength'][0] / 1e3:.1f}" in summary


def test_the_report_story_table_and_summary_show_them(results):
    """The report's story table: the four columns (yes/no flags); its summary: building yielded and V_y."""
    uplift = results[1]
    table = report_story_table(uplift, "exact engine, uplift support")
    assert table.headers[-4:] == ["ductility [-]", "residual drift ratio [%]", "hysteretic energy [kJ]",
                                  "story yielded [-]"]
    assert [row[-1] for row in table.rows] == ["yes" if f else "no" for f in uplift.peaks["story_yielded"][::-1]]
    assert "Ductility" in table.note
    summary = report_summary(list(results))
    assert "building yielded" in summary.headers and "V_y [kN]" in summary.headers


def test_the_hysteresis_figure_has_a_panel_per_yielding_story(results, deck_path):
    """A panel per story that yields (any support), its series the story's drift [mm] and shear histories; among
    the analysis figures (--plot, the report) as hysteresis_exact."""
    spec = fh.hysteresis_figure(list(results))
    stories = sorted({j + 1 for r in results for j in np.flatnonzero(r.peaks["story_yielded"])})
    assert [panel.title for panel in spec.panels] == [f"story {j}" for j in stories]
    panel = spec.panels[0]
    shown = [r for r in results if r.peaks["story_yielded"][stories[0] - 1]]
    assert len(panel.series) == len(shown)
    factor = {"kN": 1e-3, "MN": 1e-6}[panel.ylabel[panel.ylabel.rindex("[") + 1:-1]]
    np.testing.assert_allclose(panel.series[0].x, 1e3 * shown[0].histories[f"drift_{stories[0]}"])
    np.testing.assert_allclose(panel.series[0].y, factor * shown[0].histories[f"shear_{stories[0]}"])
    figures = analysis_figures(load_deck(deck_path, []), list(results))
    assert "hysteresis_exact" in figures and "hysteresis_exact" not in analysis_figures(
        load_deck(EXAMPLE, []), analysis.run(keep_histories(load_deck(EXAMPLE, ["analysis.engine=\"exact\"",
                                                                                 "ground_motion.window=[0, 4]"]))))


def test_a_sweep_row_carries_the_yielding_columns(deck_path, tmp_path):
    """The sweep of the yielding deck has the YIELDING columns, filled with the single run's largest values;
    a sweep of the elastic example has none of them."""
    sweep = upliftcli.run_sweep(deck_path, ["building.strength_coefficient=0.15,0.3"], [], engines=["exact"],
                                supports=["rigid"], rows_file=tmp_path / "rows.jsonl")
    columns = ["max_ductility", "max_residual_drift_ratio", "hysteretic_energy_J", "yielded_stories",
               "base_shear_strength_N"]
    assert set(columns) <= set(sweep.columns) and sweep.units["hysteretic_energy_J"] == "J"
    for row in sweep.rows:
        deck = load_deck(deck_path, [f"building.strength_coefficient={row['building.strength_coefficient']}"])
        single = analysis.run_one(deck, "exact", "rigid")
        assert row["max_ductility"] == single.peaks["ductility"].max() > 1.0
        assert row["hysteretic_energy_J"] == single.peaks["hysteretic_energy"].max()
        assert row["yielded_stories"] == int(single.peaks["yielded_stories"][0])
        assert row["base_shear_strength_N"] == single.peaks["base_shear_strength"][0]
    elastic = upliftcli.run_sweep(EXAMPLE, ["building.period=0.4,0.8"], ["building.stories=3"], engines=["exact"],
                                  supports=["rigid"], rows_file=tmp_path / "elastic.jsonl")
    assert not set(columns) & set(elastic.columns)


def test_a_suites_statistics_of_the_yielding_quantities(deck_path):
    """A suite of the record at two amplitudes: each statistic's per-story ductility, residual drift ratio and
    hysteretic energy are the statistic of the records' values; the JSON's statistics carry them."""
    records = [analysis.run_one(load_deck(deck_path, [f"ground_motion.scale={s}"]), "exact", "rigid")
               for s in (0.8, 1.3)]
    suite = suite_result(records, [SuiteRecord("a", "a", 0.8), SuiteRecord("b", "b", 1.3)], "mean")
    for name, (_, function) in STATISTICS.items():
        for quantity in ("ductility", "residual_drift_ratio", "hysteretic_energy"):
            expected = function(np.stack([r.peaks[quantity] for r in records]))
            np.testing.assert_allclose(suite.statistics[name].peaks[quantity], expected, rtol=1e-14)
    written = result_to_dict(suite)["suite"]["statistics"]["p84"]
    assert [s["ductility"] for s in written["stories"]] == pytest.approx(
        np.percentile(np.stack([r.peaks["ductility"] for r in records]), 84.0, axis=0).tolist(), rel=1e-14)
    assert written["building_yielded"] is True


#: the README example's story columns and JSON keys (before the yielding outputs)
ELASTIC_CSV_HEADER = ("engine,support,story,elevation_m,displacement_m,drift_m,drift_ratio,shear_N,moment_Nm,"
                      "floor_acceleration_m_s2")
ELASTIC_STORY_KEYS = {"story", "elevation", "displacement", "drift", "drift_ratio", "shear", "moment",
                      "floor_acceleration"}
ELASTIC_TOP_KEYS = {"source", "title", "units", "engine", "support", "base_shear", "base_shear_coefficient",
                    "base_moment", "base_moment_coefficient", "critical_base_shear", "critical_base_moment",
                    "critical_coefficient", "weight", "effective_height", "uplift", "periods", "stories",
                    "elements", "intermediates", "warnings", "details", "accuracy"}


def test_the_elastic_readme_example_has_no_new_key(tmp_path):
    """`uplift analyze inputs/ten_story_elcentro.toml --out`: the CSV header and the JSON's keys as before (no
    yielding column, key or unit)."""
    outcome = runner.invoke(app, ["analyze", str(EXAMPLE), "--out", str(tmp_path)])
    assert outcome.exit_code == 0, outcome.output
    lines = [line for line in (tmp_path / "ten_story_elcentro.csv").read_text().splitlines() if line[0] != "#"]
    assert lines[0] == ELASTIC_CSV_HEADER
    document = json.loads((tmp_path / "ten_story_elcentro.json").read_text())
    for result in document["results"]:
        assert set(result) | {"source", "title", "units"} <= ELASTIC_TOP_KEYS
        assert all(set(story) == ELASTIC_STORY_KEYS for story in result["stories"])
    yielding = {"ductility", "residual_drift_ratio", "hysteretic_energy", "base_shear_strength", "building_yielded",
                "yielded_stories", "yielded"}
    assert not yielding & set(document["units"])
    assert not yielding & set(results_document(analysis.run(load_deck(EXAMPLE, [])))["units"])


def test_plot_and_the_report_draw_the_hysteresis(deck_path, tmp_path):
    """`analyze --plot` writes <stem>.hysteresis_exact.png; the report captions the figure."""
    from upliftcli.report.build import caption

    outcome = runner.invoke(app, ["analyze", str(deck_path), "--support", "uplift", "--plot", str(tmp_path)])
    assert outcome.exit_code in (0, 3), outcome.output
    assert (tmp_path / "three.hysteresis_exact.png").stat().st_size > 0
    assert caption("hysteresis_exact").startswith("Story shear against story drift of each story that yields")
