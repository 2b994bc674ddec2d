"""Stories that yield (engines/exact/stories.py, docs/theory.md section 15), each against something
independent: the elastic engine (no strength, an infinite one and one never reached: bit for bit), an
elastoplastic SDOF integrated here by a very fine explicit step with a return map (not the engine's
code), the energy balance with the hysteretic energy, the numpy twin of the stepping loop, and the
deck's fields (ASCE 7-22 12.8.3 distribution, refusals)."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from backends import on_both

from upliftcli.analysis import run as analysis
from upliftcli.deck.load import load_deck
from upliftcli.deck.strengths import distribution_exponent, vertical_distribution
from upliftcli.engines.exact import engine
from upliftcli.engines.options import ExactOptions
from upliftcli.engines.registry import ENGINES
from upliftcli.errors import InputError
from upliftcli.model.building import shear_building
from upliftcli.model.foundations import TwoElement
from upliftcli.model.system import System
from upliftcli.runtime import backend

ROOT = Path(__file__).resolve().parent.parent
TWO = ROOT / "inputs" / "ten_story_elcentro.toml"
WINKLER = ROOT / "inputs" / "ten_story_winkler.toml"
HALFSPACE = ROOT / "inputs" / "frame_halfspace.toml"
#: the half-space deck as a shear building of all its modes (its frame matrix cannot yield by stories);
#: its mat has mass and rotary inertia (theta a coordinate with inertia)
SHEAR_FRAME = ("building.story_stiffnesses=[8e8, 7.5e8, 6.2e8, 4.5e8, 4e8]", "analysis.modes=5")

#: the SDOF: m [kg], k [N/m] (T = 0.314 s), 5 % damping, story height [m]
MASS, STIFFNESS, HEIGHT = 1e5, 4e7, 3.0


def run(path, support="uplift", *overrides):
    return analysis.run_one(load_deck(path, list(overrides)), "exact", support)


def same(a, b) -> bool:
    """Every peak and instant of two results equal bit for bit (NaN instants: no impact, alike)."""
    return a.peaks.keys() <= b.peaks.keys() and all(
        np.array_equal(a.peaks[k], b.peaks[k]) and np.array_equal(a.times.get(k, []), b.times.get(k, []),
                                                                   equal_nan=True) for k in a.peaks)


# ------------------------------------------------------------------ the elastic engine, bit for bit
def close(a, b, tolerance: float = 1e-12) -> bool:
    """Every peak of two results within `tolerance` of each quantity's largest value, every instant within
    1e-5 s (a peak on a flat top moves far more than its value: the settlement's of the half-space deck by
    2.2e-6 s for a value 4e-16 of its largest)."""
    return a.peaks.keys() <= b.peaks.keys() and all(
        np.allclose(a.peaks[k], b.peaks[k], rtol=0.0, atol=tolerance * np.abs(a.peaks[k]).max(initial=0.0))
        and np.allclose(a.times.get(k, []), b.times.get(k, []), rtol=0.0, atol=1e-5, equal_nan=True)
        for k in a.peaks)


@pytest.mark.parametrize("path", [TWO, WINKLER, HALFSPACE])
@pytest.mark.parametrize("support", ["rigid", "bonded", "uplift"])
def test_a_strength_never_reached_gives_the_elastic_run_bit_for_bit(path, support):
    """story_strengths of 1e3 W (never reached) and infinite strengths: every peak and instant and the
    energy terms are the elastic run's, bit for bit (the elastic block of each state's operators comes
    from the exponential of the matrix without the plastic drifts: operators._elastic_stories). On the
    numpy twins (UPLIFT_BACKEND=numpy) to round-off, 1e-12 of each quantity's largest value: their BLAS
    products group a sum's terms by the matrix's size, which the plastic drifts' zero columns change."""
    modes = {WINKLER: ("analysis.modes=10",), HALFSPACE: SHEAR_FRAME}.get(path, ())
    elastic = run(path, support, *modes)
    strong = run(path, support, *modes, "building.strength_coefficient=1000")
    exact = backend.in_use() == "compiled"
    assert same(elastic, strong) if exact else close(elastic, strong)
    assert strong.peaks["yielded_stories"][0] == 0.0 and not strong.peaks["hysteretic_energy"].any()
    input_work = abs(elastic.details["energy"]["input"])
    for name, value in elastic.details["energy"].items():
        assert strong.details["energy"][name] == (value if exact else pytest.approx(value, abs=1e-12 * input_work))
    assert strong.details["energy"]["hysteretic"] == 0.0
    assert strong.intermediates["transitions"] == elastic.intermediates["transitions"]


