"""Simplified engine (docs/theory.md section 7): checked against independent computations and limits."""

import math
from dataclasses import replace

import numpy as np
import pytest
from paper_example import paper_system
from scipy.integrate import solve_ivp
from spectrum_stand_ins import ConstantSpectrum

from upliftcli.engines.options import SimplifiedOptions
from upliftcli.engines.paper import cqc, cqc_correlation, srss, uplift_base_shear
from upliftcli.engines.simplified import analyze, effective_properties
from upliftcli.model.building import shear_building, uniform_building
from upliftcli.model.foundations import HalfSpace, TwoElement, Winkler
from upliftcli.model.system import System

G = 9.80665
PAPER = SimplifiedOptions(procedure="paper")


class SmoothSpectrum:
    """A smooth made-up S_a(T, xi) [m/s^2] that depends on damping (Eurocode-like damping factor)."""

    def sa(self, periods, damping):
        t = np.asarray(periods, dtype=float)
        eta = np.sqrt(0.10 / (0.05 + damping))
        return eta * G * np.where(t < 0.4, 0.4 + 1.5 * t / 0.4 * 0.6 / 0.6, 0.76 / np.maximum(t, 1e-9) ** 0.8)



# ----------------------------------------------------------------------------- rigid base

def independent_rsa(building, spectrum, combination=np.sqrt):
    """Textbook modal RSA (Chopra ch. 13) written from scratch: u_n = Gamma_n phi_n S_a / w_n^2,
    story shears from story stiffness x drift, moments by statics from f_n = K u_n; SRSS."""
    m = building.masses
    k = building.stiffness
    values, vectors = np.linalg.eig(np.linalg.solve(np.diag(m), k))
    order = np.argsort(values.real)
    w2, phi = values.real[order], vectors.real[:, order]
    peaks = {"u": [], "drift": [], "shear": [], "moment": []}
    h = building.heights
    for n in range(m.size):
        gamma = phi[:, n] @ m / (phi[:, n] @ (m * phi[:, n]))
        sa = spectrum.sa(np.array([2 * np.pi / np.sqrt(w2[n])]), building.damping[n])[0]
        u = gamma * phi[:, n] * sa / w2[n]
        drift = np.diff(np.concatenate(([0.0], u)))
        f = k @ u
        moment = np.array([np.sum(f[j:] * (h[j:] - (h[j - 1] if j else 0.0))) for j in range(m.size)])
        for name, value in zip(peaks, (u, drift, building.story_stiffness * drift, moment), strict=False):
            peaks[name].append(value)
    return {name: np.sqrt(np.sum(np.array(v) ** 2, axis=0)) for name, v in peaks.items()}


def test_rigid_equals_independent_response_spectrum_analysis():
    building = shear_building([4e5, 3.5e5, 3e5, 2e5, 1.5e5], [4.5, 3.5, 3.5, 3.5, 3.0],
                              np.array([9, 8, 6, 5, 3]) * 1e8, damping=[0.05, 0.04, 0.05, 0.06, 0.05])
    system = System(building, TwoElement(1e9, 0.0), 6.0)
    spectrum = SmoothSpectrum()
    result = analyze(system, spectrum, "rigid")
    expected = independent_rsa(building, spectrum)
    np.testing.assert_allclose(result.displacement, expected["u"], rtol=1e-9)
    np.testing.assert_allclose(result.drift, expected["drift"], rtol=1e-9)
    np.testing.assert_allclose(result.shear, expected["shear"], rtol=1e-9)
    np.testing.assert_allclose(result.moment, expected["moment"], rtol=1e-9)
    np.testing.assert_allclose(result.drift_ratio, expected["drift"] / building.story_heights, rtol=1e-9)
    assert result.base_shear == pytest.approx(expected["shear"][0], rel=1e-9)
    assert result.uplift is False


def test_modal_base_moment_is_shear_times_effective_height():
    """Per mode M_bn = V_n h_n* [14a, 14b]: check via a one-mode analysis of each mode's share."""
    system = paper_system()
    result = analyze(system, SmoothSpectrum(), "rigid", SimplifiedOptions(n_modes=1))
    assert result.base_moment == pytest.approx(result.base_shear * system.effective_height, rel=1e-10)


# ----------------------------------------------------------------------------- bonded

