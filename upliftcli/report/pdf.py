"""The report as a PDF printed from its HTML by a headless Chromium (`uplift report --pdf-engine
chromium`; the default engine is reportlab, report/pdf_document.py): the Debian package
`chromium`, with the report's own print CSS (A4, running header, "page N of M") and without the
browser's header and footer (--no-pdf-header-footer: no file URL, no date of its own).

Chromium is not a Python dependency: where it is not installed, `--pdf-engine chromium` is
refused in one line (exit 2); the reportlab PDF and the HTML report still work."""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

from ..errors import InputError
from ..runtime.atomic import write_bytes

#: executables tried, in order
BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
#: seconds a print may take (a report of every engine prints in about 3 s)
TIMEOUT = 180
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--no-first-run",
         "--no-default-browser-check", "--disable-background-networking", "--disable-component-update",
         "--disable-sync", "--no-pdf-header-footer")


def browser() -> str | None:
    """The path of a Chromium executable on PATH, or None."""
    return next((found for name in BROWSERS if (found := shutil.which(name))), None)


def check_browser(option: str, value: str) -> str:
    """The Chromium executable, or InputError naming the option: a PDF needs it."""
    found = browser()
    if found is None:
        raise InputError(option, value, "a PDF of --pdf-engine reportlab (the default) or a .html file name: "
                         "--pdf-engine chromium needs Chromium, which is not installed (apt-get install chromium)")
    return found


def print_pdf(html: str, out: Path, executable: str, option: str = "--out") -> None:
    """Print the HTML document to `out` (PDF) with Chromium; the file appears whole or not at
    all (printed into a temporary folder, then moved). InputError when the browser fails."""
    out = Path(out)
    with tempfile.TemporaryDirectory(prefix="uplift-report-") as folder:
        page, pdf = Path(folder) / "report.html", Path(folder) / "report.pdf"
        page.write_text(html, encoding="utf-8")
        command = [executable, *FLAGS, f"--user-data-dir={Path(folder) / 'profile'}", f"--print-to-pdf={pdf}",
                   page.as_uri()]
        done = _run(command, executable, option, out)
        if not _is_pdf(pdf):
            last = (done.stderr.strip().splitlines() or ["no message"])[-1]
            raise InputError(option, str(out), f"a PDF printed by {executable} (exit {done.returncode}: {last})")
        write_bytes(out, pdf.read_bytes())  # atomically, with the user's permissions


def _run(command: list[str], executable: str, option: str, out: Path) -> subprocess.CompletedProcess:
    """The browser run (TIMEOUT); InputError when it cannot start or takes too long."""
    try:
        return subprocess.run(command, capture_output=True, text=True, timeout=TIMEOUT, check=False)
    except (OSError, subprocess.TimeoutExpired) as error:
        raise InputError(option, str(out), f"a PDF printed by {executable} ({error})") from None


def _is_pdf(path: Path) -> bool:
    """Whether the browser wrote a PDF there (a file, not empty, starting %PDF)."""
    return path.is_file() and path.stat().st_size > 0 and path.read_bytes().startswith(b"%PDF")
