"""OpenSeesPy against the exact engine on the rocking analyses (issue 28): the model of
benchmarks/opensees_model.py (an independent build of the project's model: zeroLength contact
elements, compression-only penalty contacts, Kelvin units, stiffness-proportional damping) at a
fine fixed step (Newmark, average acceleration), under El Centro 1940 N-S.

Without a bearing capacity (the elastic foundation of the paper) it checks the harness itself:
for each period T_1 of the paper's ten-story example (w_v/w_1 = 8, xi_v = 0.4, h_1*/b = 10;
xi_n = 0.05 w_n/w_1, stiffness-proportional, in both models) the peaks of V_b, M_b, theta, the
roof displacement and the rise of each edge, and the largest difference of the histories over
the largest value, are compared for each step of a halving sequence; the step's
own convergence is the change from one step to the next. With `--capacity FS_v` each element
gets Q_y = FS_v W/2 (Winkler: q_w = FS_v W/2b), in both engines: the exact engine models the
yielding elements too (docs/theory.md section 14), so the same comparison checks it on yielding
soil (the comparison over several records and FS_v: benchmarks/opensees_capacity.py).

    python benchmarks/opensees_yielding.py                         # T_1 = 0.3, 0.5, 1, 2 s
    python benchmarks/opensees_yielding.py --periods 1 --steps 0.002,0.001 --foundation winkler
    python benchmarks/opensees_yielding.py --periods 1 --capacity 1.5

Results are cached (--cache, default /tmp/uplift-opensees): a rerun prints at once.
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import opensees_model as om

from upliftcli.engines.exact import engine as exact
from upliftcli.engines.options import ExactOptions
from upliftcli.model.building import modal_analysis, uniform_building
from upliftcli.model.foundations import Winkler, two_element_from_ratios
from upliftcli.model.system import System
from upliftcli.motion.records import Record, read_record

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"
COMPARED = ("base_shear", "base_moment", "theta", "roof", "left_rise", "right_rise")
#: the exact engine's history names of the compared signals
EXACT_NAMES = {"base_shear": "base_shear", "base_moment": "base_moment", "theta": "theta", "roof": "roof_displacement",
               "left_edge_displacement": "left_edge_displacement",
               "right_edge_displacement": "right_edge_displacement"}


def example_system(period: float, foundation: str = "two-element", capacity: float | None = None) -> System:
    """The paper's example (docs/theory.md section 6) with stiffness-proportional damping
    (xi_n = 0.05 w_n/w_1) so that OpenSees has the same damping; a Winkler strip with the same
    K_theta and C_theta as the two elements (20 elements); capacity: FS_v."""
    plain = uniform_building(10, 350e3, 3.5, period=period)
    modes = modal_analysis(plain)
    building = uniform_building(10, 350e3, 3.5, period=period,
                                damping=om.stiffness_proportional_damping(modes.omega, 0.05))
    two = two_element_from_ratios(building.masses.sum(), modes.omega[0], 8.0, 0.4)
    b = modes.effective_height[0] / 10.0
    system = System(building, two, b)
    if foundation == "winkler":
        system = replace(system, foundation=Winkler(3.0 * two.stiffness / b, 3.0 * two.damping / b, 20))
    if capacity is not None:
        per_length = capacity * system.weight / (2.0 * b)
        value = per_length if foundation == "winkler" else per_length * b
        system = replace(system, foundation=replace(system.foundation, capacity=value))
    return system


def exact_run(system: System, record: Record) -> tuple[dict, dict]:
    """Peaks and histories (finely sampled: 48 steps per governing period) of the exact engine."""
    result = exact.analyze(system, record, "uplift", ExactOptions(histories=True, steps_per_period=48))
    h = result.histories
    histories = {name: h[exact_name] for name, exact_name in EXACT_NAMES.items()}
    histories["time"] = h["time"]
    return om.peaks(histories), histories


def opensees_run(system: System, record: Record, dt: float, penalty: float, cache: Path, key: str) -> dict:
    path = cache / f"{key}.npz"
    if path.exists():
        histories = dict(np.load(path))
        positions = system.foundation.contact_elements(system.half_width).positions
        return {**histories, **om.edge_displacements(histories, positions)}
    start = time.perf_counter()
    histories = om.run(system, record.acceleration, record.dt, dt, "uplift", penalty)
    histories["seconds"] = np.array(time.perf_counter() - start)
    np.savez(path, **histories)
    return histories


def compare(os_hist: dict, exact_peaks: dict, exact_hist: dict) -> dict:
    """Relative differences of the peaks, and of the histories (largest over the largest value)."""
    peaks = om.peaks(os_hist)
    out = {f"peak_{name}": peaks[name] / exact_peaks[name] - 1.0 for name in COMPARED}
    for name in ("base_shear", "theta", "roof"):
        out[f"history_{name}"] = om.relative_history_difference(os_hist["time"], os_hist[name], exact_hist["time"],
                                                                exact_hist[name])
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--periods", default="0.3,0.5,1,2", help="T_1 [s], comma-separated")
    parser.add_argument("--steps", default="0.002,0.001,0.0005", help="fixed steps dt [s], comma-separated")
    parser.add_argument("--penalty", type=float, default=om.PENALTY, help="contact stiffness / element stiffness")
    parser.add_argument("--foundation", default="two-element", choices=("two-element", "winkler"))
    parser.add_argument("--capacity", type=float, default=None, help="FS_v (default: elastic)")
    parser.add_argument("--duration", type=float, default=None, help="first seconds of the record [s]")
    parser.add_argument("--cache", default="/tmp/uplift-opensees", help="folder of cached OpenSees histories")
    args = parser.parse_args()
    cache = Path(args.cache)
    cache.mkdir(parents=True, exist_ok=True)
    record = read_record(RECORD, units="g")
    if args.duration:
        record = replace(record, acceleration=record.acceleration[: round(args.duration / record.dt) + 1])
    steps = [float(s) for s in args.steps.split(",")]
    report = []
    for period in (float(p) for p in args.periods.split(",")):
        system = example_system(period, args.foundation, args.capacity)
        reference = exact_run(system, record)
        previous = None
        for dt in steps:
            key = (f"{args.foundation}-T{period:g}-dt{dt:g}-p{args.penalty:g}-fs{args.capacity}-"
                   f"n{record.acceleration.size}")
            os_hist = opensees_run(system, record, dt, args.penalty, cache, key)
            row = {"T_1": period, "dt": dt, "seconds": float(os_hist["seconds"]), **om.peaks(os_hist)}
            if reference is not None:
                row.update(compare(os_hist, *reference))
            if previous is not None:  # the change from the previous step: the fixed step's convergence
                row.update({f"step_change_{name}": row[name] / previous[name] - 1.0 for name in COMPARED
                            if previous[name]})
            report.append(row)
            previous = row
            print(json.dumps({k: (round(v, 8) if isinstance(v, float) else v) for k, v in row.items()}))
    if reference is not None:
        worst = {name: max(abs(r[name]) for r in report if r["dt"] == min(steps))
                 for name in report[-1] if name.startswith(("peak_", "history_"))}
        print("largest difference at dt =", min(steps), json.dumps({k: round(v, 8) for k, v in worst.items()}))


if __name__ == "__main__":
    main()
