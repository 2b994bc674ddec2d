"""sweep/executors.py: local processes and Dask give the serial rows; dead workers, full disks,
parents that die; local workers forked from the warm server start with the engines loaded."""

import dataclasses
import functools
import multiprocessing
import os
import signal
import sys
import time
from pathlib import Path

import pytest
from sweep_cases import EXAMPLE, SHORT

from upliftcli.errors import InputError
from upliftcli.sweep.chunks import Chunk, make_chunks
from upliftcli.sweep.dask_executor import DaskExecutor
from upliftcli.sweep.executors import ProcessExecutor
from upliftcli.sweep.plan import (
    plan_sweep,
)
from upliftcli.sweep.run import run_sweep
from upliftcli.sweep.store import RowStore
from upliftcli.sweep.worker import run_chunk

# ----------------------------------------------------------------------------- parsing


def test_local_processes_give_the_serial_rows(small_plan, serial_rows, tmp_path):
    outcome = run_sweep(small_plan, ProcessExecutor(2), RowStore(tmp_path / "rows.jsonl"), size=3)
    assert outcome.rows == serial_rows
    assert len(RowStore(tmp_path / "rows.jsonl").read()) == len(serial_rows)


def _dies_once_then_runs(chunk, emit):
    """Chunk runner for the test below: the first worker to reach the case with building.period 1.2,
    rigid support, exits abruptly (as if killed); later attempts run."""
    marker = Path(os.environ["UPLIFT_TEST_MARKER"])
    for case in chunk.cases:
        if dict(case.overrides).get("building.period") == 1.2 and case.support == "rigid" and not marker.exists():
            emit(("start", [case.key]))
            marker.write_text("died")
            os._exit(1)
    return run_chunk(chunk, emit)


def _always_dies(chunk, emit):
    for case in chunk.cases:
        if dict(case.overrides).get("building.period") == 1.2 and case.support == "rigid":
            emit(("start", [case.key]))
            os._exit(1)
    return run_chunk(chunk, emit)


def _stops_once_then_runs(chunk, emit):
    """Chunk runner: the first worker to reach the case with building.period 1.2, rigid support,
    stops itself (SIGSTOP, as `kill -STOP` would); later attempts run; the marker file holds its pid."""
    marker = Path(os.environ["UPLIFT_TEST_MARKER"])
    for case in chunk.cases:
        if dict(case.overrides).get("building.period") == 1.2 and case.support == "rigid" and not marker.exists():
            emit(("start", [case.key]))
            marker.write_text(str(os.getpid()))
            os.kill(os.getpid(), signal.SIGSTOP)
    return run_chunk(chunk, emit)


def test_a_stalled_worker_is_killed_and_its_case_retried(small_plan, serial_rows, tmp_path, monkeypatch):
    """A stopped (SIGSTOP) worker blocked the sweep for ever: without a heartbeat for
    stall_seconds it is killed and its cases run elsewhere; the rows are the serial ones."""
    monkeypatch.setenv("UPLIFT_TEST_MARKER", str(tmp_path / "marker"))
    simplified = [c for c in small_plan.cases if c.engine == "simplified"]
    plan = dataclasses.replace(small_plan, cases=simplified)
    expected = [row for row in serial_rows if row["engine"] == "simplified"]
    outcome = run_sweep(plan, ProcessExecutor(2, runner=_stops_once_then_runs, stall_seconds=3.0),
                        RowStore(tmp_path / "rows.jsonl"), size=4)
    assert outcome.rows == expected
    assert not _running(int((tmp_path / "marker").read_text()))  # the stopped worker was killed, not waited for


def _running(pid: int) -> bool:
    """Whether a process runs (or is stopped): it exists and is not a zombie (Linux: /proc; elsewhere a
    signal 0)."""
    status = Path(f"/proc/{pid}/stat")
    if Path("/proc/self/stat").exists():
        try:
            return status.read_text().rsplit(")", 1)[1].split()[0] != "Z"
        except OSError:
            return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


