"""Issue 36 item 1: a well-posed deck is not refused for its energy balance. Where the record's
step governs the internal step (one internal step a sample), doubling steps_per_period from 6
to 12 left the step, and the residual, as they were; the engine then said "the step is not the
cause" and exited 4, while 24 steps per period ran. The step is now refined until it is finer,
within the limits of runtime/limits.py, and a suite says so in one warning line."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_helpers import invoke

from upliftcli.deck.load import load_deck
from upliftcli.engines.exact import engine as exact
from upliftcli.engines.options import ExactOptions
from upliftcli.errors import AnalysisError

ROOT = Path(__file__).resolve().parent.parent
SUITE = ROOT / "records" / "ten_story_asce7_suite"

#: a lightly damped ten-story building (1 % in its modes, xi_v = 1 %) on a stocky foundation
#: (h_1*/b = 2.5) under two of the bundled MCE_R records: their residuals at the default 6 steps
#: per period are 2.6e-3 and 3.6e-5, 6.6e-5 and 1.3e-4 at 24 (the issue's deck, h_1*/b = 3 and
#: xi_v = 2 %, missed at 6 with the cubic quadrature of the work integrals, 1.2e-3 and 1.8e-3; with
#: the quintic one, docs/theory.md 11.6, it closes there to 1.4e-4 and 3.6e-4)
DECK = """
title = "Ten stories, lightly damped, on a stocky two-element foundation"
[building]
stories = 10
floor_mass = 350e3
story_height = 3.5
period = 1.0
damping = 0.01
[foundation]
type = "two-element"
slenderness = 2.5
frequency_ratio = 8
damping_ratio = 0.01
[ground_motion]
design_spectrum = {{ type = "asce7", sds = 1.0, sd1 = 0.6, tl = 8, level = "mce_r" }}
suite = ["{first}", "{second}"]
scaling = "none"
statistics = "mean"
[analysis]
engine = "exact"
supports = ["uplift"]
"""


@pytest.fixture
def deck_file(tmp_path) -> Path:
    path = tmp_path / "stocky.toml"
    path.write_text(DECK.format(first=(SUITE / "artificial_2024_02.txt").as_posix(),
                                second=(SUITE / "artificial_2024_03.txt").as_posix()))
    return path


def test_a_deck_that_misses_the_balance_at_the_default_step_runs_refined_and_says_so(deck_file, tmp_path):
    deck = load_deck(deck_file)
    record = deck.ground_motion.motions()[0]
    coarse = exact.analyze(deck.system, record, "uplift", ExactOptions(), refine=False)
    assert coarse.intermediates["energy_residual"] > exact.ENERGY_TOLERANCE  # misses at the default step
    assert exact.finer_options(deck.system, record, "uplift", ExactOptions()).steps_per_period == 24  # 12: same step
    result = invoke("analyze", deck_file, "--out", tmp_path / "out")
    assert result.exit_code == 0, result.output
    lines = [line for line in result.stderr.splitlines() if "refining the step" in line]
    assert lines == ["warning: the energy balance closed to its tolerance only after refining the step on 1 of 2 "
                     "records, to 24 steps per governing period (analysis.exact.steps_per_period = 6)"]


def test_a_refinement_the_limits_stop_names_the_field_that_would_close_it(deck_file, monkeypatch):
    """The refinement's runs in all exceed limits.MAX_STEP_STATES, one run at the finer step does
    not: the line names analysis.exact.steps_per_period and the value, and never says the step is
    not the cause (refining helped)."""
    deck = load_deck(deck_file)
    record = deck.ground_motion.motions()[0]
    first = exact._work(deck.system, record, "uplift", ExactOptions(), exact.exact_model)
    finer = exact._work(deck.system, record, "uplift", ExactOptions(steps_per_period=24), exact.exact_model)
    monkeypatch.setattr(exact, "MAX_STEP_STATES", first + finer - 1)
    with pytest.raises(AnalysisError) as info:
        exact.analyze(deck.system, record, "uplift")
    message = str(info.value)
    assert message.endswith(": set analysis.exact.steps_per_period = 24")
    assert "with 6 steps per governing period" in message and "not the cause" not in message
