"""A Report (report/document.py) as one self-contained HTML file: the figures embedded as
base64 PNG, the styles inline, no script, no link, no external reference; a Content Security
Policy that forbids every network request; a title block (project, job number, subject,
revision, prepared by, checked by, date) and a sign-off block; print CSS (A4 portrait, a
running header with the project and the subject, "page N of M" and the tool at the foot of
every page in the page's margin boxes, figures and table rows kept whole, table headers
repeated on each page, each figure printed at its own size or smaller)."""

from __future__ import annotations

import base64
import re
import struct
from html import escape

from .document import PROJECT_FIELDS, Figure, Pre, Report, Section, SignOff, Table, Text

#: nothing may be fetched: images only from data: URLs, styles only inline
CSP = "default-src 'none'; img-src data:; style-src 'unsafe-inline'"
_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")
#: CSS pixels per inch
CSS_PX = 96

CSS = """
:root { --ink: #1a1a1a; --rule: #c8c8c8; --muted: #555; --ok: #0b6e4f; --fail: #b03a00; }
body { font-family: "DejaVu Sans", "Helvetica Neue", Arial, sans-serif; color: var(--ink); margin: 2em auto;
       max-width: 1180px; padding: 0 1.5em; line-height: 1.4; font-size: 15px; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.25em; border-bottom: 1px solid var(--rule); padding-bottom: 0.2em; margin-top: 2em; }
p.sub { margin: 0.1em 0; color: var(--muted); }
nav ol { columns: 3; font-size: 0.95em; }
.verdict { padding: 0.6em 0.9em; border-left: 5px solid var(--ok); background: #eef7f3; }
.verdict.fail { border-left-color: var(--fail); background: #fbefe8; }
table { border-collapse: collapse; margin: 0.8em 0 1.4em; font-size: 0.88em; }
caption { caption-side: top; text-align: left; font-weight: bold; padding-bottom: 0.3em; }
th, td { border: 1px solid var(--rule); padding: 0.18em 0.5em; vertical-align: top; }
th { background: #f2f2f2; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
p.note { font-size: 0.85em; color: var(--muted); margin-top: -1em; }
pre { background: #f7f7f7; border: 1px solid var(--rule); padding: 0.8em; font-size: 0.82em;
      font-family: "DejaVu Sans Mono", "Courier New", monospace; white-space: pre-wrap; word-break: break-word; }
figure { margin: 1.2em 0 2em; }
figure img { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { font-size: 0.9em; color: var(--muted); margin-top: 0.3em; }
.wide { overflow-x: auto; }
table.title-block { width: 100%; margin: 0.6em 0 0.8em; font-size: 0.95em; }
table.title-block th { width: 16%; }
table.title-block td { width: 34%; }
table.signoff { width: 100%; }
table.signoff th { width: 16%; }
table.signoff td { height: 2.4em; }
table.signoff td.line { width: 30%; }
@page { size: A4 portrait; margin: 17mm 12mm 15mm;
  @top-left { content: RUNNING_LEFT; font: 8pt "DejaVu Sans", Arial, sans-serif; color: #555; }
  @top-right { content: RUNNING_RIGHT; font: 8pt "DejaVu Sans", Arial, sans-serif; color: #555; }
  @bottom-left { content: FOOT_LEFT; font: 8pt "DejaVu Sans", Arial, sans-serif; color: #555; }
  @bottom-right { content: "page " counter(page) " of " counter(pages); font: 8pt "DejaVu Sans", Arial, sans-serif; }
}
@media print {
  body { margin: 0; max-width: none; padding: 0; font-size: 10pt; }
  nav { display: none; }
  h1 { font-size: 15pt; margin-top: 0; }
  h2 { break-after: avoid; page-break-after: avoid; margin-top: 1.2em; }
  figure, table.title-block, table.signoff { break-inside: avoid; page-break-inside: avoid; }
  figure { margin: 0.6em 0 1em; }
  figure img { border: none; }
  pre { font-size: 8pt; }
  tr { break-inside: avoid; page-break-inside: avoid; }
  thead { display: table-header-group; }
  table { font-size: 8.5pt; }
  td, th { overflow-wrap: anywhere; }  /* a SHA-256 or a path never widens the page (Chromium would shrink it) */
  td.num { overflow-wrap: normal; }
  table.title-block { font-size: 9pt; }
  p.note, figcaption { font-size: 8pt; }
  .wide { overflow: visible; }
  a { color: inherit; text-decoration: none; }
}
"""


