"""A Report (report/document.py) as one self-contained HTML file: the figures embedded as
base64 PNG, the styles inline, no script, no link, no external reference; a Content Security
Policy that forbids every network request; print CSS (A4, figures and table rows kept whole,
table headers repeated on each page)."""

from __future__ import annotations

import base64
import re
from html import escape

from .document import Figure, Pre, Report, Table, Text

#: nothing may be fetched: images only from data: URLs, styles only inline
CSP = "default-src 'none'; img-src data:; style-src 'unsafe-inline'"
_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")

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
      white-space: pre-wrap; word-break: break-word; }
figure { margin: 1.2em 0 2em; }
figure img { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { font-size: 0.9em; color: var(--muted); margin-top: 0.3em; }
.wide { overflow-x: auto; }
@page { size: A4; margin: 14mm 12mm; }
@media print {
  body { margin: 0; max-width: none; padding: 0; font-size: 10.5pt; }
  nav { display: none; }
  h2 { break-after: avoid; page-break-after: avoid; }
  figure, pre { break-inside: avoid; page-break-inside: avoid; }
  tr { break-inside: avoid; page-break-inside: avoid; }
  thead { display: table-header-group; }
  table { font-size: 8.5pt; }
  .wide { overflow: visible; }
  a { color: inherit; text-decoration: none; }
  section#figures figure { break-before: auto; }
}
"""


def _cell(text: str, header: bool = False) -> str:
    tag = "th" if header else "td"
    kind = ' class="num"' if not header and _NUMBER.match(text.strip() or "x") else ""
    return f"<{tag}{kind}>{escape(text)}</{tag}>"


def table_html(table: Table) -> str:
    head = "".join(_cell(h, True) for h in table.headers)
    body = "\n".join("<tr>" + "".join(_cell(c) for c in row) + "</tr>" for row in table.rows)
    note = f'<p class="note">{escape(table.note)}</p>' if table.note else ""
    return (f'<div class="wide"><table id="{escape(table.id)}"><caption>{escape(table.caption)}</caption>\n'
            f"<thead><tr>{head}</tr></thead>\n<tbody>\n{body}\n</tbody></table></div>{note}")


def figure_html(figure: Figure, png: bytes) -> str:
    data = base64.b64encode(png).decode("ascii")
    return (f'<figure id="{escape(figure.id)}"><img src="data:image/png;base64,{data}" alt="{escape(figure.caption)}">'
            f"<figcaption>{escape(figure.caption)}</figcaption></figure>")


def text_html(text: Text) -> str:
    paragraphs = "".join(f"<p>{escape(p)}</p>" for p in text.paragraphs)
    items = "".join(f"<li>{escape(i)}</li>" for i in text.items)
    return paragraphs + (f"<ul>{items}</ul>" if items else "")


def render(report: Report, images: dict[str, bytes]) -> str:
    """The HTML document; images: figure name -> PNG bytes (every Figure of the report needs one)."""
    parts = []
    for number, section in enumerate(report.sections, 1):
        blocks = []
        for block in section.blocks:
            if isinstance(block, Table):
                blocks.append(table_html(block))
            elif isinstance(block, Figure):
                blocks.append(figure_html(block, images[block.name]))
            elif isinstance(block, Pre):
                blocks.append(f'<p class="note">{escape(block.caption)}</p><pre id="{escape(block.id)}">'
                              f"{escape(block.text)}</pre>")
            elif isinstance(block, Text):
                blocks.append(text_html(block))
        if section.id == "summary":
            kind = "verdict" if report.exit_code == 0 else "verdict fail"
            blocks[0] = f'<p class="{kind}" id="verdict">{escape(report.verdict)}</p>'
        parts.append(f'<section id="{escape(section.id)}"><h2>{number}. {escape(section.title)}</h2>\n'
                     + "\n".join(blocks) + "</section>")
    toc = "".join(f'<li><a href="#{escape(s.id)}">{escape(s.title)}</a></li>' for s in report.sections)
    subtitle = "".join(f'<p class="sub">{escape(line)}</p>' for line in report.subtitle)
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f'<meta http-equiv="Content-Security-Policy" content="{CSP}">\n'
            '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
            f"<title>{escape(report.title)}</title>\n<style>{CSS}</style>\n</head>\n<body>\n"
            f"<header><h1>{escape(report.title)}</h1>{subtitle}</header>\n"
            f"<nav><ol>{toc}</ol></nav>\n" + "\n".join(parts) + "\n</body>\n</html>\n")
