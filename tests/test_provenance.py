"""Provenance (provenance/record.py) against independent values: the SHA-256 of the files computed
here, the derived stiffness against the deck's period by a modal analysis done here, the
foundation against its closed forms, the resolved deck against a second run."""

from __future__ import annotations

import hashlib
import json
import math
import os
import shutil
import tomllib
from datetime import UTC, datetime
from pathlib import Path

import numpy as np
import pytest

from upliftcli.analysis import run as analysis
from upliftcli.deck.load import build_deck, load_deck
from upliftcli.output import to_json
from upliftcli.provenance import record as provenance

DECK = """
title = "provenance test"
[building]
stories = 4
floor_mass = 2.0e5
story_height = 3.0
period = 0.4
damping = 0.05
[foundation]
slenderness = 4
frequency_ratio = 6
damping_ratio = 0.1
[ground_motion]
record = "../records/elcentro_1940_ns_chopra.txt"
[analysis]
engine = "simplified"
supports = ["rigid", "uplift"]
"""


@pytest.fixture()
def deck_file(deck_dir):
    path = deck_dir / "inputs" / "four.toml"
    path.write_text(DECK)
    return path


def digest(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_files_carry_their_sha256_and_the_record_its_format(deck_file, deck_dir):
    record = provenance.of_deck(load_deck(deck_file))
    files = {entry["role"]: entry for entry in record["files"]}
    assert files["deck"]["sha256"] == digest(deck_file) and files["deck"]["bytes"] == deck_file.stat().st_size
    elcentro = deck_dir / "records" / "elcentro_1940_ns_chopra.txt"
    assert files["record"]["sha256"] == digest(elcentro)
    assert files["record"]["path"] == str(elcentro.resolve())
    assert files["record"]["format"] == "shared" and files["record"]["units"] == "g"
    assert files["record"]["dt"] == 0.02 and files["record"]["npts"] == 1560


def test_a_changed_record_changes_its_hash(deck_file, deck_dir):
    elcentro = deck_dir / "records" / "elcentro_1940_ns_chopra.txt"
    before = provenance.of_deck(load_deck(deck_file))["files"][1]["sha256"]
    elcentro.write_text(elcentro.read_text().replace("0.0063", "0.0064", 1))
    after = provenance.of_deck(load_deck(deck_file))["files"][1]["sha256"]
    assert before != after == digest(elcentro)


def test_derived_stiffness_gives_the_deck_period(deck_file):
    """The story stiffness the deck's period gives, checked by a modal analysis here (numpy's
    eigvals of M^-1 K of the shear building assembled here); the foundation by its closed forms."""
    model = provenance.of_deck(load_deck(deck_file))["model"]
    k = np.asarray(model["story_stiffnesses"])
    m = np.asarray(model["masses"])
    assert m.tolist() == [2.0e5] * 4 and np.all(k == k[0])
    stiffness = np.zeros((4, 4))
    for j in range(4):  # story j joins floor j-1 (or the mat) and floor j
        stiffness[j, j] += k[j]
        if j > 0:
            stiffness[j - 1, j - 1] += k[j]
            stiffness[j - 1, j] -= k[j]
            stiffness[j, j - 1] -= k[j]
    values, vectors = np.linalg.eig(np.diag(1.0 / m) @ stiffness)
    order = np.argsort(values.real)
    omega = np.sqrt(values.real[order])
    assert 2 * math.pi / omega[0] == pytest.approx(0.4, rel=1e-12)
    assert model["periods"][0] == pytest.approx(0.4, rel=1e-12)
    shape = vectors[:, order[0]].real
    heights = 3.0 * np.arange(1, 5)
    h1 = float(shape @ (m * heights) / (shape @ m))
    assert model["h1_star"] == pytest.approx(h1, rel=1e-12)
    assert model["half_width"] == pytest.approx(h1 / 4, rel=1e-12) and model["slenderness"] == pytest.approx(4)
    m_t = 8.0e5
    omega_v = 6 * omega[0]
    foundation = model["foundation"]
    assert foundation["type"] == "two-element"
    assert foundation["k_f"] == pytest.approx(m_t * omega_v**2 / 2, rel=1e-12)  # w_v = sqrt(2 k_f / m_t)
    assert foundation["c_f"] == pytest.approx(0.1 * m_t * omega_v, rel=1e-12)  # xi_v = c_f / (m_t w_v)
    b = model["half_width"]
    assert foundation["K_theta"] == pytest.approx(2 * foundation["k_f"] * b**2, rel=1e-12)  # [22]
    assert foundation["C_theta"] == pytest.approx(2 * foundation["c_f"] * b**2, rel=1e-12)  # [25]
    assert model["critical_base_shear"] == pytest.approx(m_t * 9.80665 * b / h1, rel=1e-12)  # [16a]
    lengthening = math.sqrt(1 + omega[0] ** 2 * model["effective_masses"][0] * h1**2 / foundation["K_theta"])
    assert model["T1bar"] == pytest.approx(0.4 * lengthening, rel=1e-12)  # [21]
    assert model["units"]["story_stiffnesses"] == "N/m" and model["units"]["foundation"]["k_f"] == "N/m"


def test_frame_and_winkler_models(tmp_path):
    raw = {"building": {"masses": [1e5, 1e5], "story_heights": [3.0, 3.0],
                        "stiffness_matrix": [[4e8, -2e8], [-2e8, 2e8]]},
           "foundation": {"type": "winkler", "b": 5.0, "k_w": 2e8, "c_w": 1e6, "elements": 10},
           "ground_motion": {"design_spectrum": {"type": "asce7", "sds": 1.0, "sd1": 0.6, "tl": 8.0}}}
    model = provenance.of_deck(build_deck(raw, str(tmp_path / "frame.toml")))["model"]
    assert "story_stiffnesses" not in model
    assert model["stiffness_matrix"] == [[4e8, -2e8], [-2e8, 2e8]]
    foundation = model["foundation"]
    assert (foundation["k_w"], foundation["c_w"], foundation["elements"]) == (2e8, 1e6, 10)
    assert foundation["K_theta"] == pytest.approx(2 / 3 * 2e8 * 5.0**3, rel=1e-12)
    assert model["units"]["foundation"]["k_w"] == "N/m^2"


def test_resolved_deck_repeats_the_run(deck_file, deck_dir, tmp_path):
    """The resolved deck, written elsewhere, gives the same results (its record path is relative
    to the folder it is written into: no absolute path in it)."""
    deck = load_deck(deck_file, ["building.period=0.6", "analysis.supports=[\"uplift\"]"])
    copy = tmp_path / "elsewhere" / "copy.deck.toml"
    copy.parent.mkdir()
    text = provenance.deck_toml(deck, directory=copy.parent)
    assert text.startswith("# The deck of a run of uplift")
    assert str(tmp_path) not in text and str(deck_dir) not in text
    copy.write_text(text)
    again = load_deck(copy)
    assert again.title == deck.title and again.analysis.supports == ["uplift"]
    (first,), (second,) = analysis.run(deck), analysis.run(again)
    assert second.base_shear == first.base_shear and second.drift_ratio.tolist() == first.drift_ratio.tolist()
    resolved = tomllib.loads(text)
    record = (deck_dir / "records" / "elcentro_1940_ns_chopra.txt").resolve()
    assert resolved["ground_motion"]["record"] == os.path.relpath(record, copy.parent.resolve())
    assert (copy.parent / resolved["ground_motion"]["record"]).resolve() == record
    assert provenance.overrides(deck) == {"analysis.supports": ["uplift"], "building.period": 0.6}


def test_suite_records_and_table_spectrum_files(deck_dir):
    folder = deck_dir / "records" / "pair"
    folder.mkdir()
    for name in ("a.txt", "b.txt"):
        shutil.copy(deck_dir / "records" / "elcentro_1940_ns_chopra.txt", folder / name)
    (deck_dir / "inputs" / "sa.csv").write_text("period_s,sa_g\n0.0,0.5\n1.0,1.0\n10.0,0.1\n")
    raw = tomllib.loads(DECK.replace('record = "../records/elcentro_1940_ns_chopra.txt"',
                                     'suite = "../records/pair"\nperiod_range = [0.1, 2.0]\n'
                                     'design_spectrum = { type = "table", file = "sa.csv", damping = 0.05 }'))
    deck = build_deck(raw, str(deck_dir / "inputs" / "pair.toml"))
    record = provenance.of_deck(deck)
    suite = [entry for entry in record["files"] if entry["role"].startswith("suite record")]
    assert [entry["path"] for entry in suite] == [str(folder / "a.txt"), str(folder / "b.txt")]
    assert {entry["sha256"] for entry in suite} == {digest(folder / "a.txt")}
    assert [entry["factor"] for entry in suite] == [1.0, 1.0] and suite[0]["format"] == "shared"
    assert [entry["role"] for entry in suite] == ["suite record 1", "suite record 2"]
    (table,) = [entry for entry in record["files"] if entry["role"] == "design spectrum table"]
    assert table["sha256"] == digest(deck_dir / "inputs" / "sa.csv")
    resolved = record["deck"]["resolved"]["ground_motion"]
    assert resolved["suite"] == str(folder)
    assert resolved["design_spectrum"]["file"] == str(deck_dir / "inputs" / "sa.csv")


def test_version_time_and_libraries():
    from upliftcli.runtime.installed import tool_version

    now = datetime(2026, 3, 4, 5, 6, 7, tzinfo=UTC)
    record = provenance.base("uplift analyze x.toml", now)
    assert record["version"] == tool_version() and record["time_utc"] == "2026-03-04T05:06:07Z"
    assert record["libraries"]["numpy"] == np.__version__ and record["command"] == "uplift analyze x.toml"
    stamp = datetime.strptime(provenance.utc_now(), "%Y-%m-%dT%H:%M:%SZ").replace(tzinfo=UTC)
    assert abs((datetime.now(UTC) - stamp).total_seconds()) < 60


def test_command_line_is_quoted():
    assert provenance.command_line(["/usr/bin/uplift", "analyze", "my deck.toml"]) == "uplift analyze 'my deck.toml'"


@pytest.mark.parametrize(("value", "text"), [(15.299999999999999, "15.3"), (0.1 + 0.2, "0.3"), (1e-20, "1e-20"),
                                             (2524761.0, "2524761.0"), (1 / 3, "0.333333333333333"),
                                             (float("nan"), ""), (float("inf"), "")])
def test_number_text(value, text):
    assert provenance.number_text(value) == text
    if text:
        assert float(text) == pytest.approx(value, rel=5e-15)


def test_json_result_holds_the_provenance(deck_file):
    deck = load_deck(deck_file)
    results = analysis.run(deck)
    record = provenance.of_deck(deck)
    document = json.loads(to_json(results, deck.source, deck.title, record))
    assert document["provenance"]["files"][0]["sha256"] == digest(deck_file)
    assert document["provenance"]["options"]["supports"] == ["rigid", "uplift"]
    assert document["provenance"]["options"]["simplified"]["procedure"] == "improved"
    assert document["provenance"]["options"]["units"]["exact"]["time_step"] == "s"  # every option with its unit
    assert document["provenance"]["deck"]["resolved"]["building"]["period"] == 0.4


def test_the_resolved_deck_is_in_bare_si():
    """A deck with units (units = "us", or texts such as "11.5 ft") resolves to bare SI numbers."""
    root = Path(__file__).resolve().parent.parent
    deck = load_deck(root / "inputs" / "ten_story_elcentro_us.toml", ['foundation.b="7.5 ft"'],
                     load_ground_motion=False)
    resolved = provenance.resolved_deck(deck)
    assert "units" not in resolved
    assert resolved["foundation"]["b"] == pytest.approx(2.286, rel=1e-15)
    assert resolved["building"]["story_height"] == pytest.approx(3.5, rel=1e-15)
    assert deck.raw["foundation"]["b"] == "7.5 ft"  # the deck as given (and the --set shown) are kept
    text = provenance.deck_toml(load_deck(root / "inputs" / "ten_story_elcentro_us.toml"))
    assert "Every number is bare SI" in text and tomllib.loads(text)["building"]["floor_mass"] == pytest.approx(350e3)


def test_the_loops_in_use_are_recorded():
    """The backend that ran the loops is part of the record (the two agree to round-off only):
    the numpy twins when asked for, else compiled where every C extension is on disk."""
    from upliftcli.runtime import backend

    with backend.use("numpy"):
        assert provenance.base("uplift analyze x.toml")["loops"] == "numpy"
    with backend.use("auto"):
        expected = "compiled" if len(backend.built()) == len(backend.EXTENSIONS) else None
        loops = provenance.base("uplift analyze x.toml")["loops"]
        if expected is None:
            assert loops.startswith("numpy") or loops.startswith("compiled, numpy for ")
        else:
            assert loops == expected


def test_plain_and_to_jsonable_are_one_conversion():
    """provenance/values.plain (the deck's mapping, provenance entries) and to_jsonable (results)
    convert alike; only to_jsonable writes a NaN or an infinity as None, as JSON has them."""
    from upliftcli.provenance.values import plain, to_jsonable

    value = {1: (np.float64(1.5), np.array([np.nan, 2.0])), "path": Path("a") / "b", "verdict": np.bool_(True),
             "count": np.int64(3), "ratio": float("inf"), "name": "x", "none": None}
    converted = plain(value)
    assert list(converted) == ["1", "path", "verdict", "count", "ratio", "name", "none"]
    assert converted["1"][0] == 1.5 and type(converted["1"][0]) is float
    assert math.isnan(converted["1"][1][0]) and converted["1"][1][1] == 2.0
    assert converted["path"] == os.path.join("a", "b") and converted["verdict"] is True
    assert type(converted["count"]) is int and converted["ratio"] == float("inf")
    assert to_jsonable(value) == {**converted, "1": [1.5, [None, 2.0]], "ratio": None}
    assert json.dumps(to_jsonable(value), allow_nan=False)


def test_provenance_modules_import_one_way():
    """No import circle: values <- files, model <- record; model imports nothing of record."""
    import ast

    import upliftcli.provenance as package

    folder = Path(package.__file__).parent
    imported = {}
    for name in ("values", "files", "model", "record"):
        tree = ast.parse((folder / f"{name}.py").read_text(encoding="utf-8"))
        imported[name] = {node.module for node in ast.walk(tree)
                          if isinstance(node, ast.ImportFrom) and node.level == 1}
    assert imported["values"] == set()
    assert imported["files"] == set()
    assert imported["model"] == {"values"}
    assert imported["record"] == {"files", "model", "values"}
