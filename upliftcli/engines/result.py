"""Result type shared by every engine.

All quantities SI: m, N, N m, s. Story j joins floor j-1 and floor j (floor 0 is the mat).
Which quantities a result holds, with their units: engines/quantities.py.
"""

from __future__ import annotations

import copy
import sys
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..model.foundations import ContactElements
from ..model.system import System
from .quantities import SCALARS


@dataclass(frozen=True)
class AnalysisResult:
    """Peak response of one analysis (one engine, one support condition).

    elevations: floor elevations h_j above the mat [m], (N,).
    peaks: quantity name -> peak values, one per floor, story or foundation element
        (engines/quantities.py); also readable as attributes: result.drift_ratio.
    times: quantity name -> instants of the peaks [s] (the response-history engines).
    critical_base_shear, critical_base_moment: V_c, M_c [N], [N m] [16a, 16b].
    weight: m_t g [N]; effective_height: h_1* [m].
    uplift: whether the mat lifts off (always False for rigid and bonded); on soil that yields,
        whether it also yielded is `yielded`.
    periods: fixed-base periods T_n [s] of the modes used.
    element_positions: x_i [m] of the foundation's contact elements (empty for a rigid base).
    intermediates: named scalar or list values an engineer checks by hand
        (T1bar, xi1bar, V_c, zeta, ... for the simplified engine).
    details: engine-specific extras (uplift summary, energy balance, warnings ...).
    histories: response histories of the history engines when asked (ExactOptions.histories):
        signal name -> values (engines/quantities.HISTORY_SIGNALS); never written to the results
        documents (histories.write_histories writes them).

    A result is built once by its engine and not changed afterwards (frozen; what later stages
    find about it, such as the accuracy check of analysis/accuracy.py, is kept beside it).
    """

    engine: str
    support: str
    elevations: np.ndarray
    peaks: dict[str, np.ndarray]
    critical_base_shear: float
    critical_base_moment: float
    weight: float
    effective_height: float
    uplift: bool
    periods: np.ndarray
    element_positions: np.ndarray
    times: dict[str, np.ndarray] = field(default_factory=dict)
    intermediates: dict[str, Any] = field(default_factory=dict)
    details: dict[str, Any] = field(default_factory=dict)
    histories: dict[str, np.ndarray] = field(default_factory=dict)

    @classmethod
    def of(cls, system: System, engine: str, support: str, peaks: dict[str, np.ndarray], *, uplift: bool,
           periods: np.ndarray, elements: ContactElements | None, times: dict[str, np.ndarray] | None = None,
           intermediates: dict[str, Any] | None = None, details: dict[str, Any] | None = None,
           histories: dict[str, np.ndarray] | None = None) -> AnalysisResult:
        """The result of an analysis of `system`; elements: the contact elements analysed (None: rigid base)."""
        return cls(engine, support, system.building.heights.copy(), peaks, system.critical_base_shear,
                   system.critical_base_moment, system.weight, system.effective_height, uplift,
                   np.array(periods, dtype=float),
                   np.zeros(0) if elements is None else elements.positions.copy(), dict(times or {}),
                   dict(intermediates or {}), dict(details or {}), dict(histories or {}))

    def __getattr__(self, name: str) -> np.ndarray:
        peaks = self.__dict__.get("peaks")
        if peaks is not None and name in peaks:
            return peaks[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    @property
    def base_shear(self) -> float:
        """V_b [N] [14a]: the peak shear of story 1."""
        return float(self.peaks["shear"][0])

    @property
    def base_moment(self) -> float:
        """M_b [N m] [14b]: the peak overturning moment at the base."""
        return float(self.peaks["moment"][0])

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

    @property
    def yielded(self) -> bool | None:
        """Whether the soil under a contact element yielded (docs/theory.md 14.7), beside `uplift`
        (the mat lifted): from the history engines' details["yielding"] or the rocking quantity
        yielded_elements (a suite's statistic); None when the result does not tell (no bearing
        capacity, or the simplified engine, whose `uplift` then means V_c passed: 14.6)."""
        yielding = self.details.get("yielding")
        if isinstance(yielding, dict) and "yielded" in yielding:
            return bool(any(yielding["yielded"]))
        count = self.peaks.get("yielded_elements")
        return None if count is None else bool(np.any(np.asarray(count) > 0.0))

    @property
    def building_yielded(self) -> bool | None:
        """Whether a story yielded (docs/theory.md 15.5: quantities.YIELDING's yielded_stories), beside
        `yielded` (the soil); None when the result does not tell (no story strengths)."""
        count = self.peaks.get("yielded_stories")
        return None if count is None else bool(np.any(np.asarray(count) > 0.0))

    def value(self, name: str) -> float:
        """A scalar (engines/quantities.SCALARS) or the largest |value| of a quantity."""
        if name in SCALARS:
            return float(getattr(self, name))
        values = self.peaks.get(name)
        return float(np.max(np.abs(values))) if values is not None and values.size else 0.0

    def for_system(self, system: System) -> AnalysisResult:
        """This result for another system with the same building and a fixed base: its own
        V_c and M_c (a fixed-base analysis does not depend on the foundation)."""
        return replace(self, elevations=self.elevations.copy(), peaks={k: v.copy() for k, v in self.peaks.items()},
                       critical_base_shear=system.critical_base_shear,
                       critical_base_moment=system.critical_base_moment,
                       times={k: v.copy() for k, v in self.times.items()},
                       intermediates=dict(self.intermediates), details=copy.deepcopy(self.details),
                       histories={k: v.copy() for k, v in self.histories.items()})


def is_suite_result(result) -> bool:
    """Whether a result is a suite's (engines/suite_result.SuiteResult), without importing that
    module (`uplift modes` and a record's tables need none of it): a SuiteResult exists only once
    engines/suite_result.py is loaded."""
    suite_result = sys.modules.get(f"{__package__}.suite_result")
    return suite_result is not None and isinstance(result, suite_result.SuiteResult)
