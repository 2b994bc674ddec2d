"""The code's design values of a structure (ASCE 7-22): the deck's `[design]` fields, the seismic
importance factor of Table 1.5-2 and the allowable story drift of Table 12.12-1, in one home for
the linear procedures (engines/design.py: elastic x Ie/R, Cd x delta_e/Ie) and the acceptance of a
nonlinear response history analysis (chapter 16). Pure: no deck, file or terminal.

ASCE 7-22 clauses used (docs/theory.md section 16):
- 11.5.1 and Table 1.5-2: the seismic importance factor Ie of each risk category (I, II: 1.00;
  III: 1.25; IV: 1.50);
- Table 12.2-1: R, Omega_0 and C_d of the seismic force-resisting system (R from 1 to 8,
  Omega_0 from 1 to 3, C_d from 1 to 6.5 over the table's systems: the plausible ranges below);
- 12.12.1 and Table 12.12-1: the allowable story drift Delta_a as a multiple of the story height
  h_sx below level x, by structure and risk category (footnote c: no limit for a one-story
  structure of the first row). Footnote b (moment frames in Seismic Design Categories D to F:
  Delta_a / rho, 12.12.1.1) is not applied here: the deck has no redundancy factor rho.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..deck.fields import Field

#: the risk categories of ASCE 7-22 Table 1.5-1
RISK_CATEGORIES = ("I", "II", "III", "IV")

#: ASCE 7-22 Table 1.5-2: the seismic importance factor Ie of each risk category (11.5.1)
IMPORTANCE_FACTORS = {"I": 1.0, "II": 1.0, "III": 1.25, "IV": 1.5}

#: ASCE 7-22 Table 12.12-1: the structure (its rows, by short names) -> (the row's words, the allowable
#: story drift ratio Delta_a / h_sx for risk category I or II, III, IV)
ALLOWABLE_DRIFT = {
    "low-rise-drift-tolerant": (
        "structures, other than masonry shear wall structures, four stories or less above the base (ASCE 7-22 "
        "11.2), with interior walls, partitions, ceilings and exterior wall systems designed to accommodate the "
        "story drifts", (0.025, 0.020, 0.015)),
    "masonry-cantilever-shear-wall": ("masonry cantilever shear wall structures (footnote d: shear walls "
                                      "cantilevered from the base, negligible coupling)", (0.010, 0.010, 0.010)),
    "other-masonry-shear-wall": ("other masonry shear wall structures", (0.007, 0.007, 0.007)),
    "all-other": ("all other structures", (0.020, 0.015, 0.010)),
}
STRUCTURES = tuple(ALLOWABLE_DRIFT)

#: the most stories above the base of Table 12.12-1's first row
LOW_RISE_STORIES = 4

#: the [design] table of a deck (deck/schema.py): declared here, where the code's tables live
DESIGN_FIELDS: dict[str, Field] = {
    "R": Field("number", "-", "response modification coefficient R of the seismic force-resisting system (ASCE 7-22 "
               "Table 12.2-1): design forces = elastic x Ie/R (12.9.1.2)", "at-least-one",
               plausible=(1.0, 8.0)),
    "Cd": Field("number", "-", "deflection amplification factor C_d (ASCE 7-22 Table 12.2-1): design drifts = C_d "
                "x the drifts of the design forces / Ie (12.8.6, 12.9.1.2)", "at-least-one", plausible=(1.0, 6.5)),
    "Omega0": Field("number", "-", "overstrength factor Omega_0 (ASCE 7-22 Table 12.2-1): the overstrength base "
                    "shear Omega_0 x the design base shear (12.4.3)", "at-least-one", plausible=(1.0, 3.0)),
    "Ie": Field("number", "-", "seismic importance factor I_e (default: that of the risk category, ASCE 7-22 "
                "Table 1.5-2)", "importance-factor"),
    "risk_category": Field("string", "-", "risk category (ASCE 7-22 Table 1.5-1): sets I_e and the allowable drift",
                           "", None, RISK_CATEGORIES),
    "structure": Field("string", "-", "the structure's row of ASCE 7-22 Table 12.12-1 (allowable story drift): "
                       + "; ".join(f"{name}: {words}" for name, (words, _) in ALLOWABLE_DRIFT.items()), "",
                       "all-other", STRUCTURES),
}


def importance_factor(risk_category: str) -> float:
    """Ie of ASCE 7-22 Table 1.5-2."""
    return IMPORTANCE_FACTORS[risk_category]


def allowable_drift_ratio(structure: str, risk_category: str, stories: int) -> float | None:
    """Delta_a / h_sx of ASCE 7-22 Table 12.12-1 for the structure's row and the risk category; None
    (no limit) for a one-story structure of the first row (footnote c)."""
    if structure == "low-rise-drift-tolerant" and stories == 1:
        return None
    column = max(RISK_CATEGORIES.index(risk_category) - 1, 0)  # I and II share a column
    return ALLOWABLE_DRIFT[structure][1][column]


@dataclass(frozen=True)
class Design:
    """The design values of a structure ([design] of a deck): R and C_d (None: not given, as a chapter 16
    deck may; the linear procedure needs both), I_e, the risk category, the structure's row of Table
    12.12-1 and Omega_0 (None: not given)."""

    R: float | None
    Cd: float | None
    Ie: float
    risk_category: str
    structure: str = "all-other"
    Omega0: float | None = None

    @property
    def linear(self) -> bool:
        """Whether R and C_d are given (the linear procedure's design values can be computed)."""
        return self.R is not None and self.Cd is not None

    @property
    def force_factor(self) -> float:
        """Ie / R: design forces over elastic forces (ASCE 7-22 12.9.1.2)."""
        return self.Ie / self.R

    @property
    def drift_factor(self) -> float:
        """C_d / R: design drifts over elastic drifts ((Ie/R) x (C_d/Ie), ASCE 7-22 12.9.1.2 with Eq. 12.8-15)."""
        return self.Cd / self.R

    def allowable_drift_ratio(self, stories: int) -> float | None:
        """Delta_a / h_sx of Table 12.12-1 (None: no limit, footnote c)."""
        return allowable_drift_ratio(self.structure, self.risk_category, stories)

    def to_dict(self) -> dict:
        """The values as the result files record them."""
        values = {"R": self.R, "Cd": self.Cd, "Ie": self.Ie, "risk_category": self.risk_category,
                  "structure": self.structure, "Omega0": self.Omega0}
        return {name: value for name, value in values.items() if value is not None}
