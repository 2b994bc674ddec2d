"""sweep/plan.py: case expansion and keys, the plan's checks before anything runs."""

from pathlib import Path

import pytest
from sweep_cases import ASCE7, EXAMPLE, ROOT, SHORT

from upliftcli.deck.load import load_deck
from upliftcli.errors import InputError
from upliftcli.sweep.chunks import Chunk, stream_chunks
from upliftcli.sweep.plan import (
    Case,
    expand_cases,
    parse_vary,
    plan_sweep,
)


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


def test_case_dataclass_is_picklable():
    import pickle

    case = Case(0, "k", (("building.period", 0.5),), "simplified", "rigid")
    chunk = Chunk({"a": 1}, "deck.toml", (), [case])
    assert pickle.loads(pickle.dumps(chunk)) == chunk


def peak_memory(call) -> int:
    """The most memory [bytes] call() held at once (tracemalloc: Python's objects and numpy's arrays)."""
    import tracemalloc

    tracemalloc.start()
    try:
        call()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def refused(call, match: str):
    """call, which must raise InputError matching `match`, for peak_memory."""
    def run():
        with pytest.raises(InputError, match=match):
            call()
    return run


def test_range_sizes_are_refused_before_expanding():
    """Each was minutes and hundreds of MB (10^8 values, 10^6 parsed values, 2.4 million cases):
    refused before anything is expanded, which the memory they take bounds (not a clock, which a
    loaded machine stretches): a copy of the text for the ranges, no more than planning two cases
    of the same deck for the sweep (reading the deck and its record reserves their size limits)."""
    many = "foundation.b=" + ",".join(str(1 + 1e-6 * i) for i in range(1_000_000))  # 10 MB of text
    assert peak_memory(refused(lambda: parse_vary("foundation.b=1:2:100000000"),
                               r"^--vary foundation.b: 1:2:100000000: at most 10,000 values in one range")) < 1e6
    assert peak_memory(refused(lambda: parse_vary(many), r"at most 10,000 values in one range \(limit of the tool\), "
                                                          r"got 1,000,000")) < 2 * len(many)
    with pytest.raises(InputError, match=r"^--vary foundation.b: values on one line"):
        parse_vary("foundation.b=1,2\n3")
    two_cases = peak_memory(lambda: plan_sweep(EXAMPLE, [], ["foundation.b=1:2:2"], ["simplified"], ["uplift"]))
    varies = ["foundation.b=1:2:30", "building.period=0.5:1:30", "foundation.damping_ratio=0.1:0.3:30",
              "foundation.frequency_ratio=4:8:30"]
    assert peak_memory(refused(lambda: plan_sweep(EXAMPLE, [], varies), r"^--vary: at most 100,000 cases, got "
                               r"2,430,000 \(30 x 30 x 30 x 30 x 3\)")) <= two_cases


def test_plan_fingerprints_the_records_and_the_version():
    from upliftcli.provenance.files import sha256 as file_sha256

    plan = plan_sweep(EXAMPLE, SHORT, ["building.period=0.5,1"], ["simplified"], ["rigid"])
    (record,) = plan.records
    assert Path(record).resolve() == (ROOT / "records" / "elcentro_1940_ns_chopra.txt").resolve()
    assert plan.records[record] == file_sha256(record) and len(plan.records[record]) == 64
    assert plan.version and len(plan.fingerprint) == 20
    assert plan.input_files == [str(EXAMPLE), record]
    assert plan.record_steps[record] == (0.02, 301)
    other = plan_sweep(EXAMPLE, SHORT, ["building.period=0.5,2"], ["simplified"], ["rigid"])
    assert other.fingerprint == plan.fingerprint  # the varied values are in the case keys, not in the fingerprint


def test_base_deck_is_the_deck_with_its_overrides_before_vary_built_once():
    plan = plan_sweep(EXAMPLE, ["building.damping=0.03"], ["building.period=0.5,1"])
    deck = plan.base_deck
    assert plan.base_deck is deck and deck.ground_motion is None
    assert (deck.system.building.damping == 0.03).all()
    assert deck.system.modes.periods[0] == pytest.approx(load_deck(EXAMPLE).system.modes.periods[0], rel=1e-12)


def test_the_plan_carries_the_decks_warnings_once_each():
    plan = plan_sweep(EXAMPLE, ["building.floor_mass=300"], ["building.story_height=3,3200", "building.period=0.4,0.5"])
    assert [w.split(": ")[1] for w in plan.warnings] == ["building.floor_mass", "building.story_height"]
    assert plan_sweep(EXAMPLE, [], ["building.period=0.5,1"]).warnings == ()


