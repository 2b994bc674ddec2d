"""Calibration of the improved simplified procedure (engines/improved.py; docs/accuracy.md).

On the calibration records only (FEMA P695 far field) x the family of systems x T_1 of
benchmarks/accuracy.py, uplift support, the cases where the exact engine lifts the mat:
1. the per-case terms the procedure combines are computed once with the engine's own function
   (improved.uplift_terms) and cached in --cache, with the paper procedure's bonded values (the
   result where the simplified estimate does not lift the mat);
2. the coefficients of the forces (improved.FITTED) are fitted by Nelder-Mead within
   improved.BOUNDS to the two-sided goals of issue 25 for V_b, M_b, the largest drift ratio and
   the roof displacement: the squared shortfalls of the 5 % quantile of log(simplified/exact)
   below log 0.83, of the 80 % quantile above log 1.17 and of the median outside [log 0.99,
   log 1.06] (each a small margin inside the goals: at most 5 % more than 20 % low, at most 20 %
   more than 20 % high, median in [0.95, 1.10]), weight 1 for T_1 >= 0.2 s pooled, 0.3 for each
   band 0.2-0.5, 0.5-1 and 1-3 s, 0.1 below 0.2 s (impacts), plus 0.1 x the mean squared log-ratio;
3. then the two coefficients of the motion (improved.FITTED_MOTION), one at a time by bisection:
   displacement_period so that the median of simplified/exact mat rotation is 1, and impact so
   that IMPACT_LOW of the lifting cases have a floor acceleration more than 20 % low;
4. the fitted values and the residuals by quantity and band are printed (the engine gives the
   vectorised prediction to rounding: tests/test_improved.py).

    nice -n 19 python benchmarks/calibrate.py          # after analysis/accuracy.py --exact-only has run
"""

from __future__ import annotations

import argparse
import os
import pickle
import sys
from dataclasses import asdict, replace
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np
from scipy.optimize import brentq, minimize

sys.path.insert(0, str(Path(__file__).resolve().parent))
import accuracy_cases as cases
from accuracy import CACHE, FULL, PERIODS

from upliftcli.engines import improved
from upliftcli.engines.options import SimplifiedOptions
from upliftcli.engines.quantities import COMPARED, compared_values
from upliftcli.engines.simplified import paper_analyze
from upliftcli.motion.spectra import RecordSpectrum

N_MAX = 20  # stories and modes padded to this
#: the values the forces are fitted to
FORCES = ("base_shear", "base_moment", "drift_ratio", "roof_displacement")
#: (band [s], weight) of the fit: T_1 >= 0.2 s pooled, each band, and below 0.2 s
WEIGHTS = (((0.2, 3.01), 1.0), ((0.2, 0.5), 0.3), ((0.5, 1.0), 0.3), ((1.0, 3.01), 0.3), ((0.0, 0.2), 0.1))
#: share of the lifting cases whose floor acceleration may be more than 20 % low (goal: 10 %)
IMPACT_LOW = 0.06


def gather(cache: Path) -> dict[str, np.ndarray]:
    """Per-case terms, bonded values and exact uplift values of the calibration set, stacked."""
    _, n_systems, n_periods, seed = FULL["calibration"]
    specs = cases.family(n_systems, seed)
    periods = np.geomspace(*PERIODS, n_periods)
    chosen = cases.records("calibration")
    path = cache / f"calibration-terms-v{cases.CACHE_VERSION}-{improved.TERMS_VERSION}-{len(chosen)}.pkl"
    if path.exists():
        with open(path, "rb") as handle:
            return pickle.load(handle)
    options = SimplifiedOptions(procedure="paper")
    rows: list[dict] = []
    done = [r for r in chosen if cases.cached(r, specs, periods, cache)]
    if len(done) < len(chosen):
        print(f"  only {len(done)} of {len(chosen)} records have exact results: a partial calibration "
              "(run analysis/accuracy.py --exact-only first)", file=sys.stderr)
    for k, record in enumerate(done):
        exact = cases.exact_peaks(record, specs, periods, cache)
        spectrum = RecordSpectrum(record)
        for i, spec in enumerate(specs):
            for j, period in enumerate(periods):
                system = cases.build(spec, period)
                spectrum.sa(system.modes.periods, 0.05)
                terms = improved.uplift_terms(system, spectrum, options, N_MAX)
                bonded = paper_analyze(system, spectrum, "bonded", options)
                terms.update({f"bonded_{name}": value for name, value in compared_values(bonded).items()})
                terms["bonded_max_rotation"] = bonded.base_moment / bonded.intermediates["K_theta"]
                terms["bonded_max_uplift"] = 0.0
                terms.update({f"exact_{name}": exact["uplift"][name][i, j] for name in (*COMPARED, "flight")})
                terms.update({"lifted": exact["uplift"]["lifted"][i, j], "record": k, "system": i,
                              "kind": cases.KINDS.index(spec.kind)})
                rows.append(terms)
        print(f"  terms {k + 1} {record.name}", file=sys.stderr, flush=True)
    data = improved.stacked(rows)
    if len(done) == len(chosen):
        with open(path, "wb") as handle:
            pickle.dump(data, handle)
    return data


def light(data: dict) -> dict:
    """The terms with only the columns the forces need (story 1 of the shears and moments, the
    roof displacement as column 0, the drift ratios): the fit's objective, 5 times faster."""
    roof = np.take_along_axis(data["unit_displacement"], (data["n_floors"] - 1)[:, None, None], axis=2)
    return {**data, "unit_shear": data["unit_shear"][:, :, :1], "unit_moment": data["unit_moment"][:, :, :1],
            "unit_displacement": roof, "unit_drift": data["unit_drift"][:, :, :1],
            "unit_floor_acceleration": data["unit_floor_acceleration"][:, :, :1],
            "n_floors": np.ones_like(data["n_floors"])}


