"""Sweeps: parsing, case expansion, rows equal single analyses, storage and resume,
executors (serial, local processes, Dask LocalCluster) giving identical rows, worker deaths,
summary and envelope."""

import json
import math
import os
from pathlib import Path

import numpy as np
import pytest

from upliftcli.analysis import run_one
from upliftcli.deck import load_deck
from upliftcli.errors import InputError
from upliftcli.sweep import table as sweep_table
from upliftcli.sweep.executors import DaskExecutor, ProcessExecutor, SerialExecutor
from upliftcli.sweep.plan import (
    Case,
    Chunk,
    expand_cases,
    make_chunks,
    parse_choices,
    parse_values,
    parse_vary,
    plan_sweep,
)
from upliftcli.sweep.run import run_sweep
from upliftcli.sweep.store import RowStore
from upliftcli.sweep.worker import run_chunk

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
ASCE7 = ROOT / "inputs" / "ten_story_asce7.toml"
SHORT = ["ground_motion.window=[0, 6]"]  # a short record keeps the response-history cases fast

OUTPUTS = ("base_shear_N", "base_moment_N", "base_shear_coefficient", "base_moment_coefficient", "max_drift_ratio",
           "max_drift_story", "uplift", "V_c_N", "T1_s", "T1bar_s", "xi1bar")


# ----------------------------------------------------------------------------- parsing

def test_parse_values_ranges_and_lists():
    values, spacing = parse_values("1e7:1e10:4:log", "--vary")
    assert spacing == "log" and values == [1e7, 1e8, 1e9, 1e10]
    values, spacing = parse_values("0.2:3:15", "--vary")
    assert spacing == "linear" and len(values) == 15 and values[0] == 0.2 and values[-1] == 3.0
    assert values[1] == 0.4  # rounded to 12 digits, not 0.39999999999999997
    np.testing.assert_allclose(np.diff(values), 0.2, rtol=1e-12)
    assert parse_values("1:5:5", "--vary") == ([1, 2, 3, 4, 5], "linear")  # integers stay integers
    assert parse_values("srss,cqc", "--vary") == (["srss", "cqc"], "list")
    assert parse_values("[0.5, 1]", "--vary") == ([0.5, 1], "list")
    assert parse_values("0.05:5:3", "--periods", "log")[0] == [0.05, 0.5, 5.0]
    for bad in ("1:2", "0:10:5:log", "a:b:3", "1:2:0", "1:2:3:cubic", "[]"):
        with pytest.raises(InputError):
            parse_values(bad, "--vary")


def test_parse_vary_checks_the_path():
    vary = parse_vary("foundation.k_f=1e7:1e9:3:log")
    assert vary.path == "foundation.k_f" and vary.unit == "N/m" and vary.values == (1e7, 1e8, 1e9)
    with pytest.raises(InputError, match="did you mean 'foundation.k_f'"):
        parse_vary("foundation.kf=1:2:2")
    with pytest.raises(InputError, match="--engine"):
        parse_vary("analysis.engine=exact,simplified")
    with pytest.raises(InputError):
        parse_vary("building.period")
    assert parse_choices(["exact,simplified", "all"], ("simplified", "approximate", "exact"), "--engine") == \
        ["exact", "simplified", "approximate"]
    with pytest.raises(InputError, match="--support"):
        parse_choices(["rigid,flying"], ("rigid", "bonded", "uplift"), "--support")


def test_cartesian_product_order_and_stable_keys():
    varies = [parse_vary("foundation.k_f=1e8,1e9"), parse_vary("building.period=0.5,1.0,2.0")]
    cases = expand_cases(varies, ["simplified"], ["rigid", "uplift"], "deck-hash")
    assert len(cases) == 2 * 3 * 2
    assert [c.index for c in cases] == list(range(12))
    assert cases[0].overrides == (("foundation.k_f", 1e8), ("building.period", 0.5))
    assert (cases[0].support, cases[1].support) == ("rigid", "uplift")  # support innermost: one deck, adjacent
    assert cases[-1].overrides == (("foundation.k_f", 1e9), ("building.period", 2.0))
    again = expand_cases(varies, ["simplified"], ["rigid", "uplift"], "deck-hash")
    assert [c.key for c in cases] == [c.key for c in again]
    assert len({c.key for c in cases}) == 12
    other = expand_cases(varies, ["simplified"], ["rigid", "uplift"], "another-deck")
    assert not {c.key for c in cases} & {c.key for c in other}


