"""Warm start of local sweep workers: importing this module imports the engines and runs a tiny
analysis with each history engine and support (every module and first-call path loaded).

The forkserver of the local worker processes imports it before it forks them
(sweep/executors.py), so each worker starts with the modules and the compiled code in memory
instead of importing numpy and the engines again.
"""

from __future__ import annotations

import contextlib

import numpy as np

from ..analysis.run import run_batch
from ..deck.load import build_deck
from ..engines.registry import ENGINES, SUPPORTS
from ..motion.records import Record
from ..motion.spectra import RecordSpectrum
from . import worker  # noqa: F401 - the chunk runner and what it imports

#: a two-story building on the paper's two-element foundation, lifting off under a short pulse
_DECK = {
    "title": "warm-up",
    "building": {"stories": 2, "floor_mass": 1e5, "story_height": 3.0, "period": 0.2, "damping": 0.05},
    "foundation": {"type": "two-element", "slenderness": 5.0, "frequency_ratio": 5.0, "damping_ratio": 0.1},
    "ground_motion": {"record": "warm-up.txt", "units": "m/s2"},
}


def warm_up() -> None:
    """One tiny analysis per history engine and support (results discarded)."""
    deck = build_deck(_DECK, "warm-up", load_ground_motion=False)
    time = np.arange(41) * 0.01
    record = Record("warm-up", 0.01, 20.0 * np.sin(2 * np.pi * time / 0.2) * (time < 0.3), "warm-up")
    deck.ground_motion, deck.spectrum = record, RecordSpectrum(record)
    for name, engine in ENGINES.items():
        if engine.needs_record:
            for support in SUPPORTS:
                run_batch([deck], name, support)


with contextlib.suppress(Exception):  # only a head start: a worker then loads what it needs itself
    warm_up()
