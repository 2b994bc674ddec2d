"""Exact engine against independent results (issue 4, "How it is checked")."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from paper_example import paper_system

from upliftcli.engines import approximate
from upliftcli.engines.exact import engine as exact
from upliftcli.engines.options import ExactOptions
from upliftcli.errors import AnalysisError
from upliftcli.model.foundations import TwoElement, Winkler
from upliftcli.model.system import System
from upliftcli.motion.spectra import sdof_history

G = 9.80665
RECORD = Path(__file__).resolve().parents[1] / "records" / "elcentro_1940_ns_chopra.txt"



def short(record, seconds: float):
    n = round(seconds / record.dt) + 1
    return SimpleNamespace(acceleration=record.acceleration[:n], dt=record.dt)


def test_rigid_equals_modal_superposition_of_sdof_histories(elcentro):
    system = paper_system(0.5)
    options = ExactOptions(histories=True, time_step=elcentro.dt)
    result = exact.analyze(system, elcentro, "rigid", options)
    hist = result.histories
    modes = system.modes
    base_shear = np.zeros(elcentro.npts)
    for n in range(modes.n_modes):
        u, _ = sdof_history(elcentro.acceleration, elcentro.dt, modes.periods[n], modes.damping[n])
        # Y_n* of the renormalised shape obeys the SDOF equation with unit participation
        base_shear += modes.omega[n] ** 2 * modes.effective_mass[n] * u
    np.testing.assert_allclose(hist["time"], np.arange(elcentro.npts) * elcentro.dt, atol=1e-12)
    scale = np.abs(base_shear).max()
    assert np.abs(hist["base_shear"] - base_shear).max() < 1e-6 * scale


def _frequency_domain_bonded(system: System, acceleration: np.ndarray, dt: float):
    """Independent linear solution of [1a-1c] in physical coordinates (u, theta, v), bonded.

    The mass matrix is singular for a massless mat (docs/theory.md section 5): no matter in the
    frequency domain, where (-w^2 M + i w C + K) is regular for w > 0.
    """
    b = system.building
    n = b.n_stories
    modes = system.modes
    mass_phi = b.masses[:, None] * modes.shapes
    c_struct = mass_phi @ np.diag(2 * modes.damping * modes.omega) @ mass_phi.T
    k_f, c_f, half = system.foundation.stiffness, system.foundation.damping, system.half_width
    size = n + 2
    mass = np.zeros((size, size))
    mass[:n, :n] = np.diag(b.masses)
    mass[:n, n] = mass[n, :n] = b.masses * b.heights
    mass[n, n] = np.sum(b.masses * b.heights**2)
    mass[n + 1, n + 1] = system.total_mass
    stiff = np.zeros((size, size))
    damp = np.zeros((size, size))
    stiff[:n, :n], damp[:n, :n] = b.stiffness, c_struct
    stiff[n, n], damp[n, n] = 2 * k_f * half**2, 2 * c_f * half**2
    stiff[n + 1, n + 1], damp[n + 1, n + 1] = 2 * k_f, 2 * c_f
    load = -np.concatenate((b.masses, [np.sum(b.masses * b.heights), 0.0]))
    padded = 1 << int(np.ceil(np.log2(acceleration.size * 4)))
    spectrum = np.fft.rfft(acceleration, padded)
    omega = 2 * np.pi * np.fft.rfftfreq(padded, dt)
    response = np.zeros((omega.size, size), dtype=complex)
    for k in range(1, omega.size):
        w = omega[k]
        response[k] = np.linalg.solve(-w * w * mass + 1j * w * damp + stiff, load * spectrum[k])
    history = np.fft.irfft(response, padded, axis=0)[: acceleration.size]
    # base shear = sum of the elastic forces K u
    return history[:, :n] @ b.stiffness.sum(axis=0), history[:, n]


def test_bonded_equals_frequency_domain_solution(elcentro):
    system = paper_system(1.0)
    # a finely resampled (still piecewise-linear) record keeps the FFT's band limit harmless
    factor = 8
    t = np.arange(elcentro.npts) * elcentro.dt
    fine_t = np.arange((elcentro.npts - 1) * factor + 1) * (elcentro.dt / factor)
    fine = SimpleNamespace(acceleration=np.interp(fine_t, t, elcentro.acceleration), dt=elcentro.dt / factor)
    result = exact.analyze(system, fine, "bonded", ExactOptions(histories=True, time_step=fine.dt))
    base_shear, theta = _frequency_domain_bonded(system, fine.acceleration, fine.dt)
    hist = result.histories
    assert np.abs(hist["base_shear"] - base_shear).max() < 2e-3 * np.abs(base_shear).max()
    assert np.abs(hist["theta"] - theta).max() < 2e-3 * np.abs(theta).max()


def test_stiff_foundation_tends_to_rigid_and_wide_mat_to_bonded(elcentro):
    record = short(elcentro, 8.0)
    system = paper_system(0.5)
    rigid = exact.analyze(system, record, "rigid")
    stiff = replace(system, foundation=TwoElement(system.foundation.stiffness * 1e4, system.foundation.damping * 1e2))
    bonded_stiff = exact.analyze(stiff, record, "bonded")
    assert bonded_stiff.base_shear == pytest.approx(rigid.base_shear, rel=5e-3)
    wide = replace(system, half_width=system.half_width * 100)
    bonded = exact.analyze(wide, record, "bonded")
    uplift = exact.analyze(wide, record, "uplift")
    assert not uplift.uplift
    assert uplift.base_shear == pytest.approx(bonded.base_shear, rel=1e-9)


def test_static_push_lifts_at_critical_moment_and_shear():
    """A slow ramp of ground acceleration on the first-mode model: lift-off at M_c and V_c."""
    system = paper_system(0.5)  # 5 % damping: the ramp's start transient has died out at lift-off
    dt = 0.01
    duration = 60.0
    ramp = -np.linspace(0.0, 1.0, int(duration / dt) + 1) * 0.3 * G   # a_g down -> forces up the building
    record = SimpleNamespace(acceleration=ramp, dt=dt)
    options = ExactOptions(n_modes=1, histories=True)
    for criterion in ("reaction", "displacement"):
        result = exact.analyze(system, record, "uplift", replace(options, criterion=criterion))
        hist = result.histories
        first = np.nonzero(hist["contact_state"])[0][0]
        assert abs(hist["base_moment"][first]) == pytest.approx(system.critical_base_moment, rel=2e-3)
        assert abs(hist["base_shear"][first]) == pytest.approx(system.critical_base_shear, rel=2e-3)


def test_undamped_elements_criteria_coincide(elcentro):
    record = short(elcentro, 10.0)
    system = paper_system(0.4, damping_ratio=0.0)
    runs = [exact.analyze(system, record, "uplift", ExactOptions(criterion=c, histories=True))
            for c in ("reaction", "displacement")]
    a, b = (r.histories for r in runs)
    assert runs[0].uplift
    np.testing.assert_array_equal(a["contact_state"], b["contact_state"])
    np.testing.assert_allclose(a["base_shear"], b["base_shear"], rtol=0, atol=1e-9 * np.abs(a["base_shear"]).max())


@pytest.mark.parametrize("support", ["rigid", "bonded", "uplift"])
def test_energy_balance_closes(elcentro, support):
    result = exact.analyze(paper_system(0.5), elcentro, support)
    energy = result.details["energy"]
    assert energy["input"] > 0
    assert energy["relative_residual"] < 1e-4


INPUTS = Path(__file__).resolve().parents[1] / "inputs"


@pytest.mark.parametrize("deck", sorted(p.name for p in INPUTS.glob("*.toml")))
def test_energy_balance_closes_for_every_example_deck(deck):
    """Two-element, Winkler and half-space foundations, all three supports, default step."""
    from upliftcli.analysis.run import run
    from upliftcli.deck.load import load_deck

    loaded = load_deck(Path(__file__).resolve().parents[1] / "inputs" / deck)
    if not hasattr(loaded.ground_motion, "acceleration"):
        pytest.skip("design-spectrum deck: no history")
    for result in run(loaded, "exact", ["rigid", "bonded", "uplift"]):
        assert result.intermediates["energy_residual"] < 1e-4, result.support


def test_step_at_a_fifth_of_the_governing_period_finds_every_transition(elcentro):
    """A brief lift-off shorter than the step is caught (cubic test of the event functions)."""
    system = paper_system(float(np.geomspace(0.05, 5.0, 25)[4]))  # 0.108 s: short episodes
    coarse = exact.analyze(system, elcentro, "uplift", ExactOptions(steps_per_period=5))
    fine = exact.analyze(system, elcentro, "uplift", ExactOptions(steps_per_period=40))
    assert coarse.intermediates["transitions"] == fine.intermediates["transitions"]
    np.testing.assert_allclose(coarse.shear, fine.shear, rtol=1e-3)


def test_deck_default_step_is_the_engine_default():
    from upliftcli.deck.schema import TABLES

    assert TABLES["analysis.exact"]["steps_per_period"].default == ExactOptions().steps_per_period


@pytest.mark.parametrize("period", [0.05, 0.3, 1.0, 3.0, 5.0])
def test_halving_the_step_changes_no_peak_by_half_a_percent(elcentro, period):
    system = paper_system(period)
    coarse = exact.analyze(system, elcentro, "uplift")
    h = coarse.intermediates["time_step"]
    fine = exact.analyze(system, elcentro, "uplift", ExactOptions(time_step=h / 2))
    for name in ("displacement", "drift", "shear", "moment"):
        np.testing.assert_allclose(getattr(fine, name), getattr(coarse, name), rtol=5e-3)


def test_rigid_history_is_exact_at_any_step(elcentro):
    """The step operator is exact for piecewise-linear input: samples agree whatever the step."""
    system = paper_system(0.5)
    record = short(elcentro, 6.0)
    a = exact.analyze(system, record, "rigid", ExactOptions(time_step=record.dt, histories=True))
    b = exact.analyze(system, record, "rigid", ExactOptions(time_step=record.dt / 8, histories=True))
    np.testing.assert_allclose(b.histories["base_shear"][::8], a.histories["base_shear"],
                               atol=1e-8 * np.abs(a.base_shear))


def test_paper_findings_ten_story_el_centro(elcentro):
    """Paper Figs. 3-5: long periods do not uplift; short periods uplift, base shear drops
    below bonded but stays above V_c, base moment near M_c; higher modes barely change."""
    long_period = paper_system(3.0)
    bonded = exact.analyze(long_period, elcentro, "bonded")
    uplift = exact.analyze(long_period, elcentro, "uplift")
    assert not uplift.uplift
    assert uplift.base_shear == pytest.approx(bonded.base_shear, rel=1e-9)
    for period in (0.3, 0.5, 1.0):
        system = paper_system(period)
        bonded = exact.analyze(system, elcentro, "bonded")
        uplift = exact.analyze(system, elcentro, "uplift")
        rigid = exact.analyze(system, elcentro, "rigid")
        assert uplift.uplift
        assert system.critical_base_shear < uplift.base_shear < bonded.base_shear
        assert 1.0 <= uplift.base_moment / system.critical_base_moment < 1.5
        # modes 2 and 3: uplift changes them little against the bonded system (measured up to
        # +18 % at T_1 = 0.5 s); at the paper's Fig. 5 period (1 s) also little against rigid
        # (mode 2 relative; the small modes 3-5 within 0.015 m_t g)
        higher = {r.support: np.array(r.details["modal_base_shear"][1:5]) / system.weight
                  for r in (rigid, bonded, uplift)}
        references = ("bonded", "rigid") if period == 1.0 else ("bonded",)
        for reference in references:
            assert higher["uplift"][0] == pytest.approx(higher[reference][0], rel=0.25)
            np.testing.assert_allclose(higher["uplift"][1:], higher[reference][1:], atol=0.015)


def test_approximate_matches_exact_without_uplift(elcentro):
    """Paper Fig. 6: one-mode interaction + fixed-base higher modes is excellent when bonded."""
    for period in (0.5, 1.5):
        system = paper_system(period)
        e = exact.analyze(system, elcentro, "bonded")
        a = approximate.analyze(system, elcentro, "bonded")
        assert a.base_shear == pytest.approx(e.base_shear, rel=0.05)
        r_exact = exact.analyze(system, elcentro, "rigid")
        r_approx = approximate.analyze(system, elcentro, "rigid")
        assert r_approx.base_shear == pytest.approx(r_exact.base_shear, rel=1e-12)


def test_flight_refused_with_a_clear_error(elcentro):
    system = paper_system(0.08)
    with pytest.raises(AnalysisError, match="flight"):
        exact.analyze(system, elcentro, "uplift", ExactOptions(flight="error"))
    result = exact.analyze(system, elcentro, "uplift")
    assert result.details["uplift_summary"]["flight_time"] > 0.0


def test_too_short_record_is_an_error():
    with pytest.raises(AnalysisError, match="too short"):
        exact.analyze(paper_system(0.5), SimpleNamespace(acceleration=np.zeros(1), dt=0.01), "uplift")


def test_cumulative_modal_base_shear_ends_at_the_total(elcentro):
    result = exact.analyze(paper_system(1.0), short(elcentro, 10.0), "uplift")
    cumulative = result.details["cumulative_modal_base_shear"]
    assert cumulative[0] == pytest.approx(result.details["modal_base_shear"][0], rel=1e-12)
    assert cumulative[-1] == pytest.approx(result.base_shear, rel=1e-12)


def test_winkler_converges_as_elements_grow(elcentro):
    """Winkler strip discretised into n unilateral elements (midpoint rule): the uplift response
    settles as n grows, and K_theta of the discrete elements tends to (2/3) k_w b^3."""
    from upliftcli.model.foundations import Winkler

    base = paper_system(0.5)
    b = base.half_width
    two = base.foundation
    # same rocking stiffness and damping as the paper's two elements: (2/3) k_w b^3 = 2 k_f b^2
    k_w, c_w = 3.0 * two.stiffness / b, 3.0 * two.damping / b
    record = short(elcentro, 8.0)
    shears, moments = [], []
    for n in (5, 10, 20, 40):
        system = replace(base, foundation=Winkler(k_w, c_w, n))
        elements = system.foundation.contact_elements(b)
        k_theta = np.sum(elements.stiffness * elements.positions**2)
        assert k_theta == pytest.approx(2.0 / 3.0 * k_w * b**3 * (1 - 1 / n**2), rel=1e-12)
        result = exact.analyze(system, record, "uplift")
        shears.append(result.base_shear)
        moments.append(result.base_moment)
    # base moment (measured 0.854, 0.883, 0.895, 0.899 M_c): differences shrink about 2-4x per doubling
    steps = np.abs(np.diff(moments))
    assert np.all(steps[1:] < 0.6 * steps[:-1])
    assert steps[-1] < 0.01 * moments[-1]
    np.testing.assert_allclose(shears[1:], shears[-1], rtol=0.01)


# ----------------------------------------------------------------------------- batches

def _assert_same_result(a, b):
    """Every field equal, bit for bit (arrays, intermediates, details)."""
    for name in a.__dataclass_fields__:
        np.testing.assert_equal(getattr(a, name), getattr(b, name), err_msg=name)


@pytest.mark.parametrize("engine", [exact, approximate])
@pytest.mark.parametrize("support", ["rigid", "bonded", "uplift"])
def test_batch_equals_one_at_a_time(elcentro, engine, support):
    """analyze_batch over foundations, mat widths, a mat mass and a Winkler foundation (another
    state layout) gives each system's own analyze result bit for bit; a system that cannot be
    run (too stiff a foundation for the step limit) gets its error and the others go on."""
    record = short(elcentro, 3.0)
    systems = [paper_system(0.5, frequency_ratio=ratio) for ratio in (3.0, 8.0, 20.0)]
    systems += [paper_system(0.5, slenderness=5.0), paper_system(0.5, mat_mass=350e3)]
    winkler = Winkler(2.0 * systems[1].foundation.stiffness / (2.0 * systems[1].half_width),
                      2.0 * systems[1].foundation.damping / (2.0 * systems[1].half_width), 6)
    systems.append(replace(systems[1], foundation=winkler))
    systems.append(paper_system(0.5, frequency_ratio=1e6))
    batch = engine.analyze_batch(systems, record, support)
    for system, result in zip(systems[:-1], batch, strict=False):
        _assert_same_result(result, engine.analyze(system, record, support))
    if support == "rigid":  # a fixed base does not see the foundation: one analysis serves all
        assert batch[-1].base_shear == batch[0].base_shear
        assert {r.critical_base_shear for r in batch} == {s.critical_base_shear for s in systems}
    else:
        assert isinstance(batch[-1], AnalysisError) and "steps would be needed" in str(batch[-1])
        with pytest.raises(AnalysisError, match="steps would be needed"):
            engine.analyze(systems[-1], record, support)
    if support == "uplift":  # runs that lift off at different times and ones that never do
        assert [r.uplift for r in batch[:3]] == [False, True, True]
        assert batch[1].intermediates["transitions"] != batch[2].intermediates["transitions"]


def test_a_large_energy_residual_refines_the_step_or_fails_naming_the_option(elcentro, monkeypatch):
    """Never a silent large residual: with a tolerance below the default step's residual the
    engine halves the step until it closes (and says so); with a fixed time_step it stops."""
    record = short(elcentro, 6.0)
    system = paper_system(0.5)
    first = exact.analyze(system, record, "uplift")
    monkeypatch.setattr(exact, "ENERGY_TOLERANCE", first.intermediates["energy_residual"] / 3)
    refined = exact.analyze(system, record, "uplift")
    assert refined.intermediates["steps_per_period"] in (12, 24, 48)
    assert refined.intermediates["energy_residual"] <= first.intermediates["energy_residual"] / 3
    assert any("refining the step" in w for w in refined.details["warnings"])
    with pytest.raises(AnalysisError, match=r"analysis\.exact\.time_step = 0\.01 s"):
        exact.analyze(system, record, "uplift", ExactOptions(time_step=0.01))


def test_refinement_is_bounded_by_the_work_limit_and_stops_without_progress(elcentro, monkeypatch):
    """The refinements of one analysis count against limits.MAX_STEP_STATES with its first run
    (frequency_ratio = 1000, c_f = 1e-12 ran 16 s a run and 240 s in all, its residual
    unchanged), and a halving that leaves the residual where it was ends the refinement; the
    line then says the step is not the cause (tests/test_refinement.py: the field that would close it)."""
    record = short(elcentro, 4.0)
    system = paper_system(0.5)
    runs = []
    original = exact.iter_batch

    def counted(*args, **kwargs):
        options = args[3] if len(args) > 3 else kwargs.get("options")
        runs.append((options or ExactOptions()).steps_per_period)
        return original(*args, **kwargs)

    monkeypatch.setattr(exact, "iter_batch", counted)
    monkeypatch.setattr(exact, "ENERGY_TOLERANCE", 1e-30)  # never met
    monkeypatch.setattr(exact, "MIN_PROGRESS", 10.0)  # every halving counts as progress
    first = exact._work(system, record, "uplift", ExactOptions(), exact.exact_model)
    finer = exact.finer_options(system, record, "uplift", ExactOptions())
    second = exact._work(system, record, "uplift", finer, exact.exact_model)
    monkeypatch.setattr(exact, "MAX_STEP_STATES", first + second + 1)  # the first run and one halving fit
    with pytest.raises(AnalysisError, match=rf"with {finer.steps_per_period} steps per governing period \(refined "
                                            r"from 6, .*would exceed the limits \(at most [\d,]+ internal steps x "
                                            r"states of one analysis.*: no step within the limits reaches it"):
        exact.analyze(system, record, "uplift")
    assert runs[1:] == [finer.steps_per_period]
    runs.clear()
    monkeypatch.setattr(exact, "MAX_STEP_STATES", 100 * first)
    monkeypatch.setattr(exact, "MIN_PROGRESS", 0.0)  # any residual left counts as no progress
    with pytest.raises(AnalysisError, match=r"a halving of the step left it at [\d.e-]+ of its value: the step is "
                                            r"not the cause$"):
        exact.analyze(system, record, "uplift")
    assert runs[1:] == [finer.steps_per_period]


@pytest.mark.parametrize("damping_ratio", [0.01, 4.3e-4])
def test_energy_balance_closes_when_lifted_elements_relax_within_a_step(elcentro, damping_ratio):
    """xi_v small: a lifted element's top relaxes (time c/k) far faster than the step; its
    dashpot's dissipation is the spring energy it releases, exactly (was 1e-2 and 0.37)."""
    result = exact.analyze(paper_system(1.0, damping_ratio=damping_ratio), short(elcentro, 12.0), "uplift")
    assert result.uplift
    assert result.intermediates["energy_residual"] < 5e-4
    assert "steps_per_period" not in result.intermediates  # no refinement was needed


