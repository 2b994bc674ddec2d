"""The PDF report that reportlab writes from the Report (upliftcli.report.pdf_document): tables fit
A4 with no word broken (smaller type, wrapped cells, landscape pages, column groups), each
figure whole on one page (a figure taller than the page scaled to fit it), the running header,
"page N of M" and the title and sign-off blocks; read back with poppler-utils (pdftotext,
pdfimages, pdfinfo), which .ci/run installs (without them those tests are skipped)."""

import html
import io
import re
import shutil
import subprocess
from pathlib import Path

import pytest
from figure_cases import EXAMPLE_DECK, SMALL, small_run
from typer.testing import CliRunner

from upliftcli.cli import app
from upliftcli.cli.report import REPORT_DPI
from upliftcli.report.build import build_report
from upliftcli.report.document import Figure, Pre, Report, Section, Table, Text
from upliftcli.report.pdf_document import write_pdf
from upliftcli.report.pdf_style import frame_size
from upliftcli.report.pdf_tables import FONT_SIZES, fit
from upliftcli.report.provenance import provenance

needs_poppler = pytest.mark.skipif(any(shutil.which(tool) is None for tool in ("pdftotext", "pdfimages", "pdfinfo")),
                                   reason="poppler-utils is not installed (apt-get install -y poppler-utils; "
                                          ".ci/run installs it)")
#: words the PDF prints that are not the report's own text: the title and sign-off blocks' labels
LABELS = {"Project", "Job", "number", "Subject", "Revision", "Prepared", "by", "Checked", "Date", "(UTC)", "Program",
          "Sign-off", "name", "signature", "date", "page", "of", "\u2014", "job", "rev.", "\u2022", "\u2026",
          "columns"}
PROJECT = ["--project", "Harbour St", "--job-number", "24-117", "--engineer", "A. Engineer", "--checker",
           "B. Checker", "--revision", "A"]


def poppler(*args) -> str:
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, check=True, timeout=120).stdout


def page_words(pdf: Path) -> list[list[str]]:
    """The words of each page (pdftotext -bbox: a word is what the PDF sets apart by space)."""
    pages = poppler("pdftotext", "-bbox", pdf, "-").split("<page ")[1:]
    return [[html.unescape(w) for w in re.findall(r"<word [^>]*>([^<]*)</word>", page)] for page in pages]


def images(pdf: Path) -> list[list[str]]:
    """pdfimages -list rows of the images (not their masks): page, num, type, width, height ... x-ppi, y-ppi."""
    rows = [line.split() for line in poppler("pdfimages", "-list", pdf).splitlines()[2:]]
    return [row for row in rows if row[2] == "image"]


def page_sizes(pdf: Path) -> list[tuple[float, float]]:
    """(width, height) of every page [pt]."""
    info = poppler("pdfinfo", "-f", 1, "-l", 10_000, pdf)
    return [(float(w), float(h)) for w, h in re.findall(r"Page +\d+ size: +([\d.]+) x ([\d.]+)", info)]


def texts(report: Report):
    """Every text of a report (title, subtitle, blocks ...)."""
    yield from (report.title, report.verdict, report.subject, f"{report.footer}, {report.date}", *report.subtitle)
    yield from report.project.values()
    for number, section in enumerate(report.sections, 1):
        yield f"{number}. {section.title}"
        for block in section.blocks:
            yield from block_texts(block)


def block_texts(block):
    if isinstance(block, Table):
        return [block.caption, block.note, *block.headers, *(c for row in block.rows for c in row)]
    if isinstance(block, Text):
        return [*block.paragraphs, *block.items]
    if isinstance(block, Pre | Figure):
        return [block.caption, getattr(block, "text", "")]
    return [text for row in block.rows for text in row]


def unbroken(report: Report, pdf: Path) -> list[str]:
    """The words of the PDF that are not words of the report (a word broken in two gives two such
    pieces), other than the blocks' labels and page numbers."""
    words = {word for text in texts(report) for word in text.split()}
    return [w for page in page_words(pdf) for w in page if w not in words | LABELS and not w.isdigit()]


@pytest.fixture(scope="module")
def small_pdf(tmp_path_factory):
    """The report of the small run written by reportlab, with its figures drawn."""
    from upliftcli.figures import draw as plots

    deck, results = small_run()
    report, specs = build_report(deck, results, Path(deck.source).read_text(), SMALL, provenance(deck, ["test"]))
    drawn = {name: plots.figure_bytes(spec, dpi=REPORT_DPI) for name, spec in specs.items()}
    out = tmp_path_factory.mktemp("pdf") / "report.pdf"
    write_pdf(report, drawn, REPORT_DPI, out)
    return report, out


