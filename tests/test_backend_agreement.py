"""Both backends of the loops (upliftcli.runtime.backend) on every example deck, in one process: the same
results to round-off (tests/backends.py; skipped where the C extensions were not built; the
loops themselves, case by case: test_stepping_numpy.py, test_response_numpy.py,
test_spectra_numpy.py)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from backends import on_both

import upliftcli
from upliftcli.motion.records import Record

DECKS = sorted((Path(__file__).resolve().parents[1] / "inputs").glob("*.toml"))
#: a deck with one record runs every engine too (as given, it runs the simplified one; a suite
#: deck runs the exact engine on each of its records already)
ALL_ENGINES = ['analysis.engine = ["simplified", "exact", "approximate"]']
#: Each number of a result agrees to RELATIVE of its scale. The twins differ from the loops by the
#: order of their sums (BLAS products of the signals and responses; the stepping twin's block
#: recurrence, y_j = A^j y_0 + forced part, where the loop multiplies step by step): one or two
#: units in the last place per product. The damped dynamics carry such differences without growth
#: except through contact events: an impact amplifies a last-place change of the step operators
#: up to 3.3e-9 of a peak at T_1 = 0.1 s (docs/exact-engine.md, benchmarks/roundoff.py). Measured
#: on the example decks: at most 6.4e-10 (the smallest reaction of the README deck's uplift run),
#: 1e-14 elsewhere. Hence 1e-9, against a scale that does not come from a cancellation:
RELATIVE = 1e-9


def _numbers(tree, path=()):
    """(path, value) of every number and string of a result document, provenance left out."""
    if isinstance(tree, dict):
        for key, value in tree.items():
            if key != "provenance":
                yield from _numbers(value, (*path, key))
    elif isinstance(tree, list):
        for index, value in enumerate(tree):
            yield from _numbers(value, (*path, index))
    else:
        yield path, tree


def _scale(path, value, result) -> float:
    """The magnitude a difference in `value` is measured against: the value itself, except for
    differences of large terms: the energy terms (the change of gravity energy is m_t g times the
    change of the mat's settlement, the residual a sum of terms of the input work's size) against
    the largest energy term, the relative residual (a ratio to the input work) and the relative
    differences of a residual check (of a run and its twin) against 1, and the
    smallest reaction (the weight minus a near equal overturning share) against the largest
    element reaction of its result; a residual of a residual check (near zero where nothing
    stays) against at least the floor below which the check ignores it."""
    name = path[-1]
    if "energy" in path and name != "relative_residual":
        return max(abs(v) for k, v in result["details"]["energy"].items() if k != "relative_residual")
    if name in ("relative_residual", "energy_residual"):
        return 1.0
    if "residual_check" in path and "quantities" in path:
        return _residual_scale(path, value, result)
    if isinstance(name, str) and name.startswith("min_reaction"):
        return max(abs(element["reaction"]) for element in result["elements"])
    if "rocking" in path and "settlement" in path[path.index("rocking") + 1] and "time" not in path[-2]:
        # a settlement is v - v_st (and x theta): the largest settlement of the result is its scale
        return max(abs(v) for k, values in result["rocking"].items() if "settlement" in k and "time" not in k
                   for v in values.values())
    return abs(value)


def _residual_scale(path, value, result) -> float:
    """A residual of a residual check against at least the floor below which the check ignores it;
    the relative difference of a run and its twin (a ratio of near-equal numbers) against 1 where
    the residual reaches the floor, and not at all below it (a ratio of round-off)."""
    check = result["details"]["residual_check"]
    name = path[path.index("quantities") + 1]
    floor = check["floors"][name]
    if "difference" not in path:
        return max(abs(value), floor)
    quantity = _at(result, path[len(_owner_path(path, result)):-2])
    index = path[-1]
    below = max(abs(quantity["values"][index]), abs(quantity["twin"][index])) < floor
    return math.inf if below else 1.0


def _owner_path(path, result):
    """The part of `path` that leads to `result` (the rest is inside it)."""
    return path[:path.index("details")]


def _results(document):
    """The result objects of a document (those of each suite record too), by their path."""
    for path, _ in _numbers(document):
        if path and path[-1] == "engine":
            yield path[:-1]


def _at(tree, path):
    for key in path:
        tree = tree[key]
    return tree


@pytest.mark.parametrize("deck_path", DECKS, ids=[deck.stem for deck in DECKS])
def test_both_backends_give_every_deck_the_same_results(deck_path):
    def run():
        documents = []
        for overrides in ([], ALL_ENGINES):
            deck = upliftcli.load_deck(deck_path, overrides)
            if overrides and not isinstance(deck.ground_motion, Record):  # a design spectrum or a suite
                continue
            documents.append(upliftcli.to_dict(upliftcli.run(deck), deck))
        return documents

    compiled, twin = on_both(run)
    results = {path: _at(compiled, path) for path in _results(compiled)}
    twins = dict(_numbers(twin))
    compared = 0
    for path, value in _numbers(compiled):
        other = twins.pop(path)
        if isinstance(value, float) and isinstance(other, float) and math.isfinite(value):
            owner = max((p for p in results if path[:len(p)] == p), key=len, default=None)
            scale = _scale(path, value, results[owner]) if owner is not None else abs(value)
            assert abs(other - value) <= RELATIVE * scale, (path, value, other)
            compared += 1
        else:
            assert other == value or (value != value and other != other), (path, value, other)
    assert not twins and compared > 50
