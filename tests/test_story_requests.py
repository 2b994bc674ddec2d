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
        built[0] += len(requests)
        return add_quick(requests)

    monkeypatch.setattr(operators, "add_quick", counted)
    if not quick:
        monkeypatch.setattr(operators, "quick_requests", lambda requests: None)
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
    for name in ("ops", "events", "event_rates", "matrices", "patterns"):
        assert np.array_equal(getattr(quick, name)[:n], getattr(slow, name)[:n]), name
    for got, want in zip(quick.contact, slow.contact, strict=True):
        for name in FIELDS:
            assert np.array_equal(getattr(got, name), getattr(want, name)), name
    assert quick.by_matrix == slow.by_matrix
