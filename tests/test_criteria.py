"""The deck's acceptance criteria applied to results (upliftcli/deck/criteria.py): the same outcomes
for the exit code of `uplift analyze`, the sweep's violations column and the report's table."""

from pathlib import Path

import numpy as np
import pytest

from upliftcli.analysis.run import run
from upliftcli.deck.criteria import check_criteria, outcomes
from upliftcli.deck.load import load_deck
from upliftcli.errors import InputError
from upliftcli.report.checks import criteria_rows


def test_criteria(example_deck):
    results = run(example_deck)
    worst_drift = max(float(max(r.drift_ratio)) for r in results)
    assert check_criteria(results, {"drift_ratio": worst_drift * 1.001}) == []
    messages = check_criteria(results, {"drift_ratio": worst_drift * 0.999})
    assert len(messages) == 1 and "simplified/rigid: drift_ratio" in messages[0]
    messages = check_criteria(results, {"uplift": False, "base_shear_coefficient": 0.3})
    assert any("lifts off" in m for m in messages)
    assert sum("base_shear_coefficient" in m for m in messages) == 2  # rigid 0.78, bonded 0.42 > 0.3 > uplift 0.15
    assert check_criteria(results, {"uplift": True}) == []


def test_criteria_on_floor_accelerations_and_reactions(example_deck):
    """Every quantity of engines/quantities.py with criterion=True is a [criteria] field."""
    results = run(example_deck)
    accel = max(float(r.floor_acceleration.max()) for r in results)
    reaction = max(float(r.reaction.max(initial=0.0)) for r in results)
    assert check_criteria(results, {"floor_acceleration": accel * 1.001, "reaction": reaction * 1.001}) == []
    messages = check_criteria(results, {"floor_acceleration": accel * 0.999, "reaction": reaction * 0.999})
    assert any("floor_acceleration" in m and "[m/s^2]" in m for m in messages)
    assert any("reaction" in m and "[N]" in m for m in messages)
    deck_with_limit = load_deck(example_deck.source, ["criteria.floor_acceleration=1.0"])
    assert deck_with_limit.criteria == {"drift_ratio": 0.02, "floor_acceleration": 1.0}


def test_outcomes_values_units_and_report_rows_agree(example_deck):
    results = run(example_deck)
    limits = {"drift_ratio": 0.004, "base_shear": 1e7, "uplift": False}
    found = outcomes(results, limits)
    assert [(o.result.support, o.name) for o in found] == [(r.support, n) for r in results for n in limits]
    for outcome in found:
        if outcome.name == "drift_ratio":
            assert outcome.value == max(abs(outcome.result.drift_ratio)) and outcome.unit == "-"
            assert outcome.ok == (outcome.value <= 0.004)
        elif outcome.name == "base_shear":
            assert outcome.value == abs(outcome.result.base_shear) and outcome.unit == "N"
        else:
            assert outcome.ok == (not outcome.result.uplift)
    rows, violated = criteria_rows(results, limits)
    assert violated == sum(not o.ok for o in found) == len(check_criteria(results, limits)) > 0
    assert [row[-1] == "ok" for row in rows] == [o.ok for o in found]


def test_rocking_limits_judge_the_results_that_report_them(example_deck):
    """ASCE 41-17 8.4 rotation and settlement limits (engines/quantities.ROCKING): judged on a
    result that carries the quantity, with its unit; results without it are not judged."""
    results = run(example_deck)
    rocking = results[-1]
    rocking.peaks["rotation"] = np.array([0.012])
    rocking.peaks["residual_settlement"] = np.array([0.004, 0.010, 0.016])
    limits = {"rotation": 0.01, "residual_settlement": 0.02}
    found = outcomes(results, limits)
    assert [(o.result.support, o.name) for o in found] == [(rocking.support, "rotation"),
                                                            (rocking.support, "residual_settlement")]
    messages = check_criteria(results, limits)
    assert messages == [f"simplified/{rocking.support}: rotation = 0.012 exceeds the limit 0.01 [rad]"]


def test_a_rocking_limit_needs_the_analysis_that_reports_it(example_deck):
    """The exact engine's uplift runs report the mat's rotation and settlement, with or without a
    bearing capacity (docs/theory.md 14.7): a rocking limit needs that analysis only."""
    with pytest.raises(InputError, match=r"the exact engine in analysis\.engine") as info:
        load_deck(example_deck.source, ["criteria.rotation=0.01"])
    assert (info.value.source, info.value.location) == ("--set", "criteria.rotation")
    deck = load_deck(example_deck.source, ["criteria.rotation=0.01", "analysis.engine=exact"])
    assert deck.criteria["rotation"] == 0.01
    with pytest.raises(InputError, match=r"the uplift support in analysis\.supports"):
        load_deck(example_deck.source, ["criteria.settlement=0.01", "analysis.engine=exact",
                                        'analysis.supports=["bonded"]'])


