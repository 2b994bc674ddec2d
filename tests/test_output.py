"""Result writers (output.py): JSON, the story and foundation CSV tables, TOML, atomic writes."""

import csv
import io
import json
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from upliftcli import output as results_module
from upliftcli.deck.load import load_deck
from upliftcli.engines.result import AnalysisResult
from upliftcli.output import elements_csv, results_document, to_csv, to_json, write_results
from upliftcli.provenance.record import of_deck, read_csv_provenance
from upliftcli.provenance.values import to_text_numbers

EXAMPLE_DECK = Path(__file__).resolve().parents[1] / "inputs" / "ten_story_elcentro.toml"


def make_result(support="uplift", scale=1.0):
    elevations = np.array([3.0, 6.0, 9.0])
    displacement = scale * np.array([0.01, 0.018, 0.024])
    drift = np.diff(np.concatenate(([0.0], displacement)))
    peaks = {"displacement": displacement, "drift": drift, "drift_ratio": drift / 3.0,
             "shear": scale * np.array([3e6, 2.2e6, 1.2e6]), "moment": scale * np.array([2.0e7, 1.0e7, 3.6e6]),
             "floor_acceleration": scale * np.array([2.0, 3.0, 4.5]),
             "reaction": scale * np.array([4.0e6, 5.0e6]) if support != "rigid" else np.zeros(0)}
    positions = np.array([-2.0, 2.0]) if support != "rigid" else np.zeros(0)
    return AnalysisResult(
        engine="simplified", support=support, elevations=elevations, peaks=peaks, critical_base_shear=1.5e6,
        critical_base_moment=1.2e7, weight=9.80665 * 6e5, effective_height=7.0, uplift=support == "uplift",
        periods=np.array([0.5, 0.17, 0.1]), element_positions=positions,
        intermediates={"T1bar": 0.7, "V_n": [1.0, 2.0], "nan": float("nan")}, details={"warnings": []},
    )


def test_single_result_json_document_has_required_fields():
    document = json.loads(to_json([make_result()], "deck.toml", "A"))
    for key in ("engine", "support", "base_shear", "base_shear_coefficient", "base_moment", "critical_base_shear",
                "uplift", "periods", "stories"):
        assert key in document
    assert document["base_shear_coefficient"] == pytest.approx(3e6 / (9.80665 * 6e5))
    assert document["uplift"] is True
    assert document["stories"][1] == pytest.approx(
        {"story": 2, "elevation": 6.0, "displacement": 0.018, "drift": 0.008, "drift_ratio": 0.008 / 3,
         "shear": 2.2e6, "moment": 1.0e7, "floor_acceleration": 3.0})
    assert document["elements"] == [{"element": 1, "position": -2.0, "reaction": 4.0e6},
                                    {"element": 2, "position": 2.0, "reaction": 5.0e6}]
    assert document["units"]["floor_acceleration"] == "m/s^2" and document["units"]["reaction"] == "N"
    assert document["intermediates"]["nan"] is None  # JSON has no NaN


def test_several_results_are_one_document_with_a_list():
    document = results_document([make_result("rigid"), make_result("uplift", 0.5)], "deck.toml")
    assert [r["support"] for r in document["results"]] == ["rigid", "uplift"]
    assert document["units"]["base_shear"] == "N"


def test_csv_long_format_round_trip():
    rows = list(csv.DictReader(io.StringIO(to_csv([make_result("rigid"), make_result("uplift", 0.5)]))))
    assert len(rows) == 6
    assert rows[4]["support"] == "uplift" and rows[4]["story"] == "2"
    assert float(rows[4]["shear_N"]) == pytest.approx(1.1e6)
    assert float(rows[0]["drift_ratio"]) == pytest.approx(0.01 / 3)
    assert float(rows[5]["floor_acceleration_m_s2"]) == pytest.approx(0.5 * 4.5)
    assert float(rows[5]["elevation_m"]) == 9.0


def test_foundation_csv_has_one_row_per_element():
    rows = list(csv.DictReader(io.StringIO(elements_csv([make_result("rigid"), make_result("uplift", 0.5)]))))
    assert [(r["support"], r["element"], float(r["position_m"]), float(r["reaction_N"])) for r in rows] == [
        ("uplift", "1", -2.0, 2.0e6), ("uplift", "2", 2.0, 2.5e6)]


def test_write_results_atomic(tmp_path):
    paths = write_results([make_result()], tmp_path / "out", "deck", "deck.toml", "A")
    names = ["deck.csv", "deck.elements.csv", "deck.json"]  # no deck given: no <stem>.deck.toml
    assert sorted(p.name for p in paths) == names
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == names


