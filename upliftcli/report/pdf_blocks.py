"""The blocks of a Report (report/document.py) as reportlab flowables: tables fitted to the page
(report/pdf_tables.py: no word broken, header rows repeated on every page, rows kept whole,
landscape or column groups when a table is too wide for portrait), figures kept whole and
scaled to fit the page, paragraphs, lists, preformatted text and the title and sign-off blocks.

Each block gives (landscape, flowables): report/pdf_document.py turns the page where that changes."""

from __future__ import annotations

import io
from xml.sax.saxutils import escape

from reportlab.platypus import Image, KeepTogether, Paragraph, Preformatted, Spacer, Table, TableStyle

from .document import PROJECT_FIELDS, Figure, Pre, Report, SignOff, Text
from .document import Table as ReportTable
from .html import _is_number, png_size
from .pdf_style import FAIL, OK, RULE, SHADE, frame_size, measure, style
from .pdf_tables import Layout, fit, pick

#: the width of a DejaVu Sans Mono character [em]
MONO_ADVANCE = 0.602
#: the size of preformatted text [pt]
PRE_SIZE = 8.0
#: room kept above a figure as tall as the page, for the heading of its section [pt]
HEADING_ROOM = 36.0


def text(value: str, kind: str = "body", size: float = 10.0) -> Paragraph:
    """A paragraph of plain text (escaped for reportlab's markup)."""
    return Paragraph(escape(value), style(kind, size))


def cell(value: str, header: bool, size: float, split: bool = False) -> Paragraph:
    """A table cell: bold in the header row, right-aligned when it holds a number; split: a word
    wider than the cell may break (pdf_tables.Layout.split_long)."""
    kind = "head" if header else ("num" if _is_number(value) else "body")
    return Paragraph(escape(value), style(kind, size, split))


def grid(rows: list[list], widths, header_rows: int = 1, heights=None) -> Table:
    """A ruled table of flowables, its header rows shaded and repeated on every page; heights:
    of the rows (None: as their cells need)."""
    table = Table(rows, colWidths=list(widths), rowHeights=heights, repeatRows=header_rows, hAlign="LEFT")
    table.setStyle(TableStyle([("GRID", (0, 0), (-1, -1), 0.5, RULE), ("VALIGN", (0, 0), (-1, -1), "TOP"),
                               ("BACKGROUND", (0, 0), (-1, header_rows - 1), SHADE),
                               ("LEFTPADDING", (0, 0), (-1, -1), 3), ("RIGHTPADDING", (0, 0), (-1, -1), 3),
                               ("TOPPADDING", (0, 0), (-1, -1), 1.5), ("BOTTOMPADDING", (0, 0), (-1, -1), 2)]))
    return table


def table_flowables(table: ReportTable) -> tuple[bool, list]:
    """(landscape, [caption, the table or its column groups, note])."""
    rows = [table.headers, *table.rows]
    layout = fit(rows, frame_size()[0], frame_size(True)[0], measure)
    parts = [text(table.caption, "caption", 9.0)]
    for number, (group, widths) in enumerate(zip(layout.groups, layout.widths, strict=True), 1):
        parts += group_flowables(pick(rows, group), widths, layout, (number, len(layout.groups)))
    return layout.landscape, parts + ([text(table.note, "note", 8.0)] if table.note else [])


def group_flowables(rows: list[list[str]], widths, layout: Layout, place: tuple[int, int]) -> list:
    """A table (or its column group `place` = (number, of how many), labelled when there are
    several) in the layout's type, its first row the header."""
    label = [text(f"columns {place[0]} of {place[1]}", "note", 8.0)] if place[1] > 1 else []
    cells = [[cell(value, k == 0, layout.size, layout.split_long) for value in row] for k, row in enumerate(rows)]
    return [*label, grid(cells, widths), Spacer(1, 6)]


def figure_flowables(figure: Figure, png: bytes, dpi: float) -> tuple[bool, list]:
    """(False, [the figure and its caption kept together]): the image at the size it was drawn
    (`dpi`), or smaller to fit the page's width and, with its caption and a section heading
    (HEADING_ROOM), its height: a figure is never split across pages."""
    caption = text(figure.caption, "note", 8.0)
    width, height = frame_size()
    caption_height = caption.wrap(width, height)[1] + 12 + HEADING_ROOM
    pixels = png_size(png)
    drawn = pixels[0] / dpi * 72, pixels[1] / dpi * 72
    scale = min(1.0, width / drawn[0], (height - caption_height) / drawn[1])
    image = Image(io.BytesIO(png), drawn[0] * scale, drawn[1] * scale, hAlign="LEFT")
    return False, [KeepTogether([Spacer(1, 4), image, caption])]


