"""The curvature rows of the signals the work integrals interpolate (engines/exact/signal_maps.py
signal_rows, curvature_columns; read by energy.py): evaluated in the same pass as the response
signals, they leave every response signal's bits as they were, and they are the second rates
R A^2 x of the input signal, the element velocities and Y*' (the slopes of Y*'')."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from backends import compiled_or_skip

from upliftcli.engines.exact import response, response_kernels, signal_maps
from upliftcli.engines.exact.engine import model_for
from upliftcli.engines.exact.stepping import simulate
from upliftcli.engines.options import ExactOptions
from upliftcli.model.foundations import Winkler
from upliftcli.runtime import backend


@pytest.fixture(scope="module")
def histories(elcentro):
    """Uplift histories: the ten-story example at T_1 = 0.05 s (flight) and 0.5 s, and a Winkler mat."""
    from paper_example import paper_system

    base = paper_system(0.5)
    two, b = base.foundation, base.half_width
    winkler = replace(base, foundation=Winkler(3.0 * two.stiffness / b, 3.0 * two.damping / b, 6))
    out = []
    for system in (paper_system(0.05), base, winkler):
        space = model_for(system, "uplift", ExactOptions())
        ((_, history),) = simulate([space], [4], elcentro.acceleration[:600], elcentro.dt, "reaction", uplift=True,
                                   allow_flight=True)
        out.append(history)
    return out


def _layout(history) -> tuple[dict, int, int]:
    """The signal layout of a history, the number of value columns and of slope columns of the signals."""
    lay = history.space.layout
    names = signal_maps.signal_layout(history.space.model.n_modes, lay.n_elements, lay.n_plastic)
    return names, names[signal_maps.VALUES_ONLY[-1]].stop, names[signal_maps.WITH_RATES[-1]].stop


def test_the_curvature_rows_leave_every_response_signal_bit_for_bit(histories):
    """The signals evaluated from the response rows alone (values and rates, as before the curvature rows
    joined them) equal those of response.signals bit for bit, at the samples and the left limits: the
    compiled loop evaluates each row on its own. (numpy's twin multiplies all rows of a state in one
    matmul, whose blocking follows the number of rows: there a few signals move by an ulp.)"""
    compiled_or_skip()
    for history in histories:
        with backend.use("compiled"):
            sig = response.signals(history)
        _, start, n_slopes = _layout(history)
        used, ids = signal_maps.used_states(history.state_ids, len(history.contact))
        rows = np.ascontiguousarray(signal_maps.signal_rows(history, used)[:, :start + n_slopes])
        values, slopes = np.empty((ids.size, start)), np.empty((ids.size, n_slopes))
        ends = np.empty((sig.end_values.shape[0], start + n_slopes))
        with backend.use("compiled"):
            response_kernels.evaluate_signals(history.states, ids, rows, values, slopes, ends)
        assert sig.end_values.shape[0] > 0  # transitions were met
        assert values.tobytes() == sig.values.tobytes()
        assert slopes.tobytes() == np.ascontiguousarray(sig.slopes[:, :n_slopes]).tobytes()
        assert ends[:, :start].tobytes() == sig.end_values.tobytes()
        assert ends[:, start:].tobytes() == np.ascontiguousarray(sig.end_slopes[:, :n_slopes]).tobytes()


def test_the_curvature_columns_hold_the_second_rates(histories):
    """sig.slopes[:, curvatures[name]] = R A^2 x of each interpolated signal in each sample's own state, the
    ground slope that the left limits' correction reads is the state's own, and slope_rows hold each
    curvature row's coefficient on it."""
    for history in histories:
        sig = response.signals(history)
        names, start, _ = _layout(history)
        lay = history.space.layout
        used, ids = signal_maps.used_states(history.state_ids, len(history.contact))
        rows = signal_maps.signal_rows(history, used)
        np.testing.assert_array_equal(sig.slopes[:, names["a"].start], history.states[:, lay.index_slope])
        for name, columns in sig.curvatures.items():
            rate_rows = rows[:, start + names[name].start:start + names[name].stop]  # R A
            matrices = np.stack([history.contact[s].matrix for s in used])
            second = rate_rows @ matrices  # R A^2, (S, m, n_aug)
            expected = np.einsum("imk,ik->im", second[ids], history.states)
            # to the rounding of the sum of products (its terms far larger than the sum where they cancel)
            size = np.einsum("imk,ik->im", np.abs(second[ids]), np.abs(history.states))
            assert np.all(np.abs(sig.slopes[:, columns] - expected) <= 1e-12 * size)
            coefficients = second[:, :, lay.index_slope]
            np.testing.assert_allclose(sig.slope_rows[:, names[name]], coefficients, rtol=0,
                                       atol=1e-12 * np.abs(coefficients).max())
            assert np.abs(coefficients).max() > 0.0


def _rows_with_temporaries(history, used) -> np.ndarray:
    """signal_maps.signal_rows as it was before the products were written in place: every state's velocity map
    stacked, each product a temporary copied in."""
    space = history.space
    lay = space.layout
    names, start, n_slopes = _layout(history)
    velocity = np.stack([history.contact[s].velocity for s in used])
    matrix = np.stack([history.contact[s].matrix for s in used])
    rows = np.zeros(signal_maps.signal_rows(history, used).shape)
    rows[:, names["Y"]] = space.modal
    rows[:, names["Ydot"]] = space.to_modal @ velocity
    rows[:, names["Yddot"]] = rows[:, names["Ydot"]] @ matrix
    if space.model.flexible:
        rows[:, names["theta"]] = space.position[space.model.n_modes]
        rows[:, names["v"]] = space.position[space.model.n_modes + 1]
    rows[:, names["a"].start, lay.index_acceleration] = 1.0
    rows[:, names["input"]] = (space.forcing[:, lay.index_acceleration] @ velocity)[:, None, :]
    rows[:, names["element_velocity"]] = space.directions @ velocity
    rows[:, names["element_displacement"]] = space.displacement_rows
    rows[:, np.arange(names["z"].start, names["z"].stop), lay.z_indices] = 1.0
    rows[:, np.arange(names["P"].start, names["P"].stop), lay.plastic_indices] = 1.0
    rows[:, names["Pdot"]] = matrix[:, lay.plastic_indices]
    rows[:, start:start + n_slopes] = rows[:, :n_slopes] @ matrix
    rates = start + names["input"].start
    rows[:, start + n_slopes:] = rows[:, rates:rates + rows.shape[1] - start - n_slopes] @ matrix
    return rows


@pytest.mark.parametrize("support", ["rigid", "uplift"])
def test_the_signal_rows_of_a_yielding_run_are_those_of_temporary_products(elcentro, support):
    """A yielding building (hundreds of states; on the rigid base every state holds the same velocity map, whose
    products signal_rows takes once): the rows written in place have the bits of the products as temporaries."""
    from paper_example import paper_system

    system = paper_system(0.5)
    building = replace(system.building, story_strength=0.04 * system.building.masses.sum() * 9.81
                       * np.linspace(1.0, 0.3, system.building.n_stories), hardening_ratio=0.05)
    system = replace(system, building=building)
    space = model_for(system, support, ExactOptions())
    ((_, history),) = simulate([space], [4], elcentro.acceleration[:1500], elcentro.dt, "reaction",
                               uplift=support == "uplift", allow_flight=True)
    used, _ = signal_maps.used_states(history.state_ids, len(history.contact))
    assert space.layout.n_plastic and used.size > signal_maps.FEW_STATES
    assert signal_maps.signal_rows(history, used).tobytes() == _rows_with_temporaries(history, used).tobytes()
