"""The first run after an install (engines/exact/first_compile.py): a child process compiles the
post-processing loops from their declared signatures while the run compiles the stepping loop;
the run then loads them from the cache and its results are those of a warm run."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from upliftcli.deck import load_deck
from upliftcli.engines.exact import engine, first_compile, response_kernels

DECK = Path(__file__).resolve().parent.parent / "inputs" / "ten_story_elcentro.toml"

COLD_RUN = """
import json, sys
from upliftcli.deck import load_deck
from upliftcli.engines.exact import engine, first_compile, response_kernels
deck = load_deck(sys.argv[1])
result = engine.analyze(deck.system, deck.ground_motion, "uplift")
print(json.dumps({
    "launched": first_compile.launched,
    "loaded": {name: sum(getattr(response_kernels, name).stats.cache_hits.values())
               for name in first_compile.SIGNATURES},
    "compiled": {name: sum(getattr(response_kernels, name).stats.cache_misses.values())
                 for name in first_compile.SIGNATURES},
    "shear": result.peaks["shear"].tolist(), "drift": result.peaks["drift"].tolist(),
}))
"""


def test_declared_signatures_are_those_the_engine_calls():
    deck = load_deck(DECK)
    engine.analyze(deck.system, deck.ground_motion, "uplift")
    for name, signature in first_compile.SIGNATURES.items():
        assert signature in getattr(response_kernels, name).signatures, name


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX only")
def test_a_cold_cache_run_loads_what_the_child_compiled_and_gives_the_warm_results(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    done = subprocess.run([sys.executable, "-c", COLD_RUN, str(DECK)], capture_output=True, text=True, env=env,
                          timeout=600, check=True)
    cold = json.loads(done.stdout.splitlines()[-1])
    assert cold["launched"] == list(first_compile.SIGNATURES)
    assert all(count >= 1 for count in cold["loaded"].values()), cold
    assert not any(cold["compiled"].values()), cold
    deck = load_deck(DECK)
    warm = engine.analyze(deck.system, deck.ground_motion, "uplift")
    np.testing.assert_array_equal(cold["shear"], warm.peaks["shear"])
    np.testing.assert_array_equal(cold["drift"], warm.peaks["drift"])
    # the next run finds everything cached: no child
    again = subprocess.run([sys.executable, "-c", COLD_RUN, str(DECK)], capture_output=True, text=True, env=env,
                           timeout=600, check=True)
    again = json.loads(again.stdout.splitlines()[-1])
    assert again["launched"] == [] and not any(again["compiled"].values())
