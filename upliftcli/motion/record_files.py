"""Text of the records and of the manifest that `uplift record generate/match` write.

A record file is the plain-text format records.read_record detects ('text'): '#' header lines
(the name, `dt = ... s ; npts = ...`, `units: g`, then the provenance), then one acceleration
value per line in g with 7 significant digits. The manifest (JSON) states the target, the code
rule, the period range, the tolerance and, per record, its file, factor, PGA, duration, the
ratios S_a/target reached and whether the tolerance is met.
"""

from __future__ import annotations

import hashlib
import json
from typing import Any

import numpy as np

from ..units import STANDARD_GRAVITY
from .matching import MatchSettings
from .measures import character_change, measures
from .origins import COMMAND_ORIGINS
from .suites import Suite


def record_text(name: str, dt: float, acceleration: np.ndarray, provenance: list[str]) -> str:
    """The file text of one record: acceleration [m/s^2] at step dt [s], written in g."""
    values = np.asarray(acceleration, dtype=float) / STANDARD_GRAVITY
    header = [name, f"dt = {dt:.10g} s ; npts = {values.size}", "units: g (acceleration, one value per line)",
              *provenance]
    lines = [f"# {line}" for line in header] + [f"{value:.6e}" for value in values]
    return "\n".join(lines) + "\n"


def sha256(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def record_checks(suite: Suite, settings: MatchSettings) -> list[dict[str, Any]]:
    """Per scaled record: ratio_min, ratio_max of S_a/target over the check periods, PGA [g],
    duration [s], and whether it is within the tolerance (low, high x the matching target)."""
    target = suite.target.sa(suite.periods, suite.damping)
    rows = []
    for motion, spectrum in zip(suite.motions(), suite.spectra(), strict=True):
        ratios = spectrum / target
        low, high = settings.low * settings.reference, settings.high * settings.reference
        rows.append({"ratio_min": round(float(ratios.min()), 4), "ratio_max": round(float(ratios.max()), 4),
                     "tolerance_met": bool(ratios.min() >= low * (1 - 1e-9) and ratios.max() <= high * (1 + 1e-9)),
                     "pga_g": round(motion.pga / STANDARD_GRAVITY, 4), "duration_s": round(motion.duration, 4),
                     "dt_s": motion.dt})
    return rows


def measure_row(motion) -> dict[str, float]:
    """What a record looks like (measures.py): zero crossings [1/s], Fourier ratio 15-40 / 1-3 Hz,
    D5-95 [s], the larger end sample / PGA."""
    m = measures(motion.acceleration, motion.dt)
    return {"zero_crossings_per_s": round(m.zero_crossings, 3), "fourier_ratio_15_40_hz": round(m.fourier_ratio, 4),
            "d5_95_s": round(m.d5_95, 3), "end_offset": round(m.end_offset, 5)}


def character_row(original, matched) -> dict[str, float]:
    """What matching changed (measures.character_change) in a record: D5-95 ratio, net early gain
    of the Arias intensity, PGV and PGD ratios (the original scaled to the matched record's Arias
    intensity)."""
    change = character_change(original.acceleration, matched.acceleration, matched.dt)
    return {"d5_95_ratio": round(change.d5_95_ratio, 4), "early_arias_gain": round(change.early_gain, 5),
            "pgv_ratio": round(change.pgv_ratio, 4), "pgd_ratio": round(change.pgd_ratio, 4)}


def model_row(parameters) -> dict[str, float]:
    """The filter of an artificial record (generate.FilterParameters), rounded."""
    return {key: round(float(value), 5) for key, value in vars(parameters).items()}


def manifest_text(suite: Suite, settings: MatchSettings, command: str, deck: str, records: list[dict[str, Any]],
                  extra: dict[str, Any] | None = None) -> str:
    """The manifest of a written suite (JSON): `records` are per-record rows (file, name, factor,
    ... merged with record_checks)."""
    mean = suite.mean_ratio()
    minimum = suite.mean_minimum
    document = {
        "tool": "uplift", "command": command, "made": COMMAND_ORIGINS[command], "deck": deck,
        "target": suite.target.name, "damping": suite.damping,
        "statistics": suite.rule.name, "rule": suite.rule.label, "statistic": suite.statistic,
        "period_range_s": [round(value, 6) for value in suite.period_range], "period_range_note": suite.period_note,
        "tolerance": {"low": settings.low, "high": settings.high,
                      "relative_to": f"{settings.reference:g} x target", "check_periods": int(suite.periods.size),
                      "periods_per_octave": settings.periods_per_octave},
        "mean_ratio_min": round(float(mean.min()), 4), "mean_rule": minimum,
        "mean_rule_met": bool(mean.min() >= minimum * (1 - 1e-9)),
        **(extra or {}),
        "warnings": list(suite.warnings),
        "records": records,
    }
    return json.dumps(document, indent=2) + "\n"
