"""Atomic writes follow the umask (a replaced file keeps its permissions) and never replace an input."""

import os
import stat

import pytest

from upliftcli.atomic import current_umask, refuse_inputs, write_text
from upliftcli.errors import InputError


def mode(path):
    return stat.S_IMODE(os.stat(path).st_mode)


@pytest.fixture()
def umask():
    def set_mask(mask):
        os.umask(mask)
    saved = os.umask(0o022)
    yield set_mask
    os.umask(saved)


def test_new_files_follow_the_umask(tmp_path, umask):
    for mask, expected in ((0o022, 0o644), (0o002, 0o664), (0o077, 0o600)):
        umask(mask)
        assert current_umask() == mask
        path = tmp_path / f"out{mask:o}.txt"
        write_text(path, "x")
        assert mode(path) == expected and path.read_text() == "x"
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary file left


def test_a_replaced_file_keeps_its_permissions(tmp_path, umask):
    umask(0o022)
    path = tmp_path / "table.csv"
    path.write_text("old")
    os.chmod(path, 0o640)
    write_text(path, "new")
    assert path.read_text() == "new" and mode(path) == 0o640


def test_outputs_may_not_replace_inputs(tmp_path):
    deck = tmp_path / "d" / "deck.toml"
    deck.parent.mkdir()
    deck.write_text("x")
    refuse_inputs([tmp_path / "out" / "deck.toml"], [deck], "--out")  # another folder: fine
    with pytest.raises(InputError, match=r"^--out: .*deck.toml: a path that does not replace an input of the run"):
        refuse_inputs([tmp_path / "d" / ".." / "d" / "deck.toml"], [deck], "--out")
    link = tmp_path / "link.toml"
    link.symlink_to(deck)
    with pytest.raises(InputError):  # the same file under another name
        refuse_inputs([link], [deck], "--histories")
