"""`uplift analyze` / `uplift modes` end to end through typer's test runner."""

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import invoke

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"




def test_modes_table_reproduces_the_paper():
    result = invoke("modes", EXAMPLE, "--format", "json")
    assert result.exit_code == 0, result.output
    document = json.loads(result.stdout)
    modes = document["modes"]
    assert [entry["role"] for entry in document["provenance"]["files"]] == ["deck"]  # no record is read
    np.testing.assert_allclose([m["frequency_ratio"] for m in modes[:5]], [1, 2.98, 4.89, 6.69, 8.34], atol=0.01)
    np.testing.assert_allclose([m["effective_mass_ratio"] for m in modes[:5]], [0.844, 0.091, 0.031, 0.014, 0.007],
                               atol=0.005)
    np.testing.assert_allclose([m["effective_height_over_b"] for m in modes[:5]], [10, -3.4, 2, -1.5, 1.2], atol=0.05)
    assert modes[-1]["cumulative_mass_ratio"] == pytest.approx(1.0)
    table = invoke("modes", EXAMPLE)
    assert table.exit_code == 0
    assert "h_n*/b" in table.stdout and "2.978" in table.stdout


def test_analyze_table_without_terminal():
    result = invoke("analyze", EXAMPLE)
    assert result.exit_code == 0, result.output
    for words in ("rigid support", "bonded support", "uplift support", "Summary", "T1bar", "xi1bar", "V_c",
                  "drift ratio [%]"):
        assert words in result.stdout


def test_analyze_json_single_support_matches_paper_quantities():
    result = invoke("analyze", EXAMPLE, "--format", "json", "--support", "uplift")
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    for key in ("engine", "support", "base_shear", "base_shear_coefficient", "base_moment", "critical_base_shear",
                "uplift", "periods", "stories"):
        assert key in doc
    assert doc["engine"] == "simplified" and doc["support"] == "uplift"
    assert doc["uplift"] is True
    inter = doc["intermediates"]
    assert inter["T1bar/T1"] == pytest.approx(1.525, abs=5e-4)
    assert inter["xi1bar"] == pytest.approx(0.0328, abs=5e-5)
    # critical coefficient V_c/(m_t g) = b/h_1* = 0.1 for the paper's example
    assert doc["critical_base_shear"] / doc["weight"] == pytest.approx(0.1)
    stories = doc["stories"]
    assert [s["story"] for s in stories] == list(range(1, 11))
    assert stories[0]["shear"] == pytest.approx(doc["base_shear"])
    assert stories[0]["moment"] == pytest.approx(doc["base_moment"])
    for key in ("displacement", "drift", "drift_ratio"):
        assert all(s[key] > 0 for s in stories)


def test_three_supports_order_the_base_shears():
    doc = json.loads(invoke("analyze", EXAMPLE, "--format", "json").stdout)
    shears = {r["support"]: r["base_shear"] for r in doc["results"]}
    assert shears["uplift"] < shears["bonded"] < shears["rigid"]


def test_set_override_changes_the_period():
    doc = json.loads(invoke("analyze", EXAMPLE, "--format", "json", "--support", "rigid",
                            "--set", "building.period=1.0", "--set", "foundation.b=4").stdout)
    assert doc["periods"][0] == pytest.approx(1.0)


def test_out_writes_the_result_files(deck_dir):
    out = deck_dir / "results"
    result = invoke("analyze", deck_dir / "inputs" / "deck.toml", "--out", out)
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in out.iterdir()) == ["deck.csv", "deck.deck.toml", "deck.elements.csv", "deck.json"]
    doc = json.loads((out / "deck.json").read_text())
    assert len(doc["results"]) == 3
    deck_entry = doc["provenance"]["files"][0]
    assert deck_entry["role"] == "deck" and deck_entry["path"] == str((deck_dir / "inputs" / "deck.toml").resolve())
    again = invoke("analyze", out / "deck.deck.toml", "--format", "json")  # the resolved deck repeats the run
    assert again.exit_code == 0, again.output
    repeated = json.loads(again.stdout)
    assert [r["base_shear"] for r in repeated["results"]] == [r["base_shear"] for r in doc["results"]]
    assert repeated["title"] == doc["title"]


