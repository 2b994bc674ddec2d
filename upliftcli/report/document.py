"""The report as data: sections of tables, figures, paragraphs and preformatted text (strings,
already formatted), rendered by report/html.py. Nothing here knows HTML."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


@dataclass
class Table:
    """A table: id (unique in the report), caption, column headers (with units), rows of
    cells (text), a note under it."""

    id: str
    caption: str
    headers: list[str]
    rows: list[list[str]]
    note: str = ""


@dataclass
class Figure:
    """A figure of the run: id, caption and the name of its FigureSpec (figures/sets.py)."""

    id: str
    caption: str
    name: str


@dataclass
class Text:
    """Paragraphs of plain text; `items`: a bulleted list after them."""

    paragraphs: list[str]
    items: list[str] = field(default_factory=list)


@dataclass
class Pre:
    """Preformatted text (the deck as given) with a caption."""

    id: str
    caption: str
    text: str


@dataclass
class Section:
    id: str
    title: str
    blocks: list = field(default_factory=list)


@dataclass
class Report:
    """Title, the lines under it, the sections, the criteria verdict and the exit code
    `uplift analyze` gives for the same run."""

    title: str
    subtitle: list[str]
    sections: list[Section]
    verdict: str
    exit_code: int

    def tables(self) -> list[Table]:
        return [b for s in self.sections for b in s.blocks if isinstance(b, Table)]

    def figures(self) -> list[Figure]:
        return [b for s in self.sections for b in s.blocks if isinstance(b, Figure)]


def number(value, digits: int = 5) -> str:
    """A value as text: numbers to `digits` significant digits (plain between 1e-4 and 1e9,
    at least their integer digits, no trailing zeros), lists joined, booleans yes/no, non-finite as '-'."""
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (list, tuple, np.ndarray)):
        return ", ".join(number(v, digits) for v in value)
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        value = float(value)
        if not math.isfinite(value):
            return "-"
        if value == 0.0 or not 1e-4 <= abs(value) < 1e9:
            return f"{value:.{digits}g}"
        decimals = max(0, digits - 1 - math.floor(math.log10(abs(value))))
        text = f"{value:.{decimals}f}"  # `digits` significant digits, no exponent
        return text.rstrip("0").rstrip(".") if "." in text else text
    return "-" if value is None else str(value)