def test_plan_validates_every_case_before_running():
    with pytest.raises(InputError) as info:
        plan_sweep(EXAMPLE, [], ["foundation.b=-1,2"])
    assert str(info.value).startswith("--vary: foundation.b:")
    with pytest.raises(InputError, match="record for the exact engine"):
        plan_sweep(ASCE7, [], ["building.period=0.5,1"], ["exact"])
    with pytest.raises(InputError, match="each field varied once"):
        plan_sweep(EXAMPLE, [], ["building.period=0.5,1", "building.period=2"])


# ----------------------------------------------------------------------------- rows

@pytest.fixture(scope="module")
def small_plan():
    """12 simplified cases and 2 exact ones (uplift, short record)."""
    plan = plan_sweep(EXAMPLE, SHORT, ["foundation.frequency_ratio=4:16:2", "building.period=0.4,1.2"],
                      ["simplified", "exact"], ["rigid", "bonded", "uplift"])
    plan.cases = [c for c in plan.cases if c.engine == "simplified"
                  or (c.support == "uplift" and c.overrides[0][1] == 4)]
    return plan


@pytest.fixture(scope="module")
def serial_rows(small_plan, tmp_path_factory):
    outcome = run_sweep(small_plan, SerialExecutor(), RowStore(tmp_path_factory.mktemp("serial") / "rows.jsonl"))
    assert not outcome.interrupted and outcome.reused == 0
    return outcome.rows


def test_rows_equal_single_analyses(small_plan, serial_rows):
    assert len(serial_rows) == len(small_plan.cases) == 14
    for case, row in zip(small_plan.cases, serial_rows):
        assert row["status"] == "ok", row
        settings = SHORT + [f"{path}={value}" for path, value in case.overrides]
        deck = load_deck(EXAMPLE, settings)
        result = run_one(deck, case.engine, case.support)
        assert row["base_shear_N"] == result.base_shear
        assert row["base_moment_Nm"] == result.base_moment
        assert row["base_shear_coefficient"] == result.base_shear_coefficient
        assert row["max_drift_ratio"] == float(np.max(result.drift_ratio))
        assert row["max_drift_story"] == int(np.argmax(result.drift_ratio)) + 1
        assert row["max_floor_acceleration_m_s2"] == float(np.max(result.floor_acceleration))
        assert row["max_reaction_N"] == (float(np.max(result.reaction)) if case.support != "rigid" else 0.0)
        assert row.get("max_impact_N") == (float(np.max(result.impact, initial=0.0))
                                          if case.engine != "simplified" else None)
        assert row["uplift"] is bool(result.uplift)
        assert row["T1_s"] == pytest.approx(dict(case.overrides)["building.period"], rel=1e-9)
        assert row["violations"] == "; ".join(
            f"{case.engine}/{case.support}: drift_ratio = {row['max_drift_ratio']:.4g} exceeds the limit 0.02 [-]"
            for _ in [0] if row["max_drift_ratio"] > 0.02)


def test_effective_period_of_the_rows_by_eq_21(small_plan, serial_rows):
    """T1bar = T_1 sqrt(1 + k_1* h_1*^2 / K_theta), K_theta = 2 k_f b^2, rebuilt from the deck here."""
    for case, row in zip(small_plan.cases, serial_rows):
        system = load_deck(EXAMPLE, SHORT + [f"{p}={v}" for p, v in case.overrides], load_ground_motion=False).system
        if case.support == "rigid":
            assert row["T1bar_s"] == row["T1_s"] and row["xi1bar"] == 0.05
            continue
        m1, h1 = system.modes.effective_mass[0], system.modes.effective_height[0]
        k1 = (2 * math.pi / row["T1_s"]) ** 2 * m1
        ratio = dict(case.overrides)["foundation.frequency_ratio"]
        k_f = (ratio * 2 * math.pi / row["T1_s"]) ** 2 * system.total_mass / 2  # w_v = sqrt(2 k_f / m_t)
        expected = row["T1_s"] * math.sqrt(1 + k1 * h1**2 / (2 * k_f * system.half_width**2))
        assert row["T1bar_s"] == pytest.approx(expected, rel=1e-9)