def css_string(text: str) -> str:
    """A CSS string literal of a text (quotes, backslashes, line breaks and '<' escaped: no
    text can end the string or the <style> element)."""
    out = text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", " ").replace("<", "\\3C ")
    return f'"{out}"'


def page_css(report: Report) -> str:
    """CSS with the running header and footer of this report: top left the project, job number
    and revision (or the title), top right the subject; bottom left the tool and the date,
    bottom right "page N of M"."""
    foot = ", ".join(part for part in (report.footer, report.date) if part)
    return (CSS.replace("RUNNING_LEFT", css_string(running_left(report)))
            .replace("RUNNING_RIGHT", css_string(report.subject)).replace("FOOT_LEFT", css_string(foot)))


def running_left(report: Report) -> str:
    """The project, job number and revision given, joined by dashes; else the report's title."""
    project = report.project
    parts = (project.get("project", ""), _labelled("job", project.get("job_number")),
             _labelled("rev.", project.get("revision")))
    return " \u2014 ".join(part for part in parts if part) or report.title


def _labelled(prefix: str, value: str | None) -> str:
    """'prefix value', '' when no value is given."""
    return f"{prefix} {value}" if value else ""


def _is_number(text: str) -> bool:
    """Whether a cell holds a number (right-aligned)."""
    return bool(_NUMBER.match(text.strip() or "x"))


def _cell(text: str, header: bool = False) -> str:
    tag = "th" if header else "td"
    kind = ' class="num"' if not header and _is_number(text) else ""
    return f"<{tag}{kind}>{escape(text)}</{tag}>"


def _row_html(row: list[str]) -> str:
    return "<tr>" + "".join(_cell(c) for c in row) + "</tr>"


def _note_html(note: str) -> str:
    return f'<p class="note">{escape(note)}</p>' if note else ""


def table_html(table: Table) -> str:
    head = "".join(_cell(h, True) for h in table.headers)
    body = "\n".join(_row_html(row) for row in table.rows)
    return (f'<div class="wide"><table id="{escape(table.id)}"><caption>{escape(table.caption)}</caption>\n'
            f"<thead><tr>{head}</tr></thead>\n<tbody>\n{body}\n</tbody></table></div>{_note_html(table.note)}")


def png_size(png: bytes) -> tuple[int, int]:
    """(width, height) in pixels of a PNG image (its IHDR chunk)."""
    if png[:8] != b"\x89PNG\r\n\x1a\n" or len(png) < 24:
        raise ValueError("not a PNG image")
    return struct.unpack(">II", png[16:24])


def figure_html(figure: Figure, png: bytes, dpi: float | None = None) -> str:
    """The figure; dpi: that of the PNG, whose <img> is then as wide as the figure was drawn
    (its text prints at the size it was set, or smaller on a narrower page)."""
    data = base64.b64encode(png).decode("ascii")
    width = f' width="{round(png_size(png)[0] * CSS_PX / dpi)}"' if dpi else ""
    return (f'<figure id="{escape(figure.id)}"><img src="data:image/png;base64,{data}"{width} '
            f'alt="{escape(figure.caption)}"><figcaption>{escape(figure.caption)}</figcaption></figure>')


def text_html(text: Text) -> str:
    paragraphs = "".join(f"<p>{escape(p)}</p>" for p in text.paragraphs)
    return paragraphs + _items_html(text.items)


