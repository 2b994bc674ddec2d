"""Colours and line styles (upliftcli.figures.style)."""

import numpy as np
import pytest

from upliftcli.figures.spec import Series
from upliftcli.figures.style import (
    ENGINE_COLORS,
    ENGINE_STYLES,
    LIFT_COLORS,
    MANY_LINES,
    MARKERS,
    PALETTE,
    STYLES,
    SUPPORT_COLORS,
    SUPPORT_STYLES,
    cycle,
    scaled_unit,
    shades,
)


def lines(count, color=None):
    return [Series(f"line {k}", np.arange(2.0), np.arange(2.0), "-", color) for k in range(count)]


def test_few_lines_keep_their_style_and_take_palette_colours():
    out = cycle(lines(MANY_LINES))
    assert [s.color for s in out] == list(PALETTE[:MANY_LINES]) and {s.style for s in out} == {"-"}


@pytest.mark.parametrize("count", [MANY_LINES + 1, 9, len(PALETTE) * len(STYLES), 40])
def test_many_lines_all_distinct(count):
    out = cycle(lines(count))
    assert len({(s.color, s.style, s.marker) for s in out}) == count
    assert {s.color for s in out} <= set(PALETTE)
    assert len(MARKERS) > 1


def test_given_colours_are_kept():
    given = lines(2, "#123456")
    out = cycle(given + lines(3))
    assert [s.color for s in out[:2]] == ["#123456"] * 2 and out[2].color == PALETTE[0]


def test_the_colours_are_okabe_ito_without_yellow_and_each_means_one_thing():
    okabe_ito = {"#000000", "#E69F00", "#56B4E9", "#009E73", "#F0E442", "#0072B2", "#D55E00", "#CC79A7"}
    supports, engines = set(SUPPORT_COLORS.values()), set(ENGINE_COLORS.values())
    assert supports | engines | {PALETTE[0]} == okabe_ito - {"#F0E442"}
    # a support's colour is never an engine's, nor that of another line or shading
    assert len(supports) == 3 and len(engines) == 3 and not supports & engines
    assert not (supports | engines) & (set(PALETTE) | set(LIFT_COLORS.values()))
    assert {color for _, color in SUPPORT_STYLES.values()} == supports
    assert {color for _, color in ENGINE_STYLES.values()} == engines


def test_shades_of_a_colour_are_distinct_and_start_at_it():
    out = shades("#0072B2", 3)
    assert out[0] == "#0072B2" and len(set(out)) == 3
    assert shades("#000000", 1) == ["#000000"]


def test_scaled_units():
    assert scaled_unit(9.9e6, "N") == (1e-3, "kN")
    assert scaled_unit(1.2e7, "N m") == (1e-6, "MN m")
    assert scaled_unit(2e13, "J") == (1e-9, "GJ")
    factor, unit = scaled_unit(2e7, "N", "us")  # 4496 kip
    assert unit == "kip" and factor == pytest.approx(1 / 4448.2216152605)
    factor, unit = scaled_unit(6.3e8, "N m", "us")  # 464,700 kip ft
    assert unit == "1000 kip ft" and factor == pytest.approx(1e-3 / 1355.8179483314)
