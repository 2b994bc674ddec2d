"""One foundation model for every engine (model/interaction.py): the impedance frequency, the
fixed point and its failure, and the same K_theta, C_theta in the simplified and exact engines."""

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pytest
from paper_example import paper_system

from upliftcli.deck.load import load_deck
from upliftcli.engines import simplified
from upliftcli.engines.exact import engine as exact
from upliftcli.engines.exact.modal import modal_model
from upliftcli.engines.options import ExactOptions
from upliftcli.model.foundations import TwoElement
from upliftcli.model.interaction import effective_properties, effective_properties_formula
from upliftcli.motion.records import Record

INPUTS = Path(__file__).resolve().parents[1] / "inputs"


def halfspace_system():
    return load_deck(INPUTS / "frame_halfspace.toml", load_ground_motion=False).system


def test_halfspace_impedance_is_at_the_flexible_base_frequency():
    """omega_impedance = 2 pi / T1bar(K_theta(omega_impedance)): a fixed point (the same formula evaluated
    again at the frequency found: a check of the iteration, not of the formula)."""
    system = halfspace_system()
    props = effective_properties(system)
    omega = props["omega_impedance"]
    again = effective_properties_formula(system, omega)
    assert 2 * math.pi / again["T1bar"] == pytest.approx(omega, rel=1e-10)
    b = system.half_width
    assert props["K_theta"] == pytest.approx(system.foundation.rocking_stiffness(b, omega), rel=1e-14)
    assert props["C_theta"] == pytest.approx(system.foundation.rocking_damping(b, omega), rel=1e-14)
    assert props["k_element"] == pytest.approx(props["K_theta"] / (2 * b**2), rel=1e-14)
    assert omega < 0.9 * float(system.modes.omega[0])  # the soft soil lengthens the period


def test_fixed_base_option_evaluates_at_w1():
    system = halfspace_system()
    fixed = replace(system, foundation=replace(system.foundation, impedance_frequency="fixed-base"))
    w1 = float(system.modes.omega[0])
    props = effective_properties(fixed)
    assert props["omega_impedance"] == w1
    assert props["K_theta"] == fixed.foundation.rocking_stiffness(fixed.half_width, w1)
    elements = modal_model(fixed, "bonded", 3).elements
    expected = fixed.foundation.contact_elements(fixed.half_width, w1)
    np.testing.assert_array_equal(elements.stiffness, expected.stiffness)
    np.testing.assert_array_equal(elements.damping, expected.damping)


def short_record():
    t = np.arange(0.0, 4.0, 0.01)
    return Record("pulse", 0.01, 2.0 * np.sin(2 * np.pi * 1.3 * t) * np.exp(-0.5 * t))


def test_simplified_mode_1_and_exact_single_mode_use_the_same_impedance():
    """Bonded support: the simplified engine's K_theta, C_theta and the exact engine's, with one
    mode, are the same numbers; and the exact one-mode model's elements vibrate at T1bar and
    xi1bar of the eigenvalue form of Eqs. 21-25 evaluated at that frequency."""
    system = halfspace_system()
    record = short_record()
    from upliftcli.motion.spectra import RecordSpectrum

    simple = simplified.analyze(system, RecordSpectrum(record), "bonded")
    history = exact.analyze(system, record, "bonded", ExactOptions(n_modes=1))
    for name in ("K_theta", "C_theta", "omega_impedance", "k_element", "c_element"):
        assert history.intermediates[name] == pytest.approx(simple.intermediates[name], rel=1e-12), name
    model = modal_model(system, "bonded", 1)
    b = system.half_width
    assert float(np.sum(model.elements.stiffness * model.elements.positions**2)) == pytest.approx(
        simple.intermediates["K_theta"], rel=1e-12)
    assert float(np.sum(model.elements.damping * model.elements.positions**2)) == pytest.approx(
        simple.intermediates["C_theta"], rel=1e-12)
    # the one-mode bonded system of paper Fig. 2 (massless mat), hand-expanded characteristic polynomial
    m, h = float(system.modes.effective_mass[0]), system.effective_height
    w, xi = float(system.modes.omega[0]), float(system.modes.damping[0])
    big_k = 2 * model.elements.stiffness[0] * b**2
    big_c = 2 * model.elements.damping[0] * b**2
    poly = np.poly1d([m, 2 * xi * w * m, w * w * m]) * np.poly1d([m * h * h, big_c, big_k]) \
        - np.poly1d([m * h, 0, 0]) ** 2
    root = max(poly.roots, key=lambda r: r.imag)
    from upliftcli.model.interaction import effective_properties_eigenvalue

    eigen = effective_properties_eigenvalue(system, simple.intermediates["omega_impedance"])
    assert eigen["T1bar"] == pytest.approx(2 * math.pi / abs(root), rel=1e-6)