def width_of(text: str, bold: bool, size: float) -> float:
    """A stand-in font: every character 0.6 em wide."""
    return 0.6 * size * len(text)


def test_table_layout_portrait_landscape_and_column_groups():
    narrow = [["quantity", "value"], ["T_1", "0.5"]]
    layout = fit(narrow, 500, 800, width_of)
    assert not layout.landscape and layout.size == FONT_SIZES[0] and layout.groups == ((0, 1),)
    wide = [[f"heading{k}" for k in range(9)], ["simplified support"] * 9]  # words 8-10 letters
    layout = fit(wide, 400, 800, width_of)  # 9 x 49 pt at 7 pt: not in portrait
    assert layout.landscape and len(layout.groups) == 1 and sum(layout.widths[0]) <= 800 + 1e-9
    for column, header in enumerate(wide[0]):  # each column as wide as its longest word
        assert layout.widths[0][column] >= width_of(max(header, "simplified", key=len), True, layout.size)
    widest = [[f"heading{k}" for k in range(30)], ["supported"] * 30]
    layout = fit(widest, 450, 800, width_of)
    assert layout.landscape and len(layout.groups) > 1 and layout.size == FONT_SIZES[-1]
    assert all(group[0] == 0 for group in layout.groups)  # the first column in every group
    assert sorted({c for group in layout.groups for c in group}) == list(range(30))
    assert all(sum(widths) <= 800 + 1e-9 for widths in layout.widths) and not layout.split_long


@needs_poppler
def test_a_word_wider_than_the_page_is_the_only_one_broken(tmp_path):
    """A path of 300 characters (no space) cannot fit landscape whole: that table alone breaks
    its long "words", which stay on the page (reportlab would draw them past its edge)."""
    path = "/".join(["folder"] * 42) + "/r.txt"
    layout = fit([["role", "path"], ["record", path]], 450, 800, width_of)
    assert layout.split_long and all(sum(widths) <= 800 + 1e-9 for widths in layout.widths)
    table = Table("table-files", "Input files", ["role", "path"], [["record", path]])
    report = Report("Paths", [], [Section("s", "Files", [table])], "ok", 0)
    write_pdf(report, {}, REPORT_DPI, tmp_path / "paths.pdf")
    pages = poppler("pdftotext", "-bbox", tmp_path / "paths.pdf", "-").split("<page ")[1:]
    overhang = [float(x) - float(re.match(r'width="([\d.]+)"', page).group(1))
                for page in pages for x in re.findall(r'<word xMin="[\d.]+" yMin="[\d.]+" xMax="([\d.]+)"', page)]
    assert len(overhang) > 5 and max(overhang) < -30  # every word inside the page's margin


@needs_poppler
def test_no_word_broken_in_the_report(small_pdf):
    """Every word of the PDF is a word of the report: none broken at a line end ('simplifie|d')."""
    report, pdf = small_pdf
    assert unbroken(report, pdf) == []
    words = [w for page in page_words(pdf) for w in page]
    assert len(words) > 3000 and words.count("simplified") > 20 and "support" in words
    for table in report.tables():  # every heading's and first column's words, whole
        for text in [*table.headers, *(row[0] for row in table.rows)]:
            assert set(text.split()) <= set(words), (table.id, text)


def wide_report(columns: int) -> Report:
    """A report of one table with `columns` columns of long words, and paragraphs; markup
    characters in its texts (printed as they read)."""
    headers = ["quantity", *(f"simplified/exact support{k}" for k in range(1, columns))]
    rows = [[f"supported quantity{r}", *(f"{1234.5678 * r:.4f}" for _ in range(1, columns))] for r in range(60)]
    table = Table("table-wide", "A wide table", headers, rows, "A note under it.")
    blocks = [Text(["Before the table."]), table, Text(["After the table."])]
    return Report("Wide", ["a test"], [Section("s", "Tables & <notes>", blocks)], "ok", 0,
                  {"project": "Harbour St & <Quay>"}, "subject", "2024-05-01", "uplift test")


