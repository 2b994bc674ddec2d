"""sweep/table.py: the summary and the envelope over foundation fields."""


import pytest
from sweep_cases import EXAMPLE, memory_store

from upliftcli.sweep import table as sweep_table
from upliftcli.sweep.executors import SerialExecutor
from upliftcli.sweep.plan import (
    plan_sweep,
)
from upliftcli.sweep.run import run_sweep

# ----------------------------------------------------------------------------- parsing


def test_envelope_over_foundation_stiffness():
    """Bonded tends to rigid as k_f grows (T1bar -> T_1): the upper-bound row equals the rigid one
    to the period lengthening; lower and upper bound are the rows at the smallest and largest k_f."""
    plan = plan_sweep(EXAMPLE, [], ["foundation.k_f=1e8:1e15:8:log"], ["simplified"], ["rigid", "bonded"])
    rows = run_sweep(plan, SerialExecutor(), memory_store()).rows
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
