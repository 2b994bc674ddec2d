"""The simplified engine's result against a reference (the exact engine's, or a suite's design
statistic), compared value by value with the bands outside which a ratio is flagged: the
comparison analysis/accuracy.py (the accuracy check) and analysis/suite.py (a suite deck's
simplified engine on the target spectrum) share. It runs nothing."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from ..deck.load import Deck
from ..display import label, show
from ..engines.quantities import COMPARED
from ..engines.result import AnalysisResult

#: ratios simplified / exact inside this band raise no warning (analysis.check_band)
DEFAULT_BAND = (0.8, 1.25)
#: the band of the mat's motion (edge uplift, mat rotation: analysis.check_band_motion), whose
#: simplified estimate has a wider measured spread (docs/accuracy.md: 5-95 % of about 0.4-2.5)
DEFAULT_MOTION_BAND = (0.5, 2.0)
#: the measured accuracy of the improved procedure on records never used to calibrate it
#: (docs/accuracy.md, "Per record and per suite": benchmarks/accuracy_suites.py), for the check's footnote
MEASURED = ("measured on records never used to calibrate it (docs/accuracy.md): per record, V_b "
            "simplified / exact median 1.03, 5-95 % 0.73-1.37, M_b 0.99, 0.63-1.43; per suite of 11, mean "
            "simplified / mean exact V_b 0.99, 0.81-1.19, M_b 0.99, 0.73-1.31")
#: the compared values the motion band applies to
MOTION = ("max_uplift", "max_rotation")


@dataclass(frozen=True)
class Comparison:
    """One compared value (engines/quantities.COMPARED name) of the two engines, SI units."""

    name: str
    simplified: float
    exact: float

    @property
    def ratio(self) -> float | None:
        """simplified / exact (None when the exact value is 0 or either is not finite)."""
        if not (math.isfinite(self.simplified) and math.isfinite(self.exact)) or self.exact == 0.0:
            return None
        return self.simplified / self.exact

    @property
    def error(self) -> float:
        """The relative error on the side it falls: max(ratio, 1/ratio) - 1 (0 without a ratio)."""
        ratio = self.ratio
        if ratio is None:
            return 0.0
        return math.inf if ratio <= 0.0 else max(ratio, 1.0 / ratio) - 1.0

    def outside(self, band: tuple[float, float]) -> bool:
        ratio = self.ratio
        return ratio is not None and not band[0] <= ratio <= band[1]

    def describe(self) -> str:
        """'V_b: simplified / exact = 1.43 (exact 1234.0 kN)': the exact value in its display unit
        (display.py, SI system: kN, kN m, %, mm, g, mrad)."""
        quantity = COMPARED[self.name]
        ratio = "-" if self.ratio is None else f"{self.ratio:.3g}"
        unit = "" if quantity.display == "coefficient" else f" {label(quantity.display)}"
        return f"{quantity.symbol}: simplified / exact = {ratio} (exact {show(self.exact, quantity.display)}{unit})"


@dataclass(frozen=True)
class Check:
    """The simplified result of one support against a reference result (the exact engine).

    support; reference: what was run ('exact engine, all 10 modes'); band: (low, high) of the
    ratios that raise no warning; motion_band: the same for the edge uplift and the mat rotation
    (MOTION); comparisons: one per COMPARED value both results give;
    reference_warnings: the reference run's own warnings; error: why the reference could not run
    (then there are no comparisons); left_out: compared value -> why it is not compared here
    (Compared.left_out: the edge uplift on soil that yielded). A check on a record suite
    (analysis/suite_check.py: the exact answer for a design spectrum) also has suite: what the suite was
    (source, count, seed, generator, period range, target, statistic); spectrum_ratio,
    procedure_ratio: each ratio's two factors, the records' standing against the target and the
    procedure's own error (engines/suite_result.simplified_ratios), empty when they are not known."""

    support: str
    reference: str
    band: tuple[float, float] = DEFAULT_BAND
    comparisons: tuple[Comparison, ...] = ()
    reference_warnings: tuple[str, ...] = ()
    error: str | None = None
    motion_band: tuple[float, float] = DEFAULT_MOTION_BAND
    suite: Mapping[str, Any] | None = None
    spectrum_ratio: Mapping[str, float | None] = field(default_factory=dict)
    procedure_ratio: Mapping[str, float | None] = field(default_factory=dict)
    left_out: Mapping[str, str] = field(default_factory=dict)

    @property
    def ratios(self) -> dict[str, float | None]:
        return {c.name: c.ratio for c in self.comparisons}

    def band_of(self, name: str) -> tuple[float, float]:
        """The band of a compared value: motion_band for MOTION, band otherwise."""
        return self.motion_band if name in MOTION else self.band

    @property
    def out_of_band(self) -> tuple[Comparison, ...]:
        return tuple(c for c in self.comparisons if c.outside(self.band_of(c.name)))

    def band_warnings(self) -> list[str]:
        """One line per ratio outside its band."""
        lines = []
        for c in self.out_of_band:
            (low, high), option = self.band_of(c.name), "check_band_motion" if c.name in MOTION else "check_band"
            lines.append(f"accuracy check: {c.describe()} is outside [{low:g}, {high:g}] (analysis.{option}); the "
                         "simplified value is not reliable here: use the exact engine's")
        return lines

    def warnings(self) -> list[str]:
        """One line per ratio outside its band, then the reference run's warnings."""
        lines = self.band_warnings()
        if self.error is not None:
            lines.append(f"accuracy check: the {self.reference} could not run: {self.error}")
        return lines + [f"accuracy check, {self.reference}: {w}" for w in self.reference_warnings]

    def largest_error(self) -> tuple[float, Comparison | None]:
        """(the largest relative error of the comparisons, that comparison): Comparison.error."""
        worst = max(self.comparisons, key=lambda c: c.error, default=None)
        return (0.0, None) if worst is None else (worst.error, worst)

    def to_dict(self) -> dict:
        """The JSON `accuracy` object: {support, reference, band, motion_band, simplified, exact,
        ratio, out_of_band, warnings} (SI values), or {support, reference, error, warnings}; on a
        suite also `suite` and, when known, spectrum_ratio and procedure_ratio; `left_out` {name:
        reason} when a value is not compared."""
        head = {"support": self.support, "reference": self.reference,
                **({"suite": dict(self.suite)} if self.suite is not None else {})}
        if self.error is not None:
            return {**head, "error": self.error, "warnings": self.warnings()}
        return {**head, "band": list(self.band), "motion_band": list(self.motion_band),
                "simplified": {c.name: c.simplified for c in self.comparisons},
                "exact": {c.name: c.exact for c in self.comparisons},
                "ratio": self.ratios, **_non_empty(spectrum_ratio=self.spectrum_ratio,
                                                   procedure_ratio=self.procedure_ratio, left_out=self.left_out),
                "out_of_band": [c.name for c in self.out_of_band],
                "warnings": self.warnings()}


