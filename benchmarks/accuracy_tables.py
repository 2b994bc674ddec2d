"""Markdown tables of the accuracy study (benchmarks/accuracy.py; docs/accuracy.md): two-sided
statistics of simplified/exact per compared value (engines/quantities.COMPARED), T_1 band and
foundation type, the goals of issue 25, how often the exact uplift response exceeds the bonded
one, how often the accuracy check warns, the warnings given and the exact M_b/M_c.

`data` is what accuracy.collect returns for one set of records: "exact" and each procedure, a
list over the records of {support: {name: array (systems, periods)}}, with "periods" and "specs".
"""

from __future__ import annotations

import accuracy_cases as cases
import numpy as np

from upliftcli.analysis.accuracy import DEFAULT_BAND, DEFAULT_MOTION_BAND
from upliftcli.analysis.accuracy import MOTION as CHECK_MOTION
from upliftcli.engines.quantities import COMPARED

#: T_1 bands [s]; the goals of issue 25 apply from 0.2 s up
BANDS = ((0.1, 0.2), (0.2, 0.5), (0.5, 1.0), (1.0, 3.01))
ABOVE = (0.2, 3.01)
#: the values the two-sided goals apply to, and those of the motion of the mat
FORCES = ("base_shear", "base_moment", "drift_ratio", "roof_displacement")
MOTION = ("max_uplift", "max_rotation")
#: warning flags recorded per case: name -> words of the warning line (engines/plausibility.py)
WARNINGS = {"above bonded": "above the bonded V_b", "above rigid": "above the rigid V_b", "M_b": " M_c is above",
            "xi1bar > 0.20": "largest flexible-base damping"}
HEAD = ("| value, cases | n | median | > 20 % low | > 20 % high | 5-95 % |", "|---|---|---|---|---|---|")


def stack(items: list[dict], support: str, name: str) -> np.ndarray:
    return np.stack([item[support][name] for item in items])


def label(band: tuple[float, float]) -> str:
    return f"{band[0]:g}-{min(band[1], 3.0):g} s"


def grids(data: dict, shape) -> tuple[np.ndarray, np.ndarray]:
    """(T_1, foundation kind index) of every case, broadcast to (records, systems, periods)."""
    periods = np.broadcast_to(data["periods"], shape)
    kinds = np.array([cases.KINDS.index(spec.kind) for spec in data["specs"]])
    return periods, np.broadcast_to(kinds[None, :, None], shape)


def spread(values: np.ndarray, low: float, high: float, quantiles: tuple[float, float]) -> dict:
    """n, median, the shares below `low` and above `high`, and two quantiles ("quantiles") of
    values: ratios simplified/exact (statistics) or their logarithms (accuracy_floor.summary)."""
    first, second = np.quantile(values, quantiles)
    return {"n": values.size, "median": float(np.median(values)), "low": float(np.mean(values < low)),
            "high": float(np.mean(values > high)), "quantiles": (float(first), float(second))}


def statistics(ratio: np.ndarray) -> dict:
    """spread of the finite positive ratios: shares more than 20 % low and high, 5 % and 95 % quantiles."""
    ratio = ratio[np.isfinite(ratio) & (ratio > 0)]
    if ratio.size == 0:
        return {"n": 0}
    stats = spread(ratio, 0.8, 1.2, (0.05, 0.95))
    stats["q05"], stats["q95"] = stats.pop("quantiles")
    return stats


def row(text: str, stats: dict) -> str:
    if not stats["n"]:
        return f"| {text} | 0 | | | | |"
    return (f"| {text} | {stats['n']} | {stats['median']:.3f} | {100 * stats['low']:.0f} % | "
            f"{100 * stats['high']:.0f} % | {stats['q05']:.2f}-{stats['q95']:.2f} |")


def ratios(data: dict, procedure: str, support: str, name: str) -> np.ndarray:
    return stack(data[procedure], support, name) / stack(data["exact"], support, name)


def ratio_table(data: dict, procedure: str, support: str, title: str, lifting: bool) -> list[str]:
    """simplified/exact of every compared value of the support: each band, T_1 >= 0.2 s, and each
    foundation type from 0.2 s (lifting: only the cases where the exact engine lifts the mat)."""
    lines = [f"**{title}**", "", *HEAD]
    for name, quantity in COMPARED.items():
        if support not in quantity.supports:
            continue
        ratio = ratios(data, procedure, support, name)
        keep = stack(data["exact"], support, "lifted") if lifting else np.ones(ratio.shape, bool)
        periods, kinds = grids(data, ratio.shape)
        for band in (*BANDS, ABOVE):
            where = keep & (periods >= band[0]) & (periods < band[1])
            lines.append(row(f"{quantity.symbol}, {label(band)}" + (" (all)" if band == ABOVE else ""),
                             statistics(ratio[where])))
        for k, kind in enumerate(cases.KINDS):
            where = keep & (periods >= ABOVE[0]) & (kinds == k)
            lines.append(row(f"{quantity.symbol}, {label(ABOVE)}, {kind}", statistics(ratio[where])))
    return [*lines, ""]


def goal_checks(name: str, stats: dict) -> list[tuple[str, bool]]:
    """(goal, met) of issue 25 for one value's statistics."""
    if name in FORCES:
        return [("median in [0.95, 1.10]", 0.95 <= stats["median"] <= 1.10), ("<= 5 % low", stats["low"] <= 0.05),
                ("<= 20 % high", stats["high"] <= 0.20)]
    if name == "floor_acceleration":
        return [("<= 10 % low", stats["low"] <= 0.10)]
    return [("median in [0.8, 1.25]", 0.8 <= stats["median"] <= 1.25)]