def test_infinite_strengths_are_the_elastic_building():
    """Strengths of inf on every story: no plastic drift in the state, the elastic run bit for bit."""
    elastic = run(TWO, "uplift")
    deck = load_deck(TWO, [])
    building = replace(deck.system.building, story_strength=np.full(10, np.inf))
    system = replace(deck.system, building=building)
    result = engine.analyze(system, deck.ground_motion, "uplift", deck.analysis.exact)
    assert same(elastic, result)


# ------------------------------------------------------------------ an elastoplastic SDOF, independently
def reference_sdof(ground: np.ndarray, dt: float, strength: float, alpha: float, h: float = 2e-5):
    """Peak |drift|, final drift, peak |V| and hysteretic energy of the SDOF under `ground` (linear
    between samples), by the explicit central-difference step (Newmark gamma = 1/2, beta = 0, damping
    implicit) with the bilinear kinematic-hardening return map at every step (Steel01 with b = alpha)."""
    m, k = MASS, STIFFNESS
    c = 2.0 * 0.05 * math.sqrt(k / m) * m
    steps = round((ground.size - 1) * dt / h)
    times = np.arange(steps + 1) * h
    ag = np.interp(times, np.arange(ground.size) * dt, ground).tolist()
    u = v = p = 0.0
    force = 0.0
    a = -ag[0]
    peak = peak_force = energy = 0.0
    upper, lower = (1.0 - alpha) * strength, -(1.0 - alpha) * strength
    for n in range(1, steps + 1):
        u += h * v + 0.5 * h * h * a
        trial = k * (u - p)
        bound = alpha * k * u
        new = min(max(trial, bound + lower), bound + upper)
        p_new = u - new / k
        energy += 0.5 * (force + new) * (p_new - p)
        force, p = new, p_new
        a_new = (-m * ag[n] - force - c * (v + 0.5 * h * a)) / (m + 0.5 * h * c)
        v += 0.5 * h * (a + a_new)
        a = a_new
        peak = max(peak, abs(u))
        peak_force = max(peak_force, abs(force))
    return peak, u, peak_force, energy


def sdof(strength: float | None, alpha: float) -> System:
    building = shear_building([MASS], [HEIGHT], [STIFFNESS], 0.05)
    if strength is not None:
        building = replace(building, story_strength=np.array([strength]), hardening_ratio=alpha)
    return System(building, TwoElement(1e9, 1e7), 5.0)


#: a harmonic ground motion: 3 m/s^2 at 2 Hz for 3 s, then 1 s of free vibration
DT = 0.01
TIMES = np.arange(0.0, 4.0, DT)
GROUND = 3.0 * np.sin(2.0 * np.pi * TIMES / 0.5) * (TIMES < 3.0)


@pytest.mark.parametrize("alpha", [0.0, 0.1])
def test_the_elastoplastic_sdof_matches_a_fine_step_solver(alpha):
    """Half the elastic peak force as the strength (ductility about 2.6): the peak and the residual drift,
    the peak force and the hysteretic energy of the exact engine against the fine explicit step written
    above (h = 2e-5 s, 1/16,000 of the period; the differences halve or better from h = 4e-5 s, so they
    are the reference's). Measured (alpha 0 / 0.1): peak drift 5.8e-8 / 1.4e-8 of itself, residual drift
    4.3e-8 / 1.4e-8 of the peak drift, peak force 3e-13 / 3e-9, hysteretic energy 1.0e-8 / 1.4e-8 of
    itself; the balance closes to 3.3e-7 / 2.5e-7."""
    record = SimpleNamespace(acceleration=GROUND, dt=DT)
    elastic = engine.analyze(sdof(None, 0.0), record, "rigid", ExactOptions())
    strength = 0.5 * elastic.peaks["shear"][0]
    result = engine.analyze(sdof(strength, alpha), record, "rigid", ExactOptions())
    peak, final, peak_force, energy = reference_sdof(GROUND, DT, strength, alpha)
    assert result.peaks["drift"][0] == pytest.approx(peak, rel=1e-6)
    assert abs(result.peaks["residual_drift_ratio"][0] * HEIGHT - abs(final)) <= 1e-6 * peak
    assert result.peaks["shear"][0] == pytest.approx(peak_force, rel=1e-6)
    assert result.peaks["hysteretic_energy"][0] == pytest.approx(energy, rel=1e-6)
    assert result.peaks["ductility"][0] == pytest.approx(peak / (strength / STIFFNESS), rel=1e-5)
    assert result.peaks["ductility"][0] > 2.0 and result.peaks["story_yielded"][0] == 1.0
    assert result.peaks["base_shear_strength"][0] == strength
    assert result.details["energy"]["relative_residual"] < 1e-5


