"""engines/exact/energy.py on a hand-built history: a one-story building on a fixed base under a
suddenly applied constant ground acceleration, whose response and energies are known in
closed form (nothing of the stepping is used)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from upliftcli.engines.exact.energy import energy_balance
from upliftcli.engines.exact.modal import modal_model
from upliftcli.engines.exact.patterns import contact_states
from upliftcli.engines.exact.response import signals
from upliftcli.engines.exact.statespace import state_space
from upliftcli.engines.exact.stepping import History
from upliftcli.model.building import uniform_building
from upliftcli.model.foundations import TwoElement
from upliftcli.model.system import System

MASS, PERIOD, XI, A0 = 2.0e5, 0.4, 0.05, 1.5  # kg, s, -, m/s^2


def closed_form(t):
    """u(t), u'(t) of u'' + 2 xi w u' + w^2 u = -a0 from rest."""
    w = 2 * math.pi / PERIOD
    wd = w * math.sqrt(1 - XI**2)
    decay = np.exp(-XI * w * t)
    u = -A0 / w**2 * (1 - decay * (np.cos(wd * t) + XI / math.sqrt(1 - XI**2) * np.sin(wd * t)))
    v = -A0 / w**2 * decay * (w**2 / wd) * np.sin(wd * t)
    return u, v


def test_energy_terms_equal_their_closed_forms():
    building = uniform_building(1, MASS, 3.0, period=PERIOD, damping=XI)
    system = System(building, TwoElement(1e9, 0.0), 2.0)
    space = state_space(modal_model(system, "rigid", 1))
    (state,) = contact_states([space], np.zeros((1, 0), dtype=bool), "reaction")
    lay = space.layout
    times = np.linspace(0.0, 3.0, 3001)
    u, v = closed_form(times)
    states = np.zeros((times.size, lay.n_aug))
    states[:, 0], states[:, 1] = u, v  # Y* = u for one story (phi* = 1)
    states[:, lay.index_acceleration], states[:, lay.index_one] = A0, 1.0
    history = History(space, times, states, np.zeros(times.size, dtype=np.int64), [state], times[1],
                      "reaction", np.zeros((times.size, 0), dtype=bool))
    terms = energy_balance(history, signals(history))
    w = 2 * math.pi / PERIOD
    k, c = MASS * w**2, 2 * XI * w * MASS
    damping, _ = quad(lambda t: c * closed_form(t)[1] ** 2, 0.0, 3.0, limit=400, epsabs=0, epsrel=1e-13)
    assert terms["input"] == pytest.approx(-MASS * A0 * u[-1], rel=1e-10)
    assert terms["kinetic"] == pytest.approx(0.5 * MASS * v[-1] ** 2, rel=1e-10)
    assert terms["strain"] == pytest.approx(0.5 * k * u[-1] ** 2, rel=1e-10)
    assert terms["structural_damping"] == pytest.approx(damping, rel=1e-8)
    assert terms["foundation_damping"] == 0.0 and terms["gravity"] == 0.0
    assert terms["relative_residual"] < 1e-8