def test_a_dead_worker_is_retried_and_a_killer_case_reported(small_plan, serial_rows, tmp_path, monkeypatch):
    monkeypatch.setenv("UPLIFT_TEST_MARKER", str(tmp_path / "marker"))
    simplified = [c for c in small_plan.cases if c.engine == "simplified"]
    plan = dataclasses.replace(small_plan, cases=simplified)
    expected = [row for row in serial_rows if row["engine"] == "simplified"]
    outcome = run_sweep(plan, ProcessExecutor(2, runner=_dies_once_then_runs), RowStore(tmp_path / "a.jsonl"), size=4)
    assert (tmp_path / "marker").exists()
    assert outcome.rows == expected

    outcome = run_sweep(plan, ProcessExecutor(2, max_attempts=2, runner=_always_dies), RowStore(tmp_path / "b.jsonl"),
                        size=4)
    crashed = [row for row in outcome.rows if row["status"] != "ok"]
    assert len(outcome.rows) == len(expected)
    assert [(r["support"], r["building.period"]) for r in crashed] == [("rigid", 1.2), ("rigid", 1.2)]
    assert all(r["status"] == "crashed" and "2 attempts" in r["message"] for r in crashed)
    assert [r for r in outcome.rows if r["status"] == "ok"] == \
        [r for r in expected if not (r["support"] == "rigid" and r["building.period"] == 1.2)]


def test_dask_cluster_gives_the_serial_rows(small_plan, serial_rows, dask_cluster, tmp_path):
    executor = DaskExecutor(dask_cluster.scheduler_address)
    outcome = run_sweep(small_plan, executor, RowStore(tmp_path / "rows.jsonl"), size=3)
    assert outcome.rows == serial_rows
    assert executor.workers == 2


def test_dask_cli_scheduler_option(dask_cluster, tmp_path):
    from typer.testing import CliRunner

    from upliftcli.cli import app

    args = ["sweep", str(EXAMPLE), "--vary", "building.period=0.5,1.0", "--support", "uplift", "--out",
            str(tmp_path), "--quiet"]
    remote = CliRunner().invoke(app, [*args, "--scheduler", dask_cluster.scheduler_address, "--name", "dask"],
                                env={"CI": "true"})
    assert remote.exit_code == 0, remote.output
    local = CliRunner().invoke(app, [*args, "--workers", "1", "--name", "serial"], env={"CI": "true"})
    assert local.exit_code == 0, local.output

    def table(path):  # without the '#' provenance lines (time, command)
        return [line for line in path.read_text().splitlines() if not line.startswith("#")]

    assert table(tmp_path / "dask.csv") == table(tmp_path / "serial.csv")


def test_unreachable_scheduler_is_bad_input(small_plan, tmp_path):
    pytest.importorskip("distributed")
    executor = DaskExecutor("tcp://127.0.0.1:9", connect_timeout="1s")
    with pytest.raises(InputError, match="--scheduler"):
        run_sweep(small_plan, executor, RowStore(tmp_path / "rows.jsonl"))


