"""Units: the one home of g, of the acceleration units a record or a spectrum may use, of the
unit symbols a deck value may carry ("11.5 ft", "2.0 kip s2/in") and of the unit systems of a
deck (`units = "si"` or `"us"`: the unit of a bare number, by the quantity its field declares).

Everything inside the tool is SI (kg, m, s, N, Pa); values are converted on reading. The
exact definitions: 1 in = 0.0254 m, 1 ft = 0.3048 m, 1 lbm = 0.45359237 kg (international
yard and pound, 1959), 1 lbf = 1 lbm x g_n = 4.4482216152605 N, 1 kip = 1000 lbf, g_n =
9.80665 m/s^2 (CGPM 1901). docs/deck.md, "Units", lists them all.
"""

from __future__ import annotations

import math

from .runtime.patterns import lazy

#: standard acceleration of gravity g [m/s^2] (the default of analysis.gravity; records in g)
STANDARD_GRAVITY = 9.80665

#: acceleration unit name -> factor to m/s^2
ACCELERATION_UNITS: dict[str, float] = {
    "g": STANDARD_GRAVITY,
    "m/s2": 1.0,
    "cm/s2": 0.01,
    "in/s2": 0.0254,
}

#: every spelling of an acceleration unit a record file, `ground_motion.units` or a spectrum
#: table's `units` may use -> its canonical name (ACCELERATION_UNITS); matched after lower
#: case, blanks removed and "sec" read as "s" (docs/deck.md lists them)
ACCELERATION_ALIASES: dict[str, str] = {
    "g": "g", "m/s2": "m/s2", "m/s^2": "m/s2", "m/s/s": "m/s2", "m/s**2": "m/s2", "mps2": "m/s2",
    "cm/s2": "cm/s2", "cm/s^2": "cm/s2", "cm/s/s": "cm/s2", "cm/s**2": "cm/s2", "gal": "cm/s2",
    "in/s2": "in/s2", "in/s^2": "in/s2", "in/s/s": "in/s2", "in/s**2": "in/s2",
}


def acceleration_unit(text) -> str | None:
    """The canonical name of an acceleration unit ('g', 'm/s2', 'cm/s2', 'in/s2'), or None."""
    if not isinstance(text, str):
        return None
    return ACCELERATION_ALIASES.get(text.strip().lower().replace(" ", "").replace("sec", "s"))


# ----------------------------------------------------------------------------- unit symbols

INCH = 0.0254  # m
FOOT = 0.3048  # m
POUND_MASS = 0.45359237  # kg
POUND_FORCE = POUND_MASS * STANDARD_GRAVITY  # N (4.4482216152605)
KIP = 1000.0 * POUND_FORCE  # N

#: dimension exponents (mass, length, time)
Dimension = tuple[int, int, int]
MASS, LENGTH, TIME = (1, 0, 0), (0, 1, 0), (0, 0, 1)
FORCE: Dimension = (1, 1, -2)
PRESSURE: Dimension = (1, -1, -2)

#: unit symbol -> (factor to SI, dimension); products and quotients are built by parse_unit
SYMBOLS: dict[str, tuple[float, Dimension]] = {
    "m": (1.0, LENGTH), "cm": (0.01, LENGTH), "mm": (0.001, LENGTH), "km": (1000.0, LENGTH),
    "in": (INCH, LENGTH), "ft": (FOOT, LENGTH),
    "s": (1.0, TIME), "ms": (0.001, TIME),
    "kg": (1.0, MASS), "t": (1000.0, MASS), "lbm": (POUND_MASS, MASS), "slug": (POUND_FORCE / FOOT, MASS),
    "N": (1.0, FORCE), "kN": (1e3, FORCE), "MN": (1e6, FORCE),
    "lbf": (POUND_FORCE, FORCE), "lb": (POUND_FORCE, FORCE), "kip": (KIP, FORCE), "kips": (KIP, FORCE),
    "Pa": (1.0, PRESSURE), "kPa": (1e3, PRESSURE), "MPa": (1e6, PRESSURE), "GPa": (1e9, PRESSURE),
    "psi": (POUND_FORCE / INCH**2, PRESSURE), "ksi": (KIP / INCH**2, PRESSURE),
    "psf": (POUND_FORCE / FOOT**2, PRESSURE), "ksf": (KIP / FOOT**2, PRESSURE),
    "pcf": (POUND_MASS / FOOT**3, (1, -3, 0)),
    "g": (STANDARD_GRAVITY, (0, 1, -2)), "gal": (0.01, (0, 1, -2)),
    "rad": (1.0, (0, 0, 0)), "mrad": (0.001, (0, 0, 0)),
}

