"""How records were made, from the manifest beside them or a suite entry's `made`."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from upliftcli.deck.load import load_deck
from upliftcli.errors import InputError
from upliftcli.motion.origins import origin_of

ROOT = Path(__file__).resolve().parents[1]
FOLDER = ROOT / "records" / "ten_story_asce7_suite"
ELCENTRO = ROOT / "records" / "elcentro_1940_ns_chopra.txt"


def test_the_manifest_says_how_each_record_was_made(tmp_path):
    assert origin_of(FOLDER / "artificial_2024_03.txt") == "artificial"
    assert origin_of(ELCENTRO) == "recorded"  # records/ has no manifest
    assert origin_of(ELCENTRO, "matched") == "matched"  # a suite entry's `made` wins
    shutil.copy(ELCENTRO, tmp_path / "a.txt")
    (tmp_path / "manifest.json").write_text(json.dumps({"tool": "uplift", "command": "record match",
                                                        "records": [{"file": "a.txt"}]}))
    assert origin_of(tmp_path / "a.txt") == "matched"
    (tmp_path / "manifest.json").write_text(json.dumps({"tool": "other", "made": "artificial",
                                                        "records": [{"file": "a.txt"}]}))
    assert origin_of(tmp_path / "a.txt") == "recorded"  # not a manifest of ours
    (tmp_path / "manifest.json").write_text("{not json")
    assert origin_of(tmp_path / "a.txt") == "recorded"


def test_matched_records_keep_the_110_percent_rule_wherever_loaded(tmp_path):
    deck = (ROOT / "inputs" / "ten_story_asce7_suite.toml").read_text()
    entries = ", ".join(f'{{ file = "{FOLDER / name}" }}' for name in sorted(p.name for p in FOLDER.glob("*.txt")))
    text = deck.replace('suite = "../records/ten_story_asce7_suite"', f"suite = [{entries}]")
    path = tmp_path / "deck.toml"
    path.write_text(text)
    suite = load_deck(path, ['ground_motion.scaling="amplitude"']).ground_motion
    assert suite.matched and suite.mean_minimum == 1.1 and suite.mean_ratio().min() >= 1.1
    # said to be recorded, the same files are scaled to 90 %
    path.write_text(text.replace('.txt" }', '.txt", made = "recorded" }'))
    suite = load_deck(path, ['ground_motion.scaling="amplitude"']).ground_motion
    assert not suite.matched and suite.mean_minimum == 0.9 and suite.mean_ratio().min() < 1.0
    path.write_text(text.replace('.txt" }', '.txt", made = "scaled" }', 1))
    with pytest.raises(InputError, match=r"ground_motion\.suite\[0\]\.made: one of recorded, matched, artificial"):
        load_deck(path)
