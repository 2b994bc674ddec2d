"""The numpy twin of the stepping loop (engines/exact/stepping_numpy.py) against the compiled loop,
both run in one process (tests/backends.py; skipped where the C extensions were not built): the
same samples, contact states and transitions, the states to round-off."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from backends import on_both
from paper_example import paper_system

from upliftcli.engines.exact import stepping, stepping_numpy
from upliftcli.engines.exact import stepping_kernels as kernel
from upliftcli.engines.exact.modal import modal_model
from upliftcli.engines.exact.statespace import state_space
from upliftcli.errors import AnalysisError

README_DECK = Path(__file__).resolve().parents[1] / "inputs" / "ten_story_elcentro.toml"


def _history(period, acceleration, dt, substeps=4, allow_flight=True):
    space = state_space(modal_model(paper_system(period), "uplift", 10))
    ((_, history),) = list(stepping.simulate([space], [substeps], acceleration, dt, "reaction", uplift=True,
                                             allow_flight=allow_flight))
    if isinstance(history, Exception):
        raise history
    return history.times.copy(), history.states.copy(), history.state_ids.copy()


@pytest.mark.parametrize("period", [0.05, 0.5, 2.0])
def test_twin_steps_as_the_loop_through_lift_offs_impacts_and_flight(elcentro, period):
    """Twice El Centro, 6 s: lift-offs and recontacts (T_1 = 0.5, 2 s), flight and impacts
    (0.05 s). Every sample in the same contact state, the transitions at the same times to
    1e-12 s, the states to 1e-9 of their largest value (round-off of the block products,
    amplified by the impacts)."""
    acceleration = 2.0 * elcentro.acceleration[:301]
    (t_c, x_c, s_c), (t_n, x_n, s_n) = on_both(lambda: _history(period, acceleration, elcentro.dt))
    assert np.count_nonzero(np.diff(s_c)) >= 4
    np.testing.assert_array_equal(s_n, s_c)
    np.testing.assert_allclose(t_n, t_c, rtol=0, atol=1e-12)
    scale = np.abs(x_c).max(axis=0)
    assert np.all(np.abs(x_n - x_c) <= 1e-9 * scale)


def test_twin_steps_in_chunks_as_the_loop(elcentro, monkeypatch):
    """A sample buffer filled many times (FULL, then on with the chunk's last sample): the same
    samples as the loop, chunk by chunk."""
    monkeypatch.setattr(stepping, "CHUNK_SAMPLES", 700)
    space = state_space(modal_model(paper_system(0.5), "uplift", 10))

    def run():
        chunks = []
        ((_, last),) = list(stepping.simulate([space], [4], 2.0 * elcentro.acceleration[:301], elcentro.dt,
                                              "reaction", uplift=True, allow_flight=True,
                                              on_chunk=[lambda h: chunks.append(h.times.copy())]))
        return [*chunks, last.times.copy()]

    compiled, twin = on_both(run)
    assert len(compiled) >= 3 and [c.size for c in twin] == [c.size for c in compiled]
    for mine, theirs in zip(twin, compiled, strict=True):
        np.testing.assert_allclose(mine, theirs, rtol=0, atol=1e-12)


def test_twin_refuses_flight_where_the_loop_does(elcentro):
    def run():
        with pytest.raises(AnalysisError, match="flight") as refused:
            _history(0.05, 2.0 * elcentro.acceleration[:301], elcentro.dt, allow_flight=False)
        return str(refused.value)

    compiled, twin = on_both(run)
    assert twin == compiled


def test_excursion_test_of_the_twin_is_the_loops():
    """Random event values and rates at the ends of a chunk, many near the decision."""
    rng = np.random.default_rng(2)
    events, rates = np.eye(2, 4), np.eye(2, 4, 2)
    cases = rng.normal(size=(2000, 2, 4)) * [1.0, 1.0, 3.0, 3.0]
    compiled, twin = on_both(lambda: [kernel.excursion(events, rates, x, y, 0.7) for x, y in cases])
    assert twin == compiled and 0 < sum(twin) < len(twin)
    together = stepping_numpy.excursion_between(cases[:, 0, :2].T, cases[:, 0, 2:].T, cases[:, 1, :2].T,
                                                cases[:, 1, 2:].T, 0.7)
    assert together.tolist() == twin


@pytest.mark.parametrize("support", ["rigid", "bonded"])
def test_twin_steps_as_the_loop_through_yielding_stories(elcentro, support):
    """The README building at 0.4 W with 5 % hardening under twice El Centro, 8 s: its stories yield and
    unload (crossings of the story rows bracketed with several rows above the tolerance, states of the same
    A stepping with one slot of operators: Operators.slots). The twin meets the same contact states at the
    same times to 1e-12 s, the states to 1e-9 of their largest value (and 1e-15 absolute: a bonded run's
    component that stays at round-off, 5e-14, differs by 2e-17)."""
    from upliftcli.deck.load import load_deck
    from upliftcli.engines.exact.operators import Operators
    from upliftcli.engines.exact.statespace import exact_model
    from upliftcli.engines.options import ExactOptions

    deck = load_deck(README_DECK, ["building.strength_coefficient=0.4", "building.hardening_ratio=0.05"])
    space = exact_model(deck.system, support, ExactOptions())
    acceleration = 2.0 * elcentro.acceleration[:401]

    def run():
        ops = Operators(space, elcentro.dt / 2, "reaction", uplift=False)
        ((_, history),) = list(stepping.simulate([space], [2], acceleration, elcentro.dt, "reaction",
                                                 uplift=False, allow_flight=True, operators=[ops]))
        shared = np.count_nonzero(ops.slots[:len(ops.contact)] != np.arange(len(ops.contact)))
        return history.times.copy(), history.states.copy(), history.state_ids.copy(), shared

    (t_c, x_c, s_c, shared_c), (t_n, x_n, s_n, shared_n) = on_both(run)
    assert np.count_nonzero(np.diff(s_c)) >= 20 and shared_n == shared_c >= 1
    np.testing.assert_array_equal(s_n, s_c)
    np.testing.assert_allclose(t_n, t_c, rtol=0, atol=1e-12)
    scale = np.abs(x_c).max(axis=0)
    assert np.all(np.abs(x_n - x_c) <= 1e-9 * scale + 1e-15)
