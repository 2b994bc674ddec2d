"""The compiled contact states of a foundation whose elements yield (engines/exact/_soil_states.c,
_soil_operators.c) against their numpy twins (soil_states_numpy.py, soil_operators_numpy.py: the
former numpy code), case by case and on a whole yielding run (skipped where the C extensions were
not built: tests/backends.py)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from backends import on_both

from upliftcli.analysis import run as analysis
from upliftcli.deck.load import load_deck
from upliftcli.engines.exact.operators import LEVELS
from upliftcli.engines.exact.patterns import contact_states
from upliftcli.engines.exact.statespace import exact_model
from upliftcli.engines.exact.yielding import step_operators
from upliftcli.engines.options import ExactOptions

ROOT = Path(__file__).resolve().parent.parent
TWO = ROOT / "inputs" / "ten_story_elcentro.toml"
WINKLER = ROOT / "inputs" / "ten_story_winkler.toml"


def _space(path, *overrides):
    return exact_model(load_deck(path, ["foundation.safety_factor=1.5", *overrides]).system, "uplift", ExactOptions())


def _kinds(n_e: int, count: int = 24) -> np.ndarray:
    """Element states 0 C, 1 Y, 2 L (count, n_e): every combination on two elements, random ones else."""
    if n_e == 2:
        return np.array(np.meshgrid(*[range(3)] * n_e)).reshape(n_e, -1).T
    return np.random.default_rng(35).integers(0, 3, (count, n_e))


@pytest.mark.parametrize("path, overrides", [(TWO, ()), (WINKLER, ()),
                                             (WINKLER, ("building.strength_coefficient=0.3",))])
@pytest.mark.parametrize("criterion", ["reaction", "displacement"])
def test_the_compiled_soil_states_are_their_twin(path, overrides, criterion):
    """A, the velocity map and the event rows of every pattern (with yielding stories: the soil's part, the
    stories' rows added by patterns.py alike) agree to 1e-13 of each array's largest entry (measured
    2.8e-16: the order of the sums), with the same pattern bits."""
    space = _space(path, *overrides)
    kinds = _kinds(space.layout.n_elements)
    compiled, twin = on_both(lambda: contact_states([space] * len(kinds), kinds == 2, criterion, kinds == 1))
    for a, b in zip(compiled, twin, strict=True):
        assert np.array_equal(a.lifted, b.lifted) and np.array_equal(a.yielding, b.yielding)
        for name in ("matrix", "velocity", "events"):
            x, y = getattr(a, name), getattr(b, name)
            assert x.shape == y.shape
            assert np.abs(x - y).max() <= 1e-13 * np.abs(y).max(), name


def test_both_refuse_a_massless_rotation_without_damping():
    """Every element lifted, no damping anywhere and no rotary inertia: both raise ZeroDivisionError (which
    operators._built_states turns into the run's error)."""
    space = _space(WINKLER)
    assert space.layout.massless.size == 1
    still = replace(space, damping=np.zeros_like(space.damping), element_damping=np.zeros_like(space.element_damping))
    lifted = np.ones((1, space.layout.n_elements), dtype=bool)

    def build():
        try:
            contact_states([still], lifted, "reaction", ~lifted)
        except ZeroDivisionError:
            return "refused"
        return "built"

    assert on_both(build) == ("refused", "refused")


@pytest.mark.parametrize("stories", [10, 7])
def test_the_compiled_block_operators_are_their_twin(stories):
    """Every bisection level of the block operators (yielding.step_operators) of random C/Y/L states of the
    Winkler mat, stacked and one at a time, agrees to 2e-12 of the level's largest entry (measured 5.5e-13:
    the compiled products round without fused multiply-adds, numpy's BLAS with them; each is within 6e-13
    of scipy's exponential of the whole A, tests/test_operators.py). Blocks of 28 and, on seven stories, 22
    rows: the second takes every path of compiled/product.h's matrix_product (tiles of 8 and 4 columns,
    the columns and rows left over)."""
    space = _space(WINKLER, f"building.stories={stories}")
    kinds = _kinds(space.layout.n_elements, 12)
    states = contact_states([space] * len(kinds), kinds == 2, "reaction", kinds == 1)
    for h in (0.02 / 8, 0.02):
        compiled, twin = on_both(lambda h=h: np.stack(step_operators(space, states, h, LEVELS)))
        scale = np.abs(twin).max(axis=(2, 3), keepdims=True)
        assert np.all(np.abs(compiled - twin) <= 2e-12 * scale)
        one_by_one, _ = on_both(lambda h=h: np.stack(step_operators(space, states, h, LEVELS, _slots(space, states))))
        assert np.array_equal(one_by_one, compiled)  # each state the bits it gets in a stack


def _slots(space, states) -> list[np.ndarray]:
    """Zero operator arrays (LEVELS + 1, n_aug, n_aug), one per state (step_operators' out as a list)."""
    return [np.zeros((LEVELS + 1, space.layout.n_aug, space.layout.n_aug)) for _ in states]


def test_a_yielding_winkler_run_is_the_same_on_both_backends():
    """The exact engine on the Winkler deck with FS_v = 1.5 (the mat yields): every peak agrees to 1e-9 of
    its quantity's largest value on both backends (tests/test_backend_agreement.py's bound; measured
    1.1e-10), with the same transitions (589)."""
    deck = load_deck(WINKLER, ["foundation.safety_factor=1.5"])
    compiled, twin = on_both(lambda: analysis.run_one(deck, "exact", "uplift"))
    assert compiled.details["yielding"]["plastic_work"] > 0.0
    assert compiled.intermediates["transitions"] == twin.intermediates["transitions"]
    for name, values in twin.peaks.items():
        scale = np.abs(values).max(initial=0.0)
        np.testing.assert_allclose(compiled.peaks[name], values, rtol=0, atol=1e-9 * scale, err_msg=name)
