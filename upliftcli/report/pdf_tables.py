"""How a report table fits the page of the PDF (report/pdf_document.py): no word is ever broken,
so each column is at least as wide as its longest word. Tried in order: A4 portrait at the
table sizes FONT_SIZES (each column as wide as its longest cell, or narrower with its cells
wrapped at spaces), then A4 landscape at the same sizes, then column groups (the first column
repeated in each) on landscape at the smallest size. Pure arithmetic on the fonts' widths."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

#: the font sizes a table may be set in, largest first [pt]
FONT_SIZES = (8.5, 8.0, 7.5, 7.0)
#: a cell's left plus right padding (3 pt each) and 1 pt to spare [pt]
PADDING = 7.0

#: (text, bold, size) -> the width it is set in [pt]
Measure = Callable[[str, bool, float], float]


@dataclass(frozen=True)
class Layout:
    """A table's fit: the font size, the column widths [pt] of each column group (their column
    indices in `groups`; one group: the whole table) and whether its pages are landscape;
    split_long: a "word" wider than the landscape page (a path of 200 characters) is broken, the
    only case where any is."""

    size: float
    groups: tuple[tuple[int, ...], ...]
    widths: tuple[tuple[float, ...], ...]
    landscape: bool
    split_long: bool = False


def words(text: str) -> list[str]:
    """The words of a cell (split at white space, where a cell may wrap)."""
    return text.split() or [""]


def column_widths(rows: Sequence[Sequence[str]], size: float, measure: Measure) -> tuple[list[float], list[float]]:
    """(the narrowest, the natural) width of each column at `size`: its longest word, its longest
    cell, each plus PADDING; rows[0] is the header row (bold)."""
    narrowest = [0.0] * len(rows[0])
    natural = [0.0] * len(rows[0])
    for number, row in enumerate(rows):
        for column, text in enumerate(row):
            bold = number == 0
            longest = max(measure(word, bold, size) for word in words(text))
            narrowest[column] = max(narrowest[column], longest + PADDING)
            natural[column] = max(natural[column], measure(" ".join(words(text)), bold, size) + PADDING)
    return narrowest, natural


def share(narrowest: Sequence[float], natural: Sequence[float], width: float) -> tuple[float, ...] | None:
    """Column widths within `width`: the natural ones when they fit, else each column's narrowest
    plus a share of the room left in proportion to what it lacks; None when even the narrowest
    do not fit."""
    if sum(natural) <= width:
        return tuple(natural)
    room = width - sum(narrowest)
    if room < 0:
        return None
    lacking = [b - a for a, b in zip(narrowest, natural, strict=True)]
    total = sum(lacking) or 1.0
    return tuple(a + room * d / total for a, d in zip(narrowest, lacking, strict=True))


def fit_whole(rows: Sequence[Sequence[str]], width: float, measure: Measure) -> tuple[float, tuple[float, ...]] | None:
    """(size, widths) of the largest FONT_SIZES at which the whole table fits `width`, or None."""
    for size in FONT_SIZES:
        widths = share(*column_widths(rows, size, measure), width)
        if widths is not None:
            return size, widths
    return None


def column_groups(narrowest: Sequence[float], width: float) -> list[tuple[int, ...]]:
    """The columns after the first in groups, each group with the first column within `width`
    (a column wider than the page alone stays a group of its own)."""
    groups: list[list[int]] = [[0]]
    for column in range(1, len(narrowest)):
        used = sum(narrowest[c] for c in groups[-1])
        if len(groups[-1]) > 1 and used + narrowest[column] > width:
            groups.append([0])
        groups[-1].append(column)
    return [tuple(group) for group in groups]


def pick(rows: Sequence[Sequence[str]], columns: Sequence[int]) -> list[list[str]]:
    """The rows cut to `columns`."""
    return [[row[c] for c in columns] for row in rows]


def grouped(rows: Sequence[Sequence[str]], width: float, measure: Measure) -> Layout:
    """The table in column groups at the smallest size on `width` (landscape); a group whose
    words alone are wider than that, narrowed to it with its longest "words" broken."""
    size = FONT_SIZES[-1]
    groups = column_groups(column_widths(rows, size, measure)[0], width)
    widths = [share(*column_widths(pick(rows, group), size, measure), width) for group in groups]
    narrowed = tuple(found or squeezed(column_widths(pick(rows, g), size, measure)[0], width)
                     for found, g in zip(widths, groups, strict=True))
    return Layout(size, tuple(groups), narrowed, True, None in widths)


def squeezed(narrowest: Sequence[float], width: float) -> tuple[float, ...]:
    """Column widths scaled down in proportion to sum to `width`."""
    return tuple(w * width / sum(narrowest) for w in narrowest)


def fit(rows: Sequence[Sequence[str]], portrait: float, landscape: float, measure: Measure) -> Layout:
    """The layout of a table (rows[0]: its headers) on a page `portrait` wide, else `landscape`
    wide, else in column groups on landscape."""
    everything = (tuple(range(len(rows[0]))),)
    for width, turned in ((portrait, False), (landscape, True)):
        found = fit_whole(rows, width, measure)
        if found is not None:
            return Layout(found[0], everything, (found[1],), turned)
    return grouped(rows, landscape, measure)
