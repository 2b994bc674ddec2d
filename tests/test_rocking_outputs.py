"""The rocking quantities (engines/quantities.ROCKING, docs/theory.md 14.7) in every output: JSON,
CSV, the terminal tables (si and us), the report, the moment-rotation figure with a capacity,
and [criteria] with its exit code and the limits' sources."""

from __future__ import annotations

import csv
import io
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from figure_cases import small_run
from test_report import Parsed, make_report
from typer.testing import CliRunner

from upliftcli.cli import app
from upliftcli.cli.render_rocking import rocking_table
from upliftcli.display import FOOT, INCH, KIP
from upliftcli.engines.exact.mat_motion import plastic_quantities
from upliftcli.figures import histories as fh
from upliftcli.output import elements_table, result_to_dict, rocking_csv, write_results
from upliftcli.output import rocking_table as rocking_rows

ROOT = Path(__file__).resolve().parents[1]
DECK = ROOT / "inputs" / "ten_story_elcentro.toml"
runner = CliRunner()
EXACT_UPLIFT = ["--engine", "exact", "--support", "uplift", "--set", "ground_motion.window=[0.0, 8.0]", "--no-check"]


def exact_uplift():
    _, results = small_run()
    return next(r for r in results if r.engine == "exact" and r.support == "uplift")


def yielding(result):
    """The result as the exact engine gives it on yielding soil: details["yielding"] (a made-up
    plastic state: elements 1 yielded by 3 mm, the others not, W_p = 12.5 kJ) turned into the
    ROCKING quantities as digest.py turns it, and the elastic tipping moment M_tip."""
    n = result.element_positions.size
    state = {"plastic_settlement": [-0.003] + [0.0] * (n - 1), "yielded": [True] + [False] * (n - 1),
             "plastic_work": 12.5e3}
    peaks = {**result.peaks, **plastic_quantities(state)}
    return replace(result, peaks=peaks, details={**result.details, "yielding": state},
                   intermediates={**result.intermediates, "M_tip": 1.4 * result.critical_base_moment})


def test_json_and_csv_carry_the_rocking_quantities_with_their_units():
    result = exact_uplift()
    document = result_to_dict(result)
    rocking = document["rocking"]
    assert rocking["rotation"] == result.peaks["rotation"][0] > 0.0
    assert rocking["rotation_time"] == result.times["rotation"][0]
    assert rocking["settlement"] == dict(zip(("left_edge", "centre", "right_edge"),
                                             result.peaks["settlement"].tolist(), strict=True))
    assert list(rocking["residual_settlement"]) == ["left_edge", "centre", "right_edge"]
    header, rows = rocking_rows([result])
    assert header[:5] == ["engine", "support", "rotation_rad", "rotation_time_s", "residual_rotation_rad"]
    assert "settlement_right_edge_m" in header and "residual_settlement_centre_m" in header
    row = dict(zip(header, rows[0], strict=True))
    assert row["settlement_left_edge_m"] == result.peaks["settlement"][0]
    assert row["residual_rotation_rad"] == result.peaks["residual_rotation"][0]
    parsed = list(csv.DictReader(io.StringIO(rocking_csv([result]))))
    assert float(parsed[0]["rotation_rad"]) == pytest.approx(result.peaks["rotation"][0], rel=1e-14)
    # the other analyses carry none: no rocking object, no row
    others = [r for r in small_run()[1] if r is not result]
    assert all("rocking" not in result_to_dict(r) for r in others)
    assert rocking_rows(others) == ([], [])
    assert len(rocking_rows([*others, result])[1]) == 1


def test_yielding_adds_the_plastic_settlement_yielded_elements_and_plastic_work(tmp_path):
    result = yielding(exact_uplift())
    header, rows = elements_table([result])
    assert "plastic_settlement_m" in header
    column = header.index("plastic_settlement_m")
    assert [row[column] for row in rows] == [0.003] + [0.0] * (len(rows) - 1)
    header, rows = rocking_rows([result])
    row = dict(zip(header, rows[0], strict=True))
    assert (row["yielded_elements"], row["plastic_work_J"]) == (1.0, 12.5e3)
    document = result_to_dict(result)
    assert document["rocking"]["plastic_work"] == 12.5e3 and document["rocking"]["yielded_elements"] == 1
    assert document["elements"][0]["plastic_settlement"] == 0.003
    paths = write_results([result], tmp_path, "run")
    assert [p.name for p in paths] == ["run.json", "run.csv", "run.elements.csv", "run.rocking.csv"]
    assert json.loads(paths[0].read_text())["units"]["plastic_work"] == "J"