def test_a_limit_carries_its_source_into_the_verdict(example_deck):
    """[criteria.sources]: the user's reference of each limit, repeated in its violation message
    (and the report's criteria table); a source of a limit the deck does not set is refused."""
    results = run(example_deck)
    drift = max(r.value("drift_ratio") for r in results)
    deck = load_deck(example_deck.source, [f"criteria.drift_ratio={drift * 0.999}",
                                           'criteria.sources.drift_ratio="ASCE 7-22 Table 12.12-1, risk category II"'])
    assert deck.criteria.sources == {"drift_ratio": "ASCE 7-22 Table 12.12-1, risk category II"}
    messages = check_criteria(results, deck.criteria)
    assert messages and all(m.split(" [-]")[1].startswith(" (source: ASCE 7-22 Table 12.12-1, risk category II)")
                            for m in messages)
    assert all(o.source == "ASCE 7-22 Table 12.12-1, risk category II" for o in outcomes(results, deck.criteria))
    with pytest.raises(InputError, match=r"criteria\.rotation is not set") as info:
        load_deck(example_deck.source, ['criteria.sources.rotation="ASCE 41-17"'])
    assert info.value.location == "criteria.sources.rotation"
    deck = load_deck(example_deck.source, ["criteria.uplift=false", 'criteria.sources.uplift="owner\'s brief"'])
    assert check_criteria(results, deck.criteria)[0].endswith("(criteria.uplift = false) (source: owner's brief)")


def test_a_settlement_limit_bounds_the_downward_value(example_deck):
    """A settlement limit judges the largest settlement (downward), not a rise: a mat that ends
    above its rest position passes any residual settlement limit."""
    results = run(example_deck)
    rocking = results[-1]
    rocking.peaks["residual_settlement"] = np.array([-0.03, 0.0, 0.002])
    (found,) = outcomes(results, {"residual_settlement": 0.001})
    assert (found.value, found.ok) == (0.002, False)
    rocking.peaks["residual_settlement"] = np.array([-0.03, -0.001, -0.002])
    (found,) = outcomes(results, {"residual_settlement": 0.001})
    assert (found.value, found.ok) == (0.0, True)


def test_every_rocking_limit_is_a_deck_field_with_its_unit():
    from upliftcli.deck import schema as deck_schema
    from upliftcli.engines.quantities import ROCKING, unit_of

    limited = {name for name, q in ROCKING.items() if q.criterion}
    assert limited == {"rotation", "residual_rotation", "settlement", "residual_settlement"}
    for name in limited:
        assert deck_schema.TABLES["criteria"][name].unit == unit_of(name) == ROCKING[name].unit
        assert "ASCE 41-17 section 8.4" in deck_schema.TABLES["criteria"][name].doc


def test_a_simplified_error_limit_needs_the_simplified_engine(example_deck):
    """criteria.simplified_error judges the simplified engine's accuracy check: a deck that runs only
    the exact engine would pass it unchecked (exit 0), so it is refused, as a rocking limit without
    the exact engine is."""
    with pytest.raises(InputError) as info:
        load_deck(example_deck.source, ["criteria.simplified_error=0.25", "analysis.engine=exact"])
    assert str(info.value) == ("--set: criteria.simplified_error: a limit on the accuracy check of the simplified "
                               "engine against the exact engine (docs/accuracy.md); the deck has not the simplified "
                               "engine in analysis.engine")
    deck = load_deck(example_deck.source, ["criteria.simplified_error=0.25", 'analysis.engine=["simplified", "exact"]'])
    assert deck.criteria["simplified_error"] == 0.25


@pytest.mark.parametrize("source", ["line one\\nline two", "red \\u001b[31m", "", "  "])
def test_a_source_is_one_line_of_text(example_deck, tmp_path, source):
    """A source is repeated in the one-line violation message: a line break (or a terminal escape)
    split it over two lines and reached the terminal raw; an empty one said nothing."""
    deck = Path(example_deck.source)
    text = deck.read_text().replace("../records/", f"{(deck.parent.parent / 'records').as_posix()}/")
    path = tmp_path / "deck.toml"
    path.write_text(text + f'\n[criteria.sources]\ndrift_ratio = "{source}"\n')
    with pytest.raises(InputError) as info:
        load_deck(path)
    assert (info.value.source, info.value.location) == (str(path), "criteria.sources.drift_ratio")
    assert info.value.expected.startswith("a non-empty text on one line (without line breaks or control characters)")
    assert "\n" not in str(info.value) and "\x1b" not in str(info.value)