def test_mode_contributions_of_simplified_rows(serial_rows):
    for row in serial_rows:
        if row["engine"] != "simplified":
            assert row["two_mode_base_shear_coefficient"] is None
            assert row["mode1_base_shear_coefficient"] > 0
            continue
        assert row["mode1_base_shear_coefficient"] <= row["two_mode_base_shear_coefficient"] \
            <= row["base_shear_coefficient"] * (1 + 1e-12)
        if row["uplift"]:  # Eq. 28a: the mode-1 base shear with uplift is above V_c, unless the improved
            # procedure's cap at the bonded or rigid V_b binds (then V_n is scaled with V_b)
            same = [r for r in serial_rows if r["engine"] == "simplified" and r["T1_s"] == row["T1_s"]
                    and (r["support"] == "rigid" or (r["support"] == "bonded" and r["T1bar_s"] == row["T1bar_s"]))]
            capped = row["base_shear_coefficient"] == min(r["base_shear_coefficient"] for r in same)
            assert capped or row["mode1_base_shear_coefficient"] > row["critical_coefficient"]
        assert row["critical_coefficient"] == pytest.approx(0.1)  # h_1*/b = 10


def test_failed_case_is_recorded_with_its_message():
    # a case beyond the exact engine's memory limit is refused by the worker before it
    # allocates anything, as a failed row naming the field
    plan = plan_sweep(EXAMPLE, SHORT + ["analysis.exact.time_step=1e-7"], [], ["exact"], ["rigid"])
    rows = run_chunk(make_chunks(plan, plan.cases, 4)[0])
    assert rows[0]["status"] == "failed"
    assert rows[0]["message"].startswith("--set: analysis.exact.time_step: at most 50,000,000 internal steps")
    assert rows[0]["case"] == 0 and rows[0]["engine"] == "exact"


# ----------------------------------------------------------------------------- storage and resume

def test_row_store_appends_and_ignores_a_torn_line(tmp_path):
    store = RowStore(tmp_path / "rows.jsonl")
    store.open(fresh=True)
    store.append({"key": "a", "status": "ok", "x": 1.0})
    store.append({"key": "b", "status": "failed", "message": "boom"})
    store.close()
    with open(store.path, "a") as handle:
        handle.write('{"key": "c", "sta')  # killed while writing
    assert set(store.read()) == {"a", "b"}
    store.open(fresh=False)
    store.append({"key": "c", "status": "ok"})
    store.close()
    lines = store.path.read_text().splitlines()
    assert [json.loads(line)["key"] for line in lines] == ["a", "b", "c"]


def test_resume_skips_finished_cases_and_gives_the_same_rows(small_plan, serial_rows, tmp_path):
    path = tmp_path / "rows.jsonl"
    path.write_text("".join(json.dumps({**row, "fingerprint": small_plan.fingerprint}) + "\n"
                            for row in serial_rows[:5]))
    seen = []

    class Recording(SerialExecutor):
        def run(self, chunks, on_row):
            seen.extend(case.key for chunk in chunks for case in chunk.cases)
            super().run(chunks, on_row)

    outcome = run_sweep(small_plan, Recording(), RowStore(path), resume=True)
    assert outcome.reused == 5 and sorted(seen) == sorted(c.key for c in small_plan.cases[5:])
    assert outcome.rows == serial_rows
    assert len(path.read_text().splitlines()) == len(serial_rows) + 1  # and the header line of the run


def test_resume_reruns_crashed_and_optionally_failed_cases(small_plan, serial_rows, tmp_path):
    path = tmp_path / "rows.jsonl"
    rows = [dict(r) for r in serial_rows]
    rows[0].update(status="crashed", message="worker died")
    rows[1].update(status="failed", message="boom")
    path.write_text("".join(json.dumps({**row, "fingerprint": small_plan.fingerprint}) + "\n" for row in rows))
    outcome = run_sweep(small_plan, SerialExecutor(), RowStore(path), resume=True)
    assert outcome.reused == len(rows) - 1 and outcome.rows[0] == serial_rows[0]
    assert outcome.rows[1]["status"] == "failed"  # deterministic failure: reported, not retried
    outcome = run_sweep(small_plan, SerialExecutor(), RowStore(path), resume=True, retry_failed=True)
    assert outcome.rows == serial_rows