def reference_two_stories(ground: np.ndarray, dt: float, system: System, h: float = 2e-5):
    """Peak |drift|, final drift, peak |V| and hysteretic energy of each story and the peak absolute floor
    accelerations of a two-story shear building on a rigid base, by the fine explicit step of
    reference_sdof in floor coordinates (M u'' + C u' + sum_j A_j^T V_j = -M 1 a_g, C the modal damping
    matrix M Phi diag(2 xi w) Phi^T M of docs/theory.md section 1), each story's force by the return map."""
    b = system.building
    m, k, vy, alpha = b.masses.tolist(), b.story_stiffness.tolist(), b.story_strength.tolist(), b.hardening_ratio
    w2, phi = np.linalg.eigh(np.diag(1 / np.sqrt(b.masses)) @ b.stiffness @ np.diag(1 / np.sqrt(b.masses)))
    shapes = np.diag(1 / np.sqrt(b.masses)) @ phi
    c = (np.diag(b.masses) @ shapes @ np.diag(2 * 0.05 * np.sqrt(w2)) @ shapes.T @ np.diag(b.masses)).tolist()
    steps = round((ground.size - 1) * dt / h)
    ag = np.interp(np.arange(steps + 1) * h, np.arange(ground.size) * dt, ground).tolist()
    u, v, a, p, force = [0.0, 0.0], [0.0, 0.0], [-ag[0], -ag[0]], [0.0, 0.0], [0.0, 0.0]
    peak, peak_force, energy, peak_acc = [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]
    for n in range(1, steps + 1):
        u = [u[i] + h * v[i] + 0.5 * h * h * a[i] for i in range(2)]
        d = [u[0], u[1] - u[0]]
        for j in range(2):
            bound = alpha * k[j] * d[j]
            new = min(max(k[j] * (d[j] - p[j]), bound - (1 - alpha) * vy[j]), bound + (1 - alpha) * vy[j])
            p_new = d[j] - new / k[j]
            energy[j] += 0.5 * (force[j] + new) * (p_new - p[j])
            force[j], p[j] = new, p_new
        restoring = [force[0] - force[1], force[1]]
        pred = [v[i] + 0.5 * h * a[i] for i in range(2)]
        rhs = [-m[i] * ag[n] - restoring[i] - c[i][0] * pred[0] - c[i][1] * pred[1] for i in range(2)]
        # (M + h C / 2) a = rhs
        a11, a12, a21, a22 = m[0] + 0.5 * h * c[0][0], 0.5 * h * c[0][1], 0.5 * h * c[1][0], m[1] + 0.5 * h * c[1][1]
        det = a11 * a22 - a12 * a21
        a_new = [(a22 * rhs[0] - a12 * rhs[1]) / det, (a11 * rhs[1] - a21 * rhs[0]) / det]
        v = [v[i] + 0.5 * h * (a[i] + a_new[i]) for i in range(2)]
        a = a_new
        for j in range(2):
            peak[j] = max(peak[j], abs(d[j]))
            peak_force[j] = max(peak_force[j], abs(force[j]))
            peak_acc[j] = max(peak_acc[j], abs(a[j] + ag[n]))
    return np.array(peak), np.array([u[0], u[1] - u[0]]), np.array(peak_force), np.array(energy), np.array(peak_acc)


