"""Issue 37: sweeps never collide. Two sweeps of one deck over other fields get other default names;
the same --name refused with words that say the earlier run varied other fields (never --resume);
following what an error suggests never replaces a result."""

import csv
import io
import re
import shutil
from pathlib import Path

import pytest
from cli_helpers import invoke

from upliftcli.cli.sweep_options import MAX_FIELDS_TEXT, default_stem

ROOT = Path(__file__).resolve().parent.parent
DECK = "inputs/ten_story_elcentro.toml"
#: the two sweep examples of README.md, "Sweeps, spectra and batches", as written there
FIRST = ["sweep", DECK, "--vary", "foundation.k_f=1e7:1e10:25:log", "--vary", "building.period=0.2:3:15"]
SECOND = ["sweep", DECK, "--vary", "foundation.frequency_ratio=2:20:10:log", "--engine", "exact", "--plot"]


def rows_of(path: Path) -> list[dict]:
    text = "".join(line for line in path.read_text().splitlines(keepends=True) if not line.startswith("#"))
    return list(csv.DictReader(io.StringIO(text)))


def test_the_readme_commands_are_the_ones_tested():
    readme = (ROOT / "README.md").read_text()
    assert "uplift " + " ".join(FIRST) in readme and "uplift " + " ".join(SECOND) in readme


def test_default_names_follow_the_varied_fields():
    deck = Path("inputs/ten_story_elcentro.toml")
    assert default_stem(deck, []) == "ten_story_elcentro.sweep"
    assert default_stem(deck, ["foundation.k_f=1:2:3", " building.period = 1,2"]) == \
        "ten_story_elcentro.period-k_f.sweep"
    assert default_stem(deck, ["building.period=1,2", "foundation.k_f=1,2"]) == \
        default_stem(deck, ["foundation.k_f=3,4", "building.period=5"])  # the same fields: the same sweep
    many = [f"foundation.field_number_{k}=1,2" for k in range(6)]
    stem = default_stem(deck, many)
    fields = stem.removeprefix("ten_story_elcentro.").removesuffix(".sweep")
    assert len(fields) == MAX_FIELDS_TEXT and re.fullmatch(r"[\w-]+-[0-9a-f]{8}", fields)
    assert stem != default_stem(deck, [*many[:5], "foundation.field_number_9=1,2"])


@pytest.mark.slow
def test_the_readme_sweeps_run_one_after_the_other_and_a_forced_collision_is_refused(tmp_path, monkeypatch):
    shutil.copytree(ROOT / "inputs", tmp_path / "inputs")
    shutil.copytree(ROOT / "records", tmp_path / "records")
    monkeypatch.chdir(tmp_path)
    first = invoke("sweep", *FIRST[1:], "--out", tmp_path, "--quiet")
    assert first.exit_code == 0, first.output
    second = invoke("sweep", *SECOND[1:], "--out", tmp_path, "--quiet")
    assert second.exit_code == 0, second.output
    table = tmp_path / "ten_story_elcentro.period-k_f.sweep.csv"
    assert len(rows_of(table)) == 25 * 15 * 3
    assert len(rows_of(tmp_path / "ten_story_elcentro.frequency_ratio.sweep.csv")) == 10 * 3
    before = table.read_text()
    # the same --name: refused, naming what the earlier run varied, never suggesting --resume
    forced = [*SECOND[1:], "--out", tmp_path, "--quiet", "--name", "ten_story_elcentro.period-k_f.sweep"]
    refused = invoke("sweep", *forced)
    assert refused.exit_code == 2
    message = refused.stderr
    assert "holds the rows of another sweep (1125 cases varying building.period, foundation.k_f; this one " \
           "varies foundation.frequency_ratio)" in message
    assert "--resume" not in message and "--overwrite" not in message
    assert "give this sweep its own --name, or another --out folder" in message
    # --resume anyway: refused too, the earlier sweep's table untouched
    assert invoke("sweep", *forced, "--resume").exit_code == 2
    assert table.read_text() == before
    # its rows file gone: its table still tells the other fields, and --resume is refused again
    (tmp_path / "ten_story_elcentro.period-k_f.sweep.rows.jsonl").rename(tmp_path / "kept.rows.jsonl")
    again = invoke("sweep", *forced, "--resume")
    assert again.exit_code == 2 and "holds the table of another sweep (varying building.period, foundation.k_f; " \
        "this one varies foundation.frequency_ratio)" in again.stderr and "--resume" not in again.stderr
    assert table.read_text() == before
    # what the message suggests: its own --name, or another --out folder; the earlier table untouched
    assert invoke("sweep", *forced[:-1], "its_own").exit_code == 0
    assert invoke("sweep", *SECOND[1:], "--out", tmp_path / "elsewhere", "--quiet").exit_code == 0
    assert table.read_text() == before


def test_an_earlier_run_of_the_same_sweep_still_suggests_resume(tmp_path):
    args = ["sweep", ROOT / DECK, "--vary", "building.period=0.5,1", "--support", "rigid", "--engine", "simplified",
            "--out", tmp_path, "--quiet"]
    assert invoke(*args).exit_code == 0
    again = invoke("sweep", ROOT / DECK, "--vary", "building.period=0.5,1,2", "--support", "rigid", "--engine",
                   "simplified", "--out", tmp_path, "--quiet")
    assert again.exit_code == 2 and "an earlier run of this sweep (2 cases): pass --resume" in again.stderr
    resumed = invoke("sweep", ROOT / DECK, "--vary", "building.period=0.5,1,2", "--support", "rigid", "--engine",
                     "simplified", "--out", tmp_path, "--quiet", "--resume")
    assert resumed.exit_code == 0
    assert len(rows_of(tmp_path / "ten_story_elcentro.period.sweep.csv")) == 3
