"""The significant-duration model of Afshari & Stewart (2016) (motion/durations.py) and the
envelopes drawn from it (motion/envelopes.py, issue 36)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from upliftcli.motion.code_spectra import ASCE7Spectrum, EC8Spectrum
from upliftcli.motion.durations import Scenario, draw_duration, median_duration, sigmas
from upliftcli.motion.envelopes import default_scenario, draw_envelope, site_vs30


def test_small_magnitude_case_by_hand_from_the_equations():
    """M 5.0 (below M_1 = 5.2), strike-slip, R_rup 5 km, Vs30 760 m/s, D5-95: Eq. 4 gives F_E = b_0 =
    2.302 s, Eq. 7 F_P = c_1 R = 0.3165 x 5 = 1.5825 s, Eq. 8 F_S = c_4 ln(min(760, V_1 = 600) /
    V_ref) = -0.3183 ln(600 / 369.9); Eq. 3: D = (F_E + F_P) exp(F_S) (Table 3's coefficients)."""
    expected = (2.302 + 0.3165 * 5.0) * math.exp(-0.3183 * math.log(600.0 / 369.9))
    assert median_duration(Scenario(5.0, 5.0, 760.0, "SS")) == pytest.approx(expected, rel=1e-12)
    assert expected == pytest.approx(3.3302, abs=1e-4)


@pytest.mark.parametrize(("scenario", "medians", "sigma"), [
    (Scenario(7.0, 20.0, 400.0, "SS"), (7.2954, 15.6851, 5.7961), (0.4802, 0.3982, 0.4885)),
    (Scenario(6.5, 30.0, 400.0, "NS"), (7.2898, 15.3953, 6.7110), (0.4965, 0.4301, 0.5408)),
    (Scenario(7.5, 20.0, 250.0, "RS"), (9.5965, 21.1641, 11.2529), (0.4802, 0.3982, 0.4885)),
    (Scenario(7.6, 100.0, 300.0, "RS"), (17.4131, 36.9546, 17.4521), (0.4802, 0.3982, 0.4885)),
    (Scenario(5.6, 60.0, 700.0, "NS"), (7.1913, 15.2640, 5.2950), (0.5626, 0.4700, 0.5969)),
])
def test_medians_and_sigmas_agree_with_an_independent_implementation(scenario, medians, sigma):
    """The values of pyGMM 0.8.0's AfshariStewart2016 (A. Kottke's implementation of the paper's
    Eqs. 3-9 and Table 3, written independently of this one), for D5-75, D5-95 and D20-80."""
    for measure, median, total in zip(("D5-75", "D5-95", "D20-80"), medians, sigma, strict=True):
        assert median_duration(scenario, measure) == pytest.approx(median, abs=1e-4)
        assert math.hypot(*sigmas(scenario.magnitude, measure)) == pytest.approx(total, abs=1e-4)


def test_drawn_durations_are_lognormal_about_the_median():
    rng = np.random.default_rng(3)
    scenario = Scenario(7.0, 15.0, 400.0)
    draws = np.log([draw_duration(rng, scenario) for _ in range(4000)])
    assert np.exp(np.median(draws)) == pytest.approx(median_duration(scenario), rel=0.03)
    assert np.std(draws) == pytest.approx(math.hypot(0.19, 0.35), rel=0.05)


def test_the_default_scenario_follows_the_spectrum_level_and_site():
    firm = default_scenario(ASCE7Spectrum(1.0, 0.6, 8.0))
    assert (firm.magnitude, firm.distance) == (7.0, 15.0) and 450.0 < firm.vs30 < 650.0
    low = default_scenario(ASCE7Spectrum(0.3, 0.15, 8.0))
    assert (low.magnitude, low.distance) == (6.5, 30.0)
    assert site_vs30(EC8Spectrum(0.3, "D")) == 160.0 and site_vs30(EC8Spectrum(0.3, "A")) == 900.0


def test_envelopes_are_reproducible_and_vary_within_a_suite():
    scenario = Scenario(7.0, 15.0, 400.0)
    first = [draw_envelope(5, k, scenario, 0.0, 10.0) for k in range(11)]
    assert first == [draw_envelope(5, k, scenario, 0.0, 10.0) for k in range(11)]
    durations = [e.d5_95 for e in first]
    assert max(durations) >= 1.6 * min(durations)
    assert min(e.d5_95 for e in (draw_envelope(5, k, scenario, 10.0, 10.0) for k in range(11))) >= 10.0 - 1e-9
