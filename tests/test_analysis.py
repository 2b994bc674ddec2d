"""The analysis runner: dispatch over engines x supports, the checks before running."""

from pathlib import Path

import numpy as np
import pytest

from upliftcli.analysis import run, run_one
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
    with pytest.raises(InputError, match=r"analysis\.engine"):
        run_one(deck, "fancy", "uplift")


# ----------------------------------------------------------------------------- checks before running (issue 13)

WINKLER = ROOT / "inputs" / "ten_story_winkler.toml"


def test_a_derived_damping_ratio_names_the_deck_field_not_the_record():
    """Foundation fields giving an effective damping xi1bar >= 1 [23] are the deck's mistake:
    the field is named (--set first), never the record file."""
    for path, override, field in ((WINKLER, "foundation.k_w=1e6", "foundation.k_w"),
                                  (EXAMPLE, "foundation.c_f=1e10", "foundation.c_f")):
        deck = load_deck(path, [override])
        with pytest.raises(InputError) as info:
            run(deck)
        assert (info.value.source, info.value.location) == ("--set", field)
        assert "effective damping ratio xi1bar in [0, 1) [23]" in info.value.expected
        assert "elcentro" not in str(info.value)
    # with the damping from the deck file itself, the deck file is named
    deck = load_deck(EXAMPLE, ["foundation.damping_ratio=0.4"])
    assert deck.blame("foundation.damping_ratio") == ("--set", "foundation.damping_ratio")


def test_a_period_the_record_cannot_resolve_is_refused_with_the_field():
    deck = load_deck(EXAMPLE, ["building.period=1e-20"])
    with pytest.raises(InputError, match=r"^--set: building.period: periods of at least 8e-06 s or 0 .* \(modal "
                                         r"periods\)$"):
        run(deck)


def test_steps_x_states_are_estimated_before_the_exact_engine_allocates(monkeypatch):
    from upliftcli.engines.exact import engine as exact

    def fail(*args, **kwargs):
        raise AssertionError("the engine must not start")

    monkeypatch.setattr(exact, "iter_batch", fail)
    deck = load_deck(EXAMPLE, ["foundation.frequency_ratio=1e4", 'analysis.engine="exact"',
                               'analysis.supports="uplift"'])
    with pytest.raises(InputError) as info:
        run(deck)
    assert (info.value.source, info.value.location) == ("--set", "foundation.frequency_ratio")
    assert info.value.expected.startswith("at most 50,000,000 internal steps x states (about 20 s of stepping "
                                          "on 2 cores), got 3,741,600 steps x 30")
    # the estimate uses the engine's own step rule: 5e-5 s, the bonded vertical period / 6
    assert "shortest governing period is 5e-05 s" in info.value.expected
    deck = load_deck(EXAMPLE, ["analysis.exact.time_step=1e-7", 'analysis.engine="approximate"'])
    with pytest.raises(InputError, match=r"^--set: analysis.exact.time_step: at most 50,000,000"):
        run(deck)


def test_an_overflow_inside_an_engine_is_an_analysis_error(monkeypatch, deck):
    from upliftcli.engines import simplified
    from upliftcli.errors import AnalysisError

    def overflow(*args, **kwargs):
        raise OverflowError("(34, 'Numerical result out of range')")

    monkeypatch.setattr(simplified, "analyze", overflow)
    with pytest.raises(AnalysisError, match=r"ten_story_elcentro.toml: the simplified analysis \(rigid\) failed with "
                                            r"OverflowError .*check the magnitudes of the deck's fields"):
        run_one(deck, "simplified", "rigid")


def test_every_result_carries_the_decks_warnings_first():
    deck = load_deck(EXAMPLE, ["building.floor_mass=300"])
    results = run(deck, "simplified")
    assert len(deck.warnings) == 1
    assert all(result.details["warnings"][0] == deck.warnings[0] for result in results)
    assert all("building practice" not in message for result in run(load_deck(EXAMPLE), "simplified")
               for message in result.details.get("warnings", []))


def test_a_design_spectrum_not_covering_the_periods_names_the_deck_field():
    """A table spectrum asked for a period outside it was blamed on 'deck.toml: period' (no such
    field): the field that gave the spectrum is named (or --set)."""
    deck = ROOT / "inputs" / "ten_story_asce7.toml"
    table = 'ground_motion.design_spectrum={type="table", periods=[0.5, 4], sa=[1, 1], damping=0.05}'
    with pytest.raises(InputError, match=r"^--set: ground_motion.design_spectrum: periods within 0.5 to 4 s .*got "
                                         r"0.335834 s \(a period of the building's modes"):
        run_one(load_deck(deck, [table]), "simplified", "rigid")