def test_ctrl_c_keeps_the_finished_rows(small_plan, serial_rows, tmp_path):
    class Interrupted(SerialExecutor):
        def run(self, chunks, on_row):
            for row in serial_rows[:3]:
                on_row(row)
            raise KeyboardInterrupt

    path = tmp_path / "rows.jsonl"
    outcome = run_sweep(small_plan, Interrupted(), RowStore(path))
    assert outcome.interrupted and outcome.rows == serial_rows[:3]
    assert len(RowStore(path).read()) == 3


# ----------------------------------------------------------------------------- executors

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


def test_a_dead_worker_is_retried_and_a_killer_case_reported(small_plan, serial_rows, tmp_path, monkeypatch):
    monkeypatch.setenv("UPLIFT_TEST_MARKER", str(tmp_path / "marker"))
    simplified = [c for c in small_plan.cases if c.engine == "simplified"]
    plan = type(small_plan)(**{**small_plan.__dict__, "cases": simplified})
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


@pytest.fixture(scope="module")
def dask_cluster():
    distributed = pytest.importorskip("distributed")
    import logging

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=":0", silence_logs=logging.ERROR) as cluster:
        yield cluster


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
    remote = CliRunner().invoke(app, args + ["--scheduler", dask_cluster.scheduler_address, "--name", "dask"],
                                env={"CI": "true"})
    assert remote.exit_code == 0, remote.output
    local = CliRunner().invoke(app, args + ["--workers", "1", "--name", "serial"], env={"CI": "true"})
    assert local.exit_code == 0, local.output
    assert (tmp_path / "dask.csv").read_text() == (tmp_path / "serial.csv").read_text()


def test_unreachable_scheduler_is_bad_input(small_plan, tmp_path):
    pytest.importorskip("distributed")
    executor = DaskExecutor("tcp://127.0.0.1:9", connect_timeout="1s")
    with pytest.raises(InputError, match="--scheduler"):
        run_sweep(small_plan, executor, RowStore(tmp_path / "rows.jsonl"))


# ----------------------------------------------------------------------------- summary

def test_envelope_over_foundation_stiffness():
    """Bonded tends to rigid as k_f grows (T1bar -> T_1): the upper-bound row equals the rigid one
    to the period lengthening; lower and upper bound are the rows at the smallest and largest k_f."""
    plan = plan_sweep(EXAMPLE, [], ["foundation.k_f=1e8:1e15:8:log"], ["simplified"], ["rigid", "bonded"])
    rows = run_sweep(plan, SerialExecutor(), _memory_store()).rows
    envelope = sweep_table.envelope(plan, rows)
    assert [e["group"] for e in envelope] == [{"engine": "simplified", "support": "rigid"},
                                              {"engine": "simplified", "support": "bonded"}]
    bonded = [r for r in rows if r["support"] == "bonded"]
    rigid = rows[0]
    item = envelope[1]["outputs"]["base_shear_coefficient"]
    assert item["at_lower_bound"] == bonded[0]["base_shear_coefficient"]
    assert item["at_upper_bound"] == bonded[-1]["base_shear_coefficient"]
    assert item["highest"] == max(r["base_shear_coefficient"] for r in bonded)
    assert item["lowest"] == min(r["base_shear_coefficient"] for r in bonded)
    assert bonded[-1]["T1bar_s"] == pytest.approx(rigid["T1_s"], rel=1e-4)
    assert bonded[-1]["base_shear_coefficient"] == pytest.approx(rigid["base_shear_coefficient"], rel=1e-3)
    rigid_item = envelope[0]["outputs"]["max_drift_ratio"]
    assert rigid_item["lowest"] == rigid_item["highest"]  # a rigid base does not see k_f
    governing = sweep_table.governing(plan, rows)
    top = max(rows, key=lambda r: r["base_shear_coefficient"])
    assert governing["base_shear_coefficient"]["case"] == top["case"]
    summary = sweep_table.summarize(plan, rows)
    assert summary["ok"] == len(rows) and summary["ranges"][0]["lowest"] == 1e8


def _memory_store():
    import tempfile

    return RowStore(Path(tempfile.mkdtemp()) / "rows.jsonl")


