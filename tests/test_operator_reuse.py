"""The twin of a yielding run starts from its original's step operators (engines/exact/reuse.py,
docs/theory.md 15.8): the twin's results are those of a twin built from nothing, bit for bit, the
original's are unchanged, and the twin builds few states of its own; the store keeps only yielding runs,
within its bound, each for the run of the same system, support, options and step."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from upliftcli.analysis import residuals
from upliftcli.analysis import run as analysis
from upliftcli.deck.load import load_deck
from upliftcli.engines.exact import engine as exact
from upliftcli.engines.exact import reuse

ROOT = Path(__file__).resolve().parent.parent
TWO = ROOT / "inputs" / "ten_story_elcentro.toml"
STORIES = ("ground_motion.scale=2", "building.strength_coefficient=0.4", "building.hardening_ratio=0.05")
#: issue 35's reproducer: soil that yields under a mat without a dashpot
FRAGILE = ("foundation.damping_ratio=0", "foundation.safety_factor=1.98")


def same(a, b) -> bool:
    """Whether two results (or their parts) are equal bit for bit (NaN equal to NaN)."""
    if dataclasses.is_dataclass(a):
        return type(a) is type(b) and all(same(getattr(a, f.name), getattr(b, f.name)) for f in dataclasses.fields(a))
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return isinstance(b, (list, tuple)) and len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, (np.ndarray, float, np.floating)):
        return np.array_equal(a, b, equal_nan=True) and np.shape(a) == np.shape(b)
    return a == b


def _analyses(overrides, support):
    """(original and twin, each with a store and without, the store) of one deck and support; the twin
    with its original's operators folded in full (a check's twins fold their residuals alone)."""
    deck = load_deck(TWO, list(overrides))
    options = deck.analysis.exact
    record, twin = deck.ground_motion, residuals.perturbed_motion(deck.ground_motion)
    store = reuse.OperatorStore()
    kept = exact.analyze(deck.system, record, support, options, operators=store)
    twins = store.twins()
    twins.residuals_only = False  # folded in full: all of it compared (its residuals alone: test_residual_digest.py)
    reused = exact.analyze(deck.system, twin, support, options, operators=twins)
    plain = exact.analyze(deck.system, record, support, options)
    alone = exact.analyze(deck.system, twin, support, options)
    return kept, reused, plain, alone, store


@pytest.mark.parametrize("support", ["rigid", "bonded", "uplift"])
def test_a_twin_from_its_originals_operators_is_the_twin_built_alone(support):
    """Yielding stories (0.4 W under El Centro x2) on every support: the original run that keeps its
    operators and the twin that starts from them give the results of runs without a store, bit for bit;
    the twin inherits the original's states and builds at most a fifth as many itself."""
    kept, reused, plain, alone, store = _analyses(STORIES, support)
    assert kept.building_yielded
    assert same(kept, plain)
    assert same(reused, alone)
    assert store.reused >= 10 and store.built <= store.reused / 5
    assert not store.kept  # handed over once


@pytest.mark.parametrize("loops", ["auto", "numpy"])
def test_a_twin_on_yielding_soil_reuses_too(loops, monkeypatch):
    """Issue 35's reproducer (two elements that yield, no dashpot), on the compiled loops and on their numpy
    twins (UPLIFT_BACKEND): the same twin with and without the original's operators, and its residual mat
    rotation the fragile value it has."""
    monkeypatch.setenv("UPLIFT_BACKEND", loops)
    kept, reused, plain, alone, store = _analyses(FRAGILE, "uplift")
    assert kept.yielded and same(kept, plain) and same(reused, alone)
    assert store.reused > 0 and store.built <= store.reused
    assert reused.peaks["residual_rotation"][0] != kept.peaks["residual_rotation"][0]


def test_the_numpy_loops_reuse_bit_for_bit(monkeypatch):
    """Yielding stories on the uplift support with the numpy twins of the loops (UPLIFT_BACKEND=numpy):
    the original and its twin the same with and without the store, the twin's states all inherited."""
    monkeypatch.setenv("UPLIFT_BACKEND", "numpy")
    kept, reused, plain, alone, store = _analyses(STORIES, "uplift")
    assert kept.building_yielded and same(kept, plain) and same(reused, alone)
    assert store.reused >= 10 and store.built <= store.reused / 5


def test_the_check_of_the_residuals_is_the_same_without_reuse(monkeypatch):
    """analysis.run_one: the results with their details.residual_check are the same whether the twins reuse
    the operators (each check its own store, whose twin built few states: none of 151 on the rigid base, 1
    of 13 on the uplift support) or (a store that keeps nothing)
    build their own."""
    stores: list[reuse.OperatorStore] = []

    class Recorded(reuse.OperatorStore):
        def __init__(self):
            super().__init__()
            stores.append(self)

    monkeypatch.setattr(reuse, "OperatorStore", Recorded)
    deck = load_deck(TWO, [*STORIES, *FRAGILE])
    shared = [analysis.run_one(deck, "exact", support) for support in ("rigid", "uplift")]
    assert len(stores) == 2 and all(store.reused > 0 and store.built <= store.reused / 5 for store in stores)
    assert not any(store.kept for store in stores)  # each kept run handed over to its twin
    monkeypatch.setattr(reuse, "STORE_BYTES", 0)
    alone = [analysis.run_one(deck, "exact", support) for support in ("rigid", "uplift")]
    assert len(stores) == 4 and stores[-1].reused == stores[-2].reused == 0
    assert all("residual_check" in result.details for result in shared)
    assert same(shared, alone)


def test_the_store_keeps_yielding_runs_within_its_bound_for_the_same_run_only():
    """An elastic run is not kept (it gets no twin); a run beyond max_bytes is not kept; a run of another
    support, step or system does not take what another kept; an original run never starts from kept
    operators; runs of one key (the records of a suite) go each to its own twin, in order."""
    deck = load_deck(TWO, list(STORIES))
    elastic = load_deck(TWO, [])
    store = reuse.OperatorStore()
    exact.analyze(elastic.system, elastic.ground_motion, "rigid", elastic.analysis.exact, operators=store)
    assert not store.kept
    small = reuse.OperatorStore(max_bytes=1)
    exact.analyze(deck.system, deck.ground_motion, "rigid", deck.analysis.exact, operators=small)
    assert not small.kept
    exact.analyze(deck.system, deck.ground_motion, "rigid", deck.analysis.exact, operators=store)
    ((key, [(system, operators, size)]),) = store.kept.items()
    assert system is deck.system and size == reuse.used_bytes(operators) == store.bytes
    assert store.take(key, elastic.system) is None
    assert store.take((*key[:-1], key[-1] / 2), deck.system) is None
    exact.analyze(deck.system, deck.ground_motion, "bonded", deck.analysis.exact, operators=store)
    exact.analyze(deck.system, deck.ground_motion, "rigid", deck.analysis.exact, operators=store)
    assert store.reused == 0 and len(store.kept) == 2 and len(store.kept[key]) == 2
    first, second = (entry[1] for entry in store.kept[key])
    taken = [store.take(key, deck.system) for _ in range(3)]
    assert taken[0].ops is first.ops and taken[1].ops is second.ops and taken[2] is None
    assert taken[0].contact is not first.contact and taken[0].inherited == len(first.contact) == store.reused / 2
    assert len(store.kept) == 1 and store.bytes == reuse.used_bytes(next(iter(store.kept.values()))[0][1])