def test_every_engine_reports_the_foundation_model():
    """Two elements at +-b: K_theta = 2 k_f b^2 [22], C_theta = 2 c_f b^2 [25], at any frequency."""
    system = paper_system(period=0.8)
    b, foundation = system.half_width, system.foundation
    record = short_record()
    for engine in ("exact", "approximate"):
        module = exact if engine == "exact" else __import__("upliftcli.engines.approximate", fromlist=["x"])
        result = module.analyze(system, record, "uplift")
        assert result.intermediates["k_element"] == pytest.approx(system.foundation.stiffness, rel=1e-14)
        assert result.intermediates["c_element"] == pytest.approx(system.foundation.damping, rel=1e-14)
        assert result.intermediates["K_theta"] == pytest.approx(2 * foundation.stiffness * b**2, rel=1e-12)
        assert result.intermediates["C_theta"] == pytest.approx(2 * foundation.damping * b**2, rel=1e-12)


@dataclass(frozen=True)
class SteepFoundation(TwoElement):
    """Two elements whose rocking stiffness falls steeply with frequency: K(w) = K_0 (w_0/w)^p.
    The map w -> 2 pi/T1bar(K(w)) has slope below -1 at its fixed point: plain iteration oscillates."""

    reference: float = 1.0
    power: float = 8.0

    def rocking_stiffness(self, b, omega=None):
        scale = 1.0 if omega is None else (self.reference / omega) ** self.power
        return 2.0 * self.stiffness * b**2 * scale


@dataclass(frozen=True)
class SwitchFoundation(TwoElement):
    """K jumps from a stiff to a soft value at w = switch: no fixed point exists."""

    switch: float = 1.0

    def rocking_stiffness(self, b, omega=None):
        soft = omega is not None and omega > self.switch
        return 2.0 * self.stiffness * b**2 * (0.01 if soft else 1.0)


def test_oscillating_iteration_is_resolved_by_the_bracketed_search():
    base = paper_system(period=1.0)
    w1 = float(base.modes.omega[0])
    foundation = SteepFoundation(base.foundation.stiffness, base.foundation.damping, reference=0.65 * w1, power=8.0)
    system = replace(base, foundation=foundation)
    w = w1
    for _ in range(400):  # the plain fixed-point iteration does not settle
        w = 2 * math.pi / effective_properties_formula(system, w)["T1bar"]
    assert abs(2 * math.pi / effective_properties_formula(system, w)["T1bar"] - w) > 1e-3 * w
    props = effective_properties(system)
    assert props["frequency_converged"]
    omega = props["omega_impedance"]
    assert 2 * math.pi / effective_properties_formula(system, omega)["T1bar"] == pytest.approx(omega, rel=1e-9)


def test_no_fixed_point_gives_the_values_reached_and_a_warning():
    base = paper_system(period=1.0)
    w1 = float(base.modes.omega[0])
    stiff = effective_properties_formula(base, None)
    # stiff branch gives w1bar = w1/1.525 > switch; soft branch gives far below the switch
    system = replace(base, foundation=SwitchFoundation(base.foundation.stiffness, base.foundation.damping,
                                                         switch=0.5 * (2 * math.pi / stiff["T1bar"])))
    props = effective_properties(system)
    assert not props["frequency_converged"]
    assert 0.0 < props["omega_impedance"] <= w1

    class Flat:
        def sa(self, periods, damping):
            return np.full(np.shape(np.atleast_1d(periods)), 3.0)

    result = simplified.analyze(system, Flat(), "bonded")
    (line,) = [w for w in result.details["warnings"] if "did not converge" in w]
    assert f"T1bar = {result.intermediates['T1bar']:.4g} s" in line and "impedance_frequency" in line
    assert "frequency_converged" not in result.intermediates
