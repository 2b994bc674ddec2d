"""Colours and line styles (upliftcli.figures.style)."""

import numpy as np
import pytest

from upliftcli.figures.spec import Series
from upliftcli.figures.style import MANY_LINES, PALETTE, STYLES, cycle, scaled_unit


def lines(count, color=None):
    return [Series(f"line {k}", np.arange(2.0), np.arange(2.0), "-", color) for k in range(count)]


def test_few_lines_keep_their_style_and_take_palette_colours():
    out = cycle(lines(MANY_LINES))
    assert [s.color for s in out] == list(PALETTE[:MANY_LINES]) and {s.style for s in out} == {"-"}


@pytest.mark.parametrize("count", [MANY_LINES + 1, 12, len(PALETTE) * len(STYLES)])
def test_many_lines_all_distinct(count):
    out = cycle(lines(count))
    assert len({(s.color, s.style) for s in out}) == count
    assert {s.color for s in out} <= set(PALETTE)


def test_given_colours_are_kept():
    given = lines(2, "#123456")
    out = cycle(given + lines(3))
    assert [s.color for s in out[:2]] == ["#123456"] * 2 and out[2].color == PALETTE[0]


def test_the_palette_is_okabe_ito_without_yellow():
    okabe_ito = {"#000000", "#E69F00", "#56B4E9", "#009E73", "#F0E442", "#0072B2", "#D55E00", "#CC79A7"}
    assert set(PALETTE) == okabe_ito - {"#F0E442"}


def test_scaled_units():
    assert scaled_unit(9.9e6, "N") == (1e-3, "kN")
    assert scaled_unit(1.2e7, "N m") == (1e-6, "MN m")
    assert scaled_unit(2e13, "J") == (1e-9, "GJ")
