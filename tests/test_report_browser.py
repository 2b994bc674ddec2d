"""The calculation report rendered in a real headless browser (Chromium from the Debian packages,
driven through the DevTools protocol: tests/cdp.py): it loads offline with no console error,
every figure decodes, a screenshot of the figures is not blank, the print styles apply.

.ci/run installs chromium where it is missing; without it these tests are skipped."""

import base64
import html
import io
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from cdp import Browser, chromium
from figure_cases import EXAMPLE_DECK, SMALL, small_run
from typer.testing import CliRunner

from upliftcli.cli import app
from upliftcli.figures import draw as plots
from upliftcli.figures.style import BLUE, VERMILLION
from upliftcli.report.build import build_report
from upliftcli.report.html import render
from upliftcli.report.provenance import provenance

pytestmark = pytest.mark.skipif(chromium() is None, reason="chromium is not installed (apt-get install -y chromium; "
                                                            ".ci/run installs it)")


@pytest.fixture(scope="module")
def report_file(tmp_path_factory):
    deck, results = small_run()
    report, specs = build_report(deck, results, Path(deck.source).read_text(), SMALL, provenance(deck, ["test"]))
    images = {name: plots.figure_bytes(spec) for name, spec in specs.items()}
    path = tmp_path_factory.mktemp("report") / "report.html"
    path.write_text(render(report, images), encoding="utf-8")
    return path, len(specs)


@pytest.fixture(scope="module")
def browser():
    with Browser() as opened:
        yield opened


def rect(browser, selector):
    """{x, y, width, height} of an element in page coordinates [CSS px]."""
    return browser.evaluate(f"""(() => {{ const r = document.querySelector({selector!r}).getBoundingClientRect();
        return {{x: r.x + window.scrollX, y: r.y + window.scrollY, width: r.width, height: r.height}}; }})()""")


def colours(png: bytes) -> tuple[np.ndarray, int]:
    from PIL import Image

    pixels = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).reshape(-1, 3)
    return pixels, colours_of(pixels)


def colours_of(pixels: np.ndarray) -> int:
    """The number of distinct colours of (n, 3) RGB pixels."""
    codes = (pixels[:, 0].astype(np.int32) << 16) | (pixels[:, 1].astype(np.int32) << 8) | pixels[:, 2]
    return int(np.unique(codes).size)


def share_near(pixels: np.ndarray, hex_colour: str, tolerance: int = 40) -> float:
    target = np.array([int(hex_colour[i:i + 2], 16) for i in (1, 3, 5)])
    return float(np.mean(np.abs(pixels.astype(int) - target).max(axis=1) <= tolerance))


def test_loads_with_no_console_error_and_every_figure_decodes(browser, report_file):
    path, count = report_file
    browser.open(path.as_uri())
    assert browser.errors() == []
    images = browser.evaluate("Array.from(document.images).map(i => [i.complete, i.naturalWidth, i.naturalHeight])")
    assert len(images) == count
    assert all(done and width > 300 and height > 200 for done, width, height in images)
    assert browser.evaluate("document.querySelectorAll('table').length") >= 20
    assert browser.evaluate("performance.getEntriesByType('resource').length") == 0  # nothing fetched


def test_screenshot_shows_the_figures(browser, report_file):
    path, _ = report_file
    browser.open(path.as_uri())
    figures = rect(browser, "#figures")
    parts = [colours(browser.screenshot({**figures, "y": figures["y"] + top,
                                         "height": min(figures["height"] - top, 3000)}))[0]
             for top in range(0, int(figures["height"]), 3000)]  # every figure, 3000 px a screenshot
    pixels = np.concatenate(parts)
    distinct = colours_of(pixels)
    tables = colours(browser.screenshot(rect(browser, "#table-modes")))[1]
    assert distinct > 2000 and distinct > 10 * tables  # anti-aliased lines and shading, not a blank page
    assert share_near(pixels, BLUE) > 1e-3 and share_near(pixels, VERMILLION) > 1e-3  # the supports' lines
    assert np.mean(pixels.min(axis=1) > 245) < 0.97  # not (almost) all white
    # the first figure's image fills its box: drawn, not a broken-image placeholder
    first = rect(browser, "#figures figure img")
    assert first["width"] > 800 and first["height"] > 200


def test_print_styles(browser, report_file):
    path, _ = report_file
    browser.open(path.as_uri())
    browser.call("Emulation.setEmulatedMedia", media="print")
    try:
        assert browser.evaluate("getComputedStyle(document.querySelector('nav')).display") == "none"
        assert browser.evaluate("getComputedStyle(document.querySelector('figure')).breakInside") == "avoid"
        assert browser.evaluate("getComputedStyle(document.querySelector('thead')).display") == "table-header-group"
    finally:
        browser.call("Emulation.setEmulatedMedia", media="")
    pdf = browser.call("Page.printToPDF", preferCSSPageSize=True)["data"]
    assert base64.b64decode(pdf).startswith(b"%PDF")