def test_a_varied_field_may_complete_the_deck():
    """A deck that a varied field completes is not refused for lacking it: --set bearing_pressure
    with --vary mat_length was 'foundation.mat_length: ... (missing)', naming the deck; a --set value
    that every case replaces is not checked on its own. The provenance's deck is the first case's."""
    plan = plan_sweep(EXAMPLE, ["foundation.bearing_pressure=3e6"], ["foundation.mat_length=10,30"])
    assert len(plan.cases) == 6 and plan.base_deck.system.foundation.capacity == pytest.approx(
        3e6 * 10 * plan.base_deck.system.half_width)
    assert len(plan_sweep(EXAMPLE, ["foundation.safety_factor=0.5"], ["foundation.safety_factor=2,3"]).cases) == 6
    with pytest.raises(InputError) as info:  # a deck the first values do not complete is refused as before
        plan_sweep(EXAMPLE, [], ["foundation.mat_length=10,30"])
    assert str(info.value).startswith("--vary: foundation.mat_length: only with foundation.bearing_pressure")


def test_the_engine_option_is_every_cases_analysis_engine():
    """--engine exact on a deck whose analysis.engine is simplified: a rocking limit (which needs the
    exact engine) was refused, the deck's engine checked instead of the one that runs; the workers
    build the cases with it too."""
    from upliftcli.sweep.chunks import make_chunks
    from upliftcli.sweep.worker import run_chunk

    settings = [*SHORT, "criteria.rotation=1e-6"]
    with pytest.raises(InputError, match=r"^--set: criteria\.rotation: .*has not the exact engine"):
        plan_sweep(EXAMPLE, settings, ["foundation.safety_factor=2,3"])
    plan = plan_sweep(EXAMPLE, settings, ["foundation.safety_factor=2,3"], ["exact"], ["uplift"])
    assert plan.base_deck.analysis.engines == ["exact"]
    assert plan.base_overrides == (("ground_motion.window", [0, 6]), ("criteria.rotation", 1e-6))  # the --set only
    (chunk,) = make_chunks(plan, plan.cases, 16)
    rows = run_chunk(chunk)
    assert [row["status"] for row in rows] == ["ok", "ok"]
    assert all(row["violations"].startswith("exact/uplift: rotation = ") for row in rows)
    with pytest.raises(InputError, match=r"^--vary: foundation\.elements: at most 31 contact elements"):
        plan_sweep(ROOT / "inputs" / "ten_story_winkler.toml", ["foundation.safety_factor=2"],
                   ["foundation.elements=20,40"], ["exact"])


def test_cases_are_made_on_demand_as_the_product_gives_them():
    from upliftcli.sweep.cases import Cases

    varies = [parse_vary("foundation.k_f=1e8,1e9"), parse_vary("building.period=0.5,1.0,2.0"),
              parse_vary("foundation.b=4,5")]
    cases = Cases(varies, ["simplified", "exact"], ["rigid", "uplift"], "deck-hash")
    listed = expand_cases(varies, ["simplified", "exact"], ["rigid", "uplift"], "deck-hash")
    assert len(cases) == 48 and list(cases) == listed and cases[-1] == listed[-1] and cases[5:9] == listed[5:9]
    with pytest.raises(IndexError):
        cases[48]
    # in structure order: each case once, those differing only in foundation fields together, in case order
    ordered = list(cases.in_structure_order())
    assert sorted(ordered, key=lambda c: c.index) == listed
    groups = [ordered[k:k + 4] for k in range(0, 48, 4)]
    for group in groups:
        assert len({(c.overrides[1], c.engine, c.support) for c in group}) == 1
        assert [c.index for c in group] == sorted(c.index for c in group)


def test_a_large_sweep_is_planned_without_making_its_cases(monkeypatch):
    """Issue 38 item 5: a 10^5-case sweep built every case's deck (27-210 s) and kept every case
    before its first row; now the plan builds the checked combinations only (each varied value
    alone), and the first chunk is made without making the other cases."""
    from upliftcli.sweep import cases as cases_module
    from upliftcli.sweep import plan as plan_module

    built, made = [], []
    build_deck, make = plan_module.build_deck, cases_module.Cases._case
    monkeypatch.setattr(plan_module, "build_deck", lambda *a, **k: built.append(1) or build_deck(*a, **k))
    monkeypatch.setattr(cases_module.Cases, "_case", lambda self, index: made.append(index) or make(self, index))
    plan = plan_sweep(EXAMPLE, SHORT, ["building.period=0.2:3:316", "foundation.slenderness=2:8:316"],
                      ["simplified"], ["uplift"])
    assert len(plan.cases) == 316 * 316 and not made
    assert len(built) <= 2 * 316 + 4
    first = next(stream_chunks(plan, set(), 16))
    assert [case.index for case in first.cases] == list(range(16)) and len(made) == 16
    assert plan.fingerprint == plan_sweep(EXAMPLE, SHORT, ["building.period=0.2:3:2", "foundation.slenderness=2:8:2"],
                                          ["simplified"], ["uplift"]).fingerprint


def test_a_large_sweep_still_refuses_a_bad_value_before_running():
    widths = ",".join([*(str(2 + k / 10) for k in range(39)), "-1"])  # 40 x 40 combinations: more than are checked
    with pytest.raises(InputError, match=r"^--vary: foundation\.b:"):
        plan_sweep(EXAMPLE, SHORT, ["building.period=0.2:3:40", f"foundation.b={widths}"], ["simplified"], ["uplift"])