def test_out_beside_the_deck_leaves_it_as_it_was(deck_dir):
    deck = deck_dir / "inputs" / "deck.toml"
    before = deck.read_bytes()
    result = invoke("analyze", deck, "--out", deck.parent, "--set", "building.period=0.8")
    assert result.exit_code == 0, result.output
    assert deck.read_bytes() == before
    assert (deck.parent / "deck.deck.toml").exists() and "period = 0.8" in (deck.parent / "deck.deck.toml").read_text()


def test_criteria_violation_exits_3(deck_dir):
    deck = deck_dir / "inputs" / "deck.toml"
    result = invoke("analyze", deck, "--set", "criteria.drift_ratio=0.001")
    assert result.exit_code == 3
    assert "criterion violated" in result.stderr and "drift_ratio" in result.stderr
    assert invoke("analyze", deck, "--set", "criteria.uplift=false", "--support", "bonded").exit_code == 0


BAD_DECKS = [
    ("floor_mass = 350e3", "flor_mass = 350e3", "building.flor_mass"),
    ("floor_mass = 350e3", "", "building.floor_mass"),
    ("floor_mass = 350e3", "floor_mass = -1.0", "building.floor_mass"),
    ("period = 0.5", "story_stiffness = 0.0", "building.story_stiffness"),
    ("story_height = 3.5", "story_height = -3.5", "building.story_height"),
    ("damping = 0.05", "damping = 1.2", "building.damping"),
    ("slenderness = 10", "b = 0.0", "foundation.b"),
    ("scale = 1.0", "scael = 1.0", "ground_motion.scael"),
    ("stories = 10", "stories = = 10", "line"),
    ('record = "../records/elcentro_1940_ns_chopra.txt"', 'record = "../records/missing.txt"', "missing.txt"),
]


@pytest.mark.parametrize("old, new, words", BAD_DECKS)
def test_bad_input_one_line_exit_2_no_output(deck_dir, old, new, words):
    deck = deck_dir / "inputs" / "deck.toml"
    text = deck.read_text()
    assert old in text
    deck.write_text(text.replace(old, new, 1))
    out = deck_dir / "results"
    result = invoke("analyze", deck, "--out", out)
    assert result.exit_code == 2, result.output
    assert result.stdout == ""
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0]
    assert "Traceback" not in result.output
    assert not out.exists()


def test_unreadable_record_content(deck_dir):
    (deck_dir / "records" / RECORD.name).write_text("# time_s accel_g\n0.0 0.0\n0.02 x\n")
    result = invoke("analyze", deck_dir / "inputs" / "deck.toml")
    assert result.exit_code == 2
    assert "line 3" in result.stderr and len(result.stderr.strip().splitlines()) == 1


def test_bad_set_path_and_value():
    result = invoke("analyze", EXAMPLE, "--set", "foundation.bb=4")
    assert result.exit_code == 2
    assert result.stderr.startswith("error: --set: foundation.bb:") and "did you mean 'foundation.b'" in result.stderr
    result = invoke("modes", EXAMPLE, "--set", "building.period=-1")
    assert result.exit_code == 2 and "--set: building.period" in result.stderr


def test_missing_deck_file(tmp_path):
    result = invoke("analyze", tmp_path / "none.toml")
    assert result.exit_code == 2 and "file not found" in result.stderr


def test_unknown_engine(deck_dir):
    deck = deck_dir / "inputs" / "deck.toml"
    result = invoke("analyze", deck, "--engine", "nonsense")
    assert result.exit_code == 2 and result.stderr.startswith("error: --engine: nonsense: one of")
    result = invoke("analyze", deck, "--engine", "EXACT")  # the option is named, not a --set of analysis.engine
    assert result.exit_code == 2
    assert result.stderr.strip() == ("error: --engine: EXACT: one of simplified, approximate, exact or all "
                                     "(names are lower case: 'exact')")


def test_main_entry_point_exit_code(deck_dir, monkeypatch, capsys):
    from upliftcli.cli import main

    monkeypatch.setattr("sys.argv", ["uplift", "analyze", str(deck_dir / "inputs" / "none.toml")])
    with pytest.raises(SystemExit) as info:
        main()
    assert info.value.code == 2
    assert "file not found" in capsys.readouterr().err


