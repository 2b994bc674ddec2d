"""The states of yielding-story runs built one request at a time (engines/exact/story_requests.py) against
those operators.add_states' batch machinery builds for the same requests: the same arrays, bit for bit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from upliftcli.deck.load import load_deck
from upliftcli.engines.exact import operators, story_requests
from upliftcli.engines.exact.operators import Operators, add_states, soil_rows
from upliftcli.engines.exact.statespace import exact_model
from upliftcli.engines.options import ExactOptions
from upliftcli.runtime import backend

ROOT = Path(__file__).resolve().parent.parent
TWO = ROOT / "inputs" / "ten_story_elcentro.toml"
STRENGTH = ("building.strength_coefficient=0.3", "building.hardening_ratio=0.05")
FIELDS = ("lifted", "matrix", "velocity", "events", "yielding", "story_sign")


def _patterns(lay, rng, count: int) -> list[int]:
    """Random contact patterns: a foundation pattern (an edge lifted or none) and story signs, each second one
    the first's signs flipped (the same A: its operators shared)."""
    out = []
    for _ in range(count // 2):
        soil = int(rng.choice([0, 1, 1 << (lay.n_elements - 1)])) if lay.n_elements else 0
        signs = rng.choice([-1, 0, 0, 1], lay.n_plastic)
        for flip in (1, -1):
            out.append(soil | _story_bits(lay, flip * signs))
    return out


def _story_bits(lay, signs: np.ndarray) -> int:
    base = soil_rows(lay)
    return sum((1 << (base + 2 * s)) if v > 0 else (1 << (base + 2 * s + 1)) if v < 0 else 0
               for s, v in enumerate(signs.tolist()))


def _built(space, uplift: bool, patterns: list[int], quick: bool, monkeypatch) -> tuple[Operators, int]:
    """Operators with the states of `patterns` added one request at a time, by story_requests where it
    qualifies (quick) or by add_states' batch machinery only; how many story_requests built."""
    built = [0]
    add_quick = story_requests.add_quick

    def counted(requests):
        out = add_quick(requests)
        built[0] += 0 if out is None else len(out)
        return out

    monkeypatch.setattr(operators, "add_quick", counted if quick else lambda requests: None)
    ops = Operators(space, 0.01, "reaction", uplift)
    for pattern in [0, *patterns]:
        (index,) = add_states([(ops, pattern, True)])
        assert isinstance(index, int)
    monkeypatch.undo()
    return ops, built[0]


@pytest.mark.parametrize("choice", ["compiled", "numpy"])
@pytest.mark.parametrize("support", ["rigid", "bonded", "uplift"])
def test_a_quick_state_is_the_state_add_states_builds_bit_for_bit(support, choice, monkeypatch):
    """Random story signs on the foundation patterns of each support, each followed by its flipped signs (the
    same A): the states story_requests builds, and their step operators, event rows, rates and matrices, are
    those of add_states' batch machinery bit for bit, with either backend."""
    if choice == "compiled" and "upliftcli.engines.exact._levels" not in backend.built():
        pytest.skip("the C extension _levels is not built")
    space = exact_model(load_deck(TWO, list(STRENGTH)).system, support, ExactOptions())
    patterns = _patterns(space.layout, np.random.default_rng(len(support)), 40)
    with backend.use(choice):
        quick, count = _built(space, support == "uplift", patterns, True, monkeypatch)
        slow, none = _built(space, support == "uplift", patterns, False, monkeypatch)
    assert count > 30 and none == 0  # the first state of each foundation pattern is add_states'
    n = len(quick.contact)
    assert n == len(slow.contact) == len(patterns) + 1
    for name in ("slots", "events", "event_rates", "matrices", "patterns"):
        assert np.array_equal(getattr(quick, name)[:n], getattr(slow, name)[:n]), name
    assert np.array_equal(quick.ops[quick.slots[:n]], slow.ops[slow.slots[:n]])  # each state's operators
    for got, want in zip(quick.contact, slow.contact, strict=True):
        for name in FIELDS:
            assert np.array_equal(getattr(got, name), getattr(want, name)), name
    assert quick.by_matrix == slow.by_matrix


@pytest.mark.parametrize(("zero_rows", "soil_rows"), [(0, 0), (2, 2), (0, 2)])
def test_the_compiled_story_rows_are_its_numpy_twin(zero_rows, soil_rows):
    """_levels.story_rows and levels_numpy.story_rows write the same rows, event rows, rates, A^T and fields for
    random story bits on a random table with zeros (bit for bit: copies, and rates each summed in the order of its
    terms), the rates those of the event rows by A (the foundation's rows, not zeroed, left as they were); a pick
    outside the table is refused."""
    if "upliftcli.engines.exact._levels" not in backend.built():
        pytest.skip("the C extension _levels is not built")
    from upliftcli.engines.exact import _levels, levels_numpy

    rng = np.random.default_rng(zero_rows + 3 * soil_rows)
    n, n_y, n_s = 7, 3, 2
    n_e = n_s + 2 * n_y
    table = rng.normal(size=(3 * n + n_s + 6 * n_y, n)) * (rng.random((3 * n + n_s + 6 * n_y, n)) < 0.6)
    base = np.concatenate((np.arange(n), 3 * n + np.arange(n_e)))  # as story_states._picks: the last n_y rows of A
    step = np.concatenate((np.where(np.arange(n) >= n - n_y, n, 0), np.zeros(n_s), np.full(2 * n_y, 2 * n_y)))
    story = np.concatenate((np.zeros(n - n_y), np.arange(n_y), np.zeros(n_s), np.repeat(np.arange(n_y), 2)))
    picks = np.stack((base, step, story)).astype(np.int64)
    for bits in rng.integers(0, 1 << (2 * n_y), 20).tolist():
        bits &= ~((bits >> 1) & int("01" * n_y, 2))  # no story both ways
        out = []
        for module in (_levels, levels_numpy):
            arrays = (np.empty((n + n_e, n)), np.empty((n_e, n)), np.full((n_e, n), 7.0), np.empty((n, n)),
                      np.empty(n_y, dtype=np.int64))
            module.story_rows(bits, table, picks, *arrays, zero_rows, soil_rows)
            out.append(arrays)
        for got, want in zip(*out, strict=True):
            assert np.array_equal(got, want)
        rows, events, rates, matrix_t, fields = out[0]
        assert np.array_equal(matrix_t, rows[:n].T) and not events[:zero_rows].any() and not rates[:zero_rows].any()
        assert np.all(rates[zero_rows:soil_rows] == 7.0)
        assert np.allclose(rates[soil_rows:], events[soil_rows:] @ rows[:n], rtol=1e-14, atol=1e-14)
        assert fields.tolist() == [(bits >> (2 * s)) & 3 for s in range(n_y)]
    wrong = picks.copy()
    wrong[0, 0] = table.shape[0]
    with pytest.raises(ValueError, match="story_rows"):
        _levels.story_rows(0, table, wrong, np.empty((n + n_e, n)), np.empty((n_e, n)), np.empty((n_e, n)),
                           np.empty((n, n)), np.empty(n_y, dtype=np.int64), 0, 0)
    with pytest.raises(ValueError, match="story_rows"):  # zero rows beyond the foundation's
        _levels.story_rows(0, table, picks, np.empty((n + n_e, n)), np.empty((n_e, n)), np.empty((n_e, n)),
                           np.empty((n, n)), np.empty(n_y, dtype=np.int64), 2, 0)


def test_requests_of_several_runs_are_built_as_each_alone(monkeypatch):
    """Requests of two runs in one call (a sweep's runs stepped together) are built here, each as built alone;
    two requests of one run go to add_states' batch machinery (the order of its states would differ)."""
    space = exact_model(load_deck(TWO, list(STRENGTH)).system, "rigid", ExactOptions())
    patterns = _patterns(space.layout, np.random.default_rng(7), 12)
    alone, _ = _built(space, False, patterns, True, monkeypatch)
    runs = [Operators(space, 0.01, "reaction", False) for _ in range(2)]
    add_states([(ops, 0, True) for ops in runs])
    for pattern in patterns:
        assert story_requests.quick_requests([(ops, pattern, True) for ops in runs]) is not None
        add_states([(ops, pattern, True) for ops in runs])
    n = len(alone.contact)
    for ops in runs:
        for name in ("slots", "events", "event_rates", "matrices", "patterns"):
            assert np.array_equal(getattr(ops, name)[:n], getattr(alone, name)[:n]), name
        assert np.array_equal(ops.ops[ops.slots[:n]], alone.ops[alone.slots[:n]])
    twice = [(runs[0], patterns[0], True), (runs[0], patterns[1], True)]
    assert story_requests.quick_requests(twice) is None


def test_the_elastic_stories_of_states_built_together_are_those_built_alone():
    """The first round of a yielding uplift run builds three states where no story yields (in contact, each edge
    lifted) together: their elastic building's operators from one stacked exponentiation
    (level_operators.elastic_blocks) are those each state gets built alone, bit for bit."""
    space = exact_model(load_deck(TWO, list(STRENGTH)).system, "uplift", ExactOptions())
    patterns = [0, 1, 1 << (space.layout.n_elements - 1)]
    together = Operators(space, 0.01, "reaction")
    add_states([(together, pattern, True) for pattern in patterns])
    for k, pattern in enumerate(patterns):
        alone = Operators(space, 0.01, "reaction")
        (index,) = add_states([(alone, pattern, True)])
        assert np.array_equal(together.ops[together.slots[k]], alone.ops[alone.slots[index]])
        assert np.array_equal(together.event_rates[k], alone.event_rates[index])