def test_dask_dead_worker_keeps_streamed_rows_and_reports_only_the_killer(small_plan, serial_rows, tmp_path):
    """A case that kills its Dask worker every time: the cases its chunk finished before it are
    kept (streamed, not lost with the chunk), it is run alone and reported 'crashed' once the
    scheduler gives up on it, and the cases after it in the chunk run again elsewhere."""
    distributed = pytest.importorskip("distributed")
    import logging

    import dask

    simplified = [c for c in small_plan.cases if c.engine == "simplified"]
    plan = dataclasses.replace(small_plan, cases=simplified)
    expected = [row for row in serial_rows if row["engine"] == "simplified"]
    killer = next(c for c in make_chunks(plan, simplified, 12)[0].cases[4:]
                  if c.support == "rigid")  # not the first of its chunk
    runs = tmp_path / "runs.txt"

    def runner(chunk, emit):
        with open(runs, "a") as handle:
            handle.write(" ".join(case.key for case in chunk.cases) + "\n")
        for case in chunk.cases:
            if case.key == killer.key:
                emit(("start", [case.key]))
                os._exit(1)
            run_chunk(Chunk(chunk.raw, chunk.source, chunk.base_overrides, [case]), emit)
        return []  # every row went through emit

    with dask.config.set({"distributed.scheduler.allowed-failures": 1}), \
            distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                     dashboard_address=":0", silence_logs=logging.CRITICAL) as cluster:
        outcome = run_sweep(plan, DaskExecutor(cluster.scheduler_address, runner=runner),
                            RowStore(tmp_path / "rows.jsonl"), size=12)
    by_key = {row["key"]: row for row in outcome.rows}
    assert by_key[killer.key]["status"] == "crashed" and "KilledWorker" in by_key[killer.key]["message"]
    assert [r for r in outcome.rows if r["key"] != killer.key] == [r for r in expected if r["key"] != killer.key]
    # the chunk and its retry by the scheduler; then the killer alone (and its retry), which
    # marks it 'crashed', and the cases after it together (again if its worker dies under it
    # before the client fetched the result: the rows were streamed already)
    attempts = [line.split() for line in runs.read_text().splitlines()]
    assert attempts[0] == attempts[1] and len(attempts[0]) == 12
    after = attempts[0][attempts[0].index(killer.key) + 1:]
    assert after and attempts[2:].count([killer.key]) == 2
    others = [a for a in attempts[2:] if a != [killer.key]]
    assert others and all(a == after for a in others)


def test_dask_failure_charges_only_started_cases():
    """KilledWorker also hits tasks only queued on the dying worker: cases that had not started
    are submitted again (a bounded number of times); a started case alone is 'crashed'; started
    cases of a larger chunk run again alone."""
    plan = plan_sweep(EXAMPLE, [], ["building.period=0.5,1,2"], ["simplified"], ["uplift"])
    a, b, c = plan.cases
    chunk = make_chunks(plan, plan.cases, 3)[0]
    rows, resubmits, error = [], {}, RuntimeError("KilledWorker")
    again = DaskExecutor._after_failure(chunk, error, {a.key}, {a.key, b.key}, rows.append, resubmits)
    assert [[x.key for x in ch.cases] for ch in again] == [[b.key], [c.key]] and not rows
    again = DaskExecutor._after_failure(again[0], error, set(), set(), rows.append, resubmits)  # b queued only
    assert [[x.key for x in ch.cases] for ch in again] == [[b.key]] and not rows
    assert DaskExecutor._after_failure(again[0], error, set(), {b.key}, rows.append, resubmits) == []
    assert [(r["key"], r["status"]) for r in rows] == [(b.key, "crashed")]
    single = Chunk(chunk.raw, chunk.source, chunk.base_overrides, [c])
    for _ in range(2):  # c was submitted again once already, with the first failure
        assert DaskExecutor._after_failure(single, error, set(), set(), rows.append, resubmits) == [single]
    assert DaskExecutor._after_failure(single, error, set(), set(), rows.append, resubmits) == []
    assert rows[-1]["key"] == c.key and "submitted 4 times" in rows[-1]["message"]


def test_dask_ctrl_c_keeps_the_streamed_rows_and_resumes(small_plan, serial_rows, dask_cluster, tmp_path):
    """Ctrl-C during a Dask sweep (raised here by the progress hook at the third row): the
    executor cancels its tasks, every row that arrived is in the file, and --resume completes
    the same table."""

    class CtrlC:
        def __init__(self):
            self.seen = 0

        def start(self, total, done):
            pass

        def advance(self, row):
            self.seen += 1
            if self.seen == 3:
                raise KeyboardInterrupt

        def stop(self):
            pass

    store = RowStore(tmp_path / "rows.jsonl")
    outcome = run_sweep(small_plan, DaskExecutor(dask_cluster.scheduler_address), store, size=4, progress=CtrlC())
    assert outcome.interrupted and 3 <= len(outcome.rows) <= len(serial_rows)  # all, if the workers were quick
    assert len(store.read()) == len(outcome.rows)
    resumed = run_sweep(small_plan, DaskExecutor(dask_cluster.scheduler_address), store, resume=True, size=4)
    assert resumed.reused == len(outcome.rows) and resumed.rows == serial_rows


