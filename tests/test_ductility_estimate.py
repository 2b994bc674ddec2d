"""The R-mu-T estimate of the ductility (engines/ductility_estimate.py, docs/theory.md 15.6): the
closed forms of Vidic, Fajfar & Fischinger (1994) and of the N2 method (Fajfar 2000), their
limiting cases, and the story and roof ratios built on them."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest

from upliftcli.analysis import run as analysis
from upliftcli.deck.load import load_deck
from upliftcli.engines import ductility_estimate as est


def test_vidic_strength_ratio_matches_the_papers_closed_form_in_both_ranges():
    # mu = 4, T_c = 0.5 s: T_0 = 0.75 * 4^0.2 * 0.5 = 0.49482 s
    t0 = 0.75 * 4.0 ** 0.2 * 0.5
    assert t0 == pytest.approx(0.494815, rel=1e-5)
    # T = 1 s > T_0: R = 1 + 1.1 * 3^0.95 = 4.12362
    assert est.vidic_strength_ratio(4.0, 1.0, 0.5) == pytest.approx(4.123618, rel=1e-6)
    # T = 0.2 s < T_0: R = 1 + 1.1 * 3^0.95 * 0.2 / T_0 = 2.26254
    assert est.vidic_strength_ratio(4.0, 0.2, 0.5) == pytest.approx(2.262538, rel=1e-6)


@pytest.mark.parametrize("period", [0.05, 0.3, 0.5, 1.0, 3.0])
@pytest.mark.parametrize("ratio", [1.2, 2.0, 4.0, 8.0])
def test_vidic_ductility_inverts_the_strength_ratio(ratio, period):
    mu = est.vidic_ductility(ratio, period, 0.5)
    assert mu > 1.0
    assert est.vidic_strength_ratio(mu, period, 0.5) == pytest.approx(ratio, rel=1e-10)


def test_vidic_ductility_at_long_periods_is_the_closed_form_inverse():
    # T >= T_0: mu = 1 + ((R - 1) / 1.1)^(1 / 0.95); R = 4: 1 + (3 / 1.1)^(1.052632) = 3.87516
    expected = 1.0 + (3.0 / 1.1) ** (1.0 / 0.95)
    assert expected == pytest.approx(3.87516, rel=1e-5)
    assert est.vidic_ductility(4.0, 2.0, 0.5) == pytest.approx(expected, rel=1e-12)


def test_vidic_is_continuous_at_t0():
    t0 = 0.75 * 3.0 ** 0.2 * 0.6
    below = est.vidic_strength_ratio(3.0, t0 * (1 - 1e-12), 0.6)
    above = est.vidic_strength_ratio(3.0, t0 * (1 + 1e-12), 0.6)
    assert below == pytest.approx(above, rel=1e-10)


@pytest.mark.parametrize("relation", sorted(est.RELATIONS))
def test_r_of_one_is_a_ductility_of_one_and_an_elastic_ratio_is_itself(relation):
    for period in (0.05, 0.5, 2.0):
        assert est.ductility(1.0, period, 0.5, relation) == 1.0
        assert est.ductility(0.4, period, 0.5, relation) == 0.4


def test_fajfar_is_equal_displacement_from_the_corner_on_and_the_n2_line_below():
    assert est.fajfar_ductility(3.0, 0.5, 0.5) == 3.0
    assert est.fajfar_ductility(3.0, 4.0, 0.5) == 3.0
    # T = T_c / 2: mu = (3 - 1) * 2 + 1 = 5
    assert est.fajfar_ductility(3.0, 0.25, 0.5) == pytest.approx(5.0, rel=1e-15)


def test_both_relations_tend_to_equal_displacements_at_long_periods():
    assert est.fajfar_ductility(6.0, 50.0, 0.5) == 6.0
    # Vidic's bilinear row: c_1 = 1.1, c_R = 0.95, close to but not exactly mu = R
    assert est.vidic_ductility(6.0, 50.0, 0.5) == pytest.approx(6.0, rel=0.1)


def test_short_periods_need_more_ductility_for_the_same_reduction():
    for relation in est.RELATIONS:
        mus = [est.ductility(3.0, t, 0.5, relation) for t in (0.1, 0.2, 0.4, 0.8)]
        assert all(a >= b for a, b in itertools.pairwise(mus))
        assert mus[0] > 3.0


def test_characteristic_period_of_a_record():
    # El Centro 1940 N-S: PGA 3.13 m/s^2, PGV 0.335 m/s -> 2 pi 2.0 0.335 / (2.5 3.13) = 0.5380 s
    assert est.characteristic_period(3.13, 0.335) == pytest.approx(
        2.0 * math.pi * 2.0 * 0.335 / (2.5 * 3.13), rel=1e-15)
    assert est.characteristic_period(3.13, 0.335) == pytest.approx(0.53799, rel=1e-4)


def test_story_ratios_and_ductilities():
    shears = np.array([6e6, 3e6, 1e6])
    strengths = np.array([2e6, 2e6, 2e6])
    assert est.strength_ratios(-shears, strengths).tolist() == [3.0, 1.5, 0.5]
    mus = est.story_ductilities(shears, strengths, 1.0, 0.5, "fajfar2000")
    assert mus.tolist() == [3.0, 1.5, 0.5]


def test_roof_ductility_is_the_displacement_ratio_times_r():
    # elastic roof 0.2 m, inelastic 0.25 m, R_b = 4: the yield roof displacement is 0.05 m, mu = 5
    assert est.roof_ductility(0.25, 0.2, 4.0) == pytest.approx(5.0, rel=1e-15)


@pytest.mark.parametrize("call", [
    lambda: est.ductility(2.0, 1.0, 0.5, "newmark"),
    lambda: est.ductility(2.0, 0.0, 0.5),
    lambda: est.ductility(-1.0, 1.0, 0.5),
    lambda: est.characteristic_period(0.0, 1.0),
    lambda: est.strength_ratios([1.0, 2.0], [1.0]),
    lambda: est.roof_ductility(0.1, 0.0, 2.0),
])
def test_bad_values_are_refused(call):
    with pytest.raises(ValueError):
        call()


def test_a_building_that_stays_elastic_is_estimated_exactly_from_the_exact_elastic_demand():
    # a strength never reached: the exact story ductility is peak |V_j| / V_yj = R_j, which every
    # relation returns unchanged for R <= 1 (benchmarks/ductility_estimate.py relies on it)
    deck = Path(__file__).resolve().parents[1] / "inputs" / "ten_story_elcentro.toml"
    elastic = analysis.run_one(load_deck(deck, []), "exact", "rigid")
    strong = load_deck(deck, ["building.strength_coefficient=3"])
    result = analysis.run_one(strong, "exact", "rigid")
    strengths = strong.system.building.story_strength
    assert result.peaks["yielded_stories"][0] == 0
    for relation in est.RELATIONS:
        estimate = est.story_ductilities(elastic.peaks["shear"], strengths, 0.5, 0.54, relation)
        assert np.all(estimate < 1.0)
        assert estimate == pytest.approx(result.peaks["ductility"], rel=1e-9)