_TOKEN = lazy(r"([A-Za-z]+)(?:\^|\*\*)?(-?\d+)?")
_SEPARATOR = lazy(r"\s*(?:(?<!\*)\*(?!\*)|\u00b7)\s*|\s+|(?<=[A-Za-z0-9])-(?=[A-Za-z])")
_QUANTITY = lazy(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)(?:\s*([A-Za-z].*?))?\s*")


def _groups(text: str) -> list[str]:
    """A unit's factor groups, split at '/' (the first multiplies, every other divides);
    ValueError when the unit or one of its groups is empty."""
    groups = text.split("/")
    if not text.strip() or any(not group.strip() for group in groups):
        raise ValueError(f"a unit such as m, kN, kip/in ({text!r} is not one)")
    return groups


def _symbol_power(token: str) -> tuple[float, Dimension, int]:
    """(factor to SI, dimension, exponent) of one symbol of SYMBOLS with an optional exponent
    ('s2', 's^2', 's**2'); ValueError naming an unknown symbol."""
    match = _TOKEN.fullmatch(token)
    if match is None or match.group(1) not in SYMBOLS:
        name = match.group(1) if match else token
        raise ValueError(f"a known unit symbol ({name!r} is not one; docs/deck.md lists them)")
    size, dims = SYMBOLS[match.group(1)]
    return size, dims, int(match.group(2) or 1)


def parse_unit(text: str) -> tuple[float, Dimension]:
    """(factor to SI, dimension) of a unit such as 'kip s2/in', 'N s/m', 'm/s^2', 'kip-ft',
    'lb s2/ft4': symbols of SYMBOLS with optional exponents (s2, s^2, s**2), multiplied by
    blanks, '*' or '-', divided by '/' (every '/' starts a divisor: 'm/s/s' = m/s^2).
    ValueError naming the unknown symbol."""
    factor, dimension = 1.0, (0, 0, 0)
    for index, group in enumerate(_groups(text)):
        sign = 1 if index == 0 else -1
        for token in _SEPARATOR.split(group.strip()):
            size, dims, exponent = _symbol_power(token)
            power = sign * exponent
            factor *= size**power
            dimension = (dimension[0] + dims[0] * power, dimension[1] + dims[1] * power, dimension[2] + dims[2] * power)
    return factor, dimension


def split_quantity(text: str) -> tuple[float, str] | None:
    """'11.5 ft' -> (11.5, 'ft'); '12' -> (12.0, ''); None if `text` does not start with a
    plain decimal number (no '_' separators, no 'inf' or 'nan')."""
    match = _QUANTITY.fullmatch(text)
    if match is None:
        return None
    value = float(match.group(1))
    return (value, match.group(2) or "") if math.isfinite(value) else None


# ----------------------------------------------------------------------------- quantities

#: quantity kind -> (the SI unit the deck's fields declare, the US customary unit of a bare
#: number under `units = "us"`); ASCE 7 practice: heights and plan dimensions in ft,
#: displacements in in, the kip-inch-second system for mass, stiffness and damping
QUANTITY_KINDS: dict[str, tuple[str, str]] = {
    "length": ("m", "ft"),
    "displacement": ("m", "in"),
    "time": ("s", "s"),
    "mass": ("kg", "kip s2/in"),
    "rotary inertia": ("kg m^2", "kip s2 in"),
    "stiffness": ("N/m", "kip/in"),
    "damping": ("N s/m", "kip s/in"),
    "stiffness per length": ("N/m^2", "kip/in2"),
    "force per length": ("N/m", "kip/ft"),
    "damping per length": ("N s/m^2", "kip s/in2"),
    "pressure": ("Pa", "ksf"),
    "velocity": ("m/s", "ft/s"),
    "density": ("kg/m^3", "pcf"),
    "acceleration": ("m/s^2", "in/s2"),
    "force": ("N", "kip"),
    "moment": ("N m", "kip ft"),
    "spectral acceleration": ("g", "g"),
    "rotation": ("rad", "rad"),
}

#: a field's declared unit -> its quantity kind, unless the field names another (the first kind of that unit)
KIND_OF_UNIT: dict[str, str] = {}
for _kind, (_si, _) in QUANTITY_KINDS.items():
    KIND_OF_UNIT.setdefault(_si, _kind)

#: unit systems of a deck's bare numbers and of the display (display.py, --units)
SYSTEMS = ("si", "us")


def system_unit(kind: str, system: str) -> str:
    """The unit of a bare number of quantity `kind` in unit system `system`."""
    si, us = QUANTITY_KINDS[kind]
    return us if system == "us" else si


def conversion(unit: str, to_unit: str) -> float:
    """Factor from `unit` to `to_unit` (ValueError if unknown or of different dimensions)."""
    factor, dimension = parse_unit(unit)
    target, target_dimension = parse_unit(to_unit)
    if dimension != target_dimension:
        raise ValueError(f"a unit of the dimension of {to_unit} ({unit} is not)")
    return factor / target