class FullDisk(RowStore):
    """A rows file on a disk that fills up after `room` rows."""

    def __init__(self, path, room):
        super().__init__(path)
        self.room = room

    def append(self, row, fingerprint=None):
        if self.appended >= self.room:
            raise OSError(28, "No space left on device")
        super().append(row, fingerprint)


def test_a_full_disk_stops_local_workers_at_once_and_keeps_the_rows(tmp_path):
    """The error came back but the sweep never exited (the executor's exit handler waited for
    workers blocked on a queue nobody read). Now the workers are killed and the rows kept."""
    import multiprocessing

    plan = plan_sweep(EXAMPLE, SHORT, ["foundation.frequency_ratio=4:16:60"], ["simplified"],
                      ["rigid", "bonded", "uplift"])
    store = FullDisk(tmp_path / "rows.jsonl", room=5)
    earlier = set(multiprocessing.active_children())  # processes of other tests
    with pytest.raises(OSError, match="No space left"):
        run_sweep(plan, ProcessExecutor(2), store, size=2)
    for worker in set(multiprocessing.active_children()) - earlier:  # no clock: each was sent SIGKILL before the
        worker.join()  # error came back, so each ends (one left running would hang here)
        assert worker.exitcode != 0  # stopped, not run to the end: killed, or ended on its own error first
    assert not set(multiprocessing.active_children()) - earlier
    assert len(RowStore(store.path).read()) == 5


@pytest.mark.parametrize("kernel", [True, False], ids=["prctl", "watchdog"])
def test_workers_exit_with_their_parent(tmp_path, kernel):
    """exit_with_parent: a process whose parent dies (here: exits at once) ends too, by the
    kernel's signal (Linux) or by the watchdog thread (elsewhere, forced here)."""
    import subprocess
    import sys
    import time

    script = (
        "import os, sys, time\n"
        "from upliftcli.sweep import executors\n"
        "from upliftcli.sweep.executors import exit_with_parent\n"
        f"executors.PARENT_DEATH_SIGNAL = {kernel}\n"
        "parent = os.getpid()\n"
        "child = os.fork()\n"
        "if child == 0:\n"
        "    exit_with_parent(parent)\n"
        "    time.sleep(60)\n"
        "    os._exit(0)\n"
        "print(child, flush=True)\n"
        "time.sleep(0.5)\n"
        "os._exit(0)\n"
    )
    output = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60).stdout
    child = int(output.split()[0])
    deadline = time.monotonic() + 60.0  # a bound against a hang, not a speed: the kernel kills the child at once

    def alive() -> bool:
        try:
            state = Path(f"/proc/{child}/status").read_text()
        except FileNotFoundError:
            return False
        return "\nState:\tZ" not in state

    while alive() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not alive()


def test_an_unreachable_scheduler_is_refused_at_once(monkeypatch):
    import socket

    from upliftcli.sweep.dask_executor import check_reachable

    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        port = server.getsockname()[1]
        server.listen()
        check_reachable(f"tcp://127.0.0.1:{port}")  # listening: fine
    # "at once": one connection attempt, bounded by the timeout, instead of the Dask client's 20 s
    # of retries (what a clock asserted here before, which a loaded machine could miss)
    attempts, create_connection = [], socket.create_connection

    def connect(address, timeout):
        attempts.append((address, timeout))
        return create_connection(address, timeout=timeout)

    monkeypatch.setattr("upliftcli.sweep.dask_executor.socket.create_connection", connect)
    with pytest.raises(InputError, match=rf"^--scheduler: tcp://127.0.0.1:{port}: a reachable Dask scheduler"):
        check_reachable(f"tcp://127.0.0.1:{port}")
    assert attempts == [(("127.0.0.1", port), 3.0)]
    with pytest.raises(InputError, match="an address tcp://host:port"):
        check_reachable("tcp://127.0.0.1:port")


# ----------------------------------------------------------------------------- the warm server (forkserver)

FORKSERVER = "forkserver" in multiprocessing.get_all_start_methods()


