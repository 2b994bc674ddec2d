"""Warnings of the simplified engine: conditions under which its result cannot be right, or
leaves the range design codes accept (docs/accuracy.md, warnings). Each is one line of text
for result.details["warnings"]; nothing here changes a result or the exit code.

- uplift: the mat lifts and V_b exceeds the bonded or the rigid-base V_b of the same
  procedure (uplift limits the fundamental-mode base shear; a larger value comes from X
  built with m_t where m_1* < m_t, Eq. 28a, and is not physical);
- uplift: M_b above MOMENT_LIMIT x M_c (M_c = m_t g b [16b], or the bearing capacity's, docs/theory.md
  14.4) for T_1 >= MOMENT_PERIOD = 0.5 s
  (docs/accuracy.md gives the exact engine's distribution of M_b/M_c that sets the limit;
  at shorter periods impacts make larger moments real);
- bonded or uplift: xi1bar above CODE_DAMPING_MAX, the largest flexible-base damping ASCE 7-22
  section 19.3 admits (a design code's bound). xi1bar below the fixed-base xi_1 (Eq. 23 discounts
  xi_1 by (T_1/T1bar)^3) happens on most decks: it is the intermediate "xi1bar/xi1", not a warning.
  The paper's value is kept and reported.
The effective-period iteration that does not converge is reported where it happens
(model/interaction.py, frequency_warning).
"""

from __future__ import annotations

from ..model.system import System
from .options import SimplifiedOptions
from .paper import paper_analyze
from .result import AnalysisResult

#: largest M_b / M_c of an uplifting simplified result taken as plausible [-], for T_1 of at least
#: MOMENT_PERIOD [s] (where the exact engine never exceeded 1.8 M_c in the study of docs/accuracy.md);
#: at shorter periods impacts at recontact make the exact M_b reach many times M_c
MOMENT_LIMIT = 2.0
MOMENT_PERIOD = 0.5
#: largest flexible-base damping ratio admitted by ASCE 7-22 section 19.3 [-]
CODE_DAMPING_MAX = 0.20
#: relative margin below which two values are taken as equal (rounding)
MARGIN = 1e-9


def warnings(system: System, spectrum, support: str, options: SimplifiedOptions,
             result: AnalysisResult) -> list[str]:
    """The warning lines for one simplified result (empty when none applies), the design
    spectrum's for a modal procedure among them (design_spectra.procedure_warning)."""
    from ..motion.design_spectra import procedure_warning

    lines: list[str] = []
    if support == "uplift" and result.uplift:
        lines.extend(_above_references(system, spectrum, options, result))
        lines.extend(_moment_above_limit(system, result))
    if support != "rigid" and "xi1bar" in result.intermediates:
        lines.extend(_damping_above_code(float(result.intermediates["xi1bar"])))
    if message := procedure_warning(spectrum, "modal"):
        lines.append(message)
    return lines


def _above_references(system: System, spectrum, options: SimplifiedOptions, result: AnalysisResult) -> list[str]:
    """An uplift V_b above the bonded or the rigid-base V_b of the paper's procedure: the paper's X built
    with m_t can exceed them (the improved procedure has its own accuracy check)."""
    lines = []
    for other in ("bonded", "rigid") if options.procedure == "paper" else ():
        reference = paper_analyze(system, spectrum, other, options).base_shear
        if result.base_shear > reference * (1 + MARGIN):
            lines.append(
                f"uplift V_b = {result.base_shear:.4g} N is above the {other} V_b = {reference:.4g} N "
                f"({result.base_shear / reference:.3g}x): uplift cannot raise the base shear, the estimate is "
                "not physical (the paper's X assumes m_1* = m_t; try analysis.procedure = \"improved\" or "
                "analysis.uplift_x = \"mass-consistent\")")
    return lines


def _moment_above_limit(system: System, result: AnalysisResult) -> list[str]:
    """An uplift M_b above MOMENT_LIMIT M_c for T_1 >= MOMENT_PERIOD (module docstring)."""
    ratio = result.base_moment / system.critical_base_moment
    # T_1 = 0.5 s as the deck gives it is solved as 0.499999999999995 s: compared with a margin
    if not (ratio > MOMENT_LIMIT and float(system.modes.periods[0]) >= MOMENT_PERIOD * (1 - MARGIN)):
        return []
    elastic = getattr(system.foundation, "capacity", None) is None
    given = "m_t g b" if elastic else "the bearing capacity's, docs/theory.md 14.4"
    return [f"uplift M_b = {ratio:.3g} M_c is above {MOMENT_LIMIT:g} M_c (M_c = {given} = "
            f"{system.critical_base_moment:.4g} N m): for T_1 >= {MOMENT_PERIOD:g} s the exact engine did not "
            "exceed 1.8 M_c in the study of docs/accuracy.md; check it with the exact engine"]


def _damping_above_code(xi1bar: float) -> list[str]:
    """xi1bar above CODE_DAMPING_MAX, the largest flexible-base damping ASCE 7-22 section 19.3 admits."""
    if not xi1bar > CODE_DAMPING_MAX:
        return []
    return [f"xi1bar = {xi1bar:.4g} is above {CODE_DAMPING_MAX:g}, the largest flexible-base damping "
            "ASCE 7-22 section 19.3 admits; the paper's value is used"]