def test_a_count_of_yielded_elements_is_written_as_an_integer():
    """Fuzzing found yielded_elements written 2.0 in the rocking CSV, the JSON and the sweep table
    (quantities.Quantity.count): a count is written 1, not 1.0; a suite's mean of counts (a
    statistic, not a count) keeps its fraction."""
    from upliftcli.engines.quantities import rocking_value
    from upliftcli.output import to_json
    from upliftcli.sweep.table import to_csv as sweep_csv

    result = yielding(exact_uplift())
    assert next(csv.DictReader(io.StringIO(rocking_csv([result]))))["yielded_elements"] == "1"
    assert '"yielded_elements": 1,' in to_json([result])
    row = {"yielded_elements": rocking_value(result, "yielded_elements")}  # as sweep/worker.py fills it
    assert sweep_csv([row], ["yielded_elements"]) == "yielded_elements\n1\n"
    mean = replace(result, peaks={**result.peaks, "yielded_elements": np.array([1.5])}, details={})
    assert next(csv.DictReader(io.StringIO(rocking_csv([mean]))))["yielded_elements"] == "1.5"


def test_terminal_table_in_si_and_us_units():
    result = yielding(exact_uplift())
    for units, length, digit, energy in (("si", 1e3, 5e-3, 1e-3), ("us", 1 / INCH, 5e-4, 1 / (KIP * FOOT))):
        table = rocking_table(result, units)
        cells = {(table.columns[0]._cells[k], table.columns[1]._cells[k]): (table.columns[2]._cells[k],
                                                                              table.columns[3]._cells[k])
                 for k in range(table.row_count)}
        value, unit = cells[("settlement", "centre")]
        assert unit == ("mm" if units == "si" else "in")
        assert float(value) == pytest.approx(result.peaks["settlement"][1] * length, abs=digit)
        value, unit = cells[("rotation", "mat")]
        assert (float(value), unit) == (pytest.approx(1e3 * result.peaks["rotation"][0], abs=1e-3), "mrad")
        value, unit = cells[("plastic work", "mat")]
        assert float(value) == pytest.approx(12.5e3 * energy, rel=1e-3)
    assert rocking_table(next(r for r in small_run()[1] if r.support == "bonded")) is None


def test_analyze_prints_the_table_and_writes_the_rocking_csv(tmp_path):
    shown = runner.invoke(app, ["analyze", str(DECK), *EXACT_UPLIFT, "--units", "us"])
    assert shown.exit_code == 0, shown.output
    assert "Rocking of the mat (exact, uplift)" in shown.stdout and "right edge (x = +b)" in shown.stdout
    written = runner.invoke(app, ["analyze", str(DECK), *EXACT_UPLIFT, "--format", "json", "--out", str(tmp_path)])
    assert written.exit_code == 0, written.output
    document = json.loads(written.stdout)
    lines = (tmp_path / "ten_story_elcentro.rocking.csv").read_text().splitlines()
    assert lines[0].startswith("# uplift ")  # provenance, as every CSV file
    row = next(csv.DictReader(io.StringIO("\n".join(lines[2:]))))
    assert float(row["settlement_left_edge_m"]) == pytest.approx(document["rocking"]["settlement"]["left_edge"],
                                                                 rel=1e-14)


def test_a_rotation_limit_exits_with_code_3_naming_its_source():
    document = json.loads(runner.invoke(app, ["analyze", str(DECK), *EXACT_UPLIFT, "--format", "json"]).stdout)
    rotation, settlement = document["rocking"]["rotation"], max(document["rocking"]["settlement"].values())
    source = 'criteria.sources.rotation="ASCE 41-17 Table 8-4, life safety, A_c/A = 0.5"'
    failed = runner.invoke(app, ["analyze", str(DECK), *EXACT_UPLIFT, "--set", f"criteria.rotation={rotation * 0.99}",
                                 "--set", source, "--set", f"criteria.settlement={settlement * 1.01}"])
    assert failed.exit_code == 3, failed.output
    assert (f"exact/uplift: rotation = {rotation:.4g} exceeds the limit {rotation * 0.99:.4g} [rad] (source: ASCE "
            "41-17 Table 8-4, life safety, A_c/A = 0.5)") in failed.stderr
    assert "settlement" not in failed.stderr
    passed = runner.invoke(app, ["analyze", str(DECK), *EXACT_UPLIFT, "--set", f"criteria.rotation={rotation * 1.01}",
                                 "--set", f"criteria.settlement={settlement * 1.01}"])
    assert passed.exit_code == 0, passed.output
    failed = runner.invoke(app, ["analyze", str(DECK), *EXACT_UPLIFT, "--set",
                                 f"criteria.settlement={settlement * 0.99}"])
    assert failed.exit_code == 3 and "settlement" in failed.stderr


