"""The step operators of states where a story yields (engines/exact/level_operators.state_levels: the
Taylor polynomial of the finest level and squarings, _levels.c and its numpy twin levels_numpy.py) against
an independent implementation (scipy.linalg.expm) at every level, the entries that stay constant held
exactly, and the two backends against each other."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from backends import on_both
from scipy.linalg import expm as scipy_expm

from upliftcli.deck.load import load_deck
from upliftcli.engines.exact import levels_numpy
from upliftcli.engines.exact.level_operators import LEVELS, hold_settlements, stacked_operators, state_levels
from upliftcli.engines.exact.patterns import contact_states
from upliftcli.engines.exact.statespace import exact_model
from upliftcli.engines.options import ExactOptions
from upliftcli.runtime import backend

DECK = Path(__file__).resolve().parent.parent / "inputs" / "ten_story_elcentro.toml"
H = 0.01


def _levels(matrix: np.ndarray, h: float = H) -> np.ndarray:
    """state_levels of A on the backend in use, untransposed: E_j = expm(A h / 2^j), j = 0..LEVELS."""
    ops = np.full((LEVELS + 1, *matrix.shape), np.nan)  # every entry must be written
    state_levels(matrix, h, ops)
    return ops.transpose(0, 2, 1)


def _story_states(support: str, overrides: tuple[str, ...] = (), capacity_yields: bool = False):
    """Six states of the README deck with strength 0.3 W on `support`: one to all ten stories yielding, in
    random directions (with a bearing capacity: the first element yielding where capacity_yields)."""
    space = exact_model(load_deck(DECK, ["building.strength_coefficient=0.3", *overrides]).system, support,
                        ExactOptions())
    lay = space.layout
    signs = np.random.default_rng(35).integers(-1, 2, (6, lay.n_plastic)).astype(np.int8)
    signs[0], signs[1] = 1, 0
    signs[1, 4] = -1
    lifted = np.zeros((len(signs), lay.n_elements), dtype=bool)
    yielding = None
    if lay.n_settlements:
        yielding = np.zeros((len(signs), lay.n_elements), dtype=bool)
        yielding[:, 0] = capacity_yields
    return lay, contact_states([space] * len(signs), lifted, "reaction", yielding, signs)


@pytest.mark.parametrize("name", ["compiled", "numpy"])
@pytest.mark.parametrize("support", ["rigid", "bonded", "uplift"])
def test_every_level_is_the_exponential_of_a_yielding_state(support, name):
    """exp(A h / 2^j) at every level j = 0..12 of states with one to all ten stories yielding, against
    scipy.linalg.expm of each, to 1e-12 of the largest entry (measured at most 5.5e-13, at level 0, the most
    squared; the earlier stacked numpy construction: 5.3e-13), on each backend; the zero rows of A (the
    plastic drifts of the elastic stories, the constant forcing entries) unit rows exactly."""
    if name == "compiled":
        on_both(lambda: None)  # skips where the C extensions were not built
    lay, states = _story_states(support)
    with backend.use(name):
        for r, state in enumerate(states):
            levels = _levels(state.matrix)
            held = np.flatnonzero(~state.matrix.any(axis=1))
            assert set(lay.plastic_indices[state.story_sign == 0]) <= set(held)
            for j in range(LEVELS + 1):
                reference = scipy_expm(state.matrix * (H / 2.0**j))
                assert np.abs(levels[j] - reference).max() <= 1e-12 * np.abs(reference).max(), (r, j)
                np.testing.assert_array_equal(levels[j][held], np.eye(lay.n_aug)[held])


@pytest.mark.parametrize("support", ["rigid", "bonded", "uplift"])
def test_the_compiled_levels_and_their_twin_give_the_same_bits(support):
    """_levels.c and levels_numpy.py give the same bits (the same operations in the same order, each sum of a
    product in the order of its terms), on the states of the README deck and on random matrices of 1 to 13
    rows with some rows zero: a yielding run is the same on both backends but for the stepping loop's own
    round-off (a BLAS product would change the residual drifts of ten_story_asce7_nlrha.toml by 8e-9,
    tests/test_backend_agreement.py)."""
    _, states = _story_states(support)
    rng = np.random.default_rng(7)
    matrices = [state.matrix for state in states]
    for n in range(1, 14):
        matrices.append(rng.normal(size=(n, n)) * 300.0)
        matrices[-1][rng.random(n) < 0.4] = 0.0
    for matrix in matrices:
        compiled, twin = on_both(lambda matrix=matrix: _levels(matrix))
        np.testing.assert_array_equal(compiled, twin)


@pytest.mark.parametrize("name", ["compiled", "numpy"])
def test_the_settlements_of_elements_that_do_not_yield_are_held_exactly(name):
    """On two elements with a bearing capacity the rows of the settlements of elements that do not yield are
    zero in A: the operators of a state where a story yields hold them exactly, as hold_settlements would set
    them (the stacked construction sets them so after its exponentials: level_operators.hold_settlements)."""
    if name == "compiled":
        on_both(lambda: None)
    for capacity_yields in (False, True):
        lay, states = _story_states("uplift", ("foundation.safety_factor=2",), capacity_yields)
        assert lay.n_settlements == 2
        with backend.use(name):
            for state in states:
                ops = np.empty((LEVELS + 1, lay.n_aug, lay.n_aug))
                state_levels(state.matrix, H, ops)
                held = ops.copy()
                hold_settlements(held, lay.settlement_indices[~state.yielding])
                np.testing.assert_array_equal(ops, held)


@pytest.mark.parametrize("name", ["compiled", "numpy"])
def test_any_pattern_of_zero_rows_and_any_size(name):
    """Matrices of 1 to 13 rows (the compiled products take four rows at a time, eight columns: every
    remainder), with no, some and all rows zero, and a zero matrix (the identity at every level): every level
    against scipy.linalg.expm, to 5e-12 of its largest entry (measured 1.4e-12 at level 0: twelve squarings of
    random matrices, some with growing modes)."""
    if name == "compiled":
        on_both(lambda: None)
    rng = np.random.default_rng(6)
    with backend.use(name):
        for n in range(1, 14):
            for zero_share in (0.0, 0.4, 1.0):
                a = rng.normal(size=(n, n)) * 300.0
                a[rng.random(n) < zero_share] = 0.0
                levels = _levels(a, 1e-3)
                for j in range(LEVELS + 1):
                    reference = scipy_expm(a * (1e-3 / 2.0**j))
                    assert np.abs(levels[j] - reference).max() <= 5e-12 * np.abs(reference).max(), (n, j)


@pytest.mark.parametrize("name", ["compiled", "numpy"])
def test_a_matrix_whose_powers_grow_is_halved(name):
    """A stiff matrix with eta = max(|A^2|^(1/2), |A^3|^(1/3)) above THETA_TAYLOR at the finest level (an
    oscillator of w h = 1000 to 2000, not a few large forcing columns) is halved before its Taylor polynomial:
    every level to 1e-11 of scipy's, and closer than the exponential of the finest and of the coarsest level
    with squarings between (stacked_operators; measured 9e-12 against 2e-9 at level 3)."""
    if name == "compiled":
        on_both(lambda: None)
    assert levels_numpy.THETA_TAYLOR == 0.1
    for w in (1.0e5, 2.0e5):
        a = np.array([[0.0, 1.0, 0.0], [-w**2, -0.1 * w, 1.0e3], [0.0, 0.0, 0.0]])
        with backend.use(name):
            levels = _levels(a)
        pade = stacked_operators(a.T[None], np.array([[[H]]]))[0].transpose(0, 2, 1)
        for j in range(LEVELS + 1):
            reference = scipy_expm(a * (H / 2.0**j))
            scale = max(1.0, np.abs(reference).max())
            error = np.abs(levels[j] - reference).max() / scale
            assert error <= 1e-11 and error <= np.abs(pade[j] - reference).max() / scale, (w, j)


@pytest.mark.parametrize("name", ["compiled", "numpy"])
def test_the_degree_of_the_taylor_polynomial_follows_eta(name):
    """The finest level's Taylor polynomial is of degree 6 (one product fewer) where eta is at most THETA_SIX, whose
    remainder bound sum_{k > 6} eta^k / k! is then below the unit round-off 2^-53, and of degree 9 above it: a
    README state scaled so that its eta lies just below and just above THETA_SIX, and a stiff oscillator (eta far
    above: degree 9 after halvings), every level against scipy.linalg.expm to 1e-12 of its largest entry (the
    oscillator 1e-11, as above), and the two backends give the same bits."""
    if name == "compiled":
        on_both(lambda: None)
    bound = sum(levels_numpy.THETA_SIX**k / math.factorial(k) for k in range(7, 30))
    assert bound < 2.0**-53 < sum((1.01 * levels_numpy.THETA_SIX)**k / math.factorial(k) for k in range(7, 30))
    _, states = _story_states("bonded")
    matrix = states[2].matrix
    eta = _eta(matrix, H)
    stiff = np.array([[0.0, 1.0, 0.0], [-1.0e10, -1.0e4, 1.0e3], [0.0, 0.0, 0.0]])
    for a, h, tolerance in ((matrix, 0.98 * levels_numpy.THETA_SIX / eta * H, 1e-12),
                            (matrix, 1.02 * levels_numpy.THETA_SIX / eta * H, 1e-12), (stiff, H, 1e-11)):
        with backend.use(name):
            levels = _levels(a, h)
        for j in range(LEVELS + 1):
            reference = scipy_expm(a * (h / 2.0**j))
            scale = max(1.0, np.abs(reference).max()) if a is stiff else np.abs(reference).max()
            assert np.abs(levels[j] - reference).max() <= tolerance * scale, (h, j)
        np.testing.assert_array_equal(*on_both(lambda a=a, h=h: _levels(a, h)))


def _eta(matrix: np.ndarray, h: float) -> float:
    """max(|B^2|^(1/2), |B^3|^(1/3)) in 1-norms of B = A^T h / 2^LEVELS (levels_numpy.finest_level's)."""
    b = matrix.T * (h / 2.0**LEVELS)
    power2 = b @ b
    return max(np.abs(power2).sum(axis=0).max() ** 0.5, np.abs(power2 @ b).sum(axis=0).max() ** (1.0 / 3.0))


def test_the_compiled_levels_refuse_inconsistent_arguments():
    """The C function names what it expected (shapes, a finite step, float64 C-contiguous arrays)."""
    on_both(lambda: None)
    from upliftcli.engines.exact import _levels

    with pytest.raises(ValueError, match="matrix"):
        _levels.state_levels(np.zeros((3, 3)), H, np.empty((13, 4, 4)))
    with pytest.raises(ValueError, match="finite"):
        _levels.state_levels(np.zeros((3, 3)), float("nan"), np.empty((13, 3, 3)))
    with pytest.raises(TypeError, match="ops"):
        _levels.state_levels(np.zeros((3, 3)), H, np.empty((13, 3, 3), dtype=np.float32))


@pytest.mark.parametrize("support", ["rigid", "bonded", "uplift"])
def test_a_state_where_no_story_yields_is_state_levels_with_the_elastic_block(support):
    """The first state of a run of a building whose stories may yield (none yields): its operators are
    state_levels' (the Taylor polynomial and squarings) but for the entries other than the plastic drifts, which
    are the elastic building's stacked exponentiation (elastic_blocks) exactly, so a run that never yields is the
    elastic run bit for bit; the plastic drifts' rows of E unit rows."""
    from upliftcli.engines.exact.level_operators import elastic_blocks
    from upliftcli.engines.exact.operators import Operators, add_states

    space = exact_model(load_deck(DECK, ["building.strength_coefficient=0.3"]).system, support, ExactOptions())
    lay = space.layout
    operators = Operators(space, H, "reaction", support == "uplift")
    (index,) = add_states([(operators, 0, True)])
    state = operators.contact[index]
    assert not state.story_sign.any()
    keep = np.delete(np.arange(lay.n_aug), lay.plastic_indices)
    ops = operators.ops[index]
    block = elastic_blocks([state], lay, [H])[0]
    assert np.array_equal(ops[:, keep[:, None], keep[None, :]], block)
    levels = np.empty_like(ops)
    state_levels(state.matrix, H, levels)
    plastic = lay.plastic_indices
    assert np.array_equal(ops[:, plastic[:, None], keep[None, :]], levels[:, plastic[:, None], keep[None, :]])
    assert np.array_equal(ops[:, :, plastic], np.broadcast_to(np.eye(lay.n_aug)[:, plastic], ops[:, :, plastic].shape))
