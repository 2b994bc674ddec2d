"""The paper procedure (analysis.procedure = "paper") gives, bit for bit, the numbers of main
before the improved procedure existed (commit c0f2a40), on the example decks and option variants.

tests/data/simplified_paper_regression.json holds what the generator below (`python
tests/test_simplified_regression.py OUT.json`, which needs no `procedure` option) computed on the
code of that commit. Whole numbers and flags are compared exactly, every float to 1e-12 relative
(1e-8 with the eigenvalue effective properties, EIGENVALUE): the numbers pass through a math
library whose last bits differ between builds and machines (LAPACK's eigensolver for the modes,
the C library's exp, sin, cos and pow in the spectra, numpy's own or the compiled loops' spectrum,
upliftcli.runtime.backend), each within an ulp or two (2e-16 relative); the procedure combines them in a
few dozen operations without a cancellation that would amplify that beyond 1e3 (the measured
difference between the spectrum's two implementations is at most 9.7e-14), so 1e-12 is reached on
any machine and still catches a change of the method.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from upliftcli.analysis.run import run_one
from upliftcli.deck.load import load_deck

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).resolve().parent / "data" / "simplified_paper_regression.json"
ARRAYS = ("displacement", "drift", "drift_ratio", "shear", "moment")


def compute(deck: str, overrides: list[str], support: str) -> dict:
    loaded = load_deck(ROOT / "inputs" / f"{deck}.toml", overrides)
    result = run_one(loaded, "simplified", support)
    return {"base_shear": result.base_shear, "base_moment": result.base_moment, "uplift": result.uplift,
            **{name: getattr(result, name).tolist() for name in ARRAYS}, "intermediates": result.intermediates}


#: the stored numbers; missing, the comparison has no case and test_the_snapshot_is_there fails
#: (it was skipped silently: an empty parameter set)
CASES = json.loads(DATA.read_text()) if DATA.exists() else []
#: how many cases the generator below stores (13 deck variants x 3 supports)
STORED_CASES = 39


def test_the_snapshot_is_there():
    assert DATA.exists(), f"{DATA} is missing: the paper procedure would not be compared at all"
    assert len(CASES) == STORED_CASES and {case["support"] for case in CASES} == {"rigid", "bonded", "uplift"}


#: every float to this relative tolerance (the module's docstring says why)
RELATIVE = 1e-12


#: the complex-eigenvalue effective properties come from LAPACK's QZ algorithm (scipy.linalg.eig
#: on a singular mass matrix), whose round-off differs between LAPACK builds: T1bar by 6e-12
#: relative between scipy 1.17.1 and the stored numbers, xi_f = xi1bar - xi_1 (T_1/T1bar)^3, a
#: difference, by 2e-9, and S_a(T1bar) by 3.5e-10: 1e-8 relative for those cases
EIGENVALUE = "analysis.effective_properties=eigenvalue"


def same(now, then, rel: float | None) -> bool:
    if isinstance(then, list):
        return len(now) == len(then) and all(same(a, b, rel) for a, b in zip(now, then, strict=True))
    if rel is not None and isinstance(then, float) and not isinstance(then, bool):
        return now == pytest.approx(then, rel=rel, abs=0.0)
    return now == then


@pytest.mark.parametrize("case", CASES, ids=[f"{c['deck']}-{'+'.join(c['set']) or 'deck'}-{c['support']}"
                                              for c in CASES])
def test_paper_procedure_is_unchanged(case):
    now = compute(case["deck"], [*case["set"], "analysis.procedure=paper"], case["support"])
    rel = 1e-8 if EIGENVALUE in case["set"] else RELATIVE
    for name in ("base_shear", "base_moment", "uplift", *ARRAYS):
        assert same(now[name], case[name], rel), name
    for name, value in case["intermediates"].items():
        assert same(now["intermediates"][name], value, rel), name


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
