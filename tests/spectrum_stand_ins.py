"""Spectra for tests: a flat S_a, the same at every period and damping (closed-form checks)."""

from __future__ import annotations

import numpy as np


class ConstantSpectrum:
    """S_a = value [m/s^2] at every period and damping."""

    def __init__(self, value: float):
        self.value = value

    def sa(self, periods, damping):
        return np.full(np.shape(np.atleast_1d(periods)), self.value)
