"""The level of an ASCE 7-22 spectrum: design or MCE_R, and the target of a chapter 16 suite.

ASCE 7-22 11.4.5 defines the design spectrum as 2/3 of the risk-targeted maximum considered
earthquake (MCE_R) spectrum (S_DS = 2/3 S_MS, S_D1 = 2/3 S_M1), and chapter 16 selects, scales
and matches the records of a response-history analysis to the MCE_R spectrum (16.2.1). A deck's
ASCE 7-22 spectrum says which it gives, `level = "design"` (the default: S_DS and S_D1, the
USGS multiPeriodDesignSpectrum) or `"mce_r"` (the same keys holding S_MS, S_M1, the
multiPeriodMCErSpectrum). The suite rule of ASCE 7-22 then takes as its target the MCE_R
spectrum: the given one, or MCE_R_FACTOR = 1.5 x the design spectrum, a factor stated in the
target's name. Other codes' spectra are their own targets.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

#: the spectrum levels a deck names
LEVELS = ("design", "mce_r")
#: MCE_R / design (ASCE 7-22 11.4.5: the design spectrum is 2/3 of the MCE_R spectrum)
MCE_R_FACTOR = 1.5


@dataclass(frozen=True)
class ScaledSpectrum:
    """`factor` x a design spectrum (any object with .sa, .name, .period_range), named `label`."""

    spectrum: Any
    factor: float
    label: str
    level: str = "mce_r"

    @property
    def name(self) -> str:
        return self.label

    @property
    def period_range(self) -> tuple[float, float]:
        return self.spectrum.period_range

    @property
    def permitted_procedures(self) -> tuple[str, ...]:
        return getattr(self.spectrum, "permitted_procedures", ("elf", "modal", "response-history"))

    def sa(self, periods, damping: float) -> np.ndarray:
        """S_a [m/s^2] at periods [s] and damping ratio [-]."""
        return self.factor * self.spectrum.sa(periods, damping)


def suite_target(spectrum, rule_name: str):
    """The target of a suite under the rule `rule_name`: for ASCE 7-22 ("asce7-22") the MCE_R
    spectrum (1.5 x a spectrum whose level is "design"); otherwise the spectrum itself."""
    if rule_name != "asce7-22" or getattr(spectrum, "level", None) != "design":
        return spectrum
    return ScaledSpectrum(spectrum, MCE_R_FACTOR,
                          f"MCE_R = {MCE_R_FACTOR:g} x {spectrum.name} (ASCE 7-22 16.2.1: records are scaled to "
                          f"the MCE_R spectrum; the deck gives the design level, 2/3 of MCE_R)")