def test_two_yielding_stories_match_a_fine_step_solver():
    """Two stories (the lower one weaker), alpha = 0.05, on a rigid base: the modal forcing of the plastic
    drifts (Gamma), the restoring forces in the story shears and the floor accelerations against the
    fine explicit step in floor coordinates above (ductilities 10.3 and 1.6). Measured: drifts 2.9e-8,
    residual drifts 5.6e-9 of the peak drift, story shears 3.6e-9, hysteretic energies 6.3e-8, floor
    accelerations 9e-8 and 7.0e-5 (floor 1: the reference's, 5.0e-5 with its step halved, while the
    engine's value does not move from 6 to 24 steps per period)."""
    building = shear_building([1e5, 8e4], [3.5, 3.0], [5e7, 4e7], 0.05)
    building = replace(building, story_strength=np.array([2.0e5, 1.6e5]), hardening_ratio=0.05)
    system = System(building, TwoElement(1e9, 1e7), 5.0)
    result = engine.analyze(system, SimpleNamespace(acceleration=GROUND, dt=DT), "rigid", ExactOptions())
    peak, final, peak_force, energy, peak_acc = reference_two_stories(GROUND, DT, system)
    assert result.peaks["ductility"].min() > 1.5
    assert result.peaks["drift"] == pytest.approx(peak, rel=1e-6)
    assert np.abs(result.peaks["residual_drift_ratio"] * building.story_heights - np.abs(final)).max() \
        <= 1e-6 * peak.max()
    assert result.peaks["shear"] == pytest.approx(peak_force, rel=1e-6)
    assert result.peaks["hysteretic_energy"] == pytest.approx(energy, rel=1e-6)
    assert result.peaks["floor_acceleration"] == pytest.approx(peak_acc, rel=1.5e-4)
    assert result.details["energy"]["relative_residual"] < 1e-5


def test_the_force_stays_within_its_bounding_lines():
    """Elastic-perfectly plastic (alpha = 0): the peak story shear is the strength itself (to the residue of
    the located crossing), whatever the drift."""
    record = SimpleNamespace(acceleration=2.0 * GROUND, dt=DT)
    result = engine.analyze(sdof(2e5, 0.0), record, "rigid", ExactOptions())
    assert result.peaks["shear"][0] == pytest.approx(2e5, rel=1e-9)
    assert result.peaks["ductility"][0] > 5.0


# ------------------------------------------------------------------ energy balance, every support
@pytest.mark.parametrize("path, overrides", [
    (TWO, ()),
    (TWO, ("foundation.safety_factor=2",)),
    (WINKLER, ("analysis.modes=10", "foundation.elements=10")),
    (WINKLER, ("analysis.modes=10", "foundation.elements=10", "foundation.safety_factor=2")),
    (HALFSPACE, SHEAR_FRAME),
])
@pytest.mark.parametrize("support", ["rigid", "bonded", "uplift"])
def test_the_energy_balance_closes_with_the_hysteretic_energy(path, overrides, support):
    """Ten yielding stories (base-shear strength 0.15 W, alpha = 0.05, largest ductilities 2.2 to 5.9) on
    every support, two elements, Winkler and the half-space (five stories, a mat with inertia), with and
    without a bearing capacity: the balance with the hysteretic energy closes to 1e-5 of the input at 24
    steps per governing period. Measured 4.6e-9 to 2.3e-7."""
    result = run(path, support, *overrides, "building.strength_coefficient=0.15", "building.hardening_ratio=0.05",
                 "analysis.exact.steps_per_period=24")
    energy = result.details["energy"]
    assert result.peaks["yielded_stories"][0] > 0
    assert energy["hysteretic"] > 0.0
    assert energy["hysteretic"] == pytest.approx(result.peaks["hysteretic_energy"].sum(), rel=1e-12)
    assert energy["relative_residual"] < 1e-5


def test_a_multistory_building_on_yielding_soil_runs():
    """The ten-story deck on the uplift support with a bearing capacity (FS_v = 2) and yielding stories: the
    soil and the stories both yield, and the balance (hysteretic energy and the soil's plastic work)
    closes to 1e-5."""
    result = run(TWO, "uplift", "foundation.safety_factor=1.5", "building.strength_coefficient=0.2",
                 "analysis.exact.steps_per_period=24")
    assert result.yielded and result.building_yielded
    energy = result.details["energy"]
    assert energy["plastic_work"] > 0.0 and energy["hysteretic"] > 0.0
    assert energy["relative_residual"] < 1e-5


