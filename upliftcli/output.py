"""Every file an analysis writes: the results document (JSON), the story table (CSV), the
TOML copy, and the response histories (CSV or NPZ). Each file is written atomically
(upliftcli.atomic): never half-written. SI units in every file; the units are listed in it.
"""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path
from typing import Any

import numpy as np

from .atomic import atomic_path, write_text
from .engines.result import AnalysisResult

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
    return json.dumps(results_document(results, source, title), indent=2) + "\n"


CSV_COLUMNS = ("engine", "support", "story", "height_m", "displacement_m", "drift_m", "drift_ratio",
               "shear_N", "moment_Nm")


def to_csv(results: list[AnalysisResult]) -> str:
    """Story tables of all results, one row per (engine, support, story); units in the headers."""
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