def test_the_checks_catch_a_broken_page(browser, tmp_path):
    """The same checks fail on a page with a script error and a missing image (no network used)."""
    page = tmp_path / "broken.html"
    page.write_text('<!DOCTYPE html><html><body><img src="missing.png"><script>console.error("boom");</script>'
                    "</body></html>")
    browser.open(page.as_uri())
    errors = browser.errors()
    assert any("boom" in e for e in errors) and len(errors) >= 2
    assert browser.evaluate("Array.from(document.images).map(i => i.naturalWidth)") == [0]
    assert colours(browser.screenshot({"x": 0, "y": 0, "width": 400, "height": 300}))[1] < 2000  # no figure


# ----------------------------------------------------------------------------- the PDF

needs_poppler = pytest.mark.skipif(shutil.which("pdftotext") is None or shutil.which("pdfimages") is None,
                                   reason="poppler-utils is not installed (apt-get install -y poppler-utils; "
                                          ".ci/run installs it)")
PROJECT = ["--project", "Harbour St", "--job-number", "24-117", "--engineer", "A. Engineer", "--checker",
           "B. Checker", "--revision", "A"]
#: the smallest text a printed report may hold [pt]
SMALLEST_PT = 7.0


def poppler(*args: str) -> str:
    return subprocess.run(args, capture_output=True, text=True, check=True, timeout=120).stdout


def word_boxes(pdf: Path) -> list[list[tuple[float, float, float, float, str]]]:
    """Per page, every word (xMin, yMin, xMax, yMax [pt], text) of `pdftotext -bbox`."""
    pages = poppler("pdftotext", "-bbox", str(pdf), "-").split("<page ")[1:]
    pattern = re.compile(r'<word xMin="([\d.]+)" yMin="([\d.]+)" xMax="([\d.]+)" yMax="([\d.]+)">([^<]*)</word>')
    return [[(*map(float, match.groups()[:4]), html.unescape(match.group(5))) for match in pattern.finditer(page)]
            for page in pages]


@pytest.fixture(scope="module")
def pdf_report(tmp_path_factory):
    """`uplift report --out report.pdf --pdf-engine chromium` of the small run, with the [project]
    fields given as options."""
    out = tmp_path_factory.mktemp("pdf") / "report.pdf"
    settings = [*(item for setting in SMALL for item in ("--set", setting)), "--pdf-engine", "chromium"]
    result = CliRunner().invoke(app, ["report", str(EXAMPLE_DECK), "--out", str(out), *settings, *PROJECT],
                                env={"CI": "true"})
    assert result.exit_code == 0, result.output
    return out


@pytest.fixture(scope="module")
def seven_point_height(tmp_path_factory):
    """The height pdftotext gives a word set in 7 pt, printed by the same Chromium, in the
    report's fonts: a word's box is its font's ascent plus descent, proportional to its size
    (1.16 x the size in DejaVu Sans and in DejaVu Sans Mono alike). The larger of the two: a word
    at least that tall is set in 7 pt or more in either font (pdftotext does not tell the font;
    PyMuPDF would, but is a large dependency for one test)."""
    from upliftcli.report.pdf import browser, print_pdf

    out = tmp_path_factory.mktemp("probe") / "probe.pdf"
    print_pdf('<!DOCTYPE html><html><body><p style="font: 7pt \'DejaVu Sans\'">Sample seven</p>'
              '<p style="font: 7pt \'DejaVu Sans Mono\'">Sample mono</p></body></html>', out, browser())
    heights = [y1 - y0 for page in word_boxes(out) for _, y0, _, y1, _ in page]
    assert len(heights) == 4
    return max(heights)


@needs_poppler
def test_pdf_pages_numbered_with_running_header(pdf_report):
    pages = poppler("pdftotext", "-layout", str(pdf_report), "-").split("\f")[:-1]
    count = int(re.search(r"Pages:\s+(\d+)", poppler("pdfinfo", str(pdf_report))).group(1))
    assert len(pages) == count > 5
    for number, text in enumerate(pages, 1):
        assert re.search(rf"page {number} of {count}\s*$", text.rstrip()), f"page {number}: no 'page N of M'"
        assert "Harbour St \u2014 job 24-117 \u2014 rev. A" in text.splitlines()[0]
        assert "file://" not in text and "report.html" not in text  # none of the browser's own header and footer


@needs_poppler
def test_pdf_title_and_signoff_blocks_on_page_one(pdf_report):
    first = poppler("pdftotext", "-f", "1", "-l", "1", "-layout", str(pdf_report), "-")
    for label, value in (("Project", "Harbour St"), ("Job number", "24-117"), ("Prepared by", "A. Engineer"),
                         ("Checked by", "B. Checker"), ("Revision", "A")):
        assert re.search(rf"{label}\s+{re.escape(value)}", first), label
    assert re.search(r"Sign-off\s+name\s+signature\s+date", first)
    assert re.search(r"Prepared by\s+A\. Engineer\s*\n", first) and re.search(r"Checked by\s+B\. Checker", first)
    assert "Summary" in first and "V_b [kN]" in first  # page 1 is not half empty: the summary follows the blocks