# ------------------------------------------------------------------ the numpy twin of the loop
def both_runs():
    record = SimpleNamespace(acceleration=GROUND, dt=DT)
    return (engine.analyze(sdof(3e5, 0.1), record, "rigid", ExactOptions()),
            run(TWO, "uplift", "building.strength_coefficient=0.15", "foundation.safety_factor=2"))


def test_the_loop_and_its_twin_agree_on_yielding_stories():
    """The compiled loop and its numpy twin (tests/backends.py) on the yielding SDOF and the ten-story deck
    on yielding soil: every quantity to 1e-9 of its largest value."""
    compiled, twin = on_both(both_runs)
    for a, b in zip(compiled, twin, strict=True):
        for name, value in a.peaks.items():
            assert np.max(np.abs(value - b.peaks[name]), initial=0.0) <= 1e-9 * np.max(np.abs(value), initial=0.0)
        assert a.intermediates["transitions"] == b.intermediates["transitions"]


# ------------------------------------------------------------------ the deck
def test_the_strength_coefficient_is_distributed_as_asce_7():
    """ASCE 7-22 12.8.3: k = 1 up to T = 0.5 s, 2 from 2.5 s, linear between; C_vx = w h^k / sum w h^k; the
    story strength is the story shear of C_s W so distributed (the first story's: C_s W)."""
    assert distribution_exponent(0.3) == 1.0 and distribution_exponent(3.0) == 2.0
    assert distribution_exponent(1.5) == pytest.approx(1.5)
    weights, heights = np.array([2.0, 1.0]), np.array([3.0, 6.0])
    assert vertical_distribution(weights, heights, 0.4) == pytest.approx([0.5, 0.5])
    assert vertical_distribution(weights, heights, 2.5) == pytest.approx([18 / 54, 36 / 54])
    deck = load_deck(TWO, ["building.strength_coefficient=0.1"])
    building = deck.system.building
    weight = building.masses.sum() * deck.system.gravity
    assert building.story_strength[0] == pytest.approx(0.1 * weight, rel=1e-12)
    assert np.all(np.diff(building.story_strength) < 0.0) and building.hardening_ratio == 0.0


@pytest.mark.parametrize("overrides, field", [
    (("building.story_strengths=[1e6, 1e6]",), "building.story_strengths"),
    (("building.hardening_ratio=0.1",), "building.hardening_ratio"),
    (("building.strength_coefficient=0.1", "building.hardening_ratio=1"), "building.hardening_ratio"),
])
def test_bad_strengths_are_one_error_naming_the_field(overrides, field):
    with pytest.raises(InputError) as caught:
        load_deck(TWO, list(overrides))
    assert field in str(caught.value) and "\n" not in str(caught.value)


def test_the_two_strengths_are_exclusive_alternatives(tmp_path):
    """A deck with both story_strengths and strength_coefficient: one error naming the second (a --set of
    one replaces the other, as for every group of alternatives: deck/overrides.py)."""
    text = TWO.read_text().replace("[building]", "[building]\nstrength_coefficient = 0.1\nstory_strengths = "
                                   + str([1e6] * 10), 1)
    deck = tmp_path / "deck.toml"
    deck.write_text(text.replace("../records/", str(ROOT / "records") + "/"))
    with pytest.raises(InputError) as caught:
        load_deck(deck, [])
    assert "building.story_strengths" in str(caught.value) and "\n" not in str(caught.value)


@pytest.mark.parametrize("name", ["simplified", "approximate"])
def test_the_other_engines_refuse_yielding_stories(name):
    deck = load_deck(TWO, ["building.strength_coefficient=0.1"])
    ((_, outcome),) = ENGINES[name].iter_batch([deck.system], deck.ground_motion, "uplift",
                                               getattr(deck.analysis, ENGINES[name].options))
    assert isinstance(outcome, InputError) and "story_strengths" in str(outcome)


def test_too_many_pattern_bits_are_refused_naming_the_field():
    """Ten yielding stories (20 bits) on a 25-element mat with a bearing capacity (50 bits): 70 > 62; the
    deck that runs the exact engine is refused when read, and the engine refuses the system (a caller
    that builds it in code)."""
    fields = ["building.strength_coefficient=0.1", "analysis.modes=10", "foundation.elements=25",
              "foundation.safety_factor=2"]
    with pytest.raises(InputError) as caught:
        load_deck(WINKLER, [*fields, "analysis.engine=exact"])
    assert "foundation.elements" in str(caught.value) and "62 bits" in str(caught.value)
    deck = load_deck(WINKLER, fields)
    ((_, outcome),) = ENGINES["exact"].iter_batch([deck.system], deck.ground_motion, "uplift", deck.analysis.exact)
    assert isinstance(outcome, InputError) and "foundation: elements" in str(outcome)