def test_case_dataclass_is_picklable():
    import pickle

    case = Case(0, "k", (("building.period", 0.5),), "simplified", "rigid")
    chunk = Chunk({"a": 1}, "deck.toml", (), [case])
    assert pickle.loads(pickle.dumps(chunk)) == chunk


def test_ground_motion_cache_follows_the_varied_record_fields():
    """Rigid base, simplified engine: linear, so the base shear is proportional to the record scale.
    Each scale must get its own record (the worker caches records by their fields)."""
    plan = plan_sweep(EXAMPLE, [], ["ground_motion.scale=0.5,1,2.5", "building.period=0.4,1.3"], ["simplified"],
                      ["rigid"])
    rows = run_chunk(make_chunks(plan, plan.cases, len(plan.cases))[0])
    by_input = {(r["ground_motion.scale"], r["building.period"]): r["base_shear_N"] for r in rows}
    for period in (0.4, 1.3):
        assert by_input[(0.5, period)] == pytest.approx(0.5 * by_input[(1, period)], rel=1e-12)
        assert by_input[(2.5, period)] == pytest.approx(2.5 * by_input[(1, period)], rel=1e-12)


def test_cases_sharing_a_structure_run_as_one_batch(monkeypatch):
    """Chunks put together the cases that differ only in foundation fields (whatever the --vary
    order), and the exact engine gets each such group as one batch; the rows equal the
    single analyses."""
    from upliftcli.engines import exact

    plan = plan_sweep(EXAMPLE, ["ground_motion.window=[0, 3]"],
                      ["foundation.frequency_ratio=4,8,16", "building.period=0.4,1.2"], ["exact"], ["uplift"])
    chunks = make_chunks(plan, plan.cases, 3)
    assert [[dict(c.overrides)["building.period"] for c in chunk.cases] for chunk in chunks] == [[0.4] * 3, [1.2] * 3]
    sizes = []
    original = exact.iter_batch

    def recording(systems, *args, **kwargs):
        sizes.append(len(systems))
        return original(systems, *args, **kwargs)

    monkeypatch.setattr(exact, "iter_batch", recording)
    rows = [row for chunk in chunks for row in run_chunk(chunk)]
    assert sizes == [3, 3]
    for case, row in zip([c for chunk in chunks for c in chunk.cases], rows):
        deck = load_deck(EXAMPLE, ["ground_motion.window=[0, 3]"] + [f"{p}={v}" for p, v in case.overrides])
        result = run_one(deck, "exact", "uplift")
        assert row["key"] == case.key and row["base_shear_N"] == result.base_shear
        assert row["max_drift_ratio"] == float(np.max(result.drift_ratio))


def test_dask_dead_worker_keeps_streamed_rows_and_reports_only_the_killer(small_plan, serial_rows, tmp_path):
    """A case that kills its Dask worker every time: the cases its chunk finished before it are
    kept (streamed, not lost with the chunk), it is run alone and reported 'crashed' once the
    scheduler gives up on it, and the cases after it in the chunk run again elsewhere."""
    distributed = pytest.importorskip("distributed")
    import logging

    import dask

    simplified = [c for c in small_plan.cases if c.engine == "simplified"]
    plan = type(small_plan)(**{**small_plan.__dict__, "cases": simplified})
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


def test_rows_of_a_batch_are_emitted_as_each_case_ends():
    """An exact batch reports each case as soon as it is known, not when the batch ends: a case
    refused before stepping (too stiff a foundation for the step limit) comes out first, and a
    Ctrl-C later in the batch would keep it."""
    plan = plan_sweep(EXAMPLE, ["ground_motion.window=[0, 3]", "building.period=0.5"],
                      ["foundation.frequency_ratio=8,1e6,16"], ["exact"], ["uplift"])
    (chunk,) = make_chunks(plan, plan.cases, 3)
    messages = []
    rows = run_chunk(chunk, messages.append)
    assert messages[0] == ("start", [case.key for case in chunk.cases])
    emitted = [value for kind, value in messages[1:] if kind == "row"]
    assert len(messages) == 4 and emitted[0]["case"] == 1 and emitted[0]["status"] == "failed"
    assert sorted(r["case"] for r in emitted) == [0, 1, 2] and [r["case"] for r in rows] == [0, 1, 2]
    assert all(r["status"] == "ok" for r in emitted[1:])


# ----------------------------------------------------------------------------- nothing lost, no hang (issue 13)

