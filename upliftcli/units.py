"""Units: the one home of g and of the acceleration units a record or a spectrum may use.

Everything inside the tool is SI (kg, m, s, N, Pa); values are converted on reading.
"""

from __future__ import annotations

#: standard acceleration of gravity g [m/s^2] (the default of analysis.gravity; records in g)
STANDARD_GRAVITY = 9.80665

#: acceleration unit name -> factor to m/s^2
ACCELERATION_UNITS: dict[str, float] = {
    "g": STANDARD_GRAVITY,
    "m/s2": 1.0,
    "cm/s2": 0.01,
    "in/s2": 0.0254,
}