@needs_poppler
def test_pdf_text_no_smaller_than_7_pt(pdf_report, seven_point_height):
    """Every word of the PDF (tables, notes, header, footer) at least as tall as a 7-pt word of
    the same fonts, and the figures' text at least 7 pt as printed: the smallest font a figure
    uses (read from the drawn figure) times the figure's printed scale (its image's pixels per
    printed inch, from pdfimages, against the resolution it was drawn at)."""
    from upliftcli.cli.report import REPORT_DPI
    from upliftcli.figures.sets import analysis_figures

    heights = [y1 - y0 for page in word_boxes(pdf_report) for _, y0, _, y1, _ in page]
    assert len(heights) > 2000
    assert min(heights) >= 0.999 * seven_point_height
    listed = poppler("pdfimages", "-list", str(pdf_report)).splitlines()[2:]
    images = [line.split() for line in listed if line.split()[2] == "image"]
    specs = list(analysis_figures(*small_run()).values())
    assert len(images) == len(specs)
    from matplotlib.text import Text

    for spec, image in zip(specs, images, strict=True):
        figure = plots.line_figure(spec)
        smallest = min(text.get_fontsize() for text in figure.findobj(Text) if text.get_text().strip())
        x_ppi = float(image[12])
        printed = smallest * REPORT_DPI / x_ppi
        assert printed >= SMALLEST_PT, f"{spec.title}: {printed:.2f} pt"
        width = figure.get_figwidth()
        assert int(image[3]) == round(width * REPORT_DPI)  # the image of this figure


@needs_poppler
def test_pdf_no_page_with_one_small_figure(pdf_report):
    """A page holding a figure holds more than it when the figure is small (under 40 % of the
    printable area of A4 with the report's margins)."""
    listed = [line.split() for line in poppler("pdfimages", "-list", str(pdf_report)).splitlines()[2:]]
    images = [row for row in listed if row[2] == "image"]
    boxes = word_boxes(pdf_report)
    printable = (210 - 24) / 25.4 * (297 - 32) / 25.4  # in^2
    for page in {int(row[0]) for row in images}:
        mine = [row for row in images if int(row[0]) == page]
        area = sum(int(row[3]) / float(row[12]) * int(row[4]) / float(row[13]) for row in mine)
        words = len(boxes[page - 1])
        assert len(mine) > 1 or area > 0.4 * printable or words > 150, f"page {page}: one small figure"


@needs_poppler
def test_pdf_record_spectra_fill_their_page(pdf_report):
    """The record's spectra (S_d, S_v, S_a) are laid out for A4 portrait like the histories:
    printed across the page's printable width and over most of its height (two panels a row
    filled 67 % of the page, a quarter of their grid empty)."""
    from upliftcli.figures.sets import analysis_figures

    names = list(analysis_figures(*small_run()))
    listed = [line.split() for line in poppler("pdfimages", "-list", str(pdf_report)).splitlines()[2:]]
    images = [row for row in listed if row[2] == "image"]
    assert len(images) == len(names)
    page, _, _, width, height, *_, x_ppi, y_ppi = images[names.index("spectrum")][:14]
    printable = (210 - 24) / 25.4, (297 - 32) / 25.4  # in
    printed = int(width) / float(x_ppi), int(height) / float(y_ppi)
    assert printed[0] > 0.98 * printable[0]
    assert printed[0] * printed[1] > 0.85 * printable[0] * printable[1], f"page {page}: {printed}"
    assert sum(int(row[0]) == int(page) for row in images) == 1


@needs_poppler
def test_pdf_of_a_firms_template_printed_by_chromium(tmp_path):
    """--template frames the page Chromium prints: the firm's letterhead on page 1 of the PDF."""
    template, out = tmp_path / "firm.html", tmp_path / "r.pdf"
    template.write_text('<!DOCTYPE html><html><head><meta charset="utf-8"><style>{{ css }}</style></head><body>'
                        '<p>Acme Structural Partners</p><h1>{{ report.title }}</h1>{{ sections }}</body></html>')
    settings = [item for setting in SMALL for item in ("--set", setting)]
    result = CliRunner().invoke(app, ["report", str(EXAMPLE_DECK), "--out", str(out), *settings, "--no-check",
                                      "--pdf-engine", "chromium", "--template", str(template)], env={"CI": "true"})
    assert result.exit_code == 0, result.output
    first = poppler("pdftotext", "-f", "1", "-l", "1", "-layout", str(out), "-")
    assert "Acme Structural Partners" in first and "Calculation report" in first
    assert "Job number" not in first  # the built-in title block is not in this frame
