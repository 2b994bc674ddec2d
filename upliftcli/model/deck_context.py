"""What a foundation needs from the rest of the deck to build itself (model/foundations.py, and the
bearing capacity of model/bearing.py): one small class below both."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NoReturn


@dataclass(frozen=True)
class DeckContext:
    """What a foundation needs from the rest of the deck to build itself: the mat half-width
    b [m], the total mass m_t [kg], the fixed-base w_1 [rad/s] and gravity g [m/s^2];
    missing(field, expected) raises the deck error naming foundation.<field> (a required field
    not given, or values that do not fit together)."""

    half_width: float
    total_mass: float
    omega_1: float
    missing: Callable[[str, str], NoReturn]
    gravity: float = 9.80665