def test_range_sizes_are_refused_before_expanding():
    import time

    start = time.perf_counter()
    with pytest.raises(InputError, match=r"^--vary foundation.b: 1:2:100000000: at most 10,000 values in one range"):
        parse_vary("foundation.b=1:2:100000000")
    many = ",".join(str(1 + 1e-6 * i) for i in range(1_000_000))
    with pytest.raises(InputError, match=r"at most 10,000 values in one range \(limit of the tool\), got 1,000,000"):
        parse_vary(f"foundation.b={many}")
    with pytest.raises(InputError, match=r"^--vary foundation.b: values on one line"):
        parse_vary("foundation.b=1,2\n3")
    with pytest.raises(InputError, match=r"^--vary: at most 100,000 cases, got 2,430,000 \(30 x 30 x 30 x 30 x 3\)"):
        plan_sweep(EXAMPLE, [], ["foundation.b=1:2:30", "building.period=0.5:1:30",
                                 "foundation.damping_ratio=0.1:0.3:30", "foundation.frequency_ratio=4:8:30"])
    assert time.perf_counter() - start < 10.0  # each was minutes and hundreds of MB


def test_plan_fingerprints_the_records_and_the_version():
    from upliftcli.sweep.plan import file_sha256

    plan = plan_sweep(EXAMPLE, SHORT, ["building.period=0.5,1"], ["simplified"], ["rigid"])
    (record,) = plan.records
    assert Path(record).resolve() == (ROOT / "records" / "elcentro_1940_ns_chopra.txt").resolve()
    assert plan.records[record] == file_sha256(record) and len(plan.records[record]) == 64
    assert plan.version and len(plan.fingerprint) == 20
    assert plan.input_files == [str(EXAMPLE), record]
    assert plan.record_steps[record] == (0.02, 301)
    other = plan_sweep(EXAMPLE, SHORT, ["building.period=0.5,2"], ["simplified"], ["rigid"])
    assert other.fingerprint == plan.fingerprint  # the varied values are in the case keys, not in the fingerprint


def _deck_with_own_record(tmp_path):
    record = tmp_path / "rec.txt"
    record.write_bytes((ROOT / "records" / "elcentro_1940_ns_chopra.txt").read_bytes())
    deck = tmp_path / "deck.toml"
    deck.write_text(EXAMPLE.read_text().replace("../records/elcentro_1940_ns_chopra.txt", "rec.txt"))
    return deck, record


def test_resume_refuses_rows_of_a_changed_record_or_reruns_them(tmp_path):
    deck, record = _deck_with_own_record(tmp_path)
    store = RowStore(tmp_path / "rows.jsonl")
    plan = plan_sweep(deck, SHORT, ["building.period=0.5,1"], ["simplified"], ["rigid"])
    first = run_sweep(plan, SerialExecutor(), store)
    header = json.loads(store.path.read_text().splitlines()[0])["run"]
    assert header["fingerprint"] == plan.fingerprint and header["records"] == plan.records
    lines = record.read_text().splitlines()  # double the record
    record.write_text("\n".join(line if line.startswith("#") else f"{line.split()[0]} {2 * float(line.split()[1])}"
                                for line in lines) + "\n")
    doubled = plan_sweep(deck, SHORT, ["building.period=0.5,1"], ["simplified"], ["rigid"])
    assert [c.key for c in doubled.cases] == [c.key for c in plan.cases] and doubled.fingerprint != plan.fingerprint
    with pytest.raises(InputError, match=r"^--resume: .*rows.jsonl: rows computed from the inputs of this run; 2 rows "
                                         r"were computed from another content of the record .*rec.txt \(its SHA-256 "
                                         r"changed\): pass --rerun-stale"):
        run_sweep(doubled, SerialExecutor(), store, resume=True)
    again = run_sweep(doubled, SerialExecutor(), store, resume=True, rerun_stale=True)
    assert again.reused == 0
    for old, new in zip(first.rows, again.rows, strict=True):
        assert new["base_shear_N"] == pytest.approx(2 * old["base_shear_N"], rel=1e-12)  # linear: twice the record
    assert run_sweep(doubled, SerialExecutor(), store, resume=True).reused == 2  # now they match


