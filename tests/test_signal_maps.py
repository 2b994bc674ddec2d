"""The signals of a run with yielding stories (engines/exact/signal_maps.py): the states met at a few samples have
their signals from the derivatives X' = A X, X'' = A X' of those samples (_mixed), the others from their rows; both
agree with the rows of every state to round-off, the samples of the others bit for bit; the derivatives' loop and
its twin agree (response_kernels.derivatives)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from backends import on_both

from upliftcli.engines.exact import response, response_kernels, signal_maps
from upliftcli.engines.exact.engine import model_for
from upliftcli.engines.exact.stepping import simulate
from upliftcli.engines.options import ExactOptions
from upliftcli.runtime import backend


@pytest.fixture(scope="module", params=["rigid", "bonded"])
def history(request, elcentro):
    """A yielding ten-story building (hundreds of states, most met at a few samples) on the rigid or bonded base."""
    from paper_example import paper_system

    system = paper_system(0.5)
    building = replace(system.building, story_strength=0.04 * system.building.masses.sum() * 9.81
                       * np.linspace(1.0, 0.3, system.building.n_stories), hardening_ratio=0.05)
    system = replace(system, building=building)
    space = model_for(system, request.param, ExactOptions())
    ((_, out),) = simulate([space], [4], elcentro.acceleration[:1500], elcentro.dt, "reaction", uplift=False,
                           allow_flight=True)
    return out


def _from_rows(history) -> tuple:
    """(values, slopes, end values, end slopes, slope rows' coefficients on the ground slope) from the rows of every
    state (signal_rows and evaluate_signals: the way of an elastic building)."""
    used, ids = signal_maps.used_states(history.state_ids, len(history.contact))
    rows = signal_maps.signal_rows(history, used)
    start = rows.shape[1] - response.signals(history).slopes.shape[1]
    at = np.flatnonzero(ids[1:] != ids[:-1])
    values, slopes, ends = np.empty((ids.size, start)), np.empty((ids.size, rows.shape[1] - start)), \
        np.empty((at.size, rows.shape[1]))
    response_kernels.evaluate_signals(history.states, ids, rows, values, slopes, ends)
    return values, slopes, ends[:, :start], ends[:, start:], rows[:, start:, history.space.layout.index_slope]


def _close(a: np.ndarray, b: np.ndarray) -> None:
    """a and b agree to round-off, relative to each column's largest value."""
    scale = np.maximum(np.abs(b).max(axis=0), 1e-300)
    assert np.all(np.abs(a - b) <= 1e-12 * scale)


@pytest.mark.parametrize("kind", ["compiled", "numpy"])
def test_the_signals_from_derivatives_are_those_of_the_rows_of_every_state(history, kind):
    """The run meets more than FEW_STATES states of fewer than SPLIT_USES products (so _mixed serves it); its
    signals, left limits and curvature coefficients on the ground slope are those of the rows of every state to
    round-off, and the samples of the states of many products are bit for bit theirs."""
    if kind == "compiled":
        on_both(lambda: None)  # skipped where the C loops were not built
    used, ids = signal_maps.used_states(history.state_ids, len(history.contact))
    at = np.flatnonzero(ids[1:] != ids[:-1])
    uses = signal_maps._uses(ids, at, used.size)
    assert np.count_nonzero(uses < signal_maps.SPLIT_USES) > signal_maps.FEW_STATES
    with backend.use(kind):
        sig = response.signals(history)
        values, slopes, end_values, end_slopes, slope_rows = _from_rows(history)
    many = (uses >= signal_maps.SPLIT_USES)[ids]
    assert many.any() and not many.all()
    assert sig.values[many].tobytes() == values[many].tobytes()
    assert sig.slopes[many].tobytes() == slopes[many].tobytes()
    for mine, theirs in ((sig.values, values), (sig.slopes, slopes), (sig.end_values, end_values),
                         (sig.end_slopes, end_slopes)):
        _close(mine, theirs)
    curved = np.concatenate([np.arange(c.start, c.stop) for c in sig.curvatures.values()])
    _close(sig.slope_rows, response._slope_rows(slope_rows, sig.rows, sig.curvatures))
    assert np.abs(slope_rows[:, curved]).max() > 0.0


def test_the_derivatives_loop_is_its_twin():
    """X' = A X and X'' = A X' of each state with its own A, the loop against the twin (round-off), on states of
    zeros and of several matrices; a matrix of the wrong shape is refused."""
    rng = np.random.default_rng(3)
    matrices = [rng.standard_normal((7, 7)) * (rng.random((7, 7)) < 0.4) for _ in range(3)]
    x = rng.standard_normal((11, 7))
    x[4] = 0.0
    ids = np.array([0, 0, 2, 1, 1, 1, 0, 2, 2, 1, 0], dtype=np.int64)

    def run():
        first, second = np.empty(x.shape), np.empty(x.shape)
        response_kernels.derivatives(x, ids, matrices, first, second)
        return first, second

    (c1, c2), (t1, t2) = on_both(run)
    expected = np.einsum("ijk,ik->ij", np.stack(matrices)[ids], x)
    np.testing.assert_allclose(c1, expected, rtol=0, atol=1e-13)
    np.testing.assert_allclose(t1, expected, rtol=0, atol=1e-13)
    np.testing.assert_allclose(c2, np.einsum("ijk,ik->ij", np.stack(matrices)[ids], expected), rtol=0, atol=1e-12)
    np.testing.assert_allclose(t2, c2, rtol=0, atol=1e-12)
    with backend.use("compiled"), pytest.raises(ValueError, match="inconsistent"):
        response_kernels.derivatives(x, ids, [np.zeros((6, 6))] * 3, *run())


def test_evaluate_signals_leaves_the_samples_of_negative_ids():
    """A sample of a negative id (a state the caller evaluates: signal_maps._mixed) and the left limit at the end of
    its interval are left as they were, the others are those of a call with every id; the left limits keep their
    places among all transitions (distinct negative ids, distinct states), on both backends."""
    rng = np.random.default_rng(5)
    rows = rng.standard_normal((3, 9, 6))
    states = rng.standard_normal((40, 6))
    every = np.repeat(np.array([0, 3, 1, 4, 4, 2, 0, 3, 1, 1]), 4).astype(np.int64)  # 3 and 4: the caller's
    ids = np.where(every < 3, every, 2 - every)  # -1 and -2
    at = np.flatnonzero(every[1:] != every[:-1])
    full = np.where(every < 3, every, 0)

    def run(which):
        values, slopes, ends = np.full((40, 5), np.nan), np.full((40, 4), np.nan), np.full((at.size, 9), np.nan)
        response_kernels.evaluate_signals(states, which, rows, values, slopes, ends)
        return values, slopes, ends

    for (values, slopes, ends), (all_values, all_slopes, _) in zip(on_both(lambda: run(ids)),
                                                                    on_both(lambda: run(full)), strict=True):
        mine = ids >= 0
        assert np.isnan(values[~mine]).all() and np.isnan(slopes[~mine]).all()
        np.testing.assert_array_equal(values[mine], all_values[mine])
        np.testing.assert_array_equal(slopes[mine], all_slopes[mine])
        from_mine = ids[at] >= 0
        assert np.isnan(ends[~from_mine]).all()
        expected = np.einsum("ijk,ik->ij", rows[ids[at][from_mine]], states[at[from_mine] + 1])
        np.testing.assert_allclose(ends[from_mine], expected, rtol=1e-12, atol=1e-12)