def test_effective_properties_paper_values():
    """docs/theory.md section 7: T1bar/T_1 = 1.525, xi_f = 0.0187, xi1bar = 0.0328 for the paper's example."""
    props = effective_properties(paper_system(), "formula")
    assert props["T1bar/T1"] == pytest.approx(1.525, abs=5e-4)
    assert props["xi_f"] == pytest.approx(0.0187, abs=5e-5)
    assert props["xi1bar"] == pytest.approx(0.0328, abs=5e-5)


def characteristic_roots(system):
    """Roots of det(lambda^2 M + lambda C + K) = 0 for the bonded one-mode system (Fig. 2, massless mat),
    expanded by hand: (m s^2 + c s + k)(m h^2 s^2 + C s + K) - (m h s^2)^2."""
    m = float(system.modes.effective_mass[0])
    h = system.effective_height
    w = float(system.modes.omega[0])
    xi = float(system.modes.damping[0])
    b = system.half_width
    big_c = system.foundation.rocking_damping(b)
    big_k = system.foundation.rocking_stiffness(b)
    first = np.poly1d([m, 2 * xi * w * m, w * w * m])
    second = np.poly1d([m * h * h, big_c, big_k])
    coupling = np.poly1d([m * h, 0.0, 0.0])
    return (first * second - coupling * coupling).roots


@pytest.mark.parametrize("period", [0.3, 0.5, 1.0, 2.0])
def test_formula_agrees_with_complex_eigenvalue(period):
    system = paper_system(period=period)
    formula = effective_properties(system, "formula")
    eigen = effective_properties(system, "eigenvalue")
    roots = characteristic_roots(system)
    root = roots[np.argmax(roots.imag)]
    assert eigen["T1bar"] == pytest.approx(2 * np.pi / abs(root), rel=1e-5)  # polynomial roots: ~1e-7
    assert eigen["xi1bar"] == pytest.approx(-root.real / abs(root), rel=1e-5)
    assert formula["T1bar"] == pytest.approx(eigen["T1bar"], rel=0.01)
    assert formula["xi1bar"] == pytest.approx(eigen["xi1bar"], rel=0.01)


def test_bonded_stiff_foundation_tends_to_rigid():
    stiff = paper_system(frequency_ratio=1e4, damping_ratio=0.0)
    bonded = analyze(stiff, SmoothSpectrum(), "bonded")
    rigid = analyze(stiff, SmoothSpectrum(), "rigid")
    np.testing.assert_allclose(bonded.shear, rigid.shear, rtol=1e-6)
    np.testing.assert_allclose(bonded.displacement, rigid.displacement, rtol=1e-6)


def test_winkler_with_same_rocking_properties_as_two_elements_gives_same_bonded_result():
    system = paper_system()
    b = system.half_width
    two = system.foundation
    winkler = Winkler(two.rocking_stiffness(b) * 1.5 / b**3, two.rocking_damping(b) * 1.5 / b**3)
    other = replace(system, foundation=winkler)
    a = analyze(system, SmoothSpectrum(), "bonded")
    c = analyze(other, SmoothSpectrum(), "bonded")
    np.testing.assert_allclose(a.shear, c.shear, rtol=1e-10)
    assert a.intermediates["xi1bar"] == pytest.approx(c.intermediates["xi1bar"], rel=1e-10)


def test_halfspace_properties_are_evaluated_at_the_effective_frequency():
    building = uniform_building(10, 350e3, 3.5, period=1.0)
    system = System(building, HalfSpace(6e7, 0.33, 1900.0, 10.0), 8.0)
    result = analyze(system, SmoothSpectrum(), "bonded")
    omega_bar = 2 * np.pi / result.intermediates["T1bar"]
    expected = system.foundation.rocking_stiffness(8.0, omega_bar)
    assert result.intermediates["K_theta"] == pytest.approx(expected, rel=1e-9)
    assert result.intermediates["C_theta"] == pytest.approx(system.foundation.rocking_damping(8.0, omega_bar), rel=1e-9)
    assert result.intermediates["T1bar/T1"] > 1.0
    assert result.intermediates["xi_f"] > 0.0


# ----------------------------------------------------------------------------- uplift

def spectrum_for_ratio(system, ratio):
    """Constant S_a that makes V_1 bonded = ratio * V_c."""
    return ConstantSpectrum(ratio * system.critical_base_shear / float(system.modes.effective_mass[0]))