def test_resume_refuses_rows_without_a_fingerprint(small_plan, serial_rows, tmp_path):
    path = tmp_path / "rows.jsonl"
    path.write_text("".join(json.dumps(row) + "\n" for row in serial_rows[:3]))  # as older versions wrote them
    with pytest.raises(InputError, match="3 rows were computed by a run that recorded no fingerprint"):
        run_sweep(small_plan, SerialExecutor(), RowStore(path), resume=True)


def test_a_run_that_stops_before_its_first_row_leaves_no_rows_file(small_plan, tmp_path):
    class Failing(SerialExecutor):
        def run(self, chunks, on_row):
            raise OSError(111, "Connection refused")

    path = tmp_path / "rows.jsonl"
    with pytest.raises(OSError):
        run_sweep(small_plan, Failing(), RowStore(path))
    assert not path.exists()


def test_stem_lock_refuses_a_second_sweep(tmp_path):
    from upliftcli.sweep.store import stem_lock

    out = tmp_path / "out"
    with stem_lock(out, "deck.sweep"):
        assert (out / ".deck.sweep.lock").exists()
        with pytest.raises(InputError, match=r"^--out: .*deck.sweep: an output stem no other sweep is writing"), \
                stem_lock(out, "deck.sweep"):
            pass
        with stem_lock(out, "other.sweep"):  # another stem: fine
            pass
    assert not out.exists()  # created for the lock, left empty: removed
    out.mkdir()
    with stem_lock(out, "deck.sweep"):
        pass
    assert out.exists() and list(out.iterdir()) == []


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
    import time

    plan = plan_sweep(EXAMPLE, SHORT, ["foundation.frequency_ratio=4:16:60"], ["simplified"],
                      ["rigid", "bonded", "uplift"])
    store = FullDisk(tmp_path / "rows.jsonl", room=5)
    earlier = set(multiprocessing.active_children())  # processes of other tests
    start = time.perf_counter()
    with pytest.raises(OSError, match="No space left"):
        run_sweep(plan, ProcessExecutor(2), store, size=2)
    assert time.perf_counter() - start < 60.0
    deadline = time.monotonic() + 10.0
    while set(multiprocessing.active_children()) - earlier and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not set(multiprocessing.active_children()) - earlier
    assert len(RowStore(store.path).read()) == 5


@pytest.mark.parametrize("signum", ["SIGTERM", "SIGHUP"])
def test_sigterm_and_sighup_stop_a_sweep_like_ctrl_c(small_plan, serial_rows, tmp_path, signum):
    import signal

    signum = getattr(signal, signum)

    class Terminated(SerialExecutor):
        def run(self, chunks, on_row):
            for row in serial_rows[:4]:
                on_row(row)
            os.kill(os.getpid(), signum)
            for row in serial_rows[4:]:  # never reached: the signal interrupts here
                on_row(row)

    before = signal.getsignal(signum)
    outcome = run_sweep(small_plan, Terminated(), RowStore(tmp_path / "rows.jsonl"))
    assert outcome.interrupted and outcome.signal == signum and outcome.rows == serial_rows[:4]
    assert signal.getsignal(signum) is before  # handlers restored


def test_workers_exit_with_their_parent(tmp_path):
    """exit_with_parent: a process whose parent dies (here: exits at once) ends too."""
    import subprocess
    import sys
    import time

    script = (
        "import os, sys, time\n"
        "from upliftcli.sweep.executors import exit_with_parent\n"
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
    deadline = time.monotonic() + 10.0

    def alive() -> bool:
        try:
            state = Path(f"/proc/{child}/status").read_text()
        except FileNotFoundError:
            return False
        return "\nState:\tZ" not in state

    while alive() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not alive()


def test_an_unreachable_scheduler_is_refused_at_once():
    import socket
    import time

    from upliftcli.sweep.executors import check_reachable

    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        port = server.getsockname()[1]
        server.listen()
        check_reachable(f"tcp://127.0.0.1:{port}")  # listening: fine
    start = time.perf_counter()
    with pytest.raises(InputError, match=rf"^--scheduler: tcp://127.0.0.1:{port}: a reachable Dask scheduler"):
        check_reachable(f"tcp://127.0.0.1:{port}")
    assert time.perf_counter() - start < 5.0
    with pytest.raises(InputError, match="an address tcp://host:port"):
        check_reachable("tcp://127.0.0.1:port")
