"""The exact engine on soil that yields (engines/exact/yielding.py, docs/theory.md section 14),
each against something independent: the elastic engine (a capacity no force reaches), the
closed-form static backbones and moment capacities (model/rocking_capacity.py; for n discrete
elements an equilibrium solve written here), the energy balance with the plastic work, the
numpy twin of the stepping loop, and the event functions at the transitions they locate."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from backends import on_both
from scipy.optimize import brentq

from upliftcli.analysis import run as analysis
from upliftcli.deck.load import load_deck
from upliftcli.engines.exact.engine import substeps_for
from upliftcli.engines.exact.statespace import exact_model
from upliftcli.engines.exact.stepping import simulate
from upliftcli.engines.options import ExactOptions
from upliftcli.model import rocking_capacity
from upliftcli.model.building import uniform_building
from upliftcli.model.foundations import TwoElement, Winkler
from upliftcli.model.system import System

ROOT = Path(__file__).resolve().parent.parent
TWO = ROOT / "inputs" / "ten_story_elcentro.toml"
WINKLER = ROOT / "inputs" / "ten_story_winkler.toml"
HALF_WIDTH = 6.0
#: elastic stiffness of the push tests: k of each edge element [N/m], k_w of the strip [N/m^2]
STIFFNESS = 1e9


def run(path, engine="exact", support="uplift", *overrides):
    return analysis.run_one(load_deck(path, list(overrides)), engine, support)


# ---------------------------------------------------------------- no yielding: the elastic engine
@pytest.mark.parametrize("path", [TWO, WINKLER])
@pytest.mark.parametrize("engine", ["exact", "approximate"])
def test_a_capacity_no_force_reaches_gives_the_elastic_result(path, engine):
    """FS_v = 1e15: every element stays in C, and every peak, instant and energy term is the
    elastic one to 3e-11 of the quantity's largest value (instants to 1e-10 s), with the same
    transitions. Not always bit for bit: the state gains the (zero)
    settlements s_i, so the exponentials of the larger matrices round differently in the last
    place, and on the Winkler mat the operators come from the exponential of the coupled block
    only (yielding.step_operators, tested in test_operators.py), which rounds
    differently again (the compiled loop _soil_operators.c without fused multiply-adds: about twice the
    rounding of numpy's products); a bisection bracket that flips on such a change moves a located
    transition within its last sliver h/2^12. The impacts (the reaction right after a recontact) and the
    settlements (v - v_st, a difference of larger values) amplify it: checked to 5e-10. Measured
    (compiled loops; their numpy twins: 1.9e-10, 9.4e-12): impacts 2.3e-10 (the approximate engine on
    the Winkler mat), rotation 1.0e-11, reaction 9.0e-12; before the compiled loop, residual settlement
    4.0e-12, instants 1.4e-11 s, energy 2.6e-12 of the input."""
    elastic = run(path, engine)
    strong = run(path, engine, "uplift", "foundation.safety_factor=1e15")
    assert strong.details["yielding"]["yielded"] == [False] * len(strong.element_positions)
    assert strong.details["yielding"]["plastic_work"] == 0.0
    plastic = {"plastic_settlement", "yielded_elements", "plastic_work"} if engine == "exact" else set()
    assert set(strong.peaks) == set(elastic.peaks) | plastic  # the rocking quantities on yielding soil
    assert all(not strong.peaks[name].any() for name in plastic)
    for name, values in elastic.peaks.items():
        scale = np.abs(elastic.peaks[name.removeprefix("residual_")]).max()  # a residual: against its peak
        tolerance = (5e-10 if name == "impact" or "settlement" in name else 3e-11) * scale
        np.testing.assert_allclose(strong.peaks[name], values, rtol=0, atol=tolerance, err_msg=name)
        np.testing.assert_allclose(strong.times[name], elastic.times[name], rtol=0, atol=1e-10, err_msg=name)
    assert strong.intermediates["transitions"] == elastic.intermediates["transitions"]
    scale = elastic.details["energy"]["input"]
    for name, value in elastic.details["energy"].items():
        assert strong.details["energy"][name] == pytest.approx(value, abs=1e-11 * scale), name


def test_a_pattern_is_valid_unless_an_element_is_lifted_and_yielding():
    """yielding.valid_pattern (on Python's integers) against the pattern's bits (pattern_bits): every pattern of
    three elements, and random ones of 20 and 31 (bits up to 61) as ints and as numpy int64."""
    from upliftcli.engines.exact.yielding import pattern_bits, valid_pattern

    rng = np.random.default_rng(3)
    cases = [(3, p) for p in range(64)]
    for n in (20, 31):
        cases += [(n, int(p)) for p in rng.integers(0, 2**(2 * n), 500) & rng.integers(0, 2**(2 * n), 500)]
    invalid = 0
    for n, pattern in cases:
        lifted, yielding = pattern_bits(pattern, n)
        expected = not np.any(lifted & yielding)
        invalid += not expected
        assert valid_pattern(pattern, n) is expected
        assert valid_pattern(np.int64(pattern), n) is expected
    assert 0 < invalid < len(cases)


def test_without_a_capacity_the_state_is_the_elastic_one():
    """No new state entries without a capacity (and on the bonded support, the linear reference)."""
    system = load_deck(TWO).system
    space = exact_model(system, "uplift", ExactOptions())
    assert space.layout.n_settlements == 0 and space.layout.settlement_indices.size == 0
    assert space.element_capacity is None
    yielding = load_deck(TWO, ["foundation.safety_factor=1.5"]).system
    with_capacity = exact_model(yielding, "uplift", ExactOptions()).layout
    assert with_capacity.n_x == space.layout.n_x + 2
    np.testing.assert_array_equal(with_capacity.settlement_indices, [space.layout.n_x, space.layout.n_x + 1])
    np.testing.assert_array_equal(with_capacity.z_indices, space.layout.z_indices)
    bonded = exact_model(yielding, "bonded", ExactOptions())
    assert bonded.layout.n_x == space.layout.n_x and bonded.element_capacity is None


# ---------------------------------------------------------------- slow cyclic push: the backbones
def _system(foundation) -> System:
    return System(uniform_building(3, 350e3, 3.5, period=0.3, damping=0.05), foundation, HALF_WIDTH, 0.0)


def _push(system: System, peak_moment: float, period: float, dt: float = 0.02):
    """History of one slow cycle of ground acceleration a_g = A sin(2 pi t / period), A such that
    the static overturning moment A sum m_j h_j peaks at peak_moment [N m]; and the rotation theta
    and foundation moment M = -sum x_i F_i at every sample (no dashpots: F_i = k_i (v_i - s_i) in
    contact or yielding, 0 lifted)."""
    space = exact_model(system, "uplift", ExactOptions())
    times = np.arange(0.0, period + dt / 2, dt)
    acceleration = peak_moment / system.first_moment * np.sin(2.0 * np.pi * times / period)
    ((_, history),) = simulate([space], [substeps_for(space, dt, ExactOptions())], acceleration, dt, "reaction",
                               True, True)
    x = history.states
    spring = x @ space.displacement_rows.T - x[:, space.layout.settlement_indices]
    force = np.where(history.lifted, 0.0, space.element_stiffness * spring)
    theta = x @ space.position[space.model.n_modes]
    return history, theta, -(force * space.model.elements.positions).sum(axis=1)


def discrete_backbone(theta, positions, stiffness, capacity, weight):
    """M(theta) [N m] of rigid-mat elements (x_i, k_i, Q_i) loaded monotonically under W: the mat
    settles v such that sum F_i = -W, F_i = max(k_i (v - x_i theta), -Q_i) in compression, 0 above
    (static equilibrium solved by bisection, independent of the engine)."""
    out = []
    for angle in np.atleast_1d(theta):
        def forces(v, angle=angle):
            d = v - positions * angle
            return np.where(d < 0.0, np.maximum(stiffness * d, -capacity), 0.0)
        low = -weight / stiffness.min() - abs(angle) * np.abs(positions).max() - 1.0
        v = brentq(lambda v: forces(v).sum() + weight, low, abs(angle) * np.abs(positions).max() + 1.0, xtol=1e-15)
        out.append(-(positions * forces(v)).sum())
    return np.array(out)


@pytest.mark.parametrize("factor", [1.5, 3.0])
def test_two_elements_follow_the_backbone_up_to_their_moment_capacity(factor):
    """A slow cycle whose static demand peaks at M_c = W b min(1, FS_v - 1): the moment follows
    two_element_backbone (elastic, 2 k b^2 theta) and reaches M_c, where the right element yields
    (FS_v = 1.5) or the left one lifts (FS_v = 3, the right one never yields), to the quasi-static
    error of the push (5e-5 of M_c measured at a 40 s cycle; 1.2e-4 in the rocking after a
    lift-off); the other side on the way back.
    (Past M_c the flat backbone gives no static equilibrium: the mat then rocks dynamically.)"""
    weight = _system(TwoElement(STIFFNESS, 0.0)).weight
    capacity = factor * weight / 2.0
    moment_capacity = rocking_capacity.two_element_moment_capacity(HALF_WIDTH, capacity, weight)
    history, theta, moment = _push(_system(TwoElement(STIFFNESS, 0.0, capacity)), moment_capacity, 40.0)
    backbone = np.sign(theta) * rocking_capacity.two_element_backbone(np.abs(theta), HALF_WIDTH, STIFFNESS, capacity,
                                                                      weight)
    loading = history.times <= 10.0  # the first quarter: |theta| grows
    assert np.abs(moment - backbone)[loading].max() < 1e-4 * moment_capacity
    assert moment.max() == pytest.approx(moment_capacity, rel=2e-4)
    assert moment.min() == pytest.approx(-moment_capacity, rel=2e-4)
    assert history.yielding.any(axis=0).all() == (factor < 2.0) and history.yielding.any() == (factor < 2.0)
    assert history.lifted.any(axis=0).all() == (factor >= 2.0)


@pytest.mark.parametrize("factor", [1.5, 3.0])
@pytest.mark.parametrize("count", [10, 20])
def test_a_winkler_strip_follows_its_discrete_backbone(factor, count):
    """n elements of a strip (k_i = k_w dx, Q_i = q_w dx), a slow cycle to 95 % of their M_c
    (midpoint_moment_capacity): while it loads the moment is the discrete equilibrium backbone at
    the engine's rotation, to the quasi-static error of the push (which falls as the push slows:
    below 5e-4 of M_c at a 320 s cycle, 2.4e-4 measured); that backbone approaches the strip's closed form
    (winkler_backbone) as 1/n^2, and its M_c the strip's (ASCE 41-17 8.4)."""
    weight = _system(TwoElement(STIFFNESS, 0.0)).weight
    stiffness, line = STIFFNESS / HALF_WIDTH, factor * weight / (2.0 * HALF_WIDTH)
    system = _system(Winkler(stiffness, 0.0, count, line))
    elements = system.foundation.contact_elements(HALF_WIDTH)
    moment_capacity = rocking_capacity.midpoint_moment_capacity(elements.positions, elements.capacity, weight)
    strip = rocking_capacity.winkler_moment_capacity(HALF_WIDTH, line, weight)
    assert moment_capacity == pytest.approx(strip * (1.0 - 1.0 / count**2), rel=1e-12)
    history, theta, moment = _push(system, 0.95 * moment_capacity, 320.0, dt=0.05)
    loading = history.times <= 80.0
    backbone = np.sign(theta) * discrete_backbone(np.abs(theta), elements.positions, elements.stiffness,
                                                  elements.capacity, weight)
    assert np.abs(moment - backbone)[loading].max() < 5e-4 * moment_capacity
    assert np.abs(moment).max() < moment_capacity
    closed = np.sign(theta) * rocking_capacity.winkler_backbone(np.abs(theta), HALF_WIDTH, stiffness, line, weight)
    assert np.abs(backbone - closed)[loading].max() < 0.8 / count**2 * strip
    # the toe yielded and the heel lifted on both sides; the settlement stays
    assert history.yielding[:, [0, -1]].any(axis=0).all() and history.lifted[:, [0, -1]].any(axis=0).all()
    assert history.states[-1, exact_model(system, "uplift", ExactOptions()).layout.settlement_indices].min() < 0.0


def test_the_push_converges_to_the_backbone_as_it_slows():
    """The quasi-static error of the push (damping forces ~ 1/period) falls about as 1/period."""
    weight = _system(TwoElement(STIFFNESS, 0.0)).weight
    system = _system(Winkler(STIFFNESS / HALF_WIDTH, 0.0, 10, 1.5 * weight / (2.0 * HALF_WIDTH)))
    elements = system.foundation.contact_elements(HALF_WIDTH)
    capacity = rocking_capacity.midpoint_moment_capacity(elements.positions, elements.capacity, weight)
    errors = []
    for period in (20.0, 80.0):
        history, theta, moment = _push(system, 0.9 * capacity, period)
        loading = history.times <= period / 4.0
        backbone = np.sign(theta) * discrete_backbone(np.abs(theta), elements.positions, elements.stiffness,
                                                      elements.capacity, weight)
        errors.append(np.abs(moment - backbone)[loading].max() / capacity)
    assert errors[1] < errors[0] / 3.0


# ---------------------------------------------------------------- under earthquakes
YIELDING = [(TWO, "foundation.safety_factor=1.5"), (TWO, "foundation.safety_factor=2"),
            (WINKLER, "foundation.safety_factor=1.5"), (WINKLER, "foundation.safety_factor=2")]


@pytest.mark.parametrize(("path", "capacity"), YIELDING)
def test_the_energy_balance_closes_with_the_plastic_work(path, capacity):
    """input = kinetic + strain + damping + foundation + gravity + W_p (docs/theory.md 14.5) to
    the same 1e-4 of the input as the elastic run of the deck (docs/exact-engine.md), with W_p > 0
    the yielding soil's share; W_p = sum Q_i (s_i(0) - s_i(end)) from the reported settlements."""
    result = run(path, "exact", "uplift", capacity)
    energy, yielding = result.details["energy"], result.details["yielding"]
    assert energy["relative_residual"] < 1e-4
    assert energy["plastic_work"] > 0.0
    assert yielding["plastic_work"] == energy["plastic_work"]
    settled = np.array(yielding["plastic_settlement"])
    assert np.all(settled <= 0.0) and any(yielding["yielded"])
    assert np.all((settled < 0.0) <= np.array(yielding["yielded"]))
    assert -np.dot(yielding["capacity"], settled) == pytest.approx(energy["plastic_work"], rel=1e-12)
    assert energy["relative_residual"] < 10.0 * max(run(path).details["energy"]["relative_residual"], 1e-6)


@pytest.mark.parametrize(("path", "capacity"), YIELDING[::2])
@pytest.mark.parametrize("engine", ["exact", "approximate"])
def test_the_numpy_twin_steps_yielding_as_the_loop_does(path, capacity, engine):
    """The compiled loop and its numpy twin (tests/backends.py): the same transitions, and every
    peak, settlement and energy term to 1e-9 (the tolerance of test_backend_agreement.py)."""
    compiled, twin = on_both(lambda: run(path, engine, "uplift", capacity))
    assert compiled.intermediates["transitions"] == twin.intermediates["transitions"]
    assert compiled.details["yielding"]["yielded"] == twin.details["yielding"]["yielded"]
    for name, values in compiled.peaks.items():
        np.testing.assert_allclose(twin.peaks[name], values, rtol=1e-9, atol=1e-9 * np.abs(values).max())
    np.testing.assert_allclose(twin.details["yielding"]["plastic_settlement"],
                               compiled.details["yielding"]["plastic_settlement"], rtol=1e-9, atol=1e-15)
    scale = compiled.details["energy"]["input"]
    for name, value in compiled.details["energy"].items():
        assert twin.details["energy"][name] == pytest.approx(value, abs=1e-9 * scale), name


def _history(path, capacity):
    system = load_deck(path, [capacity]).system
    loaded = load_deck(path, [capacity])
    record = loaded.ground_motion
    space = exact_model(system, "uplift", ExactOptions())
    ((_, history),) = simulate([space], [substeps_for(space, record.dt, ExactOptions())],
                               np.asarray(record.acceleration), record.dt, "reaction", True, True)
    return space, history


def _states(history, index):
    contact = history.contact[history.state_ids[index]]
    return contact.lifted, contact.yielding


@pytest.mark.parametrize(("path", "capacity"), [(TWO, "foundation.safety_factor=2"),
                                                (WINKLER, "foundation.safety_factor=1.5")])
def test_every_transition_is_located_inside_the_step(path, capacity):
    """C -> Y, Y -> C, C -> L and L -> C all occur under El Centro (FS_v = 2: 92 onsets of yield, 46
    lift-offs on two elements); at each, the event function
    of the state left is zero to 1e-9 (it is placed inside the sliver of h / 2^12 by
    interpolation), and the reset applied there holds: a yielding element's spring is at its
    capacity, k (v - s) = -Q, and a lifting element's top is at its edge."""
    space, history = _history(path, capacity)
    lay = space.layout
    seen = set()
    n_e = lay.n_elements
    for j in np.flatnonzero(np.diff(history.state_ids)) + 1:
        before, after = _states(history, j - 1), _states(history, j)
        x = history.states[j]
        old = history.contact[history.state_ids[j - 1]]
        for i in range(n_e):
            code = lambda state, i=i: "L" if state[0][i] else "Y" if state[1][i] else "C"  # noqa: E731
            move = code(before) + code(after)
            if move[0] == move[1]:
                continue
            seen.add(move)
            row = i if "L" in move else n_e + i
            assert abs(old.events[row] @ x) < 1e-9, move
            spring = space.element_stiffness[i] * (space.displacement_rows[i] @ x - x[lay.settlement_indices[i]])
            if move == "CY":
                # at -Q_i times the state's constant entry "1" (which the step operators carry
                # with a drift of a few 1e-12 over a record)
                assert spring == pytest.approx(-space.element_capacity[i] * x[lay.index_one], rel=1e-12)
            if move == "CL":
                edge = space.displacement_rows[i] @ x
                assert x[lay.z_indices[i]] == pytest.approx(edge, abs=1e-12 * space.settlement)
    assert seen == {"CY", "YC", "CL", "LC"}


def test_a_settled_element_comes_back_to_its_settled_level():
    """After an element yields (s < 0) and later lifts, it recontacts where the edge meets its top
    relaxing towards s_i, below its original level: the edge is then at v_i = z_i < 0 with the
    spring at most at its capacity, and the settlement s_i stays to the end (the gap that stays
    open). (z_i may start below s_i: at a lift-off by the reaction criterion the dashpot's pull
    c v' balances a spring still in compression.)"""
    space, history = _history(TWO, "foundation.safety_factor=2")
    lay = space.layout
    x = history.states
    settlement = x[:, lay.settlement_indices]
    edges = x @ space.displacement_rows.T
    recontacts = 0
    for j in np.flatnonzero(np.diff(history.state_ids)) + 1:
        for i in range(lay.n_elements):
            if history.lifted[j - 1, i] and not history.lifted[j, i] and settlement[j, i] < -1e-6:
                recontacts += 1
                assert edges[j, i] == pytest.approx(x[j, lay.z_indices[i]], abs=1e-9 * space.settlement)
                assert edges[j, i] < 0.0
                assert space.element_stiffness[i] * (edges[j, i] - settlement[j, i]) >= \
                    -space.element_capacity[i] * (1 + 1e-12)
    assert recontacts > 0
    # s_i only decreases (yielding), never recovers (but for the last-place drift of the step operators)
    assert np.all(np.diff(settlement, axis=0) <= 1e-12 * space.settlement)
    assert settlement[-1].min() < 0.0


@pytest.mark.parametrize("path", [TWO, WINKLER])
def test_the_displacement_criterion_yields_too(path):
    """Lift-off by the displacement criterion [4b] on the settled level, v_i - s_i > 0: the run
    yields, settles and closes its energy balance as with the reaction criterion."""
    result = run(path, "exact", "uplift", "foundation.safety_factor=1.5", "analysis.exact.criterion=\"displacement\"")
    assert result.intermediates["criterion"] == "displacement"
    assert any(result.details["yielding"]["yielded"]) and result.details["yielding"]["plastic_work"] > 0.0
    assert result.details["energy"]["relative_residual"] < 1e-4


def test_more_elements_with_a_capacity_than_the_pattern_holds_are_refused():
    """Two bits per element with a capacity: at most limits.MAX_YIELDING_ELEMENTS = 31. The deck
    refuses more up front when a history engine runs the uplift support (one line naming
    foundation.elements and the bound); without a capacity 32 elements run, and so does the
    simplified engine alone (the closed-form M_c, no contact pattern) or the bonded support.
    A model built in code (no deck) is still refused by the engine."""
    from upliftcli.errors import AnalysisError, InputError
    from upliftcli.runtime.limits import MAX_YIELDING_ELEMENTS

    assert MAX_YIELDING_ELEMENTS == 31
    elastic = run(WINKLER, "exact", "uplift", "foundation.elements=32")
    assert elastic.element_positions.size == 32
    for engine in ("exact", "approximate"):
        with pytest.raises(InputError, match=r"foundation\.elements: at most 31 contact elements with a bearing "
                                             rf"capacity for the {engine} engine.*got 32"):
            load_deck(WINKLER, ["foundation.elements=32", "foundation.safety_factor=2",
                                f'analysis.engine=["{engine}"]'])
    assert run(WINKLER, "exact", "uplift", "foundation.elements=31", "foundation.safety_factor=2").uplift
    alone = load_deck(WINKLER, ["foundation.elements=32", "foundation.safety_factor=2",
                                'analysis.engine=["simplified"]'])
    assert analysis.run_one(alone, "simplified", "uplift").intermediates["FS_v"] == pytest.approx(2.0)
    bonded = load_deck(WINKLER, ["foundation.elements=32", "foundation.safety_factor=2",
                                 'analysis.supports=["bonded"]'])
    assert analysis.run_one(bonded, "exact", "bonded").element_positions.size == 32
    with pytest.raises(InputError, match=r"foundation\.elements: at most 31"):  # the deck's engines checked first
        analysis.run_one(alone, "exact", "uplift")
    from upliftcli.engines.exact import engine as exact

    with pytest.raises(AnalysisError, match=r"at most 31 contact elements with a bearing capacity.*elements"):
        exact.analyze(alone.system, alone.ground_motion, "uplift")


def test_a_batch_of_yielding_systems_gives_each_its_result_alone():
    """Systems analysed together (their contact states built in one vectorised batch,
    operators.add_states) get the same results, bit for bit, as each alone."""
    from upliftcli.engines.exact import engine as exact

    decks = [load_deck(TWO, [f"foundation.safety_factor={factor}"]) for factor in (1.5, 2.0, 3.0)]
    record = decks[0].ground_motion
    together = exact.analyze_batch([deck.system for deck in decks], record, "uplift")
    for deck, batched in zip(decks, together, strict=True):
        alone = exact.analyze(deck.system, record, "uplift")
        for name, values in alone.peaks.items():
            np.testing.assert_array_equal(batched.peaks[name], values, err_msg=name)
        assert batched.details["yielding"] == alone.details["yielding"]


def test_the_histories_give_the_edges_and_their_settled_end():
    """--histories with a capacity: the edge displacements are the edges' own v_i = v -+ b theta
    (not the springs' v_i - s_i), and each edge ends at its static level plus its plastic
    settlement (a residual settlement that stays)."""
    from upliftcli.engines.exact import engine as exact

    loaded = load_deck(TWO, ["foundation.safety_factor=1.5"])
    system = loaded.system
    result = exact.analyze(system, loaded.ground_motion, "uplift", ExactOptions(histories=True))
    h = result.histories
    b = system.half_width
    np.testing.assert_allclose(h["left_edge_displacement"], h["v"] + b * h["theta"], rtol=0, atol=1e-15)
    np.testing.assert_allclose(h["right_edge_displacement"], h["v"] - b * h["theta"], rtol=0, atol=1e-15)
    settled = np.array(result.details["yielding"]["plastic_settlement"])
    rest = -system.weight / (2.0 * system.foundation.stiffness)  # each edge's static level
    ends = np.array([h["left_edge_displacement"][-1], h["right_edge_displacement"][-1]])
    # sunk by its plastic settlement (48 and 53 mm, 50 times the static level): the rest, 9 % of the
    # static level, is the springs' share of the moment the structure still carries at the end
    np.testing.assert_allclose(ends, rest + settled, rtol=0, atol=0.1 * abs(rest))
    assert np.all(settled < 40.0 * rest)


def test_the_settlement_histories_are_the_edges_from_rest_and_the_settled_levels():
    """--histories of the flexible supports give the settlement of the left edge, the centre and
    the right edge (down +, from the rest position, which is the first sample: the two-element
    edges are the elements, so -(v_i - v_i(0)) of their displacement histories), whose sampled
    largest value is at most the peak found between samples and within 1e-3 of it and whose last
    sample is the residual settlement; with a capacity also each element's plastic settlement
    -s_i: 0 at rest, never decreasing, ending at the engine's final -s_i. Without a capacity no
    plastic column; the unit of every new column is m (histories.history_unit)."""
    from upliftcli.engines.exact import engine as exact
    from upliftcli.engines.quantities import column_name
    from upliftcli.histories import history_unit

    loaded = load_deck(TWO, ["foundation.safety_factor=1.5", "ground_motion.window=[0, 8]"])
    result = exact.analyze(loaded.system, loaded.ground_motion, "uplift", ExactOptions(histories=True))
    h = result.histories
    for k, (edge, element) in enumerate((("left_edge", "left_edge_displacement"), ("centre", None),
                                         ("right_edge", "right_edge_displacement"))):
        settlement = h[f"{edge}_settlement"]
        if element is not None:
            np.testing.assert_allclose(settlement, -(h[element] - h[element][0]), rtol=0, atol=1e-15)
        assert abs(settlement[0]) < 1e-15
        peak = result.peaks["settlement"][k]
        assert peak * (1 - 1e-3) <= settlement.max() <= peak * (1 + 1e-12)
        assert settlement[-1] == result.peaks["residual_settlement"][k]
    final = -np.asarray(result.details["yielding"]["plastic_settlement"])
    for i in range(2):
        plastic = h[f"plastic_settlement_{i + 1}"]
        assert plastic[0] == 0.0 and np.all(np.diff(plastic) >= 0.0) and plastic[-1] == final[i] > 1e-3
    assert column_name("plastic_settlement_2", history_unit("plastic_settlement_2")) == "plastic_settlement_2_m"
    assert history_unit("centre_settlement") == "m"
    elastic = exact.analyze(load_deck(TWO, ["ground_motion.window=[0, 8]"]).system, loaded.ground_motion, "uplift",
                            ExactOptions(histories=True))
    assert "left_edge_settlement" in elastic.histories and "plastic_settlement_1" not in elastic.histories


def test_the_history_figure_shows_the_settlement_on_yielding_soil():
    """A yielding run's history figure adds a panel of the edges' settlement and the edge
    elements' plastic settlement (the histories, in mm); an elastic run's figure has no such panel."""
    from upliftcli.engines.exact import engine as exact
    from upliftcli.figures import histories as fh

    loaded = load_deck(TWO, ["foundation.safety_factor=1.5", "ground_motion.window=[0, 8]"])
    result = exact.analyze(loaded.system, loaded.ground_motion, "uplift", ExactOptions(histories=True))
    panel = fh.history_figure([result]).panels[-1]
    assert panel.title == "settlement of the mat edges (yielding soil)" and panel.ylabel == "settlement, down + [mm]"
    assert [s.label for s in panel.series] == ["uplift, left edge", "uplift, right edge",
                                               "uplift, left element, plastic", "uplift, right element, plastic"]
    for series, key in zip(panel.series, ("left_edge_settlement", "right_edge_settlement", "plastic_settlement_1",
                                          "plastic_settlement_2"), strict=True):
        np.testing.assert_allclose(series.y, 1e3 * result.histories[key], rtol=1e-15)
    elastic = exact.analyze(load_deck(TWO, ["ground_motion.window=[0, 8]"]).system, loaded.ground_motion, "uplift",
                            ExactOptions(histories=True))
    assert "settlement" not in fh.history_figure([elastic]).panels[-1].title
