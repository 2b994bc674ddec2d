"""The step operators of contact states with a bearing capacity (engines/exact/operators.py,
yielding.step_operators; docs/theory.md 14.3): against scipy's exponential of the whole matrix,
and the states built ahead against the states built when a run reaches them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from upliftcli.deck.load import load_deck
from upliftcli.engines.exact.statespace import exact_model
from upliftcli.engines.options import ExactOptions

ROOT = Path(__file__).resolve().parent.parent
TWO = ROOT / "inputs" / "ten_story_elcentro.toml"
WINKLER = ROOT / "inputs" / "ten_story_winkler.toml"


@pytest.mark.parametrize("path", [TWO, WINKLER])
def test_the_step_operators_are_the_exponentials(path):
    """yielding.step_operators (the exponential of the motion, the forcing entries and the mat's two
    load columns, the other rows in closed form) gives expm(A h / 2^j)^T at every bisection level,
    against scipy.linalg.expm of the whole A, to 1e-12 of its largest entry (measured 5.8e-13, levels
    0 and 1 of the two-element deck), in contact states with every element in C, Y or L; the rows it
    leaves out are indeed read by no coupled row of A, and the columns of the settlements of the
    elements in contact span two directions (the mat's vertical force and moment) whatever their
    number."""
    from scipy.linalg import expm as scipy_expm

    from upliftcli.engines.exact.operators import LEVELS
    from upliftcli.engines.exact.patterns import contact_states
    from upliftcli.engines.exact.yielding import step_operators

    space = exact_model(load_deck(path, ["foundation.safety_factor=1.5"]).system, "uplift", ExactOptions())
    lay = space.layout
    n_e = lay.n_elements
    rng = np.random.default_rng(28)
    # element states 0 C, 1 Y, 2 L: every combination on two elements, random ones on the strip
    kinds = np.array(np.meshgrid(*[range(3)] * n_e)).reshape(n_e, -1).T if n_e == 2 else rng.integers(0, 3, (8, n_e))
    states = contact_states([space] * len(kinds), kinds == 2, "reaction", kinds == 1)
    assert n_e == 2 or (kinds == 0).sum(axis=1).max() > 2  # states where the rank check below says something
    for state in states:
        passive = np.concatenate((lay.z_indices, lay.settlement_indices[state.lifted | state.yielding]))
        coupled = np.setdiff1d(np.arange(lay.n_aug), passive)
        assert not state.matrix[np.ix_(coupled, passive)].any()
        settling = state.matrix[np.ix_(np.setdiff1d(coupled, lay.settlement_indices),
                                       lay.settlement_indices[~state.lifted & ~state.yielding])]
        assert np.linalg.matrix_rank(settling) <= 2
        for h in (0.02 / 8, 0.02):
            (ops,) = step_operators(space, [state], h, LEVELS)
            for j in range(LEVELS + 1):
                reference = scipy_expm(state.matrix * (h / 2.0**j)).T
                assert np.abs(ops[j] - reference).max() <= 1e-12 * np.abs(reference).max(), (j, h)



def _patterns(n_e: int) -> np.ndarray:
    """Element states (0 C, 1 Y, 2 L) where the two columns of the mat's forces in
    yielding.step_operators come from few elements: one in contact at an edge or in the middle (x = 0
    with an odd count: no moment), the two middle ones (the closest pair), the two middle ones with
    every other element yielding, all in contact, none."""
    lifted = np.full(n_e, 2)
    one_edge, one_middle, pair, pair_yielding = lifted.copy(), lifted.copy(), lifted.copy(), np.ones(n_e, int)
    one_edge[0] = one_middle[n_e // 2] = 0
    pair[n_e // 2 - 1:n_e // 2 + 1] = pair_yielding[n_e // 2 - 1:n_e // 2 + 1] = 0
    return np.array([one_edge, one_middle, pair, pair_yielding, np.zeros(n_e, int), lifted, np.ones(n_e, int)])


@pytest.mark.parametrize("overrides", [["foundation.elements=21"], ["foundation.elements=3"],
                                       ["foundation.mat_rotary_inertia=1e8"]])
def test_the_step_operators_with_few_elements_in_contact(overrides):
    """yielding.step_operators against scipy.linalg.expm of the whole A (as above) where the mat's
    two load columns come from one element in contact (the least-norm pair of columns), from the
    closest pair (the worst-conditioned 2 x 2 [l_i l_j]) or from none; on 21 elements (one at
    x = 0), on 3, and on 20 with a mat that has a rotary inertia (theta then has a velocity: a block
    of 29, not 28); all the states of a pattern list in one stacked call. Measured 2e-13 to 5e-13
    of the largest entry."""
    from scipy.linalg import expm as scipy_expm

    from upliftcli.engines.exact.operators import LEVELS
    from upliftcli.engines.exact.patterns import contact_states
    from upliftcli.engines.exact.yielding import step_operators

    space = exact_model(load_deck(WINKLER, ["foundation.safety_factor=1.5", *overrides]).system, "uplift",
                        ExactOptions())
    kinds = _patterns(space.layout.n_elements)
    states = contact_states([space] * len(kinds), kinds == 2, "reaction", kinds == 1)
    for h in (0.02 / 8, 0.02):
        for state, ops in zip(states, step_operators(space, states, h, LEVELS), strict=True):
            for j in range(LEVELS + 1):
                reference = scipy_expm(state.matrix * (h / 2.0**j)).T
                assert np.abs(ops[j] - reference).max() <= 1e-12 * np.abs(reference).max(), (j, h)


def test_the_yielding_states_built_ahead_change_nothing(monkeypatch):
    """On two elements with a capacity, stepping.Run.first_lifts builds the states of an edge
    yielding (the other in contact or lifted) with the initial state: every state the run meets
    comes in that one round (instead of five: the cost bench_yielding.py measures), and the results
    are bit for bit those of a run that builds each state when it reaches it."""
    from upliftcli.engines.exact import engine as exact
    from upliftcli.engines.exact import stepping

    deck = load_deck(TWO, ["foundation.safety_factor=2"])
    rounds = []
    build = stepping.add_states
    monkeypatch.setattr(stepping, "add_states", lambda requests: rounds.append(len(requests)) or build(requests))
    ahead = exact.analyze(deck.system, deck.ground_motion, "uplift")
    # all in contact, an edge lifted (2), an edge yielding (2), one yielding and the other lifted (2)
    assert rounds == [7]
    monkeypatch.setattr(stepping.Run, "first_lifts", lambda run: [1, 2])
    rounds.clear()
    when_reached = exact.analyze(deck.system, deck.ground_motion, "uplift")
    assert rounds == [3, 1, 1, 1, 1]
    for name, values in when_reached.peaks.items():
        np.testing.assert_array_equal(ahead.peaks[name], values, err_msg=name)
    for name, values in when_reached.times.items():
        np.testing.assert_array_equal(ahead.times[name], values, err_msg=name)
    assert ahead.details["yielding"] == when_reached.details["yielding"]
    for name, value in when_reached.details["energy"].items():
        np.testing.assert_array_equal(ahead.details["energy"][name], value, err_msg=name)
    assert ahead.intermediates["transitions"] == when_reached.intermediates["transitions"]


#: (deck, overrides, support) of runs of many states: a yielding Winkler mat (hundreds of states, their
#: operators written in place by yielding.step_operators) and the README deck at El Centro x2 with strength
#: 0.4 W on the rigid base (151 states written in place by level_operators.state_levels into arrays not filled)
GROWING = [(WINKLER, ["foundation.safety_factor=1.5"], "uplift"),
           (TWO, ["ground_motion.scale=2", "building.strength_coefficient=0.4", "building.hardening_ratio=0.05"],
            "rigid")]


@pytest.mark.parametrize(("path", "overrides", "support"), GROWING)
def test_operator_arrays_that_grow_keep_the_states_written_in_place(monkeypatch, path, overrides, support):
    """A run of many states whose operator arrays start at 4 states and double (kept.doubled: the
    states written are copied) gives the results of the run whose arrays are reserved for all of them up
    front, bit for bit: every peak, the energy terms and the transitions."""
    from upliftcli.engines.exact import engine as exact
    from upliftcli.engines.exact import operators

    deck = load_deck(path, overrides)
    reserved = exact.analyze(deck.system, deck.ground_motion, support)
    sizes = []
    monkeypatch.setattr(operators, "reserved_states", lambda lay: 4)
    doubled = operators.doubled
    monkeypatch.setattr(operators, "doubled", lambda array, fill=None: sizes.append(array.shape[0]) or
                        doubled(array, fill))
    grown = exact.analyze(deck.system, deck.ground_motion, support)
    assert max(sizes) == 128  # grown from 4 to 256 states (these runs meet 129 to 256)
    for name, values in reserved.peaks.items():
        np.testing.assert_array_equal(grown.peaks[name], values, err_msg=name)
    for name, value in reserved.details["energy"].items():
        np.testing.assert_array_equal(grown.details["energy"][name], value, err_msg=name)
    assert grown.intermediates["transitions"] == reserved.intermediates["transitions"]
    assert grown.details.get("yielding") == reserved.details.get("yielding")


def test_reused_gives_an_array_back_once_nothing_holds_it(monkeypatch):
    """kept.reused: an array held (or a view of it held) is never given again; one let go is, for its shape;
    an array beyond REUSED is not kept, and a new shape takes the place of the free arrays."""
    from upliftcli.engines.exact import kept

    monkeypatch.setattr(kept, "_reused", [])
    monkeypatch.setattr(kept, "REUSED", 2)
    first = kept.reused((3, 4))
    second = kept.reused((3, 4))
    assert first is not second and len(kept._reused) == 2
    view, kept_id = first[1:], id(first)
    del first
    third = kept.reused((3, 4))
    assert id(third) != kept_id and third is not second and len(kept._reused) == 2  # the view holds the first
    del view
    assert id(kept.reused((3, 4))) == kept_id  # let go: given again
    del second  # both kept arrays free now (the third was never kept: two were, and held)
    other = kept.reused((5,))
    assert other.shape == (5,) and [array.shape for array in kept._reused] == [(5,)]
    assert kept.reused((5,)) is not other  # held: a new one
    assert third.shape == (3, 4)


def test_a_yielding_mat_writes_its_operators_over_an_earlier_runs(monkeypatch):
    """The operators of a yielding Winkler mat's run go into the array an earlier run left (kept.reused: its
    memory mapped, not zeroed), every entry written (_soil_operators.c zeroes each level as it writes it): a run
    into that array filled with NaN gives the results of the first run, bit for bit."""
    from upliftcli.engines.exact import engine as exact
    from upliftcli.engines.exact import kept

    monkeypatch.setattr(kept, "_reused", [])
    deck = load_deck(WINKLER, ["foundation.safety_factor=1.5"])
    first = exact.analyze(deck.system, deck.ground_motion, "uplift")
    (shape,) = [array.shape for array in kept._reused]  # the operators' array only
    left = kept.reused(shape)
    left[...] = np.nan
    del left
    again = exact.analyze(deck.system, deck.ground_motion, "uplift")
    left = kept.reused(shape)
    assert np.isfinite(left[0]).all()  # the second run wrote its first state over the NaN
    for name, values in first.peaks.items():
        np.testing.assert_array_equal(again.peaks[name], values, err_msg=name)
    for name, values in first.times.items():
        np.testing.assert_array_equal(again.times[name], values, err_msg=name)
    for name, value in first.details["energy"].items():
        np.testing.assert_array_equal(again.details["energy"][name], value, err_msg=name)
    assert again.details["yielding"] == first.details["yielding"]
    assert again.intermediates["transitions"] == first.intermediates["transitions"]


def test_a_run_stops_at_the_states_its_operator_memory_holds(monkeypatch):
    """limits.MAX_OPERATOR_BYTES bounds the distinct contact states a run builds (a yielding mat that
    chatters met 3,368, 1.9 GB, in 53 s): with room for exactly the states the yielding Winkler run
    meets it gives the same results bit for bit; with room for one fewer it stops with an
    AnalysisError naming the cause and the fields to change, and `uplift analyze` exits 4 with that
    one line (no traceback, no result)."""
    from cli_helpers import invoke

    from upliftcli.engines.exact import engine as exact
    from upliftcli.engines.exact import operators, stepping
    from upliftcli.errors import AnalysisError

    deck = load_deck(WINKLER, ["foundation.safety_factor=1.5"])
    built = []
    build = stepping.add_states
    monkeypatch.setattr(stepping, "add_states", lambda requests: built.append(requests) or build(requests))
    free = exact.analyze(deck.system, deck.ground_motion, "uplift")
    runs = {id(operators_) for requests in built for operators_, _, _ in requests}
    assert len(runs) == 1
    met = len(built[-1][0][0].contact)
    assert met > 64  # max_states never goes below 64
    space = exact_model(deck.system, "uplift", ExactOptions())
    monkeypatch.setattr(operators, "MAX_OPERATOR_BYTES", met * operators.state_bytes(space.layout))
    assert operators.max_states(space.layout) == met
    held = exact.analyze(deck.system, deck.ground_motion, "uplift")
    for name, values in free.peaks.items():
        np.testing.assert_array_equal(held.peaks[name], values, err_msg=name)
    monkeypatch.setattr(operators, "MAX_OPERATOR_BYTES", (met - 1) * operators.state_bytes(space.layout))
    with pytest.raises(AnalysisError, match=rf"more than {met - 1:,} distinct contact states.*foundation.elements"):
        exact.analyze(deck.system, deck.ground_motion, "uplift")
    monkeypatch.setattr(operators, "MAX_OPERATOR_BYTES", 1)  # room for the 64 states max_states keeps
    result = invoke("analyze", str(WINKLER), "--set", "foundation.safety_factor=1.5", "--engine", "exact",
                    "--support", "uplift", "--format", "json")
    assert result.exit_code == 4, result.output
    assert "Traceback" not in result.output and not result.stdout.strip()
    assert "more than 64 distinct contact states" in result.output