def test_the_report_has_the_rocking_table_and_the_sources():
    deck, _ = small_run()
    result = exact_uplift()
    limited = replace(deck, criteria=type(deck.criteria)({"rotation": result.peaks["rotation"][0] / 2},
                                                         {"rotation": "ASCE 41-17 Table 8-4"}))
    report, _, text, _, _ = make_report(deck=limited)
    tables = Parsed(text).tables
    rocking = tables["table-exact-uplift-rocking"]
    assert rocking[0] == ["quantity", "where", "value", "unit", "time [s]"]
    rows = {(row[0], row[1]): row for row in rocking[1:]}
    assert float(rows[("rotation", "mat")][2]) == pytest.approx(1e3 * result.peaks["rotation"][0], abs=1e-3)
    criteria = tables["table-criteria"]
    assert criteria[0][-1] == "source" and criteria[1][-2:] == ["VIOLATED", "ASCE 41-17 Table 8-4"]
    assert report.exit_code == 3


def test_the_moment_rotation_loop_shows_the_capacity():
    result = yielding(exact_uplift())
    panel = fh.moment_rotation_figure([result]).panels[0]
    factor = {"kN m": 1e-3, "MN m": 1e-6}[panel.ylabel[panel.ylabel.rindex("[") + 1:-1]]
    values = [line.value for line in panel.lines]
    m_c, tip = result.critical_base_moment, result.intermediates["M_tip"]
    assert values == pytest.approx([factor * m_c, -factor * m_c, factor * tip, -factor * tip])
    assert "moment capacity on yielding soil" in panel.lines[0].label and "M_tip = m_t g b" in panel.lines[2].label
    elastic = fh.moment_rotation_figure([exact_uplift()]).panels[0].lines
    assert len(elastic) == 2 and "M_c = m_t g b" in elastic[0].label
    assert np.isfinite(values).all()


def test_a_yielding_run_draws_its_capacity_and_tipping_moment():
    """The exact engine on yielding soil (the small run with FS_v = 1.5 on two elements): the
    moment-rotation loop's lines are +-M_c = W b (FS_v - 1) (docs/theory.md 14.4) and
    +-M_tip = W b, and the loop's base moment passes M_c (the capacity bounds the springs, not
    the dashpots, docs/theory.md 14.1)."""
    from figure_cases import EXAMPLE_DECK, SMALL

    from upliftcli.analysis import run as analysis
    from upliftcli.cli.plotting import keep_histories
    from upliftcli.deck.load import load_deck

    deck = keep_histories(load_deck(EXAMPLE_DECK, [*SMALL, "foundation.safety_factor=1.5",
                                                   'analysis.engine="exact"', 'analysis.supports=["uplift"]']))
    (result,) = analysis.run(deck)
    assert result.peaks["yielded_elements"][0] == 2
    weight_b = deck.system.weight * deck.system.half_width
    assert result.critical_base_moment == pytest.approx(0.5 * weight_b, rel=1e-12)
    assert result.intermediates["M_tip"] == pytest.approx(weight_b, rel=1e-12)
    panel = fh.moment_rotation_figure([result]).panels[0]
    factor = {"kN m": 1e-3, "MN m": 1e-6}[panel.ylabel[panel.ylabel.rindex("[") + 1:-1]]
    assert [line.value for line in panel.lines] == pytest.approx(
        [factor * 0.5 * weight_b, -factor * 0.5 * weight_b, factor * weight_b, -factor * weight_b])
    assert np.abs(panel.series[0].y).max() > factor * 0.5 * weight_b


