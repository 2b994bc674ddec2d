"""Result type shared by every engine, and the modal combination rules [35].

All quantities SI: m, N, N m, s. Story j joins floor j-1 and floor j (floor 0 is the mat).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass
class AnalysisResult:
    """Peak response of one analysis (one engine, one support condition).

    heights: floor heights above the mat [m], (N,).
    displacement: peak floor displacement relative to the mat [m], (N,).
    drift: peak story drift u_j - u_{j-1} [m], (N,).
    drift_ratio: peak drift / story height [-], (N,).
    shear: peak story shear [N], (N,) (shear[0] is the base shear).
    moment: peak overturning moment at the bottom of story j [N m], (N,).
    base_shear, base_moment: peaks at the base [N], [N m].
    critical_base_shear, critical_base_moment: V_c, M_c [N], [N m] [16a, 16b].
    weight: m_t g [N]; effective_height: h_1* [m].
    uplift: whether the mat lifts off (always False for rigid and bonded).
    periods: fixed-base periods T_n [s] of the modes used.
    intermediates: named scalar or list values an engineer checks by hand
        (T1bar, xi1bar, V_c, zeta, ... for the simplified engine).
    details: engine-specific extras (times of peaks, uplift summary, energy balance ...).
    """

    engine: str
    support: str
    heights: np.ndarray
    displacement: np.ndarray
    drift: np.ndarray
    drift_ratio: np.ndarray
    shear: np.ndarray
    moment: np.ndarray
    base_shear: float
    base_moment: float
    critical_base_shear: float
    critical_base_moment: float
    weight: float
    effective_height: float
    uplift: bool
    periods: np.ndarray
    intermediates: dict[str, Any] = field(default_factory=dict)
    details: dict[str, Any] = field(default_factory=dict)

    @property
    def base_shear_coefficient(self) -> float:
        """V_b / (m_t g) [-]."""
        return self.base_shear / self.weight

    @property
    def base_moment_coefficient(self) -> float:
        """M_b / (m_t g h_1*) [-]."""
        return self.base_moment / (self.weight * self.effective_height)

    @property
    def critical_coefficient(self) -> float:
        """b / h_1* [-], the critical value of both coefficients."""
        return self.critical_base_shear / self.weight


def srss(modal_peaks: np.ndarray) -> np.ndarray:
    """Square root of the sum of squares over the first axis (modes) [35]."""
    peaks = np.asarray(modal_peaks, dtype=float)
    return np.sqrt(np.sum(peaks**2, axis=0))


def cqc_correlation(omega: np.ndarray, damping: np.ndarray) -> np.ndarray:
    """Der Kiureghian's CQC correlation coefficients rho_ij for frequencies [rad/s] and damping [-]."""
    w = np.asarray(omega, dtype=float)
    xi = np.broadcast_to(np.asarray(damping, dtype=float), w.shape)
    r = w[None, :] / w[:, None]
    xi_i, xi_j = xi[:, None], xi[None, :]
    numerator = 8.0 * np.sqrt(xi_i * xi_j) * (xi_i + r * xi_j) * r**1.5
    denominator = (1.0 - r**2) ** 2 + 4.0 * xi_i * xi_j * r * (1.0 + r**2) + 4.0 * (xi_i**2 + xi_j**2) * r**2
    with np.errstate(invalid="ignore", divide="ignore"):
        rho = np.where(denominator > 0.0, numerator / denominator, 1.0)
    np.fill_diagonal(rho, 1.0)
    return rho


def cqc(modal_peaks: np.ndarray, omega: np.ndarray, damping: np.ndarray) -> np.ndarray:
    """Complete quadratic combination over the first axis (modes), signed modal peaks."""
    peaks = np.asarray(modal_peaks, dtype=float)
    rho = cqc_correlation(omega, damping)
    flat = peaks.reshape(peaks.shape[0], -1)
    total = np.einsum("ik,ij,jk->k", flat, rho, flat)
    return np.sqrt(np.maximum(total, 0.0)).reshape(peaks.shape[1:])


# ----------------------------------------------------------------------------- writers

#: units of the result fields in the written files (SI)
UNITS = {
    "height": "m", "displacement": "m", "drift": "m", "drift_ratio": "-", "shear": "N", "moment": "N m",
    "base_shear": "N", "base_moment": "N m", "critical_base_shear": "N", "critical_base_moment": "N m",
    "weight": "N", "effective_height": "m", "periods": "s", "base_shear_coefficient": "-",
    "base_moment_coefficient": "-", "critical_coefficient": "-",
}