def test_no_uplift_below_critical_shear():
    system = paper_system()
    spectrum = spectrum_for_ratio(system, 0.99)
    uplift = analyze(system, spectrum, "uplift")
    bonded = analyze(system, spectrum, "bonded")
    assert uplift.uplift is False
    np.testing.assert_allclose(uplift.shear, bonded.shear, rtol=1e-12)


@pytest.mark.parametrize("factor", ["none", "phase"])
def test_uplift_is_continuous_at_critical_shear(factor):
    """With X consistent with V_1 (mass-consistent) and no quarter-cycle decay assumption, V_1 just
    above V_c gives V_1,max -> V_c, continuous with the no-uplift branch."""
    system = paper_system()
    options = SimplifiedOptions(procedure="paper", uplift_x="mass-consistent", uplift_x_factor=factor)
    below = analyze(system, spectrum_for_ratio(system, 1.0 - 1e-9), "uplift", options)
    above = analyze(system, spectrum_for_ratio(system, 1.0 + 1e-9), "uplift", options)
    assert above.uplift and not below.uplift
    v_c = system.critical_base_shear
    assert above.intermediates["V_n"][0] == pytest.approx(v_c, rel=1e-4)
    assert above.base_shear == pytest.approx(below.base_shear, rel=1e-4)


def test_default_uplift_jump_at_critical_shear_is_small():
    """The default X (spectral, e^(xi pi)) assumes a quarter cycle from the crossing to the peak, which
    is not true at the threshold: the result jumps there. Measured bound: a few per cent of V_c."""
    system = paper_system()
    above = analyze(system, spectrum_for_ratio(system, 1.0 + 1e-9), "uplift", PAPER)
    jump = above.intermediates["V_n"][0] / system.critical_base_shear - 1.0
    assert 0.0 < jump < 0.05


def test_large_mat_does_not_uplift():
    system = paper_system()
    wide = replace(system, half_width=system.half_width * 50)  # same k_f, c_f: stiffer, V_c 50x
    result = analyze(wide, SmoothSpectrum(), "uplift")
    assert result.uplift is False
    assert result.intermediates["V1_bonded/V_c"] < 1.0


def pivot_peak(slenderness, x_value, xi):
    """Brute force: rigid-pivot SDOF (docs/theory.md section 7, derivation of [28a]) in free vibration after
    the uplift crossing: m u'' + (r/b)^2 (c u' + k u) = m g h/b, starting at V = k u = V_c with the
    velocity of a bonded oscillation of amplitude sqrt(X) V_c. Returns max k u / V_c."""
    m, w, b = 1.0, 2 * np.pi, 1.0
    h = slenderness * b
    k, c = m * w * w, 2 * xi * w * m
    ratio2 = (h * h + b * b) / (b * b)
    v_c = m * G * b / h
    u0 = v_c / k
    v0 = w * u0 * math.sqrt(x_value - 1.0)

    def rhs(t, y):
        return [y[1], (m * G * h / b - ratio2 * (c * y[1] + k * y[0])) / m]

    period_uplifted = 2 * np.pi / (w * math.sqrt(ratio2))
    solution = solve_ivp(rhs, (0, period_uplifted), [u0, v0], max_step=period_uplifted / 4000, rtol=1e-10, atol=1e-14)
    return np.max(k * solution.y[0]) / v_c


@pytest.mark.parametrize("slenderness, x_value", [(5.0, 4.0), (10.0, 26.9), (3.0, 1.5)])
def test_uplift_formula_matches_pivoting_oscillator(slenderness, x_value):
    """Undamped: [28a] is exact. Lightly damped: e^(-zeta phi) approximates the decay to 0.5 %."""
    v, _ = uplift_base_shear(1.0, slenderness, x_value, 0.0, "full")
    assert v == pytest.approx(pivot_peak(slenderness, x_value, 0.0), rel=1e-6)
    xi = 0.005
    zeta = xi * math.sqrt(1 + slenderness**2)
    v, _ = uplift_base_shear(1.0, slenderness, x_value, zeta, "full")
    assert v == pytest.approx(pivot_peak(slenderness, x_value, xi), rel=5e-3)


def test_slender_formula_close_to_full_for_slender_buildings():
    for x_value in (2.0, 10.0, 50.0):
        full, _ = uplift_base_shear(1.0, 10.0, x_value, 0.3, "full")
        slender, _ = uplift_base_shear(1.0, 10.0, x_value, 0.3, "slender")
        assert slender == pytest.approx(full, rel=0.02)


