"""Colours and line styles shared by every figure.

The colours are Okabe & Ito's colour-blind-safe set (Okabe and Ito 2008, "Color universal
design"), without its yellow (too pale on white), and a colour means one thing in every
figure: a support (rigid black, bonded blue, uplift vermillion) or an engine (exact green,
approximate orange, simplified purple, where engines are compared). Where a figure shows
supports, engines are line styles (exact solid, approximate dashed, simplified dash-dot);
several values of another field are shades of the support's colour with markers (shades).
Lines that are neither (the dampings of a record's spectra, the ground motion) take sky blue
and greys (cycle); dotted lines are kept for reference lines (critical values, limits).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

from .spec import Series

BLACK, ORANGE, SKY_BLUE, GREEN, BLUE, VERMILLION, PURPLE = (
    "#000000", "#E69F00", "#56B4E9", "#009E73", "#0072B2", "#D55E00", "#CC79A7")
DARK_GREY, GREY, LIGHT_GREY = "#4D4D4D", "#8C8C8C", "#BDBDBD"
SUPPORT_COLORS = {"rigid": BLACK, "bonded": BLUE, "uplift": VERMILLION}
ENGINE_COLORS = {"exact": GREEN, "approximate": ORANGE, "simplified": PURPLE}
ENGINE_LINES = {"exact": "-", "approximate": "--", "simplified": "-."}
SUPPORT_STYLES = {"rigid": ("-", BLACK), "bonded": ("--", BLUE), "uplift": ("-", VERMILLION)}
ENGINE_STYLES = {engine: (ENGINE_LINES[engine], color) for engine, color in ENGINE_COLORS.items()}
#: the ground motion (a design spectrum, a suite's target) and the colours of lines that are
#: neither a support nor an engine, in the order lines take them
MOTION_COLOR = SKY_BLUE
PALETTE = (SKY_BLUE, DARK_GREY, GREY)
#: line styles cycled with the colours when a panel has many lines (4 and 3 are coprime: 12
#: lines before a (colour, style) pair repeats; then markers)
STYLES = ("-", "--", "-.", (0, (5, 1, 1, 1, 1, 1)))
MARKERS = (None, "o", "s", "^", "D")
#: a panel with more automatically coloured lines than this also varies their style
MANY_LINES = 3
#: shading of the contact state: the left and the right edge of the mat lifted
LIFT_COLORS = {"left": SKY_BLUE, "right": GREY}


def cycle(series: Sequence[Series]) -> list[Series]:
    """The series with a PALETTE colour for each that has none and, when they are many
    (more than MANY_LINES), a line style cycling with the colours (and a marker after 12):
    every line distinct."""
    free = [k for k, s in enumerate(series) if s.color is None]
    many = len(free) > MANY_LINES
    out = list(series)
    for position, k in enumerate(free):
        out[k] = _cycled(out[k], position, many)
    return out


def _cycled(series: Series, position: int, many: bool) -> Series:
    """The series in the PALETTE colour of its position among the uncoloured ones; with many,
    also the style and marker of its position."""
    color = PALETTE[position % len(PALETTE)]
    if not many:
        return replace(series, color=color)
    combinations = len(PALETTE) * len(STYLES)
    return replace(series, color=color, style=STYLES[position % len(STYLES)],
                   marker=MARKERS[(position // combinations) % len(MARKERS)])


def shades(color: str, count: int) -> list[str]:
    """`count` shades of a colour, from itself towards white (at most 65 % of the way): the
    values of a field drawn in one support's colour."""
    rgb = [int(color[i:i + 2], 16) for i in (1, 3, 5)]
    return [_towards_white(rgb, 0.65 * k / max(count - 1, 1)) for k in range(count)]


def _towards_white(rgb: list[int], t: float) -> str:
    """The colour a fraction t of the way from rgb to white, as #RRGGBB."""
    return "#" + "".join(f"{round(c + (255 - c) * t):02X}" for c in rgb)


def scaled_unit(largest: float, unit: str, units: str = "si") -> tuple[float, str]:
    """(factor from SI, unit) of an axis of forces (N), moments (N m) or energies (J): in SI kilo
    or mega (or giga), whichever keeps its tick labels below 10 000; in US units kip, kip ft
    (display.py), or thousands of them."""
    if units != "si":
        return _scaled_us(largest, unit, units)
    for factor, prefix in ((1e-3, "k"), (1e-6, "M")):
        if abs(largest) * factor < 1e4:
            return factor, prefix + unit
    return 1e-9, "G" + unit


def _scaled_us(largest: float, unit: str, units: str) -> tuple[float, str]:
    """The display unit (kip, kip ft), or thousands of it where the labels would pass 10 000."""
    from ..display import unit as display_unit

    shown = display_unit(unit, units)
    if abs(largest) * shown.factor < 1e4:
        return shown.factor, shown.label
    return shown.factor * 1e-3, f"1000 {shown.label}"
