"""What the twin of a yielding run folds (analysis/residuals.py; docs/theory.md 15.8): its residuals and
its energy balance, nothing more.

The check of the residuals compares a run's residual drift ratios, residual mat rotation and residual
settlements with those of its twin (the record times 1 + 1e-6), and reads nothing else of the twin. A
twin folded by digest.Digest would also search every peak between samples, the reactions and impacts and
the mat's peaks (a seventh of the twin's time on the README example). ResidualDigest folds per chunk what
the residuals are read from (the drifts and the mat's theta and v at the last sample) and what the
engine's refinement of the step decides by (the energy balance: engine._finished halves the step where it
does not close, and the refined run is then an ordinary full one), each through StoryDigest and
MatMotion themselves (their residuals; MatMotion.add_last), so that the twin's residuals and its energy
residual are those of a full twin, bit for bit (tests/test_residual_digest.py).

Its result holds only those residuals (quantities.YIELDING's residual_drift_ratio with yielding stories;
quantities.ROCKING's residual_rotation and residual_settlement on the exact engine's uplift support), the
energy balance and the energy residual: it is a twin's, never shown nor written.
"""

from __future__ import annotations

import numpy as np

from ...model.system import System
from ..options import ExactOptions
from ..result import AnalysisResult
from .digest import StoryDigest
from .energy import balance, stored, work
from .mat_motion import MatMotion
from .response import Signals, response_rows, signals
from .statespace import StateSpace
from .stepping import History


class ResidualDigest:
    """Accumulates the residuals and the energy balance of one run of `system`'s model `space` (the
    interface of digest.Digest: add each chunk, then result)."""

    def __init__(self, system: System, space: StateSpace, options: ExactOptions):
        self.system, self.space, self.options = system, space, options
        self.stories = StoryDigest(space) if space.layout.n_plastic else None
        self.drift = response_rows(system, space).drift if self.stories is not None else None
        self.mat = MatMotion(space, system.half_width) if space.model.flexible else None
        self.works = (0.0, 0.0, 0.0)
        self.first = self.last = None
        self.uplifted = False

    def add(self, chunk: History) -> None:
        """Fold in one chunk (its first sample is the previous chunk's last), as Digest.add folds the
        work integrals, the stored energies, the yielding stories and the mat's last values."""
        sig = signals(chunk)
        self.works = tuple(a + b for a, b in zip(self.works, work(chunk, sig), strict=True))
        if self.first is None:
            self.first = stored(chunk, sig, 0)
        self.last = stored(chunk, sig, -1)
        self._fold_ends(chunk, sig)

    def _fold_ends(self, chunk: History, sig: Signals) -> None:
        """The yielding stories' hysteretic energy and last drifts, the mat's last values, whether it lifted."""
        if self.stories is not None:
            self.stories.add(chunk, sig, self.drift)
        if self.mat is not None:
            self.mat.add_last(sig)
        if self.space.layout.n_elements:
            self.uplifted |= bool(chunk.lifted.any())

    def result(self, support: str, engine: str) -> AnalysisResult:
        """The twin's AnalysisResult (after its last chunk): its residuals, its energy balance and the
        energy residual (intermediates), as Digest.result gives them."""
        system, model = self.system, self.space.model
        hysteretic = None if self.stories is None else float(self.stories.hysteretic.sum())
        energy = balance(self.space, self.works, self.first, self.last, hysteretic)
        return AnalysisResult.of(system, engine, support, self._residuals(support, engine), uplift=self.uplifted,
                                 periods=system.modes.periods[:model.n_modes], elements=model.elements,
                                 intermediates={"energy_residual": energy["relative_residual"]},
                                 details={"energy": energy})

    def _residuals(self, support: str, engine: str) -> dict[str, np.ndarray]:
        """residual_drift_ratio (StoryDigest.quantities), residual_rotation and residual_settlement
        (MatMotion.quantities, on the exact engine's uplift support as Digest._peaks gives them)."""
        values = {}
        if self.stories is not None:
            values["residual_drift_ratio"] = self.stories.residual_drift_ratio(self.system.building)
        if self.mat is not None and support == "uplift" and engine == "exact":
            values.update(self.mat.residuals())
        return values
