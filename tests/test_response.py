"""Floor accelerations and foundation reactions of the history engines (engines/exact/response.py)
against independent results: superposed SDOF responses, equilibrium at every sample, statics."""

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
from upliftcli.model.building import uniform_building
from upliftcli.model.foundations import TwoElement, Winkler, two_element_from_ratios
from upliftcli.model.system import System
from upliftcli.motion.spectra import sdof_history

RECORD = Path(__file__).resolve().parents[1] / "records" / "elcentro_1940_ns_chopra.txt"



def short(record, seconds: float, refine: int = 1):
    """The first seconds of a record, optionally resampled `refine` times finer (exactly: it is
    piecewise linear)."""
    n = round(seconds / record.dt) + 1
    coarse = record.acceleration[:n]
    fine = np.interp(np.arange((n - 1) * refine + 1) / refine, np.arange(n), coarse)
    return SimpleNamespace(acceleration=fine, dt=record.dt / refine)


def test_rigid_floor_accelerations_are_superposed_sdof_absolute_accelerations(elcentro):
    """a_j = -sum_n phi_jn* (w_n^2 u_n + 2 xi_n w_n u_n'), u_n the SDOF response of mode n
    (Nigam-Jennings, exact at the samples); peaks against a 20x finer sampling of that sum."""
    system = paper_system(0.5)
    record = short(elcentro, 8.0)
    result = exact.analyze(system, record, "rigid", ExactOptions(histories=True, time_step=record.dt))
    hist = result.histories
    fine = short(elcentro, 8.0, refine=20)
    modes = system.modes
    coarse_sum = np.zeros((record.acceleration.size, 10))
    fine_sum = np.zeros((fine.acceleration.size, 10))
    for n in range(modes.n_modes):
        for rec, total in ((record, coarse_sum), (fine, fine_sum)):
            u, v = sdof_history(rec.acceleration, rec.dt, modes.periods[n], modes.damping[n])
            total += -np.outer(modes.omega[n] ** 2 * u + 2 * modes.damping[n] * modes.omega[n] * v,
                               modes.shapes_star[:, n])
    scale = np.abs(coarse_sum).max()
    engine = np.column_stack([hist[f"floor_acceleration_{j + 1}"] for j in range(10)])
    assert np.abs(engine - coarse_sum).max() < 1e-6 * scale
    peaks = result.peaks["floor_acceleration"]
    np.testing.assert_allclose(peaks, np.abs(fine_sum).max(axis=0), rtol=2e-3)
    assert np.all(peaks >= np.abs(coarse_sum).max(axis=0) * (1 - 1e-9))  # never below the samples
    # its instant is where the 20x finer sum peaks
    top = np.argmax(np.abs(fine_sum[:, -1]))
    assert result.times["floor_acceleration"][-1] == pytest.approx(top * fine.dt, abs=2 * fine.dt)


def test_undamped_rigid_base_floor_inertia_forces_balance_the_base_shear(elcentro):
    """xi = 0, fixed base: sum_j m_j a_j = -V_b at every sample (no damping force at the base)."""
    building = uniform_building(10, 350e3, 3.5, period=0.5, damping=0.0)
    system = System(building, TwoElement(1e9, 0.0), 3.0)
    result = exact.analyze(system, short(elcentro, 6.0), "rigid", ExactOptions(histories=True))
    hist = result.histories
    inertia = sum(building.masses[j] * hist[f"floor_acceleration_{j + 1}"] for j in range(10))
    assert np.abs(inertia + hist["base_shear"]).max() < 1e-9 * np.abs(hist["base_shear"]).max()


