"""Round-off sensitivity of the exact engine's peaks (issue 14): how far the peaks of the paper's
example (40 periods T_1 from 0.05 to 5 s, rigid, bonded and uplift, El Centro) move when the step
operators change in their last place, beside how far they move with the engine's own matrix
exponential (engines/exact/expm.py) in place of scipy.linalg.expm.

Printed per variant: the largest change of a peak divided by the largest peak of that quantity.
A change of arithmetic in the operators cannot move the results less than a one-ulp perturbation
does (docs/exact-engine.md, "Compiled loops").

    python benchmarks/roundoff.py
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from bench_exact import RECORD, paper_system

from upliftcli.engines.exact import engine as exact
from upliftcli.engines.exact import stepping
from upliftcli.engines.exact.expm import expm
from upliftcli.motion.records import read_record


def peaks(exponential, systems, record) -> list[np.ndarray]:
    stepping.expm = exponential
    out = []
    for support in ("rigid", "bonded", "uplift"):
        for result in exact.analyze_batch(systems, record, support):
            out.append(np.concatenate([np.ravel(result.peaks[name]) for name in sorted(result.peaks)]))
    return out


def change(a: list[np.ndarray], b: list[np.ndarray]) -> float:
    return max(float(np.max(np.abs(x - y)) / max(np.abs(x).max(), 1e-300)) for x, y in zip(a, b, strict=True))


def main() -> None:
    record = read_record(RECORD, units="g")
    systems = [paper_system(period) for period in np.geomspace(0.05, 5.0, 40)]
    reference = peaks(scipy.linalg.expm, systems, record)
    variants = {"scipy.linalg.expm again": scipy.linalg.expm,
                "scipy's operators x (1 + 2^-52)": lambda a: scipy.linalg.expm(a) * (1 + 2.0**-52),
                "scipy's operators x (1 - 2^-53)": lambda a: scipy.linalg.expm(a) * (1 - 2.0**-53),
                "engines/exact/expm.py": expm}
    for name, exponential in variants.items():
        moved = change(reference, peaks(exponential, systems, record))
        print(f"{name:34s} largest change of a peak / largest peak: {moved:.2e}")
    stepping.expm = expm


if __name__ == "__main__":
    main()
