"""`uplift report`: the HTML report's page frame is a Jinja2 template a firm can replace
(--template; a bad one is one line naming the file and its line, exit 2), and the run's warnings
go to stderr as `uplift analyze` prints them."""

from pathlib import Path

import pytest
from figure_cases import EXAMPLE_DECK, SMALL
from test_report import Parsed, make_report
from typer.testing import CliRunner

from upliftcli.cli import app
from upliftcli.report.html import render
from upliftcli.report.template import DEFAULT, load

runner = CliRunner()
SETTINGS = [item for setting in SMALL for item in ("--set", setting)]
FIRM = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="{{ csp }}"><title>{{ report.title }}</title>
<style>{{ css }}</style></head>
<body><header class="letterhead"><p class="firm">Acme &amp; Partners Ltd, 1 Quay Road</p>
<h1>{{ report.title }}</h1><p class="job">Job {{ project.job_number }}, prepared by {{ project.engineer }}</p>
</header>
{{ sections }}
</body></html>
"""


def invoke(*args: str):
    return runner.invoke(app, ["report", str(EXAMPLE_DECK), *SETTINGS, *args], env={"CI": "true"})


def test_the_built_in_template_is_the_default():
    report, specs, text, _, _ = make_report()
    images = {name: b"\x89PNG\r\n\x1a\n" + name.encode() for name in specs}
    assert render(report, images, template=load(DEFAULT)) == text
    assert text.startswith("<!DOCTYPE html>") and '<table class="title-block" id="title-block">' in text


def test_a_firms_template_frames_the_report(tmp_path):
    template, out = tmp_path / "firm.html", tmp_path / "r.html"
    template.write_text(FIRM)
    result = invoke("--out", str(out), "--template", str(template), "--job-number", "24-117", "--engineer",
                    "A. <Engineer>", "--no-check")
    assert result.exit_code == 0, result.output
    text = out.read_text()
    assert '<p class="firm">Acme &amp; Partners Ltd, 1 Quay Road</p>' in text
    assert "Job 24-117, prepared by A. &lt;Engineer&gt;" in text  # the deck's fields, escaped
    assert 'id="title-block"' not in text and "<nav>" not in text  # the firm's frame, not the built-in one
    tables = Parsed(text).tables
    assert "table-summary" in tables and "signoff" in tables  # the sections, whole
    assert "default-src 'none'" in text  # markup passed as it is


@pytest.mark.parametrize("body, line", [
    ("<html>\n<body>\n<h1>{{ report..title }}</h1>\n</body>", 3),  # a syntax error
    ("<html>\n{{ report.title }}\n{{ letterhead.firm }}\n</html>", 3),  # an undefined name, found while rendering
])
def test_a_bad_template_is_one_line_naming_the_file_and_line(tmp_path, body, line):
    template, out = tmp_path / "bad.html", tmp_path / "r.html"
    template.write_text(body)
    result = invoke("--out", str(out), "--template", str(template), "--no-check")
    assert result.exit_code == 2
    (message,) = result.stderr.strip().splitlines()
    assert message.startswith(f"error: --template {template}: line {line}: a Jinja2 template"), message
    assert "Traceback" not in result.output and not out.exists()


def test_template_refused_where_it_cannot_apply(tmp_path):
    missing = invoke("--out", str(tmp_path / "r.html"), "--template", str(tmp_path / "none.html"))
    assert missing.exit_code == 2 and "--template" in missing.stderr and "none.html" in missing.stderr
    template = tmp_path / "firm.html"
    template.write_text(FIRM)
    pdf = invoke("--out", str(tmp_path / "r.pdf"), "--template", str(template))  # reportlab takes no HTML frame
    assert pdf.exit_code == 2 and len(pdf.stderr.strip().splitlines()) == 1
    assert "--template" in pdf.stderr and "--pdf-engine chromium" in pdf.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["firm.html"]


def warnings(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if line.startswith("warning: ")]


def test_report_prints_the_warnings_analyze_prints(tmp_path):
    """A story height far outside practice (the deck's warning) and an accuracy check out of band
    (the results'): the same lines on stderr from `uplift report` as from `uplift analyze`."""
    settings = [*SETTINGS, "--set", "building.story_height=40"]
    analyzed = runner.invoke(app, ["analyze", str(EXAMPLE_DECK), *settings], env={"CI": "true"})
    out = tmp_path / "r.html"
    reported = runner.invoke(app, ["report", str(EXAMPLE_DECK), *settings, "--out", str(out)], env={"CI": "true"})
    assert analyzed.exit_code == reported.exit_code == 0, reported.output
    expected = warnings(analyzed.stderr)
    assert any("building.story_height" in w for w in expected) and any("accuracy check" in w for w in expected)
    assert warnings(reported.stderr) == expected
    assert Path(out).exists() and "wrote" in reported.stderr