def _items_html(items: list[str]) -> str:
    """A bulleted list, '' without items."""
    return f"<ul>{''.join(f'<li>{escape(i)}</li>' for i in items)}</ul>" if items else ""


def pre_html(block: Pre) -> str:
    """Preformatted text under its caption."""
    return f'<p class="note">{escape(block.caption)}</p><pre id="{escape(block.id)}">{escape(block.text)}</pre>'


def signoff_html(block: SignOff) -> str:
    """The sign-off block: per role the name (or a line to write it on), a signature and a date."""
    rows = "".join(f'<tr><th>{escape(role)}</th><td class="line">{escape(name)}</td><td class="line"></td>'
                   '<td class="line"></td></tr>' for role, name in block.rows)
    return ('<table class="signoff" id="signoff"><caption>Sign-off</caption><thead><tr><th></th><th>name</th>'
            f"<th>signature</th><th>date</th></tr></thead><tbody>{rows}</tbody></table>")


def _field(report: Report, name: str) -> str:
    """A [project] field of the report, escaped ('' when not given)."""
    return escape(report.project.get(name, ""))


def title_block_html(report: Report) -> str:
    """Project, job number, subject, revision, prepared by, checked by, date and the tool: the
    fields not given are left blank (to be filled in by hand)."""
    rows = [(PROJECT_FIELDS["project"], _field(report, "project"), PROJECT_FIELDS["job_number"],
             _field(report, "job_number")),
            ("Subject", escape(report.subject), PROJECT_FIELDS["revision"], _field(report, "revision")),
            (PROJECT_FIELDS["engineer"], _field(report, "engineer"), PROJECT_FIELDS["checker"],
             _field(report, "checker")),
            ("Date (UTC)", escape(report.date), "Program", escape(report.footer))]
    body = "".join(f"<tr><th>{a}</th><td>{b}</td><th>{c}</th><td>{d}</td></tr>" for a, b, c, d in rows)
    return f'<table class="title-block" id="title-block"><tbody>{body}</tbody></table>'


def block_html(block, images: dict[str, bytes], dpi: float | None = None) -> str:
    """A block of a section (document.py) as HTML; a Figure with its image from `images`."""
    if isinstance(block, Table):
        return table_html(block)
    if isinstance(block, Figure):
        return figure_html(block, images[block.name], dpi)
    if isinstance(block, Pre):
        return pre_html(block)
    if isinstance(block, Text):
        return text_html(block)
    return signoff_html(block)


def verdict_html(report: Report) -> str:
    """The criteria verdict, marked as failed when `uplift analyze` would exit with an error."""
    kind = "verdict" if report.exit_code == 0 else "verdict fail"
    return f'<p class="{kind}" id="verdict">{escape(report.verdict)}</p>'


def section_html(number: int, section: Section, report: Report, images: dict[str, bytes],
                 dpi: float | None = None) -> str:
    """A numbered section; the summary's first block is the verdict."""
    blocks = [block_html(block, images, dpi) for block in section.blocks]
    if section.id == "summary":
        blocks[0] = verdict_html(report)
    return (f'<section id="{escape(section.id)}"><h2>{number}. {escape(section.title)}</h2>\n'
            + "\n".join(blocks) + "</section>")


def render(report: Report, images: dict[str, bytes], dpi: float | None = None, template=None) -> str:
    """The HTML document; images: figure name -> PNG bytes (every Figure of the report needs
    one), drawn at `dpi` (then each <img> is as wide as its figure); template: the page frame
    (report/template.py: a loaded jinja2.Template; default templates/page.html)."""
    from markupsafe import Markup

    from .template import load, render_page

    parts = [section_html(number, section, report, images, dpi) for number, section in enumerate(report.sections, 1)]
    context = {"report": report, "project": report.project, "csp": Markup(CSP), "css": Markup(page_css(report)),
               "title_block": Markup(title_block_html(report)), "sections": Markup("\n".join(parts))}
    template = template or load()
    return render_page(template, context, template.filename)