@pytest.mark.parametrize("support", ["bonded", "uplift"])
def test_floor_inertia_moment_balances_the_foundation_moment_at_every_sample(elcentro, support):
    """Massless mat, all modes: sum_j m_j h_j a_j = -sum_i x_i R_i (rocking equation [1b]), with
    the reactions R_i read off the elements and the accelerations off the modal coordinates."""
    system = paper_system(0.5)
    result = exact.analyze(system, short(elcentro, 8.0), support, ExactOptions(histories=True))
    hist = result.histories
    building = system.building
    inertia = sum(building.masses[j] * building.heights[j] * hist[f"floor_acceleration_{j + 1}"] for j in range(10))
    positions = result.element_positions
    foundation = -sum(positions[i] * hist[f"reaction_{i + 1}"] for i in range(positions.size))
    assert np.abs(inertia - foundation).max() < 1e-7 * np.abs(foundation).max()
    if support == "uplift":
        assert result.uplift and np.any(hist["contact_state"] > 0)


def test_reactions_at_rest_carry_the_weight_by_the_element_stiffness():
    """No ground motion: every element carries its static share, k_i / sum k * W."""
    still = SimpleNamespace(acceleration=np.zeros(200), dt=0.01)
    system = paper_system(0.5)
    result = exact.analyze(system, still, "uplift")
    np.testing.assert_allclose(result.peaks["reaction"], [system.weight / 2] * 2, rtol=1e-9)
    assert np.all(result.peaks["impact"] == 0.0)
    winkler = replace(system, foundation=Winkler(2e9, 1e7, 8))
    result = exact.analyze(winkler, still, "bonded")
    np.testing.assert_allclose(result.peaks["reaction"], np.full(8, winkler.weight / 8), rtol=1e-9)
    assert result.element_positions.size == 8


def test_impacts_vanish_without_element_dampers_and_stay_below_the_largest_reaction(elcentro):
    """c_f = 0: the edge comes back onto an unstressed spring, so the reaction at recontact
    is zero; with dashpots it is c_f times the closing velocity, at most the largest reaction."""
    record = short(elcentro, 10.0)
    damped = paper_system(0.5)
    result = exact.analyze(damped, record, "uplift")
    assert np.all(result.peaks["impact"] > 0.0)
    assert np.all(result.peaks["impact"] <= result.peaks["reaction"] * (1 + 1e-12))
    springs = two_element_from_ratios(damped.total_mass, damped.modes.omega[0], 8.0, 0.0)
    undamped = replace(damped, foundation=springs)
    result = exact.analyze(undamped, record, "uplift")
    assert result.uplift
    assert np.all(result.peaks["impact"] < 1e-6 * undamped.weight)


def test_approximate_engine_gives_the_same_quantities(elcentro):
    """The approximate engine reports the same quantities; on a rigid base it is the exact
    engine (no coupling to approximate), whose floor accelerations are checked against the
    superposed SDOF responses above; at rest each edge carries half the weight."""
    system, record = paper_system(0.5), short(elcentro, 4.0)
    result = approximate.analyze(system, record, "uplift")
    for name in ("floor_acceleration", "reaction", "impact"):
        assert name in result.peaks and name in result.times
    rigid = approximate.analyze(system, record, "rigid").peaks["floor_acceleration"]
    np.testing.assert_allclose(rigid, exact.analyze(system, record, "rigid").peaks["floor_acceleration"], rtol=1e-12)
    at_rest = approximate.analyze(system, SimpleNamespace(acceleration=np.zeros(200), dt=0.01), "bonded")
    np.testing.assert_allclose(at_rest.peaks["reaction"], [system.weight / 2] * 2, rtol=1e-9)


def test_flight_is_reported_as_a_property_of_the_model(elcentro):
    """T_1 = 0.05 s under El Centro: both edges leave the foundation (docs/theory.md section 9)."""
    result = exact.analyze(paper_system(0.05), short(elcentro, 6.0), "uplift")
    assert result.details["uplift_summary"]["flight_time"] > 0.0
    assert any("flight" in w and "property of the model" in w for w in result.details["warnings"])
    bonded = exact.analyze(paper_system(0.5), short(elcentro, 6.0), "uplift")
    assert not any("flight" in w for w in bonded.details["warnings"])
