"""ASCE 7-22's linear design values of a result (engines/design.py, docs/theory.md 16) as a table: per story
(top first) the design shear, the elastic and the design drift ratio, the allowable one of Table 12.12-1 and
the verdict. The report's table here; the terminal's (cli/render_design.py) has the same rows."""

from __future__ import annotations

from ..display import label, show
from ..engines.design import has_design
from ..engines.result import AnalysisResult
from .document import Table

#: the table's note: where each column comes from
NOTE = ("Design shear = elastic x Ie/R (ASCE 7-22 12.9.1.2); design drift ratio = C_d/R x elastic (12.8.6, "
        "12.9.1.2); allowable: Table 12.12-1 (12.12.1); not scaled to the equivalent lateral force base shear "
        "(12.9.1.4: docs/theory.md 16).")


def headers(units: str = "si") -> list[str]:
    return ["story", f"design shear [{label('N', units)}]", "elastic drift ratio [%]", "design drift ratio [%]",
            "allowable [%]", "verdict"]


def title(result: AnalysisResult, units: str = "si") -> str:
    """'ASCE 7-22 design values (simplified, rigid): R = 8, C_d = 5.5, I_e = 1.25, risk category III,
    all-other; design base shear V = 337.3 kN'."""
    design = result.details.get("design", {})
    return (f"ASCE 7-22 design values ({getattr(result, 'label', result.engine)}, {result.support}): "
            f"R = {design.get('R'):g}, C_d = {design.get('Cd'):g}, I_e = {design.get('Ie'):g}, risk category "
            f"{design.get('risk_category')}, {design.get('structure')}; design base shear V = "
            f"{show(result.peaks['design_base_shear'][0], 'N', units)} {label('N', units)}")


def rows(result: AnalysisResult, units: str = "si") -> list[list[str]]:
    """One row per story, top first (cells)."""
    return [_cells(result, j, units) for j in range(result.elevations.size - 1, -1, -1)]


def _cells(result: AnalysisResult, j: int, units: str) -> list[str]:
    """Story j+1: design shear, elastic and design drift ratio, the allowable one and ok / exceeds."""
    allowable = result.peaks.get("allowable_drift_ratio")
    design = result.peaks["design_drift_ratio"][j]
    limit = "no limit" if allowable is None else show(allowable[0], "%", units)
    verdict = "-" if allowable is None else ("exceeds" if design > allowable[0] else "ok")
    return [str(j + 1), show(result.peaks["design_shear"][j], "N", units),
            show(result.peaks["drift_ratio"][j], "%", units), show(design, "%", units), limit, verdict]


def design_table(result: AnalysisResult, units: str = "si") -> Table | None:
    """The report's table of the design values, None for a result without them."""
    if not has_design(result):
        return None
    return Table(f"table-{result.engine}-{result.support}-design", title(result, units), headers(units),
                 rows(result, units), NOTE)
