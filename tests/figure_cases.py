"""A small run shared by the figure and report tests: the example deck cut to 4 stories and
the first 8 s of El Centro, exact and simplified engines, all three supports, histories kept
(the mat lifts off under the uplift support). Computed once per test session."""

from __future__ import annotations

import functools
from pathlib import Path

from upliftcli.analysis import run as analysis
from upliftcli.cli.plotting import keep_histories
from upliftcli.deck.load import load_deck

EXAMPLE_DECK = Path(__file__).resolve().parents[1] / "inputs" / "ten_story_elcentro.toml"

SMALL = ['analysis.engine=["exact", "simplified"]', "building.stories=4", "ground_motion.window=[0, 8]"]


@functools.cache
def small_run():
    """(deck, results) of the small run; the results carry their histories (AnalysisResult.histories)."""
    deck = keep_histories(load_deck(EXAMPLE_DECK, SMALL))
    return deck, tuple(analysis.run(deck))