def test_a_sweep_of_the_exact_engine_carries_the_rocking_columns(tmp_path):
    """sweep/table.ROCKING_COLUMNS: a sweep that runs the exact engine on the uplift support has
    the rocking columns (the largest settlement downward, as [criteria] judges it), filled on its
    exact uplift rows with the single analysis's values; a sweep without that analysis has none."""
    import upliftcli

    overrides = ["ground_motion.window=[0.0, 6.0]", "building.stories=4", "foundation.safety_factor=1.5"]
    sweep = upliftcli.run_sweep(DECK, ["building.period=0.4,0.8"], overrides, engines=["exact"],
                                supports=["bonded", "uplift"], rows_file=tmp_path / "rows.jsonl")
    assert {"rotation_rad", "max_settlement_m", "plastic_work_J", "yielded_elements"} <= set(sweep.columns)
    assert sweep.units["max_residual_settlement_m"] == "m" and sweep.units["plastic_work_J"] == "J"
    for row in sweep.rows:
        if row["support"] == "bonded":
            assert "rotation_rad" not in row
            continue
        deck = upliftcli.load_deck(DECK, [*overrides, f"building.period={row['building.period']}"])
        (single,) = upliftcli.run(deck, engine="exact", supports="uplift")
        assert row["rotation_rad"] == single.peaks["rotation"][0]
        assert row["max_settlement_m"] == max(single.peaks["settlement"].max(), 0.0)
        assert row["yielded_elements"] == single.peaks["yielded_elements"][0] == 2
        assert row["plastic_work_J"] == single.peaks["plastic_work"][0] > 0.0
    simplified = upliftcli.run_sweep(DECK, ["building.period=0.4,0.8"], overrides, supports=["uplift"],
                                     rows_file=tmp_path / "simplified.jsonl")
    assert "rotation_rad" not in simplified.columns


def test_a_run_that_yields_without_lifting_says_so_beside_uplift():
    """FS_v = 1.5 on the two-element example for 8 s: the toes yield (both elements settle for
    good: the residual settlement of each edge is its plastic settlement) and the mat never
    lifts (uplift = no, its meaning unchanged). The summary and the JSON say yielded = yes beside
    it; the simplified engine, which does not tell, shows '-'; an elastic deck has no such column."""
    capacity = ["--support", "uplift", "--set", "foundation.safety_factor=1.5", "--set",
                "ground_motion.window=[0.0, 8.0]", "--no-check"]
    document = json.loads(runner.invoke(app, ["analyze", str(DECK), "--engine", "exact", *capacity,
                                              "--format", "json"]).stdout)
    assert document["uplift"] is False and document["yielded"] is True
    assert document["intermediates"]["uplift_time"] == 0.0 and document["intermediates"]["episodes"] == 0
    assert min(element["plastic_settlement"] for element in document["elements"]) > 1e-3
    assert document["rocking"]["residual_settlement"]["left_edge"] > 1e-3
    shown = runner.invoke(app, ["analyze", str(DECK), "--engine", "exact,simplified", *capacity])
    assert shown.exit_code == 0, shown.output
    summary = shown.stdout[shown.stdout.index("Summary"):]
    assert "uplift" in summary and "yielded" in summary and "V_c passed" in summary
    rows = {line.split("│")[1].strip(): [cell.strip() for cell in line.split("│")[-3:-1]]
            for line in summary.splitlines() if line.startswith("│")}
    assert rows == {"exact": ["no", "yes"], "simplified": ["yes", "-"]}
    elastic = runner.invoke(app, ["analyze", str(DECK), *EXACT_UPLIFT, "--format", "json"])
    assert "yielded" not in json.loads(elastic.stdout)
    plain = runner.invoke(app, ["analyze", str(DECK), *EXACT_UPLIFT])
    assert "yielded" not in plain.stdout[plain.stdout.index("Summary"):]


def test_the_report_summary_has_the_yielded_column_where_a_result_tells():
    from upliftcli.display import SUMMARY
    from upliftcli.report.results import summary_table

    result = exact_uplift()
    assert result.yielded is None and "yielded" not in summary_table([result]).headers
    table = summary_table([yielding(result)])
    assert table.headers[-2:] == ["uplift", "yielded"] and table.rows[0][-1] == "yes"
    assert SUMMARY["yielded"].cell(replace(result, details={})) == "-"
