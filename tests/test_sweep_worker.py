"""sweep/worker.py: each case's row equals the single analysis; batches of the exact engine; the
ground-motion cache."""

import math

import numpy as np
import pytest
from sweep_cases import EXAMPLE, SHORT

from upliftcli.analysis.run import run_one
from upliftcli.deck.load import load_deck
from upliftcli.sweep.chunks import make_chunks
from upliftcli.sweep.plan import (
    plan_sweep,
)
from upliftcli.sweep.worker import run_chunk

# ----------------------------------------------------------------------------- parsing


def test_rows_equal_single_analyses(small_plan, serial_rows):
    assert len(serial_rows) == len(small_plan.cases) == 14
    for case, row in zip(small_plan.cases, serial_rows, strict=True):
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
    for case, row in zip(small_plan.cases, serial_rows, strict=True):
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
    plan = plan_sweep(EXAMPLE, [*SHORT, "analysis.exact.time_step=1e-7"], [], ["exact"], ["rigid"])
    rows = run_chunk(make_chunks(plan, plan.cases, 4)[0])
    assert rows[0]["status"] == "failed"
    assert rows[0]["message"].startswith("--set: analysis.exact.time_step: at most 50,000,000 internal steps")
    assert rows[0]["case"] == 0 and rows[0]["engine"] == "exact"


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


def test_cases_sharing_a_structure_run_as_one_batch(batch_sizes):
    """Chunks put together the cases that differ only in foundation fields (whatever the --vary
    order), and the exact engine gets each such group as one batch; the rows equal the
    single analyses."""
    plan = plan_sweep(EXAMPLE, ["ground_motion.window=[0, 3]"],
                      ["foundation.frequency_ratio=4,8,16", "building.period=0.4,1.2"], ["exact"], ["uplift"])
    chunks = make_chunks(plan, plan.cases, 3)
    assert [[dict(c.overrides)["building.period"] for c in chunk.cases] for chunk in chunks] == [[0.4] * 3, [1.2] * 3]
    rows = [row for chunk in chunks for row in run_chunk(chunk)]
    assert batch_sizes == [3, 3]
    for case, row in zip([c for chunk in chunks for c in chunk.cases], rows, strict=True):
        deck = load_deck(EXAMPLE, ["ground_motion.window=[0, 3]"] + [f"{p}={v}" for p, v in case.overrides])
        result = run_one(deck, "exact", "uplift")
        assert row["key"] == case.key and row["base_shear_N"] == result.base_shear
        assert row["max_drift_ratio"] == float(np.max(result.drift_ratio))


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


def test_a_record_changed_between_two_sweeps_in_one_process_is_read_again(tmp_path):
    """The ground-motion cache of a worker process is keyed by the plan's fingerprint, which
    hashes every file the ground motions read (a suite's records too): a suite record scaled on
    disk between two sweeps gives scaled rows."""
    root = EXAMPLE.parent.parent
    folder = tmp_path / "suite"
    folder.mkdir()
    original = (root / "records" / "ten_story_asce7_suite" / "artificial_2024_01.txt").read_text()
    (folder / "r1.txt").write_text(original)
    deck = tmp_path / "deck.toml"
    deck.write_text((root / "inputs" / "ten_story_asce7_suite.toml").read_text()
                    .replace('"../records/ten_story_asce7_suite"', f'"{folder}"'))

    def base_shears():
        plan = plan_sweep(deck, [], ["building.period=0.5,1"], ["exact"], ["rigid"])
        return plan, [row["base_shear_N"] for chunk in make_chunks(plan, plan.cases, 2) for row in run_chunk(chunk)]

    plan, first = base_shears()
    doubled = [line if line.startswith("#") or not line.strip() else f"{2 * float(line):.10g}"
               for line in original.splitlines()]  # one acceleration [g] per line
    (folder / "r1.txt").write_text("\n".join(doubled) + "\n")
    again, second = base_shears()
    assert again.fingerprint != plan.fingerprint
    np.testing.assert_allclose(second, [2 * value for value in first], rtol=1e-6)  # linear: rigid base


def test_a_record_replaced_during_a_sweep_gives_stale_rows_not_rows_with_the_old_checksum(tmp_path):
    """A record file replaced after the plan read it: the worker's cases are not computed from the
    new bytes under the plan's checksum (2,641 of 3,000 rows were), they are 'stale' rows naming the
    file; with the file restored, the cases run."""
    import shutil

    record = tmp_path / "elcentro.txt"
    shutil.copy(EXAMPLE.parent.parent / "records" / "elcentro_1940_ns_chopra.txt", record)
    deck = tmp_path / "deck.toml"
    deck.write_text(EXAMPLE.read_text().replace("../records/elcentro_1940_ns_chopra.txt", str(record)))
    plan = plan_sweep(deck, SHORT, ["building.period=0.5,1"], ["simplified"], ["rigid"])
    original = record.read_text()
    record.write_text(original.replace("0.0063", "0.0064", 1))
    rows = [row for chunk in make_chunks(plan, plan.cases, 2) for row in run_chunk(chunk)]
    assert [row["status"] for row in rows] == ["stale", "stale"]
    assert "the record file changed after the sweep read it" in rows[0]["message"]
    assert str(record) in rows[0]["message"] and "--resume --rerun-stale" in rows[0]["message"]
    record.write_text(original)
    rows = [row for chunk in make_chunks(plan, plan.cases, 2) for row in run_chunk(chunk)]
    assert [row["status"] for row in rows] == ["ok", "ok"]