def _warm_state() -> dict:
    """What a worker has in memory when it is handed its first chunk."""
    loops = ("upliftcli.engines.exact._stepping", "upliftcli.engines.exact.stepping_numpy")  # either backend
    return {"engine": "upliftcli.engines.exact.engine" in sys.modules,
            "loops": any(name in sys.modules for name in loops), "pid": os.getpid()}


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


def _meet(directory: str, parties: int = 2) -> None:
    """Wait in a worker's first chunk until `parties` workers have each started one (each leaves
    its pid in `directory`): the work is shared whatever the timing. The bound only keeps a
    broken pool from hanging the suite (the test then fails on the pids, not on a clock)."""
    Path(directory, str(os.getpid())).touch()
    deadline = time.monotonic() + 300.0
    while len(os.listdir(directory)) < parties and time.monotonic() < deadline:
        time.sleep(0.01)


def _reports_warm_state_together(directory: str, chunk, emit):
    """_reports_warm_state, the first chunk of each worker held until both workers have one (_meet)."""
    global _FIRST
    if _FIRST is None:
        _FIRST = _warm_state()
        _meet(directory)
    return _with({"warm": _FIRST}, chunk, emit)


@pytest.mark.skipif(not FORKSERVER, reason="no forkserver on this platform (workers are spawned)")
def test_forked_workers_start_with_the_engines_loaded(small_plan, serial_rows, tmp_path):
    (tmp_path / "meet").mkdir()
    executor = ProcessExecutor(2, runner=functools.partial(_reports_warm_state_together, str(tmp_path / "meet")))
    assert executor.start_method == "forkserver"
    executor.prestart()
    rows = run_sweep(small_plan, executor, RowStore(tmp_path / "rows.jsonl"), size=1).rows
    assert all(row["warm"]["engine"] and row["warm"]["loops"] for row in rows)
    assert len({row["warm"]["pid"] for row in rows}) == 2  # both workers
    assert [{k: v for k, v in row.items() if k != "warm"} for row in rows] == serial_rows


def test_spawned_workers_give_the_same_rows(small_plan, serial_rows, tmp_path):
    executor = ProcessExecutor(2, runner=_reports_warm_state, start_method="spawn")
    rows = run_sweep(small_plan, executor, RowStore(tmp_path / "rows.jsonl"), size=4).rows
    assert not any(row["warm"]["loops"] for row in rows)  # a spawned worker starts empty
    assert [{k: v for k, v in row.items() if k != "warm"} for row in rows] == serial_rows


def test_without_a_forkserver_workers_are_spawned_and_give_the_same_rows(small_plan, serial_rows, tmp_path,
                                                                         monkeypatch):
    """Where multiprocessing has no forkserver (Windows: spawn only), the default is spawn."""
    monkeypatch.setattr(multiprocessing, "get_all_start_methods", lambda: ["spawn"])
    executor = ProcessExecutor(2, runner=_reports_warm_state)
    assert executor.start_method == "spawn" and executor._parent_pid() == os.getpid()
    executor.prestart()  # nothing to start
    rows = run_sweep(small_plan, executor, RowStore(tmp_path / "rows.jsonl"), size=4).rows
    assert not any(row["warm"]["loops"] for row in rows)  # spawned: each worker loads the engines itself
    assert [{k: v for k, v in row.items() if k != "warm"} for row in rows] == serial_rows


def test_workers_see_the_parents_environment_and_directory_of_now(small_plan, tmp_path, monkeypatch):
    """The warm server started earlier; a worker still gets the environment and the working
    directory of the sweep's start (relative deck and record paths)."""
    ProcessExecutor(2).prestart()
    monkeypatch.setenv("UPLIFT_TEST_LATE", "set after the server started")
    monkeypatch.chdir(tmp_path)
    rows = run_sweep(small_plan, ProcessExecutor(2, runner=_reports_environment),
                     RowStore(tmp_path / "rows.jsonl")).rows
    assert {row["late"] for row in rows} == {"set after the server started"}
    assert {row["directory"] for row in rows} == {str(tmp_path)}


def _reports_environment(chunk, emit):
    return _with({"late": os.environ.get("UPLIFT_TEST_LATE"), "directory": os.getcwd()}, chunk, emit)