def _non_empty(**mappings: Mapping) -> dict[str, dict]:
    """The mappings that hold something, as dicts, in the order given (optional keys of Check.to_dict)."""
    return {key: dict(value) for key, value in mappings.items() if value}


def deck_bands(deck: Deck) -> tuple[tuple[float, float], tuple[float, float]]:
    """The check's bands of a deck (analysis.check_band, check_band_motion); with [criteria]
    simplified_error = e, the band [1/(1 + e), 1 + e] and the motion band widened to hold it, so
    that the criterion fails exactly when the check flags a ratio (issue 36: e = 0.25 held the
    edge uplift and the mat rotation to [0.8, 1.25], the check's band for them being [0.5, 2])."""
    band, motion = tuple(deck.analysis.check_band), tuple(deck.analysis.check_band_motion)
    limit = deck.criteria.get("simplified_error")
    if limit is None:
        return band, motion
    judged = (1.0 / (1.0 + limit), 1.0 + limit)
    return judged, (min(motion[0], judged[0]), max(motion[1], judged[1]))


def compare(simplified: AnalysisResult, reference: AnalysisResult, band: tuple[float, float] = DEFAULT_BAND,
            label: str = "exact engine", motion_band: tuple[float, float] = DEFAULT_MOTION_BAND) -> Check:
    """The Check of a simplified result against a reference result of the same support: every
    COMPARED value both give, but those left out with their reason (Compared.left_out of either
    result); the reference's warnings but those the simplified result carries too (the deck's own,
    analysis.run_batch)."""
    comparisons, left_out = _comparisons(simplified, reference)
    own = simplified.details.get("warnings", ())  # the deck's own warnings are in both: said once
    passed_on = tuple(w for w in reference.details.get("warnings", ()) if w not in own)
    return Check(simplified.support, label, tuple(band), tuple(comparisons), passed_on,
                 motion_band=tuple(motion_band), left_out=left_out)


def _comparisons(simplified: AnalysisResult, reference: AnalysisResult) -> tuple[list[Comparison], dict[str, str]]:
    """The Comparison of every COMPARED value of the support that both results give, and the
    values left out, with the reason (Compared.left_out of the reference, else of the simplified)."""
    comparisons, left_out = [], {}
    for quantity in COMPARED.values():
        if simplified.support not in quantity.supports:
            continue
        reason = quantity.left_out(reference) or quantity.left_out(simplified)
        if reason:
            left_out[quantity.name] = reason
            continue
        comparison = _comparison(quantity, simplified, reference)
        if comparison is not None:
            comparisons.append(comparison)
    return comparisons, left_out


def _comparison(quantity: Any, simplified: AnalysisResult, reference: AnalysisResult) -> Comparison | None:
    """The Comparison of one compared value (engines/quantities.Compared), None when either result lacks it."""
    mine, theirs = quantity.value(simplified), quantity.value(reference)
    if mine is None or theirs is None:
        return None
    return Comparison(quantity.name, float(mine), float(theirs))