def test_the_size_check_and_the_analysis_build_one_model(monkeypatch):
    """analysis.run checks the steps x states of a deck before the engine runs it: both use the
    same model (engine.model_for), built once per system, support and options."""
    from upliftcli.analysis import run as analysis
    from upliftcli.deck.load import load_deck
    from upliftcli.engines.exact import statespace

    built = []
    original = statespace.state_space

    def counting(model):
        built.append(model)
        return original(model)

    monkeypatch.setattr(exact, "_MODELS", {})
    monkeypatch.setattr(statespace, "state_space", counting)
    deck = load_deck(INPUTS / "ten_story_elcentro.toml", ['analysis.engine="exact"', "ground_motion.window=[0, 2]",
                                                          'analysis.supports=["bonded", "uplift"]'])
    results = analysis.run(deck)
    assert len(built) == 2 and len(results) == 2  # one model per support, not one for the check and one to run
    system = deck.system
    first = exact.model_for(system, "uplift", deck.analysis.exact)
    assert len(built) == 2 and exact.model_for(system, "uplift", deck.analysis.exact) is first
    assert exact.model_for(system, "uplift", replace(deck.analysis.exact, steps_per_period=12)) is not first
    assert len(built) == 3


def test_a_system_the_engine_refuses_does_not_stop_the_others_of_its_batch(elcentro):
    """More than 62 contact elements is refused for that system alone; the other system of the
    batch gets the result it gets alone."""
    good = paper_system(0.5)
    many = replace(good, foundation=Winkler(1e9, 1e7, 100))
    record = short(elcentro, 2.0)
    outcomes = dict(exact.iter_batch([good, many], record, "uplift"))
    assert isinstance(outcomes[1], AnalysisError) and "at most 62 contact elements" in str(outcomes[1])
    alone = exact.analyze(good, record, "uplift")
    assert outcomes[0].base_shear == alone.base_shear
