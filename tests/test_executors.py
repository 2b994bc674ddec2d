"""Local worker processes (upliftcli.sweep.executors): forked from a warm server, they start with
the engines imported and their compiled code loaded, and give the rows of spawned workers and
of the serial executor."""

from __future__ import annotations

import multiprocessing
import os
import sys
from pathlib import Path

import pytest

from upliftcli.sweep.executors import ProcessExecutor, SerialExecutor
from upliftcli.sweep.plan import plan_sweep
from upliftcli.sweep.run import run_sweep
from upliftcli.sweep.store import RowStore
from upliftcli.sweep.worker import run_chunk

EXAMPLE = Path(__file__).resolve().parent.parent / "inputs" / "ten_story_elcentro.toml"
SHORT = ["ground_motion.window=[0, 4]"]
FORKSERVER = "forkserver" in multiprocessing.get_all_start_methods()


@pytest.fixture(scope="module")
def plan():
    """Four exact cases (two stiffnesses x rigid, uplift) and two simplified ones."""
    return plan_sweep(EXAMPLE, SHORT, ["foundation.frequency_ratio=4,8"], ["exact", "simplified"],
                      ["rigid", "uplift"])


@pytest.fixture(scope="module")
def serial_rows(plan, tmp_path_factory):
    return run_sweep(plan, SerialExecutor(), RowStore(tmp_path_factory.mktemp("serial") / "rows.jsonl")).rows


def _warm_state() -> dict:
    """What a worker has in memory when it is handed its first chunk."""
    compiled = False
    if "upliftcli.engines.exact.stepping_kernels" in sys.modules:
        compiled = bool(sys.modules["upliftcli.engines.exact.stepping_kernels"].integrate.overloads)
    return {"numba": "numba" in sys.modules, "compiled": compiled, "pid": os.getpid()}


_FIRST: dict | None = None


def _with(extra: dict, chunk, emit):
    """run_chunk with `extra` added to each row (as emitted and as returned)."""
    def tagged(message):
        kind, value = message
        emit((kind, {**value, **extra} if kind == "row" else value))

    return [{**row, **extra} for row in run_chunk(chunk, tagged)]


def _reports_warm_state(chunk, emit):
    """Chunk runner: each row carries the worker's state before its first chunk ran."""
    global _FIRST
    if _FIRST is None:
        _FIRST = _warm_state()
    return _with({"warm": _FIRST}, chunk, emit)


@pytest.mark.skipif(not FORKSERVER, reason="no forkserver on this platform (workers are spawned)")
def test_forked_workers_start_with_the_engines_loaded(plan, serial_rows, tmp_path):
    executor = ProcessExecutor(2, runner=_reports_warm_state)
    assert executor.start_method == "forkserver"
    executor.prestart()
    rows = run_sweep(plan, executor, RowStore(tmp_path / "rows.jsonl"), size=1).rows
    assert all(row["warm"]["numba"] and row["warm"]["compiled"] for row in rows)
    assert len({row["warm"]["pid"] for row in rows}) == 2  # both workers
    assert [{k: v for k, v in row.items() if k != "warm"} for row in rows] == serial_rows


def test_spawned_workers_give_the_same_rows(plan, serial_rows, tmp_path):
    executor = ProcessExecutor(2, runner=_reports_warm_state, start_method="spawn")
    rows = run_sweep(plan, executor, RowStore(tmp_path / "rows.jsonl"), size=2).rows
    assert not any(row["warm"]["compiled"] for row in rows)  # a spawned worker starts empty
    assert [{k: v for k, v in row.items() if k != "warm"} for row in rows] == serial_rows


def test_workers_see_the_parents_environment_and_directory_of_now(plan, tmp_path, monkeypatch):
    """The warm server started earlier; a worker still gets the environment and the working
    directory of the sweep's start (relative deck and record paths)."""
    ProcessExecutor(2).prestart()
    monkeypatch.setenv("UPLIFT_TEST_LATE", "set after the server started")
    monkeypatch.chdir(tmp_path)
    rows = run_sweep(plan, ProcessExecutor(2, runner=_reports_environment), RowStore(tmp_path / "rows.jsonl")).rows
    assert {row["late"] for row in rows} == {"set after the server started"}
    assert {row["directory"] for row in rows} == {str(tmp_path)}


def _reports_environment(chunk, emit):
    return _with({"late": os.environ.get("UPLIFT_TEST_LATE"), "directory": os.getcwd()}, chunk, emit)
