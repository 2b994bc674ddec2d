"""The PDF report's page and type (report/pdf_document.py): A4 with the margins of the HTML
report's print styles, and DejaVu Sans and DejaVu Sans Mono (the HTML report's fonts), read from
the copies matplotlib ships (a dependency already) and embedded as subsets: any text prints,
on any system, with no font installed."""

from __future__ import annotations

import functools
from pathlib import Path

from reportlab.lib.colors import HexColor
from reportlab.lib.enums import TA_RIGHT
from reportlab.lib.pagesizes import A4, landscape
from reportlab.lib.styles import ParagraphStyle
from reportlab.lib.units import mm

#: page sizes [pt]
PORTRAIT, LANDSCAPE = A4, landscape(A4)
#: margins: top, right and left, bottom [pt] (as the HTML report's @page)
TOP, SIDE, BOTTOM = 17 * mm, 12 * mm, 15 * mm
INK, MUTED, RULE, SHADE = HexColor("#1a1a1a"), HexColor("#555555"), HexColor("#c8c8c8"), HexColor("#f2f2f2")
OK, FAIL = HexColor("#0b6e4f"), HexColor("#b03a00")
#: font name -> the file in matplotlib's fonts
FONTS = {"DejaVuSans": "DejaVuSans.ttf", "DejaVuSans-Bold": "DejaVuSans-Bold.ttf",
         "DejaVuSansMono": "DejaVuSansMono.ttf"}
SANS, BOLD, MONO = "DejaVuSans", "DejaVuSans-Bold", "DejaVuSansMono"


def frame_size(turned: bool = False) -> tuple[float, float]:
    """(width, height) of the text area of a portrait (or landscape) page [pt]."""
    width, height = LANDSCAPE if turned else PORTRAIT
    return width - 2 * SIDE, height - TOP - BOTTOM


@functools.cache
def fonts() -> tuple[str, ...]:
    """The report's fonts registered with reportlab (once), streams written binary; their names."""
    import matplotlib
    from reportlab import rl_config
    from reportlab.pdfbase import pdfmetrics
    from reportlab.pdfbase.ttfonts import TTFont

    folder = Path(matplotlib.get_data_path()) / "fonts" / "ttf"
    for name, file in FONTS.items():
        pdfmetrics.registerFont(TTFont(name, str(folder / file)))
    pdfmetrics.registerFontFamily(SANS, normal=SANS, bold=BOLD, italic=SANS, boldItalic=BOLD)
    rl_config.useA85 = 0  # binary streams: ASCII85 in pure Python took 2 of the 3.6 s of a report
    return tuple(FONTS)


def measure(text: str, bold: bool, size: float) -> float:
    """The width of a text in the report's sans font (bold for headers) [pt]."""
    from reportlab.pdfbase.pdfmetrics import stringWidth

    fonts()
    return stringWidth(text, BOLD if bold else SANS, size)


@functools.cache
def style(kind: str, size: float = 10.0, split: bool = False) -> ParagraphStyle:
    """A paragraph style: body, head (bold table header), num (right-aligned), h1, h2, caption,
    note, sub, pre (monospace); `size` in pt. Words are never split unless `split` (a table
    whose "words" are wider than a page, pdf_tables.Layout.split_long)."""
    fonts()
    base = ParagraphStyle(kind, fontName=SANS, fontSize=size, leading=1.25 * size, textColor=INK,
                          splitLongWords=int(split))
    extra = {"head": {"fontName": BOLD}, "num": {"alignment": TA_RIGHT},
             "h1": {"fontName": BOLD, "spaceAfter": 4}, "h2": {"fontName": BOLD, "spaceBefore": 12, "spaceAfter": 6,
                                                               "keepWithNext": 1},
             "caption": {"fontName": BOLD, "spaceBefore": 6, "spaceAfter": 3, "keepWithNext": 1},
             "note": {"textColor": MUTED, "spaceBefore": 2, "spaceAfter": 8}, "sub": {"textColor": MUTED},
             "pre": {"fontName": MONO, "spaceBefore": 4, "spaceAfter": 10},
             "body": {"spaceAfter": 4}}
    return ParagraphStyle(kind, parent=base, **extra.get(kind, {}))
