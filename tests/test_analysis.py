"""The analysis runner: dispatch over engines x supports, the checks before running."""

import math
from pathlib import Path

import numpy as np
import pytest

from upliftcli.analysis.run import run, run_one
from upliftcli.deck.load import load_deck
from upliftcli.engines.simplified import analyze as simplified_analyze
from upliftcli.errors import InputError

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
WINKLER = ROOT / "inputs" / "ten_story_winkler.toml"


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


def _engine_must_not_start(monkeypatch):
    from upliftcli.engines.exact import engine as exact

    def fail(*args, **kwargs):
        raise AssertionError("the engine must not start")

    monkeypatch.setattr(exact, "iter_batch", fail)


def test_a_stiff_undamped_foundation_is_refused_by_its_steps_before_the_engine_starts(monkeypatch):
    """Issue 29: w_v/w_1 = 1000 with no damping made the mat chatter at every internal step and
    the peak search ran 11 s (11 us a step) inside the steps x states limit. The steps of one
    run are bounded (limits.MAX_STEPS), estimated as the engine does: the vertical period is
    T_1 / 1000 = 0.5 ms (w_v = 1000 w_1), 6 steps a period: ceil(0.02 s x 6 / 0.5 ms) = 240
    sub-steps of each of the 1,559 record intervals (31.18 s at 0.02 s)."""
    from upliftcli.runtime import limits

    _engine_must_not_start(monkeypatch)
    deck = load_deck(EXAMPLE, ["foundation.frequency_ratio=1000", "foundation.c_f=1e-12", 'analysis.engine="exact"'])
    expected_steps = math.ceil(0.02 * 6 / (0.5 / 1000) - 1e-9) * (deck.ground_motion.npts - 1)
    assert expected_steps == 374_160 > limits.MAX_STEPS
    with pytest.raises(InputError) as info:
        run(deck)
    assert (info.value.source, info.value.location) == ("--set", "foundation.frequency_ratio")  # not c_f
    assert info.value.expected.startswith(f"at most {limits.MAX_STEPS:,} internal steps of one run")
    assert f"got {expected_steps:,}: the shortest governing period is 0.0005 s (a foundation this stiff" \
        in info.value.expected
    # the Winkler deck likewise, named by its stiffness
    deck = load_deck(WINKLER, ["foundation.k_w=6e14", "foundation.c_w=1e-12", 'analysis.engine="exact"'])
    with pytest.raises(InputError, match=r"^--set: foundation.k_w: at most 250,000 internal steps"):
        run(deck)


def test_a_stiff_foundation_is_named_by_its_stiffness_not_by_a_capacity_field(monkeypatch, tmp_path):
    """The fields that only give the mat its bearing capacity (model/bearing.py, mat_length with
    bearing_pressure) set no period: a stiff Winkler mat is blamed on its k_w in the deck file,
    not on the capacity fields given by --set."""
    _engine_must_not_start(monkeypatch)
    text = WINKLER.read_text().replace("k_w = 6.0e8", "k_w = 6.0e14").replace("c_w = 1.5e7", "c_w = 1e-12")
    text = text.replace("../records/", f"{(ROOT / 'records').as_posix()}/")
    path = tmp_path / "stiff.toml"
    path.write_text(text)
    deck = load_deck(path, ['analysis.engine="exact"', "foundation.bearing_pressure=2e5", "foundation.mat_length=30"])
    with pytest.raises(InputError) as info:
        run(deck)
    assert (info.value.source, info.value.location) == (str(path), "foundation.k_w")
    assert "internal steps" in info.value.expected


def test_a_plausible_stiff_foundation_stays_within_the_step_limit():
    """The far end of building practice (w_v/w_1 = 100 on a 0.1 s building, El Centro: 187,080
    steps) is not refused: the limit sits between it and the issue's deck."""
    from upliftcli.engines.exact import engine as exact
    from upliftcli.runtime import limits

    deck = load_deck(EXAMPLE, ["foundation.frequency_ratio=100", "building.period=0.1"])
    _, samples, steps = exact.size_estimate(deck.system, deck.ground_motion.dt, deck.ground_motion.npts, "uplift",
                                            deck.analysis.exact)
    assert steps == math.ceil(0.02 * 6 / (0.1 / 100) - 1e-9) * (samples - 1) == 187_080 < limits.MAX_STEPS


def test_the_steps_of_a_long_record_are_blamed_on_the_record(monkeypatch):
    """One internal step a record sample (2 steps a period: the record's dt governs): a run too
    long is the record's, and the line names ground_motion.record."""
    from upliftcli.runtime import limits

    _engine_must_not_start(monkeypatch)
    monkeypatch.setattr(limits, "MAX_STEPS", 1000)
    deck = load_deck(EXAMPLE, ['analysis.engine="exact"', "analysis.exact.steps_per_period=2"])
    with pytest.raises(InputError, match=r"ten_story_elcentro.toml: ground_motion.record: at most 1,000 internal "
                                         r"steps of one run .*, got 1,559:"):
        run(deck)


def test_the_state_size_squared_is_bounded_and_blamed_on_the_stories(monkeypatch):
    """The stepping and the peak search cost the square of the state size a step (500 stories:
    19 s): steps x (states + 2)^2 is bounded too, and the line names building.stories."""
    from upliftcli.engines.exact import engine as exact
    from upliftcli.runtime import limits

    _engine_must_not_start(monkeypatch)
    deck = load_deck(EXAMPLE, ['analysis.engine="exact"', "building.stories=20"])
    space, _, steps = exact.size_estimate(deck.system, deck.ground_motion.dt, deck.ground_motion.npts, "rigid",
                                          deck.analysis.exact)
    work = steps * (space.layout.n_aug + 2) ** 2
    assert limits.steps_problem(steps, space.layout.n_aug) is None
    monkeypatch.setattr(limits, "MAX_STEP_STATES_SQUARED", work - 1)
    with pytest.raises(InputError, match=rf"^--set: building.stories: at most {work - 1:,} internal steps x "
                                         rf"states\^2 of one run .*, got {steps:,} steps x"):
        run(deck, supports="rigid")


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


def test_a_step_rate_beyond_the_limits_is_named_by_steps_per_period(monkeypatch):
    """--set analysis.exact.steps_per_period=100000 beside --set foundation.elements=31 was blamed on
    foundation.elements (the first foundation field given by --set); within the limits at the
    default rate, the rate is what to change."""
    _engine_must_not_start(monkeypatch)
    deck = load_deck(WINKLER, ["foundation.safety_factor=1.5", "foundation.elements=31", 'analysis.engine="exact"',
                               "analysis.exact.steps_per_period=100000"])
    with pytest.raises(InputError) as info:
        run(deck)
    assert (info.value.source, info.value.location) == ("--set", "analysis.exact.steps_per_period")
    assert info.value.expected.startswith("at most 50,000,000 internal steps x states")