def test_a_truncation_of_the_modes_is_refused():
    deck = load_deck(WINKLER, ["building.strength_coefficient=0.1"])
    ((_, outcome),) = ENGINES["exact"].iter_batch([deck.system], deck.ground_motion, "rigid", deck.analysis.exact)
    assert isinstance(outcome, InputError) and "modes" in str(outcome)


def test_the_other_engines_refuse_them_when_called_directly():
    from upliftcli.engines import approximate, simplified

    deck = load_deck(TWO, ["building.strength_coefficient=0.1"])
    ((_, outcome),) = approximate.iter_batch([deck.system], deck.ground_motion, "uplift", deck.analysis.exact)
    assert isinstance(outcome, InputError) and "story_strengths" in str(outcome)
    ((_, outcome),) = simplified.iter_batch([deck.system], deck.ground_motion, "uplift", deck.analysis.simplified)
    assert isinstance(outcome, InputError) and "story_strengths" in str(outcome)


def test_flight_is_refused_while_a_story_yields():
    """flight = "error": the mat leaves the foundation at t = 5.91997 s while the top story yields (a pattern
    with story bits: found by a scan with flight allowed); the loops compare the element bits only, so
    the run stops there, not 0.13 ms later when that story unloads (as a comparison of the whole pattern
    did), on both backends."""
    from upliftcli.errors import AnalysisError

    def stopped():
        deck = load_deck(TWO, ["building.period=0.08", "building.strength_coefficient=0.19",
                               "building.hardening_ratio=0.02", 'analysis.exact.flight="error"'])
        with pytest.raises(AnalysisError) as caught:
            analysis.run_one(deck, "exact", "uplift")
        return str(caught.value)

    for message in on_both(stopped):
        assert "t = 5.9200 s" in message


def test_the_story_shear_histories_trace_the_hysteresis():
    """With histories asked for, a yielding building adds shear_<story>: on the SDOF (alpha = 0.1) every
    sample lies within the bounding lines alpha k d +- (1 - alpha) V_y and on them somewhere; the elastic
    building adds no column."""
    record = SimpleNamespace(acceleration=GROUND, dt=DT)
    options = ExactOptions(histories=True)
    result = engine.analyze(sdof(3e5, 0.1), record, "rigid", options)
    shear, drift = result.histories["shear_1"], result.histories["drift_1"]
    gap = (1.0 - 0.1) * 3e5 - np.abs(shear - 0.1 * STIFFNESS * drift)
    assert gap.min() >= -1e-6 * 3e5 and np.sum(gap < 1e-6 * 3e5) > 10
    assert np.max(np.abs(shear)) == pytest.approx(result.peaks["shear"][0], rel=1e-3)
    assert "shear_1" not in engine.analyze(sdof(None, 0.0), record, "rigid", options).histories


def test_a_us_deck_reads_the_strengths_in_kip():
    deck = load_deck(ROOT / "inputs" / "ten_story_elcentro_us.toml", ["building.story_strengths=" + str([100.0] * 10)])
    assert deck.system.building.story_strength == pytest.approx(np.full(10, 100.0 * 4448.2216152605), rel=1e-12)


def test_on_a_yielding_winkler_mat_a_strength_never_reached_is_elastic_to_rounding():
    """The block operators of a Winkler mat with a bearing capacity (yielding.step_operators) include the
    plastic drifts in their block, so the elastic run is met to rounding only (docs/theory.md 15.4):
    measured 9.8e-12 of each quantity's largest value, the same transitions."""
    base = ["analysis.modes=10", "foundation.safety_factor=1e15"]
    elastic = run(WINKLER, "uplift", *base)
    strong = run(WINKLER, "uplift", *base, "building.strength_coefficient=1000")
    for name, value in elastic.peaks.items():
        assert np.max(np.abs(strong.peaks[name] - value), initial=0.0) <= 1e-10 * np.max(np.abs(value), initial=0.0)
    assert strong.intermediates["transitions"] == elastic.intermediates["transitions"]


