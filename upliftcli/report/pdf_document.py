"""The report as a PDF written directly from the Report (report/document.py) by reportlab (pure
Python, installed by pip alone on every platform; docs/report.md says why this engine): A4
portrait, a running header (project, job number and revision; the subject) and "page N of M"
with the program and the date at the foot of every page, the title and sign-off blocks, tables
fitted to the page with no word broken (landscape pages where a table needs them), each figure
kept whole on one page. The file appears whole or not at all (runtime/atomic.py)."""

from __future__ import annotations

import functools
import io
from pathlib import Path
from xml.sax.saxutils import escape

from reportlab.pdfgen.canvas import Canvas
from reportlab.platypus import (
    BaseDocTemplate,
    Frame,
    KeepTogether,
    NextPageTemplate,
    PageBreak,
    PageTemplate,
    Paragraph,
)
from reportlab.platypus.doctemplate import LayoutError

from ..errors import InputError
from ..runtime.atomic import write_bytes
from .document import Report, Section
from .html import running_left
from .pdf_blocks import block_flowables, heading_flowables, verdict_flowables
from .pdf_style import BOTTOM, LANDSCAPE, MUTED, PORTRAIT, SANS, SIDE, TOP, fonts, frame_size, style

#: the size of the running header and footer [pt]
RUNNING_SIZE = 8.0


class PagedCanvas(Canvas):
    """A canvas that holds its pages back to the end, then draws on each the running header and
    "page N of M" (N, M known only then). running: (top left, top right, bottom left) texts."""

    def __init__(self, *args, running: tuple[str, str, str] = ("", "", ""), **kwargs):
        super().__init__(*args, **kwargs)
        self.running = running
        self.pages: list[dict] = []

    def showPage(self):  # reportlab's name
        self.pages.append(dict(self.__dict__))
        self._startPage()

    def save(self):
        for number, page in enumerate(self.pages, 1):
            self.__dict__.update(page)
            draw_running(self, number, len(self.pages))
            super().showPage()
        super().save()


def draw_running(canvas: Canvas, number: int, count: int) -> None:
    """The running header and footer of a page (portrait or landscape) in small grey type."""
    width, height = canvas._pagesize
    left, right, foot = canvas.running
    canvas.setFont(SANS, RUNNING_SIZE)
    canvas.setFillColor(MUTED)
    half = (width - 2 * SIDE) / 2 - 6
    canvas.drawString(SIDE, height - TOP + 14, clipped(left, half))
    canvas.drawRightString(width - SIDE, height - TOP + 14, clipped(right, half))
    canvas.drawString(SIDE, BOTTOM - 20, foot)
    canvas.drawRightString(width - SIDE, BOTTOM - 20, f"page {number} of {count}")


def clipped(text: str, width: float) -> str:
    """The text cut at a word to fit `width` in the running type, with an ellipsis where cut."""
    from reportlab.pdfbase.pdfmetrics import stringWidth

    words = text.split()
    while len(words) > 1 and stringWidth(" ".join(words) + " \u2026", SANS, RUNNING_SIZE) > width:
        words.pop()
    kept = " ".join(words)
    return kept if kept == " ".join(text.split()) else kept + " \u2026"


class ReportTemplate(BaseDocTemplate):
    """A4 pages, portrait and landscape; each section heading an entry of the PDF's outline."""

    def afterFlowable(self, flowable):  # reportlab's name
        key = getattr(flowable, "outline_key", None)
        if key:
            self.canv.bookmarkPage(key)
            self.canv.addOutlineEntry(flowable.getPlainText(), key, 0)


def page_templates() -> list[PageTemplate]:
    """The portrait and the landscape page, each one frame inside the margins."""
    return [PageTemplate(name, [Frame(SIDE, BOTTOM, *frame_size(turned), 0, 0, 0, 0, id=name)], pagesize=size)
            for name, size, turned in (("portrait", PORTRAIT, False), ("landscape", LANDSCAPE, True))]


def section_parts(number: int, section: Section, report: Report, images: dict[str, bytes],
                  dpi: float) -> list[tuple[bool, list]]:
    """(landscape, flowables) of a numbered section; its heading goes with its first block (into
    a figure's KeepTogether: on its page)."""
    parts = [verdict_flowables(report) if section.id == "summary" and k == 0 else block_flowables(block, images, dpi)
             for k, block in enumerate(section.blocks)]
    heading = Paragraph(escape(f"{number}. {section.title}"), style("h2", 12.5))
    heading.outline_key = section.id
    turned, first = parts[0] if parts else (False, [])
    return [(turned, with_heading(heading, first)), *parts[1:]]


def with_heading(heading: Paragraph, flowables: list) -> list:
    """The heading before the flowables, inside the first when it is kept together (a figure)."""
    if flowables and isinstance(flowables[0], KeepTogether):
        return [KeepTogether([heading, *flowables[0]._content]), *flowables[1:]]
    return [heading, *flowables]


def story(report: Report, images: dict[str, bytes], dpi: float) -> list:
    """Every flowable of the report, with a page break where the orientation changes."""
    parts = [(False, heading_flowables(report))]
    for number, section in enumerate(report.sections, 1):
        parts += section_parts(number, section, report, images, dpi)
    flowables, turned = [], False
    for landscape, items in parts:
        if landscape != turned:
            flowables += [NextPageTemplate("landscape" if landscape else "portrait"), PageBreak()]
            turned = landscape
        flowables += items
    return flowables


def render_pdf(report: Report, images: dict[str, bytes], dpi: float) -> bytes:
    """The report as PDF bytes; images: figure name -> PNG drawn at `dpi`."""
    fonts()
    buffer = io.BytesIO()
    document = ReportTemplate(buffer, pagesize=PORTRAIT, pageTemplates=page_templates(), title=report.title,
                              author=report.project.get("engineer", ""), subject=report.subject,
                              creator=report.footer, invariant=1)
    running = (running_left(report), report.subject, ", ".join(p for p in (report.footer, report.date) if p))
    document.build(story(report, images, dpi), canvasmaker=functools.partial(PagedCanvas, running=running))
    return buffer.getvalue()


def write_pdf(report: Report, images: dict[str, bytes], dpi: float, out: Path, option: str = "--out") -> None:
    """The PDF into `out`, atomically; InputError when a block cannot be laid out on a page."""
    try:
        data = render_pdf(report, images, dpi)
    except LayoutError as error:
        raise InputError(option, str(out), f"a PDF the report fits ({error})") from None
    write_bytes(Path(out), data)
