"""The calculation report rendered in a real headless browser (Chromium from the Debian packages,
driven through the DevTools protocol: tests/cdp.py): it loads offline with no console error,
every figure decodes, a screenshot of the figures is not blank, the print styles apply.

.ci/run installs chromium where it is missing; without it these tests are skipped."""

import base64
import io
from pathlib import Path

import numpy as np
import pytest
from cdp import Browser, chromium
from figure_cases import SMALL, small_run

from upliftcli import plots
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
    codes = (pixels[:, 0].astype(np.int32) << 16) | (pixels[:, 1].astype(np.int32) << 8) | pixels[:, 2]
    return pixels, int(np.unique(codes).size)


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
    shot = browser.screenshot({**figures, "height": min(figures["height"], 3000)})
    pixels, distinct = colours(shot)
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
