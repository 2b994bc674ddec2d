"""The paper procedure (analysis.procedure = "paper") gives, bit for bit, the numbers of main
before the improved procedure existed (commit c0f2a40), on the example decks and option variants.

tests/data/simplified_paper_regression.json holds what the generator below (`python
tests/test_simplified_regression.py OUT.json`, which needs no `procedure` option) computed on the
code of that commit; every float is compared exactly.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from upliftcli.analysis import run_one
from upliftcli.deck import load_deck

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).resolve().parent / "data" / "simplified_paper_regression.json"
ARRAYS = ("displacement", "drift", "drift_ratio", "shear", "moment")


def compute(deck: str, overrides: list[str], support: str) -> dict:
    loaded = load_deck(ROOT / "inputs" / f"{deck}.toml", overrides)
    result = run_one(loaded, "simplified", support)
    return {"base_shear": result.base_shear, "base_moment": result.base_moment, "uplift": result.uplift,
            **{name: getattr(result, name).tolist() for name in ARRAYS}, "intermediates": result.intermediates}


CASES = json.loads(DATA.read_text()) if DATA.exists() else []


@pytest.mark.parametrize("case", CASES, ids=[f"{c['deck']}-{'+'.join(c['set']) or 'deck'}-{c['support']}"
                                              for c in CASES])
def test_paper_procedure_is_unchanged(case):
    now = compute(case["deck"], [*case["set"], "analysis.procedure=paper"], case["support"])
    for name in ("base_shear", "base_moment", "uplift", *ARRAYS):
        assert now[name] == case[name], name
    for name, value in case["intermediates"].items():
        assert now["intermediates"][name] == value, name


if __name__ == "__main__":
    SETS = (["building.period=0.15"], ["building.period=2.0"], ["analysis.combination=cqc", "building.period=0.3"],
            ["analysis.effective_properties=eigenvalue"], ["analysis.uplift_formula=slender"],
            ["analysis.uplift_x=mass-consistent", "analysis.uplift_x_factor=phase"],
            ["analysis.uplift_damping=xi1", "analysis.uplift_x_factor=none"], ["foundation.mat_mass=1e6"])
    plan = [(deck, []) for deck in ("ten_story_elcentro", "ten_story_asce7", "ten_story_winkler", "frame_halfspace")]
    plan += [("ten_story_elcentro", sets) for sets in SETS] + [("frame_halfspace", ["analysis.combination=srss"])]
    out = [{"deck": deck, "set": sets, "support": support, **compute(deck, sets, support)}
           for deck, sets in plan for support in ("rigid", "bonded", "uplift")]
    Path(sys.argv[1]).write_text(json.dumps(out, indent=1))
