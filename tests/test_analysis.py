"""The analysis runner: dispatch over engines x supports and the acceptance criteria."""

from pathlib import Path

import numpy as np
import pytest

from upliftcli.analysis import check_criteria, run, run_one
from upliftcli.deck import load_deck
from upliftcli.engines.simplified import analyze as simplified_analyze
from upliftcli.errors import InputError

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"


@pytest.fixture(scope="module")
def deck():
    return load_deck(EXAMPLE)


def test_run_every_support_in_order(deck):
    results = run(deck)
    assert [(r.engine, r.support) for r in results] == [("simplified", s) for s in ("rigid", "bonded", "uplift")]
    direct = simplified_analyze(deck.system, deck.spectrum, "bonded", deck.analysis.simplified)
    np.testing.assert_array_equal(results[1].shear, direct.shear)
    assert [r.support for r in run(deck, supports="uplift")] == ["uplift"]


def test_time_history_engines_need_a_record(deck):
    class Spectrum:
        def sa(self, periods, damping):
            return np.ones(np.shape(periods))

    deck_with_spectrum = type(deck)(**{**deck.__dict__, "ground_motion": Spectrum(), "spectrum": Spectrum()})
    with pytest.raises(InputError, match="a record for the exact engine"):
        run_one(deck_with_spectrum, "exact", "uplift")
    with pytest.raises(InputError, match="analysis.engine"):
        run_one(deck, "fancy", "uplift")


def test_criteria(deck):
    results = run(deck)
    worst_drift = max(float(max(r.drift_ratio)) for r in results)
    assert check_criteria(results, {"drift_ratio": worst_drift * 1.001}) == []
    messages = check_criteria(results, {"drift_ratio": worst_drift * 0.999})
    assert len(messages) == 1 and "simplified/rigid: drift_ratio" in messages[0]
    messages = check_criteria(results, {"uplift": False, "base_shear_coefficient": 0.3})
    assert any("lifts off" in m for m in messages)
    assert sum("base_shear_coefficient" in m for m in messages) == 2  # rigid 0.78, bonded 0.42 > 0.3 > uplift 0.15
    assert check_criteria(results, {"uplift": True}) == []


def test_criteria_on_floor_accelerations_and_reactions(deck):
    """Every quantity of engines/quantities.py with criterion=True is a [criteria] field."""
    results = run(deck)
    accel = max(float(r.floor_acceleration.max()) for r in results)
    reaction = max(float(r.reaction.max(initial=0.0)) for r in results)
    assert check_criteria(results, {"floor_acceleration": accel * 1.001, "reaction": reaction * 1.001}) == []
    messages = check_criteria(results, {"floor_acceleration": accel * 0.999, "reaction": reaction * 0.999})
    assert any("floor_acceleration" in m and "[m/s^2]" in m for m in messages)
    assert any("reaction" in m and "[N]" in m for m in messages)
    deck_with_limit = load_deck(EXAMPLE, ["criteria.floor_acceleration=1.0"])
    assert deck_with_limit.criteria == {"drift_ratio": 0.02, "floor_acceleration": 1.0}
