"""The design spectra of the codes (design_spectra.py builds them, and tabulated ones, from a deck table).

* `ASCE7Spectrum`: ASCE 7-22 11.4.5.2 two-period design spectrum (S_DS, S_D1, T_L), with the
  damping coefficient B = 4 / (5.6 - ln(100 beta)) of ASCE 41-17 Eq. (2-3), the factor used for
  soil-structure-interaction damping in NIST GCR 12-917-21 and ASCE 7-22 chapter 19 (B_SSI);
  the branch below T0 follows ASCE 41-17 Eq. (2-9). ASCE 7-22 11.4.5 permits it only with the
  equivalent lateral force procedure: `procedure_warning` gives the message for the others.
* `ASCE7MultiPeriodSpectrum`: ASCE 7-22 11.4.5.1 multi-period design spectrum, the 22 ordinates
  at T = 0..10 s as the USGS design service gives them, with the same damping coefficient.
* `EC8Spectrum`: EN 1998-1:2004 3.2.2.2 horizontal elastic spectrum, Type 1 or 2, ground types
  A to E (Tables 3.2, 3.3), damping correction eta (Eq. 3.6). The code defines it up to 4 s;
  beyond, Eq. 3.5 (the T_D branch, constant spectral displacement) is continued and
  `spectrum_warnings` says so (docs/deck.md).
* `TabulatedSpectrum` (spectrum_tables.py): a user table (T, S_a) at a stated damping.

Every spectrum has `.sa(periods, damping) -> S_a [m/s^2]`, `.name` and `.period_range` [s];
code parameters are in g as the codes give them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..units import STANDARD_GRAVITY
from .levels import LEVELS
from .spectrum_tables import (
    asce_damping_coefficient,
    check_damping,
    check_periods,
    ec8_damping_correction,
    positive,
)

#: EN 1998-1 Tables 3.2 (Type 1) and 3.3 (Type 2): ground type -> (S, T_B, T_C, T_D) [-, s, s, s]
EC8_PARAMETERS = {
    1: {"A": (1.0, 0.15, 0.4, 2.0), "B": (1.2, 0.15, 0.5, 2.0), "C": (1.15, 0.20, 0.6, 2.0),
        "D": (1.35, 0.20, 0.8, 2.0), "E": (1.4, 0.15, 0.5, 2.0)},
    2: {"A": (1.0, 0.05, 0.25, 1.2), "B": (1.35, 0.05, 0.25, 1.2), "C": (1.5, 0.10, 0.25, 1.2),
        "D": (1.8, 0.10, 0.30, 1.2), "E": (1.6, 0.05, 0.25, 1.2)},
}
EC8_CODE_MAX_PERIOD = 4.0  # s, EN 1998-1 3.2.2.2 defines the elastic spectrum up to 4 s

#: the 22 periods [s] of the ASCE 7-22 multi-period spectra of the USGS design service
USGS_PERIODS = (0.0, 0.01, 0.02, 0.03, 0.05, 0.075, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.75, 1.0,
                1.5, 2.0, 3.0, 4.0, 5.0, 7.5, 10.0)

#: procedures ASCE 7-22 names: key -> words
PROCEDURES = {"elf": "the equivalent lateral force procedure", "modal": "modal response spectrum analysis",
              "response-history": "response-history analysis"}


def _asce_ramp(periods: np.ndarray, damping: float, t0: float) -> np.ndarray:
    """Factor on the 5 % ordinates: 1/(B(beta)/B(5 %)) from T_0 on, linear in T from 1 at T = 0
    (ASCE 41-17 Eq. 2-9: S_a(0) does not depend on damping)."""
    b = float(asce_damping_coefficient(damping) / asce_damping_coefficient(0.05))
    return 1.0 + (1.0 / b - 1.0) * np.minimum(periods / t0, 1.0)


@dataclass
class ASCE7Spectrum:
    """ASCE 7-22 11.4.5.2 design spectrum. sds, sd1: design spectral accelerations at short
    periods and at 1 s [g]; tl: long-period transition period T_L [s]. Reference damping 5 %;
    other dampings divide by B(beta) / B(5 %) (so 5 % reproduces the code spectrum exactly).
    ASCE 7-22 permits it only with the equivalent lateral force procedure (procedure_warning)."""

    sds: float
    sd1: float
    tl: float
    source: str = "asce7 spectrum"
    level: str = "design"

    permitted_procedures = ("elf",)

    def __post_init__(self):
        self.level = check_level(self.level, self.source)
        self.sds = positive(self.sds, self.source, "sds", "g")
        self.sd1 = positive(self.sd1, self.source, "sd1", "g")
        self.tl = positive(self.tl, self.source, "tl", "s")
        if self.tl <= self.ts:
            raise InputError(self.source, "tl", f"T_L above T_S = S_D1/S_DS = {self.ts:g} s, got {self.tl:g} s")

    @property
    def ts(self) -> float:
        """T_S = S_D1 / S_DS [s]."""
        return self.sd1 / self.sds

    @property
    def t0(self) -> float:
        """T_0 = 0.2 S_D1 / S_DS [s]."""
        return 0.2 * self.ts

    @property
    def name(self) -> str:
        if self.level == "mce_r":
            return f"ASCE 7-22 two-period MCE_R (S_MS = {self.sds:g} g, S_M1 = {self.sd1:g} g, T_L = {self.tl:g} s)"
        return f"ASCE 7-22 two-period (S_DS = {self.sds:g} g, S_D1 = {self.sd1:g} g, T_L = {self.tl:g} s)"

    @property
    def period_range(self) -> tuple[float, float]:
        return (0.0, math.inf)

    def sa(self, periods, damping: float) -> np.ndarray:
        """S_a [m/s^2] at periods [s] and damping ratio [-]."""
        t = check_periods(periods, self.period_range, self.source, self.name)
        b = float(asce_damping_coefficient(check_damping(damping, self.source))
                  / asce_damping_coefficient(0.05))
        with np.errstate(divide="ignore", invalid="ignore"):
            sa = np.where(t < self.t0, self.sds * ((5.0 / b - 2.0) * t / self.ts + 0.4),
                 np.where(t <= self.ts, self.sds / b,
                 np.where(t <= self.tl, self.sd1 / (b * t), self.sd1 * self.tl / (b * t * t))))
        return sa * STANDARD_GRAVITY


def _check_ordinates(values: np.ndarray, source: str) -> None:
    """InputError unless there are 22 ordinates (USGS_PERIODS), finite and > 0 [g]."""
    if values.size != len(USGS_PERIODS):
        raise InputError(source, "sa", f"the {len(USGS_PERIODS)} ordinates [g] at T = "
                         f"{', '.join(f'{t:g}' for t in USGS_PERIODS)} s, got {values.size} values")
    if not (np.all(np.isfinite(values)) and np.all(values > 0.0)):
        raise InputError(source, "sa", "finite spectral accelerations > 0 [g]")


class ASCE7MultiPeriodSpectrum:
    """ASCE 7-22 11.4.5.1 multi-period design spectrum: sa, the 22 ordinates [g] at USGS_PERIODS
    (T = 0 to 10 s, 5 % damping) as the USGS design service gives them (multiPeriodDesignSpectrum).
    Linear interpolation in T between the ordinates; no values beyond 10 s (an error naming the
    period). Other dampings: the ordinates divided by B(beta)/B(5 %) (as the two-period spectrum)
    from T_0 = 0.2 S_D1/S_DS on, the factor going linearly in T from 1 at T = 0 (ASCE 41-17
    Eq. 2-9). sds, sd1 [g]: as the service gives them; if not given they are derived from the
    ordinates as ASCE 7-22 21.4 does (S_DS = 0.9 max S_a over 0.2-5 s; S_D1 = max(0.9 max T S_a over
    1-5 s, S_a(1 s)), the 1-5 s window of sites with v_s30 <= 442 m/s, giving the longer T_0)."""

    permitted_procedures = ("elf", "modal", "response-history")

    def __init__(self, sa, sds: float | None = None, sd1: float | None = None, source: str = "asce7 spectrum",
                 label: str = "", level: str = "design"):
        self.source = str(source)
        self.level = check_level(level, self.source)
        values = np.asarray(sa, dtype=float).ravel()
        _check_ordinates(values, self.source)
        self.periods = np.array(USGS_PERIODS)
        self.ordinates = values  # [g]
        self.label = label
        window = (self.periods >= 0.2) & (self.periods <= 5.0)
        long = (self.periods >= 1.0) & (self.periods <= 5.0)
        self.sds = (positive(sds, self.source, "sds", "g") if sds is not None
                    else 0.9 * float(values[window].max()))
        self.sd1 = (positive(sd1, self.source, "sd1", "g") if sd1 is not None
                    else max(0.9 * float(np.max(self.periods[long] * values[long])), float(values[14])))

    @property
    def t0(self) -> float:
        """T_0 = 0.2 S_D1 / S_DS [s] (end of the damping ramp)."""
        return 0.2 * self.sd1 / self.sds

    @property
    def name(self) -> str:
        if self.label:
            return self.label
        if self.level == "mce_r":
            return f"ASCE 7-22 multi-period MCE_R (S_MS = {self.sds:.3g} g, S_M1 = {self.sd1:.3g} g)"
        return f"ASCE 7-22 multi-period (S_DS = {self.sds:.3g} g, S_D1 = {self.sd1:.3g} g)"

    @property
    def period_range(self) -> tuple[float, float]:
        return (0.0, USGS_PERIODS[-1])

    def sa(self, periods, damping: float) -> np.ndarray:
        """S_a [m/s^2] at periods [s] (0 to 10 s) and damping ratio [-]."""
        t = check_periods(periods, self.period_range, self.source, self.name)
        factor = _asce_ramp(t, check_damping(damping, self.source), self.t0)
        return factor * np.interp(t, self.periods, self.ordinates) * STANDARD_GRAVITY


@dataclass
class EC8Spectrum:
    """EN 1998-1 3.2.2.2 horizontal elastic spectrum. ag: reference peak ground acceleration on
    type A ground a_gR [g]; ground_type 'A'..'E'; spectrum_type 1 or 2; importance: gamma_I [-]
    (a_g = gamma_I a_gR). Reference damping 5 %; other dampings through eta (Eq. 3.6).
    Beyond T = 4 s, where the code stops, Eq. 3.5 is continued (module docstring)."""

    ag: float
    ground_type: str
    spectrum_type: int = 1
    importance: float = 1.0
    source: str = "ec8 spectrum"

    permitted_procedures = ("elf", "modal", "response-history")

    def __post_init__(self):
        self.ag = positive(self.ag, self.source, "ag", "g")
        self.importance = positive(self.importance, self.source, "importance", "-")
        ground = str(self.ground_type).strip().upper()
        if ground not in ("A", "B", "C", "D", "E"):
            raise InputError(self.source, "ground_type",
                             f"ground type A, B, C, D or E (S1, S2 need special studies), got {self.ground_type!r}")
        self.ground_type = ground
        if self.spectrum_type not in (1, 2, "1", "2"):
            raise InputError(self.source, "spectrum_type", f"1 or 2, got {self.spectrum_type!r}")
        self.spectrum_type = int(self.spectrum_type)

    @property
    def parameters(self) -> tuple[float, float, float, float]:
        """(S [-], T_B [s], T_C [s], T_D [s]) of EN 1998-1 Table 3.2 / 3.3."""
        return EC8_PARAMETERS[self.spectrum_type][self.ground_type]

    @property
    def design_ground_acceleration(self) -> float:
        """a_g S [m/s^2], the zero-period ordinate (EN 1998-1 3.2.3.1.2(4)b for artificial records)."""
        return self.ag * self.importance * self.parameters[0] * STANDARD_GRAVITY

    @property
    def name(self) -> str:
        return f"EC8 Type {self.spectrum_type} ground {self.ground_type} (a_g = {self.ag * self.importance:g} g)"

    @property
    def period_range(self) -> tuple[float, float]:
        return (0.0, math.inf)

    def sa(self, periods, damping: float) -> np.ndarray:
        """S_e [m/s^2] at periods [s] and damping ratio [-] (EN 1998-1 Eqs. 3.2-3.5; Eq. 3.5 beyond 4 s)."""
        t = check_periods(periods, self.period_range, self.source, self.name)
        eta = float(ec8_damping_correction(check_damping(damping, self.source, allow_zero=True)))
        soil, tb, tc, td = self.parameters
        ag = self.ag * self.importance * STANDARD_GRAVITY
        with np.errstate(divide="ignore", invalid="ignore"):
            sa = np.where(t <= tb, 1.0 + t / tb * (2.5 * eta - 1.0),
                 np.where(t <= tc, 2.5 * eta,
                 np.where(t <= td, 2.5 * eta * tc / t, 2.5 * eta * tc * td / (t * t))))
        return ag * soil * sa


def check_level(level, source: str) -> str:
    """The level of an ASCE 7-22 spectrum, 'design' or 'mce_r' (motion/levels.py)."""
    if level not in LEVELS:
        raise InputError(source, "level", f"one of {', '.join(LEVELS)} (the level of the ordinates given), "
                         f"got {level!r}")
    return level


def procedure_warning(spectrum, procedure: str) -> str | None:
    """The message for a procedure ('elf', 'modal', 'response-history') the code does not permit
    with this spectrum (ASCE 7-22 11.4.5: the two-period spectrum only with the ELF procedure),
    or None. Engines and commands pass it on as a warning."""
    permitted = getattr(spectrum, "permitted_procedures", tuple(PROCEDURES))
    if procedure in permitted:
        return None
    return (f"ASCE 7-22 11.4.5 permits the two-period design spectrum (type = \"asce7\") only with "
            f"{PROCEDURES['elf']}; {PROCEDURES.get(procedure, procedure)} uses the multi-period spectrum "
            f"(ground_motion.design_spectrum = {{ type = \"asce7-multiperiod\", sa = [the 22 ordinates, g] }})")


def spectrum_warnings(spectrum, periods, procedure: str | None = None) -> list[str]:
    """Warnings for using `spectrum` at `periods` [s] (and for `procedure`, see procedure_warning):
    EC8 ordinates beyond the 4 s where EN 1998-1 3.2.2.2 stops."""
    messages = []
    if procedure is not None and (message := procedure_warning(spectrum, procedure)):
        messages.append(message)
    longest = float(np.max(np.atleast_1d(np.asarray(periods, dtype=float)))) if np.size(periods) else 0.0
    if isinstance(spectrum, EC8Spectrum) and longest > EC8_CODE_MAX_PERIOD:
        messages.append(f"EN 1998-1 3.2.2.2 defines the elastic spectrum up to 4 s; at T = {longest:.3g} s "
                        "Eq. 3.5 is continued (S_e ~ 1/T^2, constant spectral displacement: informative Annex A "
                        "keeps it up to T_E and is lower beyond, so this is conservative)")
    return messages