def to_jsonable(value: Any) -> Any:
    """numpy scalars/arrays -> floats/lists, non-finite floats -> None, recursively."""
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return to_jsonable(value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        value = float(value)
        return value if np.isfinite(value) else None
    return value


def result_to_dict(result: AnalysisResult) -> dict[str, Any]:
    """JSON-ready summary and story table of one result (SI units, see UNITS)."""
    stories = [
        {"story": j + 1, "height": result.heights[j], "displacement": result.displacement[j],
         "drift": result.drift[j], "drift_ratio": result.drift_ratio[j], "shear": result.shear[j],
         "moment": result.moment[j]}
        for j in range(result.heights.size)
    ]
    return to_jsonable({
        "engine": result.engine,
        "support": result.support,
        "base_shear": result.base_shear,
        "base_shear_coefficient": result.base_shear_coefficient,
        "base_moment": result.base_moment,
        "base_moment_coefficient": result.base_moment_coefficient,
        "critical_base_shear": result.critical_base_shear,
        "critical_base_moment": result.critical_base_moment,
        "critical_coefficient": result.critical_coefficient,
        "weight": result.weight,
        "effective_height": result.effective_height,
        "uplift": result.uplift,
        "periods": result.periods,
        "stories": stories,
        "intermediates": result.intermediates,
        "details": result.details,
    })


def results_document(results: list[AnalysisResult], source: str | None = None,
                     title: str | None = None) -> dict[str, Any]:
    """The document `--format json` prints: one result -> that result's dict (plus source,
    title, units); several -> {"source", "title", "units", "results": [...]}."""
    head = {"source": source, "title": title, "units": UNITS}
    head = {k: v for k, v in head.items() if v is not None}
    if len(results) == 1:
        return {**head, **result_to_dict(results[0])}
    return {**head, "results": [result_to_dict(result) for result in results]}


def to_json(results: list[AnalysisResult], source: str | None = None, title: str | None = None) -> str:
    import json

    return json.dumps(results_document(results, source, title), indent=2) + "\n"


CSV_COLUMNS = ("engine", "support", "story", "height_m", "displacement_m", "drift_m", "drift_ratio",
               "shear_N", "moment_Nm")


def to_csv(results: list[AnalysisResult]) -> str:
    """Story tables of all results, one row per (engine, support, story); units in the headers."""
    import csv
    import io

    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    for result in results:
        for j in range(result.heights.size):
            writer.writerow([result.engine, result.support, j + 1] + [
                repr(float(x)) for x in (result.heights[j], result.displacement[j], result.drift[j],
                                         result.drift_ratio[j], result.shear[j], result.moment[j])])
    return buffer.getvalue()


def _drop_none(value: Any) -> Any:
    """TOML has no null: drop None entries of tables, keep list positions as NaN."""
    if isinstance(value, dict):
        return {k: _drop_none(v) for k, v in value.items() if v is not None}
    if isinstance(value, list):
        return [float("nan") if v is None else _drop_none(v) for v in value]
    return value


def to_toml(results: list[AnalysisResult], source: str | None = None, title: str | None = None) -> str:
    """TOML document {source, title, units, results = [[...]]} (tomli-w)."""
    import tomli_w

    head = {"source": source, "title": title, "units": UNITS}
    document = {**head, "results": [result_to_dict(result) for result in results]}
    return tomli_w.dumps(_drop_none(to_jsonable(document)))


def write_results(results: list[AnalysisResult], directory, stem: str, source: str | None = None,
                  title: str | None = None) -> list:
    """Write <stem>.json, <stem>.csv and <stem>.toml into directory, each atomically; return the paths.

    All three texts are built before the first file is written, so a failure leaves no file."""
    from pathlib import Path

    from ..atomic import write_text

    directory = Path(directory)
    texts = {
        directory / f"{stem}.json": to_json(results, source, title),
        directory / f"{stem}.csv": to_csv(results),
        directory / f"{stem}.toml": to_toml(results, source, title),
    }
    for path, text in texts.items():
        write_text(path, text)
    return list(texts)


#: units of the history columns written by --histories
HISTORY_UNITS = {
    "time": "s", "ground_acceleration": "m/s2", "base_shear": "N", "base_moment": "N m",
    "roof_displacement": "m", "theta": "rad", "v": "m", "left_edge_displacement": "m",
    "right_edge_displacement": "m", "contact_state": "bitmask: bit i set = element i lifted",
}


def write_histories(path, histories: dict[str, np.ndarray]) -> None:
    """Write response histories atomically: NPZ if the name ends in .npz, else CSV with units
    in the header (drift_j columns in m)."""
    from pathlib import Path

    from ..atomic import atomic_path, write_text

    path = Path(path)
    if path.suffix.lower() == ".npz":
        with atomic_path(path) as tmp:
            with open(tmp, "wb") as handle:
                np.savez_compressed(handle, **histories)
        return
    names = list(histories)
    header = ",".join(f"{name} [{HISTORY_UNITS.get(name, 'm')}]" for name in names)
    table = np.column_stack([np.asarray(histories[name], dtype=float) for name in names])
    lines = [header] + [",".join(f"{value:.10g}" for value in row) for row in table]
    write_text(path, "\n".join(lines) + "\n")
