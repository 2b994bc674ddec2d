"""The small sweep the tests of sweep/ share (fixtures registered in conftest.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

from upliftcli.sweep.executors import SerialExecutor
from upliftcli.sweep.plan import plan_sweep
from upliftcli.sweep.run import run_sweep
from upliftcli.sweep.store import RowStore

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
ASCE7 = ROOT / "inputs" / "ten_story_asce7.toml"
SHORT = ["ground_motion.window=[0, 6]"]  # a short record keeps the response-history cases fast

OUTPUTS = ("base_shear_N", "base_moment_N", "base_shear_coefficient", "base_moment_coefficient", "max_drift_ratio",
           "max_drift_story", "uplift", "V_c_N", "T1_s", "T1bar_s", "xi1bar")


def memory_store():
    """A RowStore in a new temporary folder."""
    import tempfile

    return RowStore(Path(tempfile.mkdtemp()) / "rows.jsonl")


@pytest.fixture()
def batch_sizes(monkeypatch):
    """The number of systems of each batch the exact engine is given (a list filled as it runs)."""
    from upliftcli.engines import exact

    sizes = []
    original = exact.iter_batch

    def recording(systems, *args, **kwargs):
        sizes.append(len(systems))
        return original(systems, *args, **kwargs)

    monkeypatch.setattr(exact, "iter_batch", recording)
    return sizes


@pytest.fixture(scope="session")
def small_plan():
    """12 simplified cases and 2 exact ones (uplift, short record)."""
    plan = plan_sweep(EXAMPLE, SHORT, ["foundation.frequency_ratio=4:16:2", "building.period=0.4,1.2"],
                      ["simplified", "exact"], ["rigid", "bonded", "uplift"])
    plan.cases = [c for c in plan.cases if c.engine == "simplified"
                  or (c.support == "uplift" and c.overrides[0][1] == 4)]
    return plan


@pytest.fixture(scope="session")
def serial_rows(small_plan, tmp_path_factory):
    outcome = run_sweep(small_plan, SerialExecutor(), RowStore(tmp_path_factory.mktemp("serial") / "rows.jsonl"))
    assert not outcome.interrupted and outcome.reused == 0
    return outcome.rows


@pytest.fixture(scope="session")
def dask_cluster():
    distributed = pytest.importorskip("distributed")
    import logging

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=":0", silence_logs=logging.ERROR) as cluster:
        yield cluster
