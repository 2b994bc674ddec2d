"""Shared fixtures."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from sweep_cases import batch_sizes, dask_cluster, serial_rows, small_plan  # noqa: F401 (shared fixtures)

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE_DECK = ROOT / "inputs" / "ten_story_elcentro.toml"
ELCENTRO = ROOT / "records" / "elcentro_1940_ns_chopra.txt"


@pytest.fixture(scope="session", autouse=True)
def _cache_home(tmp_path_factory):
    """The user's cache folder (XDG_CACHE_HOME: the check suites of suite_check.py) in a temporary
    folder of the session: the tests never write the real one, and generate each check suite once."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.mktemp("cache")))
        yield


@pytest.fixture(scope="module")
def example_deck():
    """The bundled example deck (inputs/ten_story_elcentro.toml), loaded once per test module."""
    from upliftcli.deck import load_deck

    return load_deck(EXAMPLE_DECK)


@pytest.fixture(scope="module")
def elcentro():
    """The bundled El Centro 1940 NS record (records/README.md), read once per test module."""
    from upliftcli.motion.records import read_record

    return read_record(ELCENTRO)


@pytest.fixture()
def deck_dir(tmp_path):
    """A copy of the example deck (inputs/deck.toml) and its record in a temporary directory."""
    (tmp_path / "inputs").mkdir()
    (tmp_path / "records").mkdir()
    shutil.copy(EXAMPLE_DECK, tmp_path / "inputs" / "deck.toml")
    shutil.copy(ELCENTRO, tmp_path / "records" / ELCENTRO.name)
    return tmp_path
