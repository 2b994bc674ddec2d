"""Exact engine: nonlinear response history of the N + 2 equations (THEORY.md sections 3-5).

(Work in progress: the options below are the public contract used by the deck.)
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class ExactOptions:
    """Options of the exact (and approximate) engine.

    n_modes: fixed-base modes kept (None = all N).
    criterion: uplift criterion, "reaction" (tensile reaction, default) or "displacement"
        (edge above the unstressed position) [4a, 4b].
    steps_per_period: internal steps per shortest governing period (first-mode, rocking and
        vertical periods of the contact states) [-].
    time_step: internal step [s]; None = min(record dt, governing period / steps_per_period).
    free_vibration: duration of free vibration appended after the record [s].
    flight: "allow" (free flight under gravity when both edges lift) or "error".
    """

    n_modes: int | None = None
    criterion: str = "reaction"
    steps_per_period: int = 20
    time_step: float | None = None
    free_vibration: float = 0.0
    flight: str = "allow"