@pytest.mark.parametrize("deck", sorted((ROOT / "inputs").glob("*.toml")), ids=lambda p: p.name)
def test_every_bundled_deck_runs(deck):
    result = invoke("analyze", deck, "--format", "json")
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    for item in doc.get("results", [doc]):
        assert math.isfinite(item["base_shear"]) and item["base_shear"] > 0
        if "suite" in deck.name:  # record suites: the history engines run every record
            assert item["engine"] == "exact" and item["suite"]["count"] >= 11
            assert len(item["suite"]["records"]) == item["suite"]["count"]
    assert invoke("modes", deck).exit_code == 0


def test_out_must_be_a_directory(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    result = invoke("analyze", EXAMPLE, "--out", blocker)
    assert result.exit_code == 2 and "--out" in result.stderr
    assert blocker.read_text() == "x"


# ----------------------------------------------------------------------------- never an input overwritten (issue 13)

def _deck_beside_its_record(tmp_path, record_name="rec.csv"):
    """A deck and its record in one folder (a record named like a --histories target)."""
    folder = tmp_path / "d"
    folder.mkdir()
    (folder / record_name).write_bytes(RECORD.read_bytes())
    deck = folder / "deck.toml"
    deck.write_text(EXAMPLE.read_text().replace("../records/elcentro_1940_ns_chopra.txt", record_name)
                    .replace('units = "g"', 'units = "g"\nformat = "shared"'))
    return deck


def test_out_into_the_decks_folder_never_replaces_the_deck(tmp_path):
    """The results are <stem>.json, .csv, .elements.csv and .deck.toml: beside the deck they
    replace nothing; a record named like one of them is refused before anything runs."""
    deck = _deck_beside_its_record(tmp_path)
    before = deck.read_bytes()
    result = invoke("analyze", deck, "--out", deck.parent)
    assert result.exit_code == 0, result.output
    assert deck.read_bytes() == before
    assert sorted(p.name for p in deck.parent.iterdir()) == ["deck.csv", "deck.deck.toml", "deck.elements.csv",
                                                             "deck.json", "deck.toml", "rec.csv"]
    (tmp_path / "clash").mkdir()
    clash = _deck_beside_its_record(tmp_path / "clash", record_name="deck.csv")
    record = clash.parent / "deck.csv"
    result = invoke("analyze", clash, "--out", clash.parent)
    assert result.exit_code == 2 and result.stdout == ""
    assert result.stderr.strip().startswith(f"error: --out: {record}: a path that does not replace an input of the run")
    assert record.read_bytes() == RECORD.read_bytes() and sorted(p.name for p in clash.parent.iterdir()) == [
        "deck.csv", "deck.toml"]


def test_histories_refuse_the_record_and_existing_files(tmp_path):
    deck = _deck_beside_its_record(tmp_path)
    record = deck.parent / "rec.csv"
    before = record.read_bytes()
    args = ["analyze", deck, "--engine", "exact", "--support", "uplift", "--set", "ground_motion.window=[0, 3]"]
    result = invoke(*args, "--histories", record, "--overwrite")  # never an input, even with --overwrite
    assert result.exit_code == 2 and "--histories" in result.stderr and "does not replace an input" in result.stderr
    assert record.read_bytes() == before
    target = tmp_path / "h.csv"
    assert invoke(*args, "--histories", target).exit_code == 0
    first = target.read_text()
    target.write_text("mine")
    result = invoke(*args, "--histories", target)
    assert result.exit_code == 2 and target.read_text() == "mine"
    assert result.stderr.strip() == f"error: --histories: {target}: a new file (it exists; pass --overwrite to " \
                                    "replace it)"
    assert invoke(*args, "--histories", target, "--overwrite").exit_code == 0

    def table(text):  # without the provenance lines (they hold the time)
        return [line for line in text.splitlines() if not line.startswith("#")]

    assert table(target.read_text()) == table(first)


def test_results_follow_the_umask(tmp_path):
    import os
    import stat

    saved = os.umask(0o002)
    try:
        assert invoke("analyze", EXAMPLE, "--out", tmp_path).exit_code == 0
    finally:
        os.umask(saved)
    modes = {p.suffix: stat.S_IMODE(p.stat().st_mode) for p in tmp_path.iterdir()}
    assert modes == {".json": 0o664, ".csv": 0o664, ".toml": 0o664}


# ----------------------------------------------------------------------------- one line naming the source (issue 13)

@pytest.mark.parametrize(("args", "line"), [
    (["--format", "xml"], "error: --format: 'xml' is not one of 'table', 'json'."),
    (["--engine", "EXACT"], "error: --engine: EXACT: one of simplified, approximate, exact or all (names are lower "
                            "case: 'exact')"),
    (["--support", "lifted"], "error: --support: lifted: one of rigid, bonded, uplift or all"),
    (["--set", "analysis.exact.steps_per_period=1"], "error: --set: analysis.exact.steps_per_period: an integer "
                                                     ">= 2, got 1"),
    (["--set", "building.period=0.5\nx=1"], "error: --set: building.period: a value on one line (without line "
                                             "breaks or control characters)"),
])
def test_bad_options_give_one_line(args, line):
    result = invoke("analyze", EXAMPLE, *args)
    assert result.exit_code == 2 and result.stdout == ""
    assert result.stderr.strip().splitlines() == [line] or result.stderr.strip().startswith(line), result.stderr


def test_a_newline_in_a_path_gives_one_line(tmp_path):
    result = invoke("analyze", tmp_path / "no\nsuch.toml")
    assert result.exit_code == 2
    assert result.stderr.strip().splitlines() == [f"error: {tmp_path}/no\\nsuch.toml: an existing deck file (file "
                                                  "not found)"]


def test_a_one_sample_record_is_bad_input_for_every_engine(tmp_path):
    record = tmp_path / "one.txt"
    record.write_text("# dt = 0.01\n# units: g\n0.05\n")
    deck = tmp_path / "deck.toml"
    deck.write_text(EXAMPLE.read_text().replace("../records/elcentro_1940_ns_chopra.txt", "one.txt"))
    for engine in ("simplified", "exact"):
        result = invoke("analyze", deck, "--engine", engine)
        assert result.exit_code == 2
        assert result.stderr.strip() == f"error: {record}: at least two acceleration samples, found 1"


def test_an_engine_the_deck_cannot_serve_names_the_option():
    result = invoke("analyze", ROOT / "inputs" / "ten_story_asce7.toml", "--engine", "exact")
    assert result.exit_code == 2
    deck = ROOT / "inputs" / "ten_story_asce7.toml"
    assert result.stderr == (f"error: {deck}: ground_motion.record: a record for the "
                             "exact engine (asked by --engine or --set analysis.engine; a design spectrum serves only "
                             "the simplified engine)\n")


# ----------------------------------------------------------------------------- units, errors, warnings (issues 27, 29)

def _results(document):
    """The results of a JSON document (without the source, title and provenance of the run)."""
    return document["results"]


def test_the_us_deck_gives_the_si_decks_results():
    si = invoke("analyze", EXAMPLE, "--format", "json")
    us = invoke("analyze", ROOT / "inputs" / "ten_story_elcentro_us.toml", "--format", "json")
    assert si.exit_code == us.exit_code == 0, us.output
    first, second = _results(json.loads(si.stdout)), _results(json.loads(us.stdout))

    def close(a, b, path):
        if isinstance(a, dict):
            assert set(a) == set(b), path
            for key in a:
                close(a[key], b[key], f"{path}.{key}")
        elif isinstance(a, list):
            assert len(a) == len(b), path
            for k, (x, y) in enumerate(zip(a, b, strict=True)):
                close(x, y, f"{path}[{k}]")
        elif isinstance(a, float):
            assert b == pytest.approx(a, rel=1e-12, abs=1e-12 * (1 + abs(a))), path
        else:
            assert a == b, path

    close(first, second, "results")


def test_a_resolved_us_deck_repeats_the_run_in_si(tmp_path):
    us = ROOT / "inputs" / "ten_story_elcentro_us.toml"
    run = invoke("analyze", us, "--set", "building.story_height=12", "--out", tmp_path, "--format", "json")
    assert run.exit_code == 0, run.output
    resolved = tmp_path / "ten_story_elcentro_us.deck.toml"
    text = resolved.read_text()
    assert "units = \"us\"" not in text and "story_height = 3.6576" in text and "floor_mass = 350000.0" in text
    again = invoke("analyze", resolved, "--format", "json")
    assert _results(json.loads(again.stdout)) == _results(json.loads(run.stdout))


def test_record_units_contradicting_the_header_exit_2_with_one_line():
    """--set ground_motion.units=cm/s2 silently divided El Centro by 981 (V_b/W = 0.0008)."""
    for units in ("cm/s2", "gal"):
        result = invoke("analyze", EXAMPLE, "--set", f"ground_motion.units={units}")
        assert result.exit_code == 2
        assert result.stderr.count("\n") == 1 and "ground_motion.units" in result.stderr
        assert "declares, g" in result.stderr
    meant = invoke("analyze", EXAMPLE, "--set", "ground_motion.units=cm/s2", "--set",
                   "ground_motion.override_header_units=true", "--format", "json", "--no-check")
    assert meant.exit_code == 0 and json.loads(meant.stdout)["results"][0]["base_shear_coefficient"] < 0.01


def test_every_deck_error_is_reported_in_one_run(tmp_path):
    deck = tmp_path / "four.toml"
    deck.write_text('[building]\nstories = 10\nfloor_mas = 350e3\nstory_height = "3.5 furlongs"\nperiod = -1\n'
                    "[foundation]\nslenderness = 6\ndamping_ratio = true\n"
                    '[ground_motion]\ndesign_spectrum = { type = "asce7", sds = true, sd1 = 0.6, tl = 8.0 }\n')
    result = invoke("analyze", deck)
    assert result.exit_code == 2 and result.stdout == ""
    lines = result.stderr.splitlines()
    assert [line.split(": ")[2] for line in lines] == ["building.floor_mas", "building.story_height", "building.period",
                                                      "foundation.damping_ratio", "ground_motion.design_spectrum.sds"]
    assert all(line.startswith(f"error: {deck}: ") for line in lines)


@pytest.mark.parametrize("value", [
    '{type="table",periods=[0,1,8],sa=[1,1,1],damping="5%"}',
    '{type="asce7",sds=true,sd1=0.6,tl=8}',
    '{type="asce7",sds=1e300,sd1=0.6,tl=8}',
    '{type="table",periods=[0,1,8],sa=[1,1,1],damping=0.05,name=1979-05-27}',
])
def test_bad_design_spectrum_keys_are_one_line_exit_2(tmp_path, value):
    result = invoke("analyze", ROOT / "inputs" / "ten_story_asce7.toml", "--set",
                    f"ground_motion.design_spectrum={value}", "--out", tmp_path)
    assert result.exit_code == 2 and result.stderr.count("\n") == 1, result.output
    assert result.stderr.startswith("error: --set: ground_motion.design_spectrum.") and not list(tmp_path.iterdir())


def test_implausible_values_warn_once_and_keep_the_exit_code():
    result = invoke("analyze", EXAMPLE, "--set", "building.floor_mass=300", "--set", "building.story_height=3200",
                    "--set", "criteria.drift_ratio=2", "--format", "json", "--no-check")
    assert result.exit_code == 0, result.output
    warnings = [line for line in result.stderr.splitlines() if "building practice" in line]
    assert [line.split(": ")[2] for line in warnings] == ["building.floor_mass", "building.story_height",
                                                         "criteria.drift_ratio"]
    for entry in json.loads(result.stdout)["results"]:
        assert sum("building practice" in message for message in entry["warnings"]) == 3


def test_a_second_run_into_the_same_out_folder_needs_overwrite(tmp_path):
    """--out never replaces the results of an earlier run silently: refused before the run (exit 2,
    the files unchanged) unless --overwrite; several decks the same."""
    from pathlib import Path

    example = Path(__file__).resolve().parent.parent / "inputs" / "ten_story_asce7.toml"  # the simplified engine
    out = tmp_path / "out"
    assert invoke("analyze", example, "--out", out).exit_code == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    result = invoke("analyze", example, "--out", out, "--set", "building.period=0.5")
    assert result.exit_code == 2 and {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert result.stderr == (f"error: --out: {out / 'ten_story_asce7.json'}: a new file (it exists: the results of "
                             "an earlier run; pass --overwrite to replace it)\n")
    result = invoke("analyze", example, example.parent / "ten_story_elcentro.toml", "--no-check", "--out", out)
    assert result.exit_code == 2 and "pass --overwrite" in result.stderr
    assert invoke("analyze", example, "--out", out, "--set", "building.period=0.5", "--overwrite").exit_code == 0
    assert (out / "ten_story_asce7.json").read_bytes() != before["ten_story_asce7.json"]


@pytest.mark.parametrize("engine", ["exact", "approximate", "simplified"])
def test_a_bearing_capacity_runs_on_every_engine(engine, tmp_path):
    """Every engine models yielding soil (docs/theory.md section 14, issue 28): FS_v = 1.5 on the
    example runs; the exact engine's uplift results carry the rocking of the mat, the plastic
    settlement of each element and the plastic work (<deck>.rocking.csv, docs/deck.md)."""
    out = tmp_path / "results"
    result = invoke("analyze", EXAMPLE, "--engine", engine, "--support", "uplift", "--set",
                    "foundation.safety_factor=1.5", "--set", "ground_motion.window=[0.0, 8.0]", "--no-check",
                    "--format", "json", "--out", out)
    assert result.exit_code == 0, result.output
    document = json.loads(result.stdout)
    assert (out / "ten_story_elcentro.rocking.csv").exists() == (engine == "exact")
    if engine == "exact":
        assert document["rocking"]["yielded_elements"] == 2 and document["rocking"]["plastic_work"] > 0.0
        assert all(element["plastic_settlement"] > 0.0 for element in document["elements"])
    elif engine == "simplified":
        assert document["intermediates"]["FS_v"] == pytest.approx(1.5)


@pytest.mark.parametrize("engine", ["exact", "approximate"])
def test_a_bearing_capacity_runs_on_the_history_engines(engine):
    """They model yielding soil (docs/theory.md section 14, tests/test_yielding.py): the uplift
    result carries each element's plastic settlement and the plastic work."""
    result = invoke("analyze", EXAMPLE, "--engine", engine, "--set", "foundation.safety_factor=1.5", "--support",
                    "uplift", "--no-check", "--format", "json")
    assert result.exit_code == 0, result.output
    document = json.loads(result.stdout)
    (uplift,) = [r for r in document.get("results", [document]) if r.get("support") == "uplift"]
    yielding = uplift["details"]["yielding"]
    assert yielding["plastic_work"] > 0.0 and min(yielding["plastic_settlement"]) < 0.0
    assert uplift["details"]["energy"]["plastic_work"] == yielding["plastic_work"]


def test_several_decks_print_every_warning_once_naming_the_deck():
    """Each per-analysis warning on stderr once, naming its deck and the analyses that gave it:
    the ASCE 7-22 11.4.5 warning of the two-period spectrum included (only --format json had them),
    and those of each deck's accuracy check (accuracy.Check.warnings)."""
    asce7, winkler = ROOT / "inputs" / "ten_story_asce7.toml", ROOT / "inputs" / "ten_story_winkler.toml"
    invoke("analyze", asce7, "--support", "rigid", "--format", "json")  # the check suite generated and cached
    result = invoke("analyze", asce7, winkler)
    assert result.exit_code == 0, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == len(set(lines)) and all(line.startswith("warning: ") for line in lines)
    two_period = [line for line in lines if "ASCE 7-22 11.4.5" in line]
    assert len(two_period) == 1 and two_period[0].startswith(
        f"warning: {asce7}: simplified/rigid, simplified/bonded, simplified/uplift: ASCE 7-22 11.4.5 permits")
    assert any(line.startswith(f"warning: {winkler}: simplified/uplift: accuracy check: V_b: simplified / exact")
               for line in lines)
    assert not any(line.startswith(f"warning: {winkler}") for line in invoke("analyze", asce7, winkler,
                                                                          "--no-check").stderr.splitlines())
    # every warning of the JSON documents is heard, and no other
    documents = json.loads(invoke("analyze", asce7, winkler, "--format", "json").stdout)["decks"]
    given = {(document["source"], warning) for document in documents for r in document["results"]
             for warning in r["warnings"]}
    heard = {(line.split(": ", 2)[1], line.split(": ", 3)[3]) for line in lines}
    assert {(str(Path(source)), warning) for source, warning in given} == heard
    # one deck: the same lines without the deck's name
    for deck in (asce7, winkler):
        alone = invoke("analyze", deck).stderr.strip().splitlines()
        assert alone == [line.replace(f" {deck}:", "", 1) for line in lines if str(deck) in line]


def test_units_us_in_every_table():
    """--units us: kip, kip ft, in, ft; the coefficients unchanged; the JSON in US units too
    (tests/test_units_files.py), SI without --units."""
    document = json.loads(invoke("analyze", EXAMPLE, "--format", "json").stdout)
    us = json.loads(invoke("analyze", EXAMPLE, "--format", "json", "--units", "us").stdout)
    assert document["units"]["base_shear"] == "N" and us["units"]["base_shear"] == "kip"
    for si_row, us_row in zip(document["results"], us["results"], strict=True):
        assert us_row["base_shear"] == pytest.approx(si_row["base_shear"] / 4448.2216152605, rel=1e-12)
        assert us_row["base_shear_coefficient"] == si_row["base_shear_coefficient"]
    result = invoke("analyze", EXAMPLE, "--units", "us", "--no-check", env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    text = result.stdout
    for heading in ("elevation [ft]", "disp. [in]", "shear [kip]", "moment [kip ft]", "V_b [kip]", "M_b [kip ft]",
                    "h_n* [ft]", "V_n [kip]"):
        assert heading in text, heading
    assert "[kN" not in text and "[mm]" not in text
    rows = {(r["engine"], r["support"]): r for r in document["results"]}
    summary = text[text.index("Summary"):]
    for (engine, support), r in rows.items():
        cells = r"\s*[│|]\s*([\d.]+)" * 3
        match = re.search(rf"{engine}\s*[│|]\s*{support}{cells}", summary)
        assert float(match.group(1)) == pytest.approx(r["base_shear"] / 4448.2216152605, abs=0.05)
        assert float(match.group(2)) == pytest.approx(r["base_shear_coefficient"], abs=5e-5)
        assert float(match.group(3)) == pytest.approx(r["base_moment"] / (4448.2216152605 * 0.3048), abs=0.05)
    batch = invoke("analyze", EXAMPLE, ROOT / "inputs" / "ten_story_winkler.toml", "--units", "us",
                   env={"COLUMNS": "200"})
    assert "V_b [kip]" in batch.stdout and "M_b [kip ft]" in batch.stdout
    modes = invoke("modes", EXAMPLE, "--units", "us", env={"COLUMNS": "200"}).stdout
    assert "h_n* [ft]" in modes and "kip s^2/in" in modes  # m_t in the title
    bad = invoke("analyze", EXAMPLE, "--units", "imperial")
    assert bad.exit_code == 2 and "--units" in bad.stderr


def test_a_capacity_on_more_elements_than_the_history_engines_step_is_refused_up_front(tmp_path):
    """More than limits.MAX_YIELDING_ELEMENTS = 31 elements with a capacity and the exact engine on
    the uplift support: one line naming foundation.elements and the bound, exit 2, nothing written
    (before any engine runs). The simplified engine alone runs the same foundation (no such bound);
    its accuracy check, which needs the exact engine, says why it could not run."""
    winkler = ROOT / "inputs" / "ten_story_winkler.toml"
    capacity = ("--set", "foundation.elements=40", "--set", "foundation.safety_factor=2")
    out = tmp_path / "results"
    refused = invoke("analyze", winkler, *capacity, "--engine", "exact", "--support", "uplift", "--out", out)
    assert refused.exit_code == 2 and refused.stdout == "" and not out.exists()
    (line,) = refused.stderr.strip().splitlines()
    assert line.startswith("error: --set: foundation.elements: at most 31 contact elements with a bearing capacity")
    assert "got 40" in line and "Traceback" not in refused.output
    alone = invoke("analyze", winkler, *capacity, "--engine", "simplified", "--support", "uplift", "--format", "json")
    assert alone.exit_code == 0, alone.output
    document = json.loads(alone.stdout)
    assert document["intermediates"]["FS_v"] == pytest.approx(2.0)
    assert "foundation.elements: at most 31" in document["accuracy"]["error"]


def test_no_check_with_a_simplified_error_limit_is_refused(tmp_path):
    """[criteria] simplified_error is judged on the accuracy check: --no-check would pass it unchecked
    (exit 0); analyze (one deck or several) and report refuse the pair before anything runs."""
    line = ("error: --no-check: criteria.simplified_error: the accuracy check that this limit of the deck judges: "
            "drop --no-check or the limit\n")
    limit = ["--set", "criteria.simplified_error=0.25", "--no-check"]
    for args in (["analyze", EXAMPLE, "--out", tmp_path / "out"], ["analyze", EXAMPLE, EXAMPLE],
                 ["report", EXAMPLE, "--out", tmp_path / "r.html"]):
        result = invoke(*args, *limit)
        assert (result.exit_code, result.stderr, result.stdout) == (2, line, "")
    assert sorted(tmp_path.iterdir()) == []