def pre_flowables(block: Pre) -> tuple[bool, list]:
    """(False, [caption, the text in monospace]): lines longer than the page wrapped at spaces."""
    columns = int((frame_size()[0] - 8) / (MONO_ADVANCE * PRE_SIZE))
    body = Preformatted(block.text, style("pre", PRE_SIZE), maxLineLength=columns, splitChars=" ", newLineChars="")
    return False, [text(block.caption, "note", 8.0), body]


def text_flowables(block: Text) -> tuple[bool, list]:
    """(False, the paragraphs and the bulleted items)."""
    items = [Paragraph(escape(item), style("body", 10.0), bulletText="\u2022") for item in block.items]
    return False, [text(paragraph) for paragraph in block.paragraphs] + items


def signoff_flowables(block: SignOff) -> tuple[bool, list]:
    """(False, [the sign-off block]): per role the name, and room for a signature and a date."""
    width = frame_size()[0]
    rows = [[cell(v, True, 9.0) for v in ("", "name", "signature", "date")]]
    rows += [[cell(role, True, 9.0), cell(name, False, 9.0), "", ""] for role, name in block.rows]
    table = grid(rows, [0.16 * width, 0.28 * width, 0.28 * width, 0.28 * width],
                 heights=[None] + [24] * len(block.rows))  # room to sign
    table.setStyle(TableStyle([("BACKGROUND", (0, 1), (0, -1), SHADE)]))
    return False, [KeepTogether([text("Sign-off", "caption", 9.0), table]), Spacer(1, 6)]


def verdict_flowables(report: Report) -> tuple[bool, list]:
    """(False, [the criteria verdict in a box ruled green, or orange when the run fails])."""
    box = Table([[text(report.verdict)]], colWidths=[frame_size()[0]], hAlign="LEFT")
    box.setStyle(TableStyle([("LINEBEFORE", (0, 0), (0, 0), 4, OK if report.exit_code == 0 else FAIL),
                             ("BACKGROUND", (0, 0), (-1, -1), "#eef7f3" if report.exit_code == 0 else "#fbefe8")]))
    return False, [box, Spacer(1, 8)]


def title_block(report: Report) -> Table:
    """Project, job number, subject, revision, prepared by, checked by, date and the program
    (the fields not given blank, to be filled in by hand)."""
    field = report.project.get
    pairs = [(PROJECT_FIELDS["project"], field("project", ""), PROJECT_FIELDS["job_number"], field("job_number", "")),
             ("Subject", report.subject, PROJECT_FIELDS["revision"], field("revision", "")),
             (PROJECT_FIELDS["engineer"], field("engineer", ""), PROJECT_FIELDS["checker"], field("checker", "")),
             ("Date (UTC)", report.date, "Program", report.footer)]
    rows = [[cell(a, True, 9.0), text(b, size=9.0), cell(c, True, 9.0), text(d, size=9.0)] for a, b, c, d in pairs]
    width = frame_size()[0]
    table = grid(rows, [0.16 * width, 0.34 * width, 0.16 * width, 0.34 * width], header_rows=0)
    table.setStyle(TableStyle([("BACKGROUND", (0, 0), (0, -1), SHADE), ("BACKGROUND", (2, 0), (2, -1), SHADE)]))
    return table


def block_flowables(block, images: dict[str, bytes], dpi: float) -> tuple[bool, list]:
    """(landscape, flowables) of a block of a section."""
    if isinstance(block, ReportTable):
        return table_flowables(block)
    if isinstance(block, Figure):
        return figure_flowables(block, images[block.name], dpi)
    if isinstance(block, Pre):
        return pre_flowables(block)
    if isinstance(block, Text):
        return text_flowables(block)
    return signoff_flowables(block)


def heading_flowables(report: Report) -> list:
    """The title, the title block and the lines under the title."""
    lines = [Paragraph(escape(line), style("sub", 9.0)) for line in report.subtitle]
    return [text(report.title, "h1", 15.0), title_block(report), Spacer(1, 6), *lines, Spacer(1, 4)]