@needs_poppler
@pytest.mark.parametrize("columns, groups", [(8, 1), (16, 2)])
def test_wide_tables_on_landscape_pages(tmp_path, columns, groups):
    """A table too wide for portrait goes on landscape pages (and back to portrait after it);
    wider still, in column groups each led by the first column; header rows repeat on every
    page; no word broken."""
    report, out = wide_report(columns), tmp_path / "wide.pdf"
    write_pdf(report, {}, REPORT_DPI, out)
    sizes, pages = page_sizes(out), page_words(out)
    turned = [w > h for w, h in sizes]
    assert turned[0] is False and turned[-1] is False and any(turned)
    assert unbroken(report, out) == []
    assert {"&", "<Quay>", "<notes>"} <= set(pages[0])  # the title block's and the heading's text as given
    for words, landscape in zip(pages, turned, strict=True):
        if landscape:
            assert "quantity" in words and any(re.fullmatch(r"support\d+", w) for w in words)  # header repeated
    first_column = [w for words in pages for w in words if re.fullmatch(r"quantity\d+", w)]
    assert len(first_column) == 60 * groups


def tall_png(width: int, height: int) -> bytes:
    from PIL import Image

    buffer = io.BytesIO()
    Image.new("RGB", (width, height), (0, 114, 178)).save(buffer, "PNG")
    return buffer.getvalue()


@needs_poppler
def test_figure_taller_than_the_page_scaled_onto_one_page(tmp_path):
    """A figure 20 in tall (a 5-panel history is 13.3 in) prints whole on one page with its
    caption, scaled to fit; the page count is that of the blocks."""
    blocks = [Text(["Some text before the figures."] * 30), Figure("figure-tall", "Figure 1. Tall.", "tall"),
              Figure("figure-small", "Figure 2. Small.", "small")]
    report = Report("Figures", [], [Section("figures", "Figures", blocks)], "ok", 0)
    out = tmp_path / "figures.pdf"
    write_pdf(report, {"tall": tall_png(900, 3000), "small": tall_png(900, 600)}, REPORT_DPI, out)
    listed = images(out)
    assert len(listed) == 2 and len(page_sizes(out)) == 3  # text; the tall figure; the small one
    height = frame_size()[1] / 72  # in
    for row, caption in zip(listed, ("1.", "2."), strict=True):
        page, printed = int(row[0]), int(row[4]) / float(row[13])
        assert printed <= height
        assert caption in page_words(out)[page - 1]  # the caption on the figure's page
    assert int(listed[0][4]) / float(listed[0][13]) > 0.85 * height  # scaled to the page, not below it


@needs_poppler
def test_report_figures_whole_each_on_one_page(small_pdf):
    report, pdf = small_pdf
    listed, pages = images(pdf), page_words(pdf)
    assert len(listed) == len(report.figures())  # each figure drawn once: none cut into pieces
    height = frame_size()[1] / 72
    for number, row in enumerate(listed, 1):
        assert int(row[4]) / float(row[13]) <= height
        assert f"{number}." in pages[int(row[0]) - 1]  # 'Figure N.' under it, on its page


@needs_poppler
def test_uplift_report_pdf_without_a_browser(tmp_path):
    """`uplift report --out r.pdf` with no browser on PATH: reportlab writes it, every page with
    the running header and 'page N of M', the title and sign-off blocks on page 1."""
    out = tmp_path / "r.pdf"
    settings = [item for setting in SMALL for item in ("--set", setting)]
    result = CliRunner().invoke(app, ["report", str(EXAMPLE_DECK), "--out", str(out), *settings, *PROJECT],
                                env={"CI": "true", "PATH": ""})
    assert result.exit_code == 0, result.output
    assert out.read_bytes().startswith(b"%PDF") and sorted(p.name for p in tmp_path.iterdir()) == ["r.pdf"]
    pages = poppler("pdftotext", "-layout", out, "-").split("\f")[:-1]
    assert len(pages) > 5
    for number, text in enumerate(pages, 1):
        assert re.search(rf"page {number} of {len(pages)}\s*$", text.rstrip()), number
        assert "Harbour St \u2014 job 24-117 \u2014 rev. A" in text.splitlines()[0]
    for label, value in (("Project", "Harbour St"), ("Job number", "24-117"), ("Prepared by", "A. Engineer"),
                         ("Checked by", "B. Checker"), ("Revision", "A")):
        assert re.search(rf"{label}\s+{re.escape(value)}", pages[0]), label
    assert re.search(r"Sign-off\s+name\s+signature\s+date", pages[0]) and "V_b [kN]" in pages[0]
    assert b"/Title (1. Summary)" in out.read_bytes()  # each section an entry of the PDF's outline
