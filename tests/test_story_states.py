"""The states of a building whose stories yield, assembled from their foundation pattern's base
(engines/exact/story_states.py) against patterns.contact_states, and the step operators that states
with the same A share (operators.add_states; docs/theory.md 15.9)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from upliftcli.deck.load import load_deck
from upliftcli.engines.exact.operators import Operators, add_states, soil_rows
from upliftcli.engines.exact.patterns import contact_states
from upliftcli.engines.exact.statespace import exact_model
from upliftcli.engines.exact.stories import StoryYield, hysteretic_work, story_bits
from upliftcli.engines.exact.story_states import story_bases, story_state
from upliftcli.engines.options import ExactOptions

ROOT = Path(__file__).resolve().parent.parent
TWO = ROOT / "inputs" / "ten_story_elcentro.toml"
WINKLER = ROOT / "inputs" / "ten_story_winkler.toml"
STRENGTH = ("building.strength_coefficient=0.3", "building.hardening_ratio=0.05")


def _space(path: Path, support: str, *overrides: str):
    modes = ("analysis.modes=10",) if path == WINKLER else ()
    return exact_model(load_deck(path, [*modes, *STRENGTH, *overrides]).system, support, ExactOptions())


def _foundation(space, rng) -> tuple[np.ndarray, np.ndarray | None]:
    """A random foundation pattern: lifted, and yielding (with a bearing capacity) where not lifted."""
    lay = space.layout
    lifted = rng.random(lay.n_elements) < 0.3
    yielding = (rng.random(lay.n_elements) < 0.3) & ~lifted if lay.n_settlements else None
    return lifted, yielding


@pytest.mark.parametrize(("path", "support", "overrides"), [
    (TWO, "rigid", ()), (TWO, "bonded", ()), (TWO, "uplift", ()), (TWO, "uplift", ("foundation.safety_factor=1.5",)),
    (WINKLER, "uplift", ()), (WINKLER, "uplift", ("foundation.safety_factor=2",)),
])
def test_a_state_from_its_base_is_the_assembled_state_bit_for_bit(path, support, overrides):
    """story_state (a copy of the base's A with the rows of the yielding stories set, the event rows chosen)
    gives the matrix, the velocity map and the event rows of contact_states exactly, for random story signs
    on random foundation patterns (both criteria)."""
    space = _space(path, support, *overrides)
    lay = space.layout
    rng = np.random.default_rng(35)
    for criterion in ("reaction", "displacement"):
        for _ in range(4):
            lifted, yielding = _foundation(space, rng)
            (base,) = story_bases([space], lifted[None], None if yielding is None else yielding[None], criterion,
                                  soil_rows(lay))
            signs = rng.integers(-1, 2, (6, lay.n_plastic)).astype(np.int8)
            signs[0] = 0
            expected = contact_states([space] * len(signs), np.repeat(lifted[None], len(signs), axis=0), criterion,
                                      None if yielding is None else np.repeat(yielding[None], len(signs), axis=0),
                                      signs)
            for sign, want in zip(signs, expected, strict=True):
                got = story_state(base, sign)
                for name in ("lifted", "matrix", "velocity", "events", "yielding", "story_sign"):
                    assert np.array_equal(getattr(got, name), getattr(want, name)), name


def _pattern(lay, signs: np.ndarray) -> int:
    """The contact pattern of every element in contact with the stories' signs (stories.story_bits)."""
    base = soil_rows(lay)
    return sum((1 << (base + 2 * s)) if v > 0 else (1 << (base + 2 * s + 1)) if v < 0 else 0
               for s, v in enumerate(signs.tolist()))


@pytest.mark.parametrize("support", ["rigid", "uplift"])
def test_states_whose_stories_yield_in_the_same_places_share_their_operators(support):
    """Two states that differ only in the sign of a yielding story (same A) get the same step operators, the
    second the first's slot of them (Operators.slots, no copy), bit for bit what it gets built alone; their
    event rows differ."""
    space = _space(TWO, support)
    lay = space.layout
    signs = np.zeros(lay.n_plastic, dtype=np.int8)
    signs[[0, 3]] = (1, -1)
    one, other = _pattern(lay, signs), _pattern(lay, -signs)
    shared = Operators(space, 0.01, "reaction")
    first, second = add_states([(shared, one, True), (shared, other, True)])
    alone = Operators(space, 0.01, "reaction")
    (index,) = add_states([(alone, other, True)])
    assert len(shared.by_matrix) == 1
    assert shared.slots[second] == shared.slots[first] == first
    assert np.array_equal(shared.ops[shared.slots[second]], alone.ops[alone.slots[index]])
    assert np.array_equal(shared.matrices[second], alone.matrices[index])
    assert np.array_equal(shared.events[second], alone.events[index])
    assert not np.array_equal(shared.events[second], shared.events[first])


def test_the_sign_of_each_story_is_its_two_pattern_bits():
    """stories.story_bits: P - N of each story's bits (base + 2 s: P, base + 2 s + 1: N), 0 for both, over
    random patterns up to the 62 bits of a pattern, the foundation's bits below base ignored."""
    rng = np.random.default_rng(62)
    for _ in range(2000):
        count = int(rng.integers(1, 32))
        base = int(rng.integers(0, 62 - 2 * count + 1))
        pattern = int(rng.integers(0, 2**62, dtype=np.int64)) & ((1 << (base + 2 * count)) - 1)
        want = [((pattern >> (base + 2 * s)) & 1) - ((pattern >> (base + 2 * s + 1)) & 1) for s in range(count)]
        got = story_bits(pattern, base, count)
        assert got.dtype == np.int8
        assert got.tolist() == want


@pytest.mark.parametrize("count", [1, 3, 10])
def test_the_hysteretic_work_skips_only_elastic_intervals_bit_for_bit(count):
    """stories.hysteretic_work, which evaluates only the intervals where some story yields, gives the sum over
    every interval of the work while yielding (theory 15.3) bit for bit, one story or many, and so with the
    yielding samples given (Digest's, from the states' first samples)."""
    rng = np.random.default_rng(count)
    story = StoryYield(np.arange(count), rng.uniform(1e7, 1e8, count), rng.uniform(1e5, 1e6, count), 0.05,
                       np.ones((count, 1)), 10.0)
    drifts = np.cumsum(rng.normal(0.0, 1e-3, (500, count)), axis=0)
    sign = rng.choice(np.array([-1, 0, 0, 0, 0, 1], dtype=np.int8), (500, count))
    sign[100:200] = 0  # a stretch where every story is elastic
    d0, d1, s = drifts[:-1], drifts[1:], sign[:-1]
    a = story.alpha
    per = (1.0 - a) * (0.5 * a * story.stiffness * (d1**2 - d0**2) + s * (1.0 - a) * story.strength * (d1 - d0))
    want = np.where(s != 0, per, 0.0).sum(axis=0)
    assert np.array_equal(hysteretic_work(story, drifts, sign), want)
    assert np.array_equal(hysteretic_work(story, drifts, sign, sign.any(axis=1)), want)
    assert np.array_equal(hysteretic_work(story, drifts, np.zeros_like(sign)), np.zeros(count))
