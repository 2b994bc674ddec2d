"""Colours and line styles shared by every figure.

The palette is Okabe & Ito's colour-blind-safe set (Okabe and Ito 2008, "Color universal
design"), without its yellow (too pale on white). Supports have fixed colours, engines fixed
line styles, so that rigid/bonded/uplift and exact/approximate/simplified read the same in
every figure; dotted lines are kept for reference lines (critical values, limits).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

from .spec import Series

BLACK, ORANGE, SKY_BLUE, GREEN, BLUE, VERMILLION, PURPLE = (
    "#000000", "#E69F00", "#56B4E9", "#009E73", "#0072B2", "#D55E00", "#CC79A7")
#: colour-blind-safe colours in the order lines take them
PALETTE = (BLUE, VERMILLION, GREEN, PURPLE, ORANGE, SKY_BLUE, BLACK)
#: line styles cycled with the colours when a panel has many lines (4 and 7 are coprime:
#: 28 lines before a (colour, style) pair repeats)
STYLES = ("-", "--", "-.", (0, (5, 1, 1, 1, 1, 1)))
#: a panel with more automatically coloured lines than this also varies their style
MANY_LINES = 4

SUPPORT_COLORS = {"rigid": BLACK, "bonded": BLUE, "uplift": VERMILLION}
ENGINE_LINES = {"exact": "-", "approximate": "--", "simplified": "-."}
SUPPORT_STYLES = {"rigid": ("-", BLACK), "bonded": ("--", BLUE), "uplift": ("-", VERMILLION)}
ENGINE_STYLES = {"exact": ("-", BLACK), "approximate": ("--", ORANGE), "simplified": ("-.", GREEN)}
#: shading of the contact state: the left and the right edge of the mat lifted
LIFT_COLORS = {"left": ORANGE, "right": SKY_BLUE}


def cycle(series: Sequence[Series]) -> list[Series]:
    """The series with a palette colour for each that has none and, when they are many
    (more than MANY_LINES), a line style cycling with the colours: every line distinct."""
    free = [k for k, s in enumerate(series) if s.color is None]
    many = len(free) > MANY_LINES
    out = list(series)
    for position, k in enumerate(free):
        style = STYLES[position % len(STYLES)] if many else out[k].style
        out[k] = replace(out[k], color=PALETTE[position % len(PALETTE)], style=style)
    return out


def scaled_unit(largest: float, unit: str) -> tuple[float, str]:
    """(factor from SI, unit) of an axis of forces (N), moments (N m) or energies (J): kilo or
    mega (or giga), whichever keeps its tick labels below 10 000."""
    for factor, prefix in ((1e-3, "k"), (1e-6, "M")):
        if abs(largest) * factor < 1e4:
            return factor, prefix + unit
    return 1e-9, "G" + unit