@pytest.mark.parametrize("support", ["rigid", "uplift"])
def test_chunks_fold_the_yielding_quantities_to_the_single_pass(monkeypatch, support):
    """A run stepped in chunks (stepping.CHUNK_SAMPLES, every interval in one chunk) gives the yielding
    stories' quantities and hysteretic energy of the single pass (the energy sums in another order)."""
    from upliftcli.engines.exact import stepping

    deck = load_deck(TWO, ["building.strength_coefficient=0.15", "building.hardening_ratio=0.05"])
    record = SimpleNamespace(acceleration=deck.ground_motion.acceleration[:600], dt=deck.ground_motion.dt)
    whole = engine.analyze(deck.system, record, support, deck.analysis.exact)
    monkeypatch.setattr(stepping, "CHUNK_SAMPLES", 700)
    chunked = engine.analyze(deck.system, record, support, deck.analysis.exact)
    assert chunked.intermediates["samples"] == whole.intermediates["samples"] > 1400  # 3 chunks or more
    assert whole.peaks["yielded_stories"][0] > 0
    for name in ("ductility", "residual_drift_ratio", "story_yielded", "yielded_stories", "shear", "moment"):
        np.testing.assert_allclose(chunked.peaks[name], whole.peaks[name], rtol=1e-12, err_msg=name)
    np.testing.assert_allclose(chunked.peaks["hysteretic_energy"], whole.peaks["hysteretic_energy"], rtol=1e-12,
                               atol=1e-12 * whole.peaks["hysteretic_energy"].max())
    assert chunked.details["energy"]["relative_residual"] < 1e-4


@pytest.mark.parametrize("deck, engine_name, expected", [
    (TWO, "simplified", "error: --set: building.strength_coefficient: the simplified engine"),
    (TWO, "approximate", "error: --set: building.strength_coefficient: the approximate engine"),
    (WINKLER, "exact", f"error: {WINKLER.relative_to(ROOT)}: analysis.modes: all 10 modes"),
])
def test_the_command_refuses_with_one_line_naming_the_field(deck, engine_name, expected, monkeypatch):
    """uplift analyze: exit 2 and one line naming --set or the deck and the field (analysis/run.py
    check_yielding_stories), before anything runs."""
    from typer.testing import CliRunner

    from upliftcli.cli import app

    monkeypatch.chdir(ROOT)
    result = CliRunner().invoke(app, ["analyze", str(deck.relative_to(ROOT)), "--set",
                                      "building.strength_coefficient=0.2", "--engine", engine_name])
    assert result.exit_code == 2
    assert result.stderr.strip().splitlines() == [result.stderr.strip()] and result.stderr.startswith(expected)


def test_yielding_runs_are_stepped_at_most_two_together(monkeypatch):
    """A batch of five yielding buildings (periods 0.4-0.8 s) and two elastic ones is stepped in groups of at
    most stepping.YIELDING_GROUP = 2 yielding runs (each touches its own step operators, tens of MB; the
    elastic ones are not counted), and each result is the one it gets analysed alone, bit for bit."""
    from upliftcli.engines.exact import stepping

    groups = []
    many = stepping.simulate_many
    monkeypatch.setattr(stepping, "simulate_many", lambda runs: groups.append(
        [int(run.layout.n_plastic > 0) for run in runs]) or many(runs))
    window = ["ground_motion.window=[0, 3]", "ground_motion.scale=2", "building.hardening_ratio=0.05"]
    decks = [load_deck(TWO, [*window, f"building.period={period}", "building.strength_coefficient=0.2"])
             for period in (0.4, 0.5, 0.6, 0.7, 0.8)]
    decks[1:1] = [load_deck(TWO, window[:1]), load_deck(TWO, [window[0], "building.period=0.7"])]
    systems = [deck.system for deck in decks]
    together = engine.analyze_batch(systems, decks[0].ground_motion, "uplift")
    assert stepping.YIELDING_GROUP == 2 and groups == [[1, 0, 0, 1], [1, 1], [1]]
    for system, result in zip(systems, together, strict=True):
        assert same(result, engine.analyze(system, decks[0].ground_motion, "uplift"))
    assert min(float(r.peaks["ductility"].max()) for r in together[:1] + together[3:]) > 1.0