def test_uplift_reduces_first_mode_and_reports_intermediates():
    system = paper_system()
    result = analyze(system, SmoothSpectrum(), "uplift", PAPER)
    inter = result.intermediates
    assert result.uplift
    for name in ("T1bar", "xi1bar", "xi_f", "V_c", "V1_bonded", "zeta", "phi", "X", "V1_uplift", "V_n"):
        assert name in inter
    assert inter["V_c"] < inter["V1_uplift"] < inter["V1_bonded"]
    r = math.hypot(system.effective_height, system.half_width)
    assert inter["zeta"] == pytest.approx(inter["xi1bar"] * r / system.half_width)
    xi1 = analyze(system, SmoothSpectrum(), "uplift", SimplifiedOptions(procedure="paper", uplift_damping="xi1"))
    assert xi1.intermediates["zeta"] == pytest.approx(0.05 * r / system.half_width)


def test_winkler_uplift_carries_kern_caveat():
    system = paper_system()
    b = system.half_width
    winkler = Winkler(system.foundation.rocking_stiffness(b) * 1.5 / b**3, 0.0)
    other = replace(system, foundation=winkler)
    result = analyze(other, spectrum_for_ratio(other, 0.5), "uplift", PAPER)
    assert not result.uplift
    assert any("kern" in warning for warning in result.details["warnings"])


# ----------------------------------------------------------------------------- combination

def test_srss_and_cqc_agree_for_well_separated_modes():
    # two stories with very different stiffness: w_2/w_1 about 14
    building = shear_building([1e5, 1e5], [3.0, 3.0], [1e7, 1e10], damping=0.05)
    system = System(building, TwoElement(1e9, 1e6), 3.0)
    for support in ("rigid", "bonded", "uplift"):
        srss = analyze(system, SmoothSpectrum(), support, SimplifiedOptions(combination="srss"))
        cqc = analyze(system, SmoothSpectrum(), support, SimplifiedOptions(combination="cqc"))
        np.testing.assert_allclose(cqc.shear, srss.shear, rtol=1e-3)
        np.testing.assert_allclose(cqc.displacement, srss.displacement, rtol=1e-3)
    paper = paper_system()
    srss = analyze(paper, SmoothSpectrum(), "rigid")
    cqc = analyze(paper, SmoothSpectrum(), "rigid", SimplifiedOptions(combination="cqc"))
    np.testing.assert_allclose(cqc.shear, srss.shear, rtol=0.02)


def test_srss_and_cqc_limits():
    peaks = np.array([[3.0, -1.0], [4.0, 2.0]])
    np.testing.assert_allclose(srss(peaks), [5.0, np.sqrt(5.0)])
    # identical frequencies and damping: fully correlated, the algebraic sum
    np.testing.assert_allclose(cqc(peaks, np.array([10.0, 10.0]), 0.05), [7.0, 1.0])
    # far apart: uncorrelated, SRSS
    np.testing.assert_allclose(cqc(peaks, np.array([1.0, 1000.0]), 0.05), srss(peaks), rtol=1e-4)
    rho = cqc_correlation(np.array([10.0, 11.0]), np.array([0.05, 0.05]))
    # Der Kiureghian, equal damping: rho = 8 xi^2 (1 + r) r^1.5 / ((1 - r^2)^2 + 4 xi^2 r (1 + r)^2)
    r, xi = 1.1, 0.05
    expected = 8 * xi**2 * (1 + r) * r**1.5 / ((1 - r**2) ** 2 + 4 * xi**2 * r * (1 + r) ** 2)
    assert rho[0, 1] == pytest.approx(expected, rel=1e-12)


def test_floor_accelerations_are_modal_pseudo_accelerations_combined():
    """a_jn = Gamma_n phi_jn S_a(T_n, xi_n), combined by SRSS over the modes (rigid base)."""
    system = paper_system(1.0)
    result = analyze(system, ConstantSpectrum(3.0), "rigid")
    modes = system.modes
    modal = modes.participation_h[None, :] * modes.shapes * 3.0  # (floors, modes), Gamma phi S_a
    np.testing.assert_allclose(result.peaks["floor_acceleration"], np.sqrt((modal**2).sum(axis=1)), rtol=1e-12)