def goal_table(data: dict, procedure: str, title: str) -> list[str]:
    """The goals of issue 25 on the cases where the exact engine lifts the mat: forces from 0.2 s
    (also per band), floor acceleration and the mat's motion at every T_1."""
    lines = [f"**Goals of issue 25, {title}, procedure `{procedure}`** (cases where the exact engine lifts the mat)",
             "", "| value, cases | n | median | > 20 % low | > 20 % high | goals | met |",
             "|---|---|---|---|---|---|---|"]
    lifted = stack(data["exact"], "uplift", "lifted")
    for name in (*FORCES, "floor_acceleration", *MOTION):
        ratio = ratios(data, procedure, "uplift", name)
        periods, _ = grids(data, ratio.shape)
        bands = (ABOVE, *BANDS[1:]) if name in FORCES else ((0.0, 3.01),)
        for band in bands:
            stats = statistics(ratio[lifted & (periods >= band[0]) & (periods < band[1])])
            if stats["n"]:
                lines.append(goal_row(name, band, stats))
    return [*lines, ""]


def goal_row(name: str, band: tuple[float, float], stats: dict) -> str:
    """A row of goal_table: the statistics of a value in a T_1 band, its goals and whether they are met."""
    checks = goal_checks(name, stats)
    met = "yes" if all(ok for _, ok in checks) else "no (" + ", ".join(g for g, ok in checks if not ok) + ")"
    text = "all T_1" if band[0] == 0.0 else label(band)
    return (f"| {COMPARED[name].symbol}, {text} | {stats['n']} | {stats['median']:.3f} | "
            f"{100 * stats['low']:.1f} % | {100 * stats['high']:.1f} % | "
            f"{'; '.join(g for g, _ in checks)} | {met} |")


def exceedance_table(data: dict) -> list[str]:
    """How often the exact uplift value exceeds the exact bonded one where the mat lifts: why the
    improved procedure caps nothing."""
    lifted = stack(data["exact"], "uplift", "lifted")
    lines = ["| value | " + " | ".join(label(b) for b in BANDS) + " | max ratio |", "|---|" + "---|" * (len(BANDS) + 1)]
    for name in ("base_shear", "base_moment", "drift_ratio", "floor_acceleration"):
        ratio = stack(data["exact"], "uplift", name) / stack(data["exact"], "bonded", name)
        periods, _ = grids(data, ratio.shape)
        shares = [100 * float(np.mean(ratio[lifted & (periods >= lo) & (periods < hi)] > 1.0)) for lo, hi in BANDS]
        lines.append(f"| {COMPARED[name].symbol} | " + " | ".join(f"{s:.0f} %" for s in shares)
                     + f" | {np.nanmax(ratio[lifted]):.2f} |")
    return [*lines, ""]


def check_table(data: dict, procedure: str = "improved") -> list[str]:
    """How often the accuracy check of `uplift analyze` (default bands) warns on a lifting case, for
    at least one compared value and per value, by band."""
    lifted = stack(data["exact"], "uplift", "lifted")
    outside = {}
    for name in COMPARED:
        low, high = DEFAULT_MOTION_BAND if name in CHECK_MOTION else DEFAULT_BAND
        ratio = ratios(data, procedure, "uplift", name)
        outside[name] = np.isfinite(ratio) & ~((ratio >= low) & (ratio <= high))
    periods, _ = grids(data, lifted.shape)
    lines = ["| value | " + " | ".join(label(b) for b in BANDS) + " |", "|---|" + "---|" * len(BANDS)]
    for name, flags in (("any", np.any(list(outside.values()), axis=0)), *outside.items()):
        text = "at least one" if name == "any" else COMPARED[name].symbol
        shares = [100 * float(np.mean(flags[lifted & (periods >= lo) & (periods < hi)])) for lo, hi in BANDS]
        lines.append(f"| {text} | " + " | ".join(f"{s:.0f} %" for s in shares) + " |")
    return [*lines, ""]


def warning_table(data: dict, procedures) -> list[str]:
    """How often each warning of the simplified engine is given, per procedure and support."""
    lines = ["| procedure, support | " + " | ".join(WARNINGS) + " |", "|---|" + "---|" * len(WARNINGS)]
    for procedure in procedures:
        for support in ("bonded", "uplift"):
            shares = [100 * float(np.mean(stack(data[procedure], support, w))) for w in WARNINGS]
            lines.append(f"| {procedure}, {support} | " + " | ".join(f"{v:.1f} %" for v in shares) + " |")
    return [*lines, ""]


def moment_table(data: dict) -> list[str]:
    """Quantiles of the exact M_b/M_c where the exact engine lifts the mat (sets plausibility.MOMENT_LIMIT)."""
    specs, periods = data["specs"], data["periods"]
    m_c = np.array([[cases.build(spec, t).critical_base_moment for t in periods] for spec in specs])
    ratio = stack(data["exact"], "uplift", "base_moment") / m_c[None]
    lifted = stack(data["exact"], "uplift", "lifted")
    grid, _ = grids(data, ratio.shape)
    lines = ["| T_1 band | n | median | 90 % | 95 % | 99 % | max | share above 2 |",
             "|---|---|---|---|---|---|---|---|"]
    for band in (*BANDS, (0.0, 3.01)):
        r = ratio[lifted & (grid >= band[0]) & (grid < band[1]) & np.isfinite(ratio)]
        if r.size:
            q = np.quantile(r, [0.5, 0.9, 0.95, 0.99])
            lines.append(f"| {'all' if band[0] == 0.0 else label(band)} | {r.size} | "
                         + " | ".join(f"{v:.2f}" for v in q) + f" | {r.max():.2f} | {100 * np.mean(r > 2.0):.1f} % |")
    return [*lines, ""]
