"""ASCE 7-22's linear procedure on the simplified engine's result (docs/theory.md section 16): with the
deck's design values (model/design.Design), the design forces and the design story drifts of a modal
response spectrum analysis, and the allowable story drift they are judged against.

- design forces (12.9.1.2): each mode's forces from the spectrum divided by R/Ie, so the combined
  story shears are the elastic ones x Ie/R (`design_shear`, `design_base_shear`);
- design story drifts (12.9.1.2 with 12.8.6, Eq. 12.8-15: delta_x = C_d delta_xe / Ie): the drifts of
  the design forces x C_d/Ie, i.e. the elastic story drift ratios x C_d/R (`design_drift_ratio`; the
  drift of each story combined over the modes, 12.9.1.3, as the engine combines it);
- the allowable story drift ratio Delta_a/h_sx of Table 12.12-1 (12.12.1; `allowable_drift_ratio`).

Not applied: the scaling of 12.9.1.4 to the equivalent lateral force base shear (forces, 12.9.1.4.1;
drifts where Eq. 12.8-6 governs, 12.9.1.4.2), which needs the ELF base shear V = C_s W of 12.8.1 with
the period limit C_u T_a of 12.8.2 (the structure's system and height parameters of Table 12.8-2,
not in a deck): the design forces here are the unscaled modal ones. R and C_d apply at the design
level (11.4.5): a result at MCE_R (analysis/level.py) is given none, with a warning; so is one of a
deck whose [design] gives no R and C_d (a chapter 16 deck's may not).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..model.design import Design
from .quantities import DESIGN
from .result import AnalysisResult

#: the warning of a result at MCE_R on a deck with [design]
NO_FACTORS_WARNING = ("[design]: no design values: the linear procedure needs design.R and design.Cd (ASCE 7-22 "
                      "12.9.1.2; docs/theory.md 16)")
MCE_R_WARNING = ("[design]: no design values at the MCE_R level: R and C_d apply to the design-level spectrum "
                 "(ASCE 7-22 12.9.1.2, 11.4.5: 2/3 of MCE_R); give ground_motion.design_spectrum.level = \"design\" "
                 "for the linear procedure (docs/theory.md 16)")


def with_design(result: AnalysisResult, design: Design | None) -> AnalysisResult:
    """The simplified engine's result with the design values of `design` in its peaks (quantities.DESIGN)
    and the values used in details["design"]; at MCE_R, or without R and C_d, a warning instead; any other
    result (another engine, no [design]) as it is."""
    if design is None or result.engine != "simplified":
        return result
    if result.details.get("level", {}).get("level") == "mce_r":
        return _warned(result, MCE_R_WARNING)
    if not design.linear:
        return _warned(result, NO_FACTORS_WARNING)
    details = {**result.details, "design": design.to_dict()}
    return replace(result, peaks={**result.peaks, **design_peaks(result, design)}, details=details)


def _warned(result: AnalysisResult, warning: str) -> AnalysisResult:
    """The result with `warning` after its own."""
    return replace(result, details={**result.details, "warnings": [*result.details.get("warnings", []), warning]})


def design_peaks(result: AnalysisResult, design: Design) -> dict[str, np.ndarray]:
    """design_shear, design_drift_ratio, design_base_shear and (where Table 12.12-1 sets one)
    allowable_drift_ratio of an elastic result."""
    shear = np.abs(np.asarray(result.peaks["shear"], dtype=float))
    peaks = {"design_shear": shear * design.force_factor,
             "design_drift_ratio": np.abs(np.asarray(result.peaks["drift_ratio"], dtype=float)) * design.drift_factor,
             "design_base_shear": shear[:1] * design.force_factor}
    allowable = design.allowable_drift_ratio(len(shear))
    if allowable is not None:
        peaks["allowable_drift_ratio"] = np.array([allowable])
    return peaks


def has_design(result: AnalysisResult) -> bool:
    """Whether the result carries design values (a simplified result of a deck with [design])."""
    return "design_drift_ratio" in result.peaks


def drift_exceedances(result: AnalysisResult) -> list[int]:
    """The stories (from 1) whose design drift ratio exceeds the allowable one (none without either)."""
    allowable = result.peaks.get("allowable_drift_ratio")
    drifts = result.peaks.get("design_drift_ratio")
    if allowable is None or drifts is None:
        return []
    return [j + 1 for j in np.flatnonzero(drifts > allowable[0])]


#: the units of the design values in a results document that has them (output.file_units)
DESIGN_UNITS = {q.name: q.unit for q in DESIGN.values()}


def design_scalars(result: AnalysisResult) -> dict[str, float | None]:
    """The design values of a whole result as the results document writes them: design_base_shear [N] and
    allowable_drift_ratio (None: no limit, Table 12.12-1 footnote c); {} for a result without them."""
    if "design_base_shear" not in result.peaks:
        return {}
    allowable = result.peaks.get("allowable_drift_ratio")
    return {"design_base_shear": float(result.peaks["design_base_shear"][0]),
            "allowable_drift_ratio": None if allowable is None else float(allowable[0])}
