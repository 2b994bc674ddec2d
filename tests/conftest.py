"""Shared fixtures."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from sweep_cases import batch_sizes, dask_cluster, serial_rows, small_plan  # noqa: F401 (shared fixtures)

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE_DECK = ROOT / "inputs" / "ten_story_elcentro.toml"
ELCENTRO = ROOT / "records" / "elcentro_1940_ns_chopra.txt"


def pytest_collection_modifyitems(items):
    """The tests marked slow first (pyproject.toml's markers), the others in their order: a test
    of half a minute started last leaves the other workers of pytest-xdist idle till it ends."""
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)


@pytest.fixture(scope="session", autouse=True)
def _cache_home(tmp_path_factory):
    """The user's cache folder (XDG_CACHE_HOME: the check suites of analysis/suite_check.py) in a temporary
    folder of the session: the tests never write the real one, and generate each check suite once.
    The workers of pytest-xdist share it (the folder of the run, above each worker's own): a check
    suite is written atomically, so two workers that generate the same one at once both read a
    whole file. $UPLIFT_TEST_CACHE names another folder for it: .ci/run gives its two runs one, so
    that the run on the numpy twins reads the check suites the compiled run generated, as a user's
    cache would serve them (`record generate` and `record match` run on the twins in that run),
    rather than spend most of its time generating them again.
    $COLUMNS and $LINES are removed: the commands' tables are as wide in xdist's workers (given
    COLUMNS=80) as in one process, the width they have without a terminal (cli/render.py;
    tests/test_cli_render.py sets the variable where it tests it)."""
    base = tmp_path_factory.getbasetemp()
    cache = base.parent / "cache" if os.environ.get("PYTEST_XDIST_WORKER") else base / "cache"
    cache = Path(os.environ.get("UPLIFT_TEST_CACHE") or cache)
    cache.mkdir(parents=True, exist_ok=True)
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("XDG_CACHE_HOME", str(cache))
        patch.delenv("COLUMNS", raising=False)
        patch.delenv("LINES", raising=False)
        yield


@pytest.fixture(scope="module")
def example_deck():
    """The bundled example deck (inputs/ten_story_elcentro.toml), loaded once per test module."""
    from upliftcli.deck.load import load_deck

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