def test_reactions_are_the_statics_of_the_weight_and_the_base_moment():
    system = paper_system(1.0)
    weight, b = system.weight, system.half_width
    bonded = analyze(system, ConstantSpectrum(3.0), "bonded")
    np.testing.assert_allclose(bonded.peaks["reaction"], weight / 2 + bonded.base_moment / (2 * b), rtol=1e-12)
    uplift = analyze(system, ConstantSpectrum(30.0), "uplift")
    assert uplift.uplift and uplift.base_moment > system.critical_base_moment
    np.testing.assert_allclose(uplift.peaks["reaction"], [weight, weight], rtol=1e-12)  # the mat tips
    assert analyze(system, ConstantSpectrum(3.0), "rigid").peaks["reaction"].size == 0


# ----------------------------------------------------------------------------- bearing capacity

def with_capacity(system, capacity):
    """The system with each of its two elements given the capacity Q_y [N]."""
    return replace(system, foundation=replace(system.foundation, capacity=capacity))


@pytest.mark.parametrize("procedure", ["paper", "improved"])
def test_a_capacity_never_reached_gives_the_elastic_result(procedure):
    """FS_v >= 2 on two elements: M_c = W b, the same V_c, the same peaks bit for bit (docs/theory.md 14.4)."""
    system = paper_system(0.5)
    options = SimplifiedOptions(procedure=procedure)
    elastic = analyze(system, SmoothSpectrum(), "uplift", options)
    strong = analyze(with_capacity(system, 10.0 * system.weight), SmoothSpectrum(), "uplift", options)
    assert strong.critical_base_shear == elastic.critical_base_shear
    for name, values in elastic.peaks.items():
        assert np.array_equal(strong.peaks[name], values), name
    assert strong.intermediates["FS_v"] == 20.0 and strong.intermediates["M_tip"] == system.tipping_moment


def test_the_paper_procedure_uses_the_critical_shear_of_the_capacity():
    """V_c = M_c / h_1* with M_c = W b (FS_v - 1) for FS_v = 1.4: X0 = (m_t S_a1bar / V_c)^2 and
    V_1 by [28a] with that V_c; the reactions at most Q_y."""
    system = with_capacity(paper_system(0.5), 0.7 * paper_system(0.5).weight)
    result = analyze(system, SmoothSpectrum(), "uplift", PAPER)
    inter = result.intermediates
    v_c = 0.4 * system.weight * system.half_width / system.effective_height
    assert inter["V_c"] == pytest.approx(v_c, rel=1e-14)
    assert inter["M_c"] == pytest.approx(v_c * system.effective_height, rel=1e-14)
    assert inter["X0"] == pytest.approx((system.total_mass * inter["Sa1bar"] / v_c) ** 2, rel=1e-12)
    expected, _ = uplift_base_shear(v_c, system.effective_height / system.half_width, inter["X"], inter["zeta"])
    assert inter["V1_uplift"] == pytest.approx(expected, rel=1e-12)
    assert result.uplift and inter["Q_y"] == 0.7 * system.weight
    assert np.all(result.reaction <= inter["Q_y"] * (1 + 1e-12))
    elastic = analyze(paper_system(0.5), SmoothSpectrum(), "uplift", PAPER)
    assert inter["V1_uplift"] < elastic.intermediates["V1_uplift"]


def test_improved_winkler_capacity_is_the_backbone_at_the_bonded_rotation():
    """A Winkler capacity whose toe yields only past the bonded rotation (theta = FS_v^2 W/(8 k_w b^2)
    against 1.5 x W/(k_w b^2), x = V_1/V_c: FS_v = 20 here) gives the elastic strip's effective
    moment, hence the same mode-1 base shear; FS_v = 3 and 1.3 lower it."""
    base = paper_system(0.5)
    b = base.half_width
    strip = Winkler(3.0 * base.foundation.stiffness / b, 3.0 * base.foundation.damping / b)  # same K_theta
    elastic = replace(base, foundation=strip)
    results = {}
    for fs in (None, 20.0, 3.0, 1.3):
        foundation = strip if fs is None else replace(strip, capacity=fs * base.weight / (2.0 * b))
        results[fs] = analyze(replace(elastic, foundation=foundation), SmoothSpectrum(), "uplift").intermediates
    assert results[20.0]["V1_uplift"] == pytest.approx(results[None]["V1_uplift"], rel=1e-12)
    assert results[20.0]["capacity"] * results[20.0]["M_c"] == pytest.approx(
        results[None]["capacity"] * results[None]["M_c"], rel=1e-12)
    assert results[1.3]["V1_uplift"] < results[3.0]["V1_uplift"] < results[None]["V1_uplift"]