def test_write_results_with_the_deck_writes_the_resolved_deck(deck_dir):
    deck = load_deck(deck_dir / "inputs" / "deck.toml", ["building.period=0.7"])
    out = deck_dir / "out"
    paths = write_results([make_result()], out, "deck", deck=deck)
    assert [p.name for p in paths] == ["deck.json", "deck.csv", "deck.elements.csv", "deck.deck.toml"]
    resolved = tomllib.loads((out / "deck.deck.toml").read_text())
    assert resolved["building"]["period"] == 0.7 and resolved["title"] == deck.title
    document = json.loads((out / "deck.json").read_text())
    assert document["provenance"]["deck"]["set"] == {"building.period": 0.7}
    assert document["source"] == deck.source and document["title"] == deck.title


def test_write_results_failure_leaves_no_file(tmp_path, monkeypatch):
    def broken(*args, **kwargs):
        raise RuntimeError("boom")

    monkeypatch.setattr(results_module, "elements_csv", broken)
    with pytest.raises(RuntimeError):
        write_results([make_result()], tmp_path, "deck")
    assert list(tmp_path.iterdir()) == []


def test_numbers_are_written_with_15_significant_digits():
    result = replace(make_result(), elevations=np.cumsum([5.1, 5.1, 5.1]))  # 15.299999999999999 in binary
    assert result.elevations[-1] != 15.3
    rows = list(csv.reader(io.StringIO(to_csv([result]))))
    assert rows[3][3] == "15.3"
    document = json.loads(to_json([result]))
    assert document["stories"][2]["elevation"] == 15.3
    assert '"elevation": 15.3,' in to_json([result])


def test_csv_opens_with_the_provenance(deck_dir):
    deck = load_deck(deck_dir / "inputs" / "deck.toml")
    record = of_deck(deck)
    text = to_csv([make_result("rigid"), make_result("uplift", 0.5)], record)
    lines = text.splitlines()
    assert lines[0].startswith("# uplift ") and lines[1].startswith("# provenance: {")
    assert lines[2].startswith("engine,support,story,elevation_m")
    assert read_csv_provenance(text) == json.loads(json.dumps(to_text_numbers(record)))
    pandas = pytest.importorskip("pandas")
    with_comments = pandas.read_csv(io.StringIO(text), comment="#")
    plain = pandas.read_csv(io.StringIO(to_csv([make_result("rigid"), make_result("uplift", 0.5)])))
    pandas.testing.assert_frame_equal(with_comments, plain)
    assert with_comments["shear_N"].tolist() == pytest.approx([3e6, 2.2e6, 1.2e6, 1.5e6, 1.1e6, 6e5])


def test_histories_files_carry_the_provenance(deck_dir):
    from upliftcli.histories import write_histories

    deck = load_deck(deck_dir / "inputs" / "deck.toml")
    record = of_deck(deck)
    histories = {"time": np.arange(4) * 0.01, "base_shear": np.array([0.0, 1.5e6, -2.0e6, 0.5e6])}
    write_histories(deck_dir / "h.csv", histories, record)
    text = (deck_dir / "h.csv").read_text()
    assert read_csv_provenance(text)["files"][1]["role"] == "record"
    table = np.loadtxt(deck_dir / "h.csv", delimiter=",", skiprows=3)  # two '#' lines and the header
    np.testing.assert_array_equal(table[:, 1], histories["base_shear"])
    assert text.splitlines()[2] == "time_s,base_shear_N"  # quantity_unit, as every CSV file
    write_histories(deck_dir / "h.npz", histories, record)
    with np.load(deck_dir / "h.npz") as data:
        assert json.loads(str(data["provenance"]))["deck"]["title"] == deck.title
        np.testing.assert_array_equal(data["base_shear"], histories["base_shear"])


def test_results_are_written_all_or_none(tmp_path, monkeypatch, example_deck):
    """A full disk at the third file of --out left two new files beside two old ones: none now."""
    import errno

    from upliftcli.analysis.run import run_one
    from upliftcli.output import write_results
    from upliftcli.runtime import atomic

    result = run_one(example_deck, "simplified", "bonded")
    original, calls = atomic._finish, []

    def full_disk(tmp, target):
        calls.append(target.name)
        if len(calls) == 3:
            raise OSError(errno.ENOSPC, "No space left on device")
        original(tmp, target)

    monkeypatch.setattr(atomic, "_finish", full_disk)
    with pytest.raises(OSError):
        write_results([result], tmp_path / "out", "deck", deck=example_deck)
    assert len(calls) == 3 and not (tmp_path / "out").exists()


def test_the_units_map_covers_every_intermediate_of_every_engine():
    """The JSON's units: every key, the intermediates' too (units.intermediates), for every engine."""
    from upliftcli.analysis import run as analysis
    from upliftcli.engines.quantities import INTERMEDIATES

    deck = load_deck(EXAMPLE_DECK, ["building.stories=3", "ground_motion.window=[0, 4]",
                                    'analysis.engine=["simplified", "exact", "approximate"]'])
    document = json.loads(to_json(analysis.run(deck), deck.source, deck.title))
    units = document["units"]["intermediates"]
    assert units == {name: unit for name, (unit, _) in INTERMEDIATES.items()}
    for result in document["results"]:
        assert set(result["intermediates"]) <= set(units), result["engine"]
