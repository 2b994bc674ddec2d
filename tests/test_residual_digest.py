"""The twin of a yielding run folds its residuals and energy balance only (engines/exact/residual_digest.py,
docs/theory.md 15.8): its residual drift ratios, residual mat rotation and residual settlements, and the
energy residual the step's refinement decides by, are those of a twin folded in full, bit for bit, on
every support, on yielding soil, on the numpy loops and where the twin's step is refined; the check of
the residuals (details["residual_check"], the warnings) is the same as with full twins, for one record and
for a suite."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from test_operator_reuse import same
from test_residual_check import weak_story_suite

from upliftcli.analysis import residuals
from upliftcli.analysis import run as analysis
from upliftcli.deck.load import load_deck
from upliftcli.engines.exact import engine as exact
from upliftcli.engines.exact import reuse, stepping
from upliftcli.engines.exact.digest import Digest
from upliftcli.engines.exact.residual_digest import ResidualDigest

ROOT = Path(__file__).resolve().parent.parent
TWO = ROOT / "inputs" / "ten_story_elcentro.toml"
WINKLER = ROOT / "inputs" / "ten_story_winkler.toml"
STORIES = ("ground_motion.scale=2", "building.strength_coefficient=0.4", "building.hardening_ratio=0.05")
#: issue 35's reproducer: soil that yields under a mat without a dashpot
FRAGILE = ("foundation.damping_ratio=0", "foundation.safety_factor=1.98")


def _twins(overrides, support, path=TWO):
    """(the twin with its original's operators, residuals only; the twin run alone, in full) of a deck."""
    deck = load_deck(path, list(overrides))
    options, twin = deck.analysis.exact, residuals.perturbed_motion(deck.ground_motion)
    store = reuse.OperatorStore()
    exact.analyze(deck.system, deck.ground_motion, support, options, operators=store)
    return (exact.analyze(deck.system, twin, support, options, operators=store.twins()),
            exact.analyze(deck.system, twin, support, options))


def _same_residuals(lean, full) -> None:
    """The lean twin holds exactly the residuals of FLOORS the full one has, each equal bit for bit."""
    names = [name for name in residuals.FLOORS if name in full.peaks]
    assert names and sorted(lean.peaks) == sorted(names)
    for name in names:
        assert lean.peaks[name].dtype == full.peaks[name].dtype and same(lean.peaks[name], full.peaks[name])


@pytest.mark.parametrize(("overrides", "support", "loops", "path"), [
    (STORIES, "rigid", "auto", TWO), (STORIES, "bonded", "auto", TWO), (STORIES, "uplift", "auto", TWO),
    (STORIES, "uplift", "numpy", TWO), ((*STORIES, *FRAGILE), "uplift", "auto", TWO), (FRAGILE, "uplift", "numpy", TWO),
    (("foundation.safety_factor=1.5",), "uplift", "auto", WINKLER)])
def test_a_twins_residuals_and_energy_residual_are_those_of_a_full_twin(overrides, support, loops, path,
                                                                          monkeypatch):
    """Yielding stories on every support, stories on yielding soil, yielding soil alone (issue 35's
    reproducer; a Winkler mat of 20 elements at FS_v = 1.5), compiled and numpy loops: the same residuals and
    energy balance, bit for bit."""
    monkeypatch.setenv("UPLIFT_BACKEND", loops)
    lean, full = _twins(overrides, support, path)
    _same_residuals(lean, full)
    assert lean.intermediates == {"energy_residual": full.intermediates["energy_residual"]}
    assert same(lean.details["energy"], full.details["energy"])
    assert lean.uplift == full.uplift


@pytest.mark.parametrize("overrides", [STORIES, (*STORIES, *FRAGILE)])
def test_a_twin_stepped_in_chunks_folds_them_as_a_full_twin(overrides, monkeypatch):
    """Several chunks a run (stepping.CHUNK_SAMPLES = 700 of about 3400 samples): the work integrals
    summed, the first and last stored energies, the last drifts and mat values as the full digest's."""
    monkeypatch.setattr(stepping, "CHUNK_SAMPLES", 700)
    lean, full = _twins(overrides, "uplift")
    assert full.intermediates["samples"] > 3 * 700
    _same_residuals(lean, full)
    assert lean.intermediates == {"energy_residual": full.intermediates["energy_residual"]}
    assert same(lean.details["energy"], full.details["energy"])


def test_a_twin_whose_balance_does_not_close_is_refined_as_a_full_twin_is(monkeypatch):
    """With a tolerance below the twin's energy residual, the lean twin's step is refined as the full twin's
    (the refined run is an ordinary one): the same step and the same residuals."""
    lean, full = _twins(STORIES, "uplift")
    monkeypatch.setattr(exact, "ENERGY_TOLERANCE", full.intermediates["energy_residual"] / 3)
    lean, full = _twins(STORIES, "uplift")
    assert lean.intermediates["steps_per_period"] == full.intermediates["steps_per_period"] > 6
    for name in residuals.FLOORS:
        assert same(lean.peaks[name], full.peaks[name])


def test_only_twins_fold_their_residuals_alone():
    """An original run (a store's or none) is folded in full, its twin residuals only."""
    store = reuse.OperatorStore()
    assert reuse.digest_for(None) is Digest and reuse.digest_for(store) is Digest
    assert reuse.digest_for(store.twins()) is ResidualDigest


def _check_both_ways(monkeypatch, run) -> tuple:
    """run() with lean twins, then with full ones (reuse.Twins.residuals_only False)."""
    lean = run()
    monkeypatch.setattr(reuse.Twins, "residuals_only", False)
    return lean, run()


@pytest.mark.parametrize("support", ["rigid", "uplift"])
def test_the_check_of_the_residuals_is_the_same_with_full_twins(support, monkeypatch):
    """analysis.run_one on yielding stories over yielding soil (a sensitive residual: a warning on the
    uplift support): the results with details["residual_check"] and the warnings as with full twins."""
    deck = load_deck(TWO, [*STORIES, *FRAGILE])
    lean, full = _check_both_ways(monkeypatch, lambda: analysis.run_one(deck, "exact", support))
    assert "residual_check" in lean.details and same(lean, full)
    assert lean.details["residual_check"]["sensitive"] == (support == "uplift")


def test_a_suites_check_is_the_same_with_full_twins(tmp_path, monkeypatch):
    """A two-record suite with weak stories: each record's check as with full twins (whose suite results
    the check never read beyond their records')."""
    loaded = weak_story_suite(tmp_path)
    lean, full = _check_both_ways(monkeypatch, lambda: analysis.run_one(loaded, "exact", "rigid"))
    check = lean.details["residual_check"]
    assert len(check["records"]) == 2 and same(lean, full)
    assert np.isfinite(check["records"][0]["quantities"]["residual_drift_ratio"]["twin"]).all()