def predict(data: dict, coefficients) -> dict[str, np.ndarray]:
    """The improved procedure's compared values of every case (its bonded result where x <= 1)."""
    out = improved.combine_arrays(data, coefficients)
    values = {"base_shear": out["shear"][:, 0], "base_moment": out["moment"][:, 0],
              "drift_ratio": out["drift_ratio"].max(axis=1),
              "roof_displacement": out["displacement"][np.arange(data["x"].size), data["n_floors"] - 1],
              "floor_acceleration": out["floor_acceleration"].max(axis=1),
              "max_uplift": out["uplift"], "max_rotation": out["theta"]}
    lifting = data["x"] > 1.0
    return {name: np.where(lifting, value, data[f"bonded_{name}"]) for name, value in values.items()}


def bounded(vector: np.ndarray, names) -> tuple[dict, float]:
    """The coefficients clipped to improved.BOUNDS, and the squared distance clipped off."""
    values, outside = {}, 0.0
    for name, value in zip(names, vector, strict=True):
        low, high = improved.BOUNDS[name]
        values[name] = float(np.clip(value, low, high))
        outside += (value - values[name]) ** 2
    return values, outside


def objective(vector: np.ndarray, names, data, base) -> float:
    values, outside = bounded(vector, names)
    prediction = predict(data, replace(base, **values))
    loss = 10.0 * outside
    for name in FORCES:
        ratio = np.log(prediction[name] / data[f"exact_{name}"])
        for (low, high), weight in WEIGHTS:
            r = ratio[data["lifted"] & (data["T1"] >= low) & (data["T1"] < high) & np.isfinite(ratio)]
            q05, median, q80 = np.quantile(r, [0.05, 0.5, 0.8])
            shortfall = (max(np.log(0.83) - q05, 0.0) ** 2 + max(q80 - np.log(1.17), 0.0) ** 2
                         + max(np.log(0.99) - median, 0.0) ** 2 + max(median - np.log(1.06), 0.0) ** 2)
            loss += weight * (100.0 * shortfall + 0.1 * np.mean(r**2))
    return float(loss)


def fit_motion(data: dict, coefficients):
    """displacement_period: median simplified/exact mat rotation 1; then impact: IMPACT_LOW of
    the lifting cases' floor accelerations more than 20 % low."""
    lifted = data["lifted"]

    def rotation(value):
        ratio = predict(data, replace(coefficients, displacement_period=value))["max_rotation"] / \
            data["exact_max_rotation"]
        return float(np.median(ratio[lifted & np.isfinite(ratio)])) - 1.0

    coefficients = replace(coefficients, displacement_period=round(brentq(rotation, 0.01, 2.0, xtol=1e-4), 4))

    def acceleration(value):
        ratio = predict(data, replace(coefficients, impact=value))["floor_acceleration"] / \
            data["exact_floor_acceleration"]
        return float(np.mean(ratio[lifted] < 0.8)) - IMPACT_LOW

    return replace(coefficients, impact=round(brentq(acceleration, 0.0, 3.0, xtol=1e-4), 4))


def residual_table(data, coefficients) -> list[str]:
    """simplified/exact of every compared value on the lifting cases, by band (the fit's residuals)."""
    prediction = predict(data, coefficients)
    lines = ["| value, T_1 band | n | median | > 20 % low | > 20 % high | log sd |", "|---|---|---|---|---|---|"]
    for name in COMPARED:
        ratio = prediction[name] / data[f"exact_{name}"]
        for low, high in ((0.0, 0.2), (0.2, 0.5), (0.5, 1.0), (1.0, 3.01), (0.2, 3.01)):
            r = ratio[data["lifted"] & (data["T1"] >= low) & (data["T1"] < high) & np.isfinite(ratio) & (ratio > 0)]
            label = f"{max(low, PERIODS[0]):g}-{min(high, PERIODS[1]):g} s"
            lines.append(f"| {COMPARED[name].symbol}, {label} | {r.size} | {np.median(r):.3f} | "
                         f"{100 * np.mean(r < 0.8):.0f} % | {100 * np.mean(r > 1.2):.0f} % | {np.std(np.log(r)):.3f} |")
    return lines


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cache", type=Path, default=CACHE)
    parser.add_argument("--fit", default=",".join(improved.FITTED), help="coefficients of the forces to fit")
    args = parser.parse_args(argv)
    data = gather(args.cache)
    base = improved.COEFFICIENTS
    names = [n for n in args.fit.split(",") if n]
    print(f"cases: {data['x'].size}, lifting (exact engine): {int(data['lifted'].sum())}, lifting by the "
          f"simplified estimate: {int((data['x'] > 1).sum())}; fitted: {', '.join(names)}")
    print("start:", asdict(base))
    fitted = base
    if names:
        start = np.array([getattr(base, n) for n in names], dtype=float)
        reduced = light(data)
        fit = minimize(objective, start, args=(names, reduced, base), method="Nelder-Mead",
                       options={"maxiter": 1500, "xatol": 1e-3, "fatol": 1e-6})
        fitted = replace(base, **{k: round(v, 4) for k, v in bounded(fit.x, names)[0].items()})
        print(f"fit: loss {fit.fun:.5f} (start {objective(start, names, reduced, base):.5f}), "
              f"{fit.nit} iterations, {fit.message}")
    fitted = fit_motion(data, fitted)
    print("fitted:", asdict(fitted))
    print("\n".join(residual_table(data, fitted)))


if __name__ == "__main__":
    main()
