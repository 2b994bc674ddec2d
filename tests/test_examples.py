"""`uplift examples DIR` (cli/examples.py, runtime/examples.py): the repository's example decks and
records written byte for byte in its layout, so the decks run from DIR; nothing replaced without
--overwrite, nothing written on a refusal. The wheel's own copy (setup.py's BuildWithExamples) is
checked by tests/test_setup.py and, installed, by tools/check_wheel.sh."""

from __future__ import annotations

import json
from pathlib import Path

from cli_helpers import invoke

from upliftcli.runtime import examples

ROOT = Path(__file__).resolve().parents[1]


def _repository_files() -> dict[str, bytes]:
    """inputs/*.toml and every file under records/ of the repository, by relative path."""
    decks = sorted((ROOT / "inputs").glob("*.toml"))
    paths = [*decks, *sorted(path for path in (ROOT / "records").rglob("*") if path.is_file())]
    return {path.relative_to(ROOT).as_posix(): path.read_bytes() for path in paths}


def _written(folder: Path) -> dict[str, bytes]:
    return {path.relative_to(folder).as_posix(): path.read_bytes() for path in folder.rglob("*") if path.is_file()}


def test_examples_are_the_repositorys_decks_and_records_and_run_from_there(tmp_path):
    target = tmp_path / "new" / "ex"
    done = invoke("examples", target)
    assert done.exit_code == 0, done.output
    expected = _repository_files()
    assert "records/README.md" in expected and "inputs/ten_story_elcentro.toml" in expected
    assert _written(target) == expected
    assert done.stderr.strip() == (f"wrote {len(expected)} files into {target}: the decks in {target / 'inputs'}, "
                                   f"the records they read in {target / 'records'}")
    # the decks read their records from DIR (../records/...): the README's deck and a suite deck
    analysis = invoke("analyze", target / "inputs" / "ten_story_elcentro.toml", "--engine", "simplified",
                      "--support", "uplift", "--no-check", "--format", "json")
    assert analysis.exit_code == 0, analysis.output
    assert analysis.stdout.count(str(target / "records" / "elcentro_1940_ns_chopra.txt")) >= 1
    assert json.loads(analysis.stdout)["base_shear"] > 0
    suite = invoke("modes", target / "inputs" / "ten_story_asce7_suite.toml")
    assert suite.exit_code == 0, suite.output


def test_an_existing_file_is_never_replaced_without_overwrite(tmp_path):
    deck = tmp_path / "inputs" / "ten_story_elcentro.toml"
    deck.parent.mkdir()
    deck.write_text("# mine\n")
    refused = invoke("examples", tmp_path)
    assert refused.exit_code == 2
    assert refused.stderr == (f"error: DIR: {deck}: a new file (it exists in the folder; pass --overwrite to "
                              "replace it)\n")
    assert _written(tmp_path) == {"inputs/ten_story_elcentro.toml": b"# mine\n"}  # nothing else written either
    replaced = invoke("examples", tmp_path, "--overwrite")
    assert replaced.exit_code == 0 and _written(tmp_path) == _repository_files()


def test_a_file_named_as_the_folder_is_refused(tmp_path):
    file = tmp_path / "ex"
    file.write_text("x")
    done = invoke("examples", file)
    assert done.exit_code == 2 and done.stderr == f"error: DIR: {file}: a folder (a file of that name exists)\n"
    assert file.read_text() == "x"


def test_the_packaged_copy_is_read_where_the_package_has_one(tmp_path, monkeypatch):
    """A wheel's upliftcli/examples/ first; a source checkout's root where there is none."""
    assert examples.bundled_root() == ROOT and examples.PACKAGED == ROOT / "upliftcli" / "examples"
    (tmp_path / "inputs").mkdir()
    (tmp_path / "inputs" / "a.toml").write_text("[building]\n")
    (tmp_path / "records" / "set").mkdir(parents=True)
    (tmp_path / "records" / "set" / "r.txt").write_text("0 0\n")
    monkeypatch.setattr(examples, "PACKAGED", tmp_path)
    assert examples.bundled_root() == tmp_path
    assert examples.bundled_files() == ["inputs/a.toml", "records/set/r.txt"]
    assert examples.bundled_contents() == {"inputs/a.toml": b"[building]\n", "records/set/r.txt": b"0 0\n"}
