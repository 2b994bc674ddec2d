"""The states of yielding stories the compiled stepping loop builds itself (engines/exact/builds.h,
story_requests.loop_builds and adopt) against those Python's quick path builds when the loop returns
NEED_STATE for each: the same states in the same order, the same arrays and results, bit for bit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from upliftcli.deck.load import load_deck
from upliftcli.engines.exact import engine as exact
from upliftcli.engines.exact import stepping
from upliftcli.engines.exact import stepping_kernels as kernel
from upliftcli.runtime import backend

ROOT = Path(__file__).resolve().parent.parent
DECK = ROOT / "inputs" / "ten_story_elcentro.toml"
YIELDING = ["analysis.engine=exact", "ground_motion.scale=2", "building.strength_coefficient=0.4",
            "building.hardening_ratio=0.05"]
STATE_ARRAYS = ("patterns", "slots", "events", "event_rates", "matrices")  # rows, fields: as ContactState

pytestmark = pytest.mark.skipif("upliftcli.engines.exact._stepping" not in backend.built(),
                                reason="the compiled stepping loop is not built")


def _analyzed(support: str, builds: bool, monkeypatch) -> tuple[object, object, list[int], list[tuple]]:
    """The yielding README deck on `support`, the loop building states (builds) or Python building each; the
    result, the operators of its run and what its calls of integrate returned."""
    runs, statuses = [], []
    advance = stepping.Run.advance

    def recorded(run):
        runs.append(run.operators)
        integrate = run.integrate
        run.integrate = lambda *args: statuses.append(out := integrate(*args)) or out
        try:
            return advance(run)
        finally:
            run.integrate = integrate

    monkeypatch.setattr(stepping.Run, "advance", recorded)
    if not builds:
        monkeypatch.setattr(stepping, "loop_builds", lambda operators: None)
    deck = load_deck(DECK, YIELDING)
    with backend.use("compiled"):
        result = exact.analyze(deck.system, deck.ground_motion, support, deck.analysis.exact)
    monkeypatch.undo()
    return result, runs[-1], [outcome[0] for outcome in statuses], statuses


def _same_results(a, b) -> None:
    for name, values in a.peaks.items():
        np.testing.assert_array_equal(b.peaks[name], values, err_msg=name)
    for name, value in a.details["energy"].items():
        np.testing.assert_array_equal(b.details["energy"][name], value, err_msg=name)
    assert b.intermediates["transitions"] == a.intermediates["transitions"]


def _same_states(a, b) -> None:
    n = len(a.contact)
    assert len(b.contact) == n and b.by_matrix == a.by_matrix
    for name in STATE_ARRAYS:
        np.testing.assert_array_equal(getattr(b, name)[:n], getattr(a, name)[:n], err_msg=name)
    np.testing.assert_array_equal(b.ops[np.unique(a.slots[:n])], a.ops[np.unique(a.slots[:n])])
    for s, (mine, theirs) in enumerate(zip(a.contact, b.contact, strict=True)):
        for field in ("lifted", "matrix", "velocity", "events", "yielding", "story_sign"):
            np.testing.assert_array_equal(getattr(theirs, field), getattr(mine, field), err_msg=f"{s} {field}")


@pytest.mark.parametrize("support", ["rigid", "bonded"])
def test_the_loop_builds_the_states_python_builds_bit_for_bit(support, monkeypatch):
    """A rigid or bonded yielding run: the loop builds every state after the first itself, in one call of
    integrate, instead of returning NEED_STATE for each (151 on the rigid base); the states (their arrays,
    operators, ContactState and keys of A) and the results are those of Python's quick path."""
    python, python_ops, python_statuses, _ = _analyzed(support, False, monkeypatch)
    loop, loop_ops, loop_statuses, _ = _analyzed(support, True, monkeypatch)
    assert python_statuses.count(kernel.NEED_STATE) > 100
    assert kernel.NEED_STATE not in loop_statuses and len(loop_statuses) < 5
    _same_states(python_ops, loop_ops)
    _same_results(python, loop)


def test_a_run_in_short_chunks_is_the_same_with_states_the_loop_builds(monkeypatch):
    """Chunks of 600 samples, one of them full right after a state the loop built (returned FULL inside a
    step, as the new call of integrate that entered it would have): the results of Python's quick path, bit
    for bit."""
    monkeypatch.setattr(stepping, "CHUNK_SAMPLES", 600)
    python, _, _, _ = _analyzed("rigid", False, monkeypatch)
    monkeypatch.setattr(stepping, "CHUNK_SAMPLES", 600)
    loop, _, _, outcomes = _analyzed("rigid", True, monkeypatch)
    assert any(status == kernel.FULL and offset > 0.0 for status, _, offset, *_ in outcomes)
    _same_results(python, loop)


def test_an_uplift_run_builds_its_states_in_python(monkeypatch):
    """An uplift run's foundation rates are np.matmul's (story_requests._foundation_rates): the loop is given
    nothing to build with (loop_builds None) and returns NEED_STATE for each new state, as before."""
    _, operators, statuses, _ = _analyzed("uplift", True, monkeypatch)
    from upliftcli.engines.exact.story_requests import loop_builds

    assert loop_builds(operators) is None and kernel.NEED_STATE in statuses


def test_builds_that_do_not_fit_the_states_are_refused(monkeypatch):
    """integrate with builds whose rows do not fit the states (n_aug + n_e rows of n_aug): a ValueError."""
    _, operators, _, _ = _analyzed("rigid", True, monkeypatch)
    from upliftcli.engines.exact import _stepping
    from upliftcli.engines.exact.story_requests import loop_builds

    builds = loop_builds(operators)._replace(rows=np.empty((4, 3, 3)))
    n = operators.layout.n_aug
    states = kernel.States(operators.ops, operators.slots, operators.events, operators.event_rates,
                           operators.matrices, operators.patterns, len(operators.contact))
    n_e = operators.events.shape[1]
    elements = kernel.Elements(np.zeros(n_e, dtype=np.int64), np.zeros((n_e, n)), np.zeros(n_e, dtype=bool), 0,
                               True)
    grid = kernel.Grid(np.zeros(2), np.zeros(1), 0.01, 12, 0, 1)
    samples = kernel.Samples(np.zeros(n), np.zeros((300, n)), np.zeros(300), np.zeros(300, dtype=np.int64))
    with pytest.raises(ValueError, match="builds"):
        _stepping.integrate(states, elements, grid, samples, 0, 0, 0.0, 0, builds)
