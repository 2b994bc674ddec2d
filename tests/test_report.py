"""The calculation report (upliftcli.report): its content against the results, the HTML parsed
(every table and figure present, nothing external), `uplift report` end to end."""

import base64
import hashlib
import re
from dataclasses import replace
from datetime import UTC, datetime
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from figure_cases import SMALL, small_run
from typer.testing import CliRunner

from upliftcli.cli import app
from upliftcli.deck import criteria
from upliftcli.engines.quantities import QUANTITIES
from upliftcli.report.build import build_report
from upliftcli.report.html import CSP, render
from upliftcli.report.provenance import provenance
from upliftcli.runtime.installed import tool_version

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"
PNG = b"\x89PNG\r\n\x1a\n"
NOW = datetime(2024, 5, 1, 12, 0, 0, tzinfo=UTC)


class Parsed(HTMLParser):
    """Tables (id -> rows of cell texts), figures (id -> img src), every tag and attribute."""

    def __init__(self, text: str):
        super().__init__()
        self.tables, self.figures, self.tags, self.attributes = {}, {}, [], []
        self._table = self._figure = self._row = self._cell = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        self.tags.append(tag)
        self.attributes += list(attrs.items())
        if tag == "table":
            self._table = self.tables.setdefault(attrs["id"], [])
        elif tag == "figure":
            self._figure = attrs["id"]
        elif tag == "img":
            self.figures[self._figure] = attrs["src"]
        elif tag == "tr" and self._table is not None:
            self._row = []
        elif tag in ("td", "th") and self._row is not None:
            self._cell = ""

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self._row.append(self._cell)
            self._cell = None
        elif tag == "tr" and self._row is not None:
            self._table.append(self._row)
            self._row = None
        elif tag == "table":
            self._table = None


def make_report(deck=None, results=None, checks=()):
    small_deck, small_results = small_run()
    deck, results = deck or small_deck, list(results or small_results)
    info = provenance(deck, ["uplift", "report", "deck.toml"], NOW)
    report, specs = build_report(deck, results, Path(deck.source).read_text(), SMALL, info, checks=checks)
    images = {name: PNG + name.encode() for name in specs}  # stand-ins: drawing is tested in test_plots
    return report, specs, render(report, images), deck, results


def test_every_table_and_figure_present():
    report, specs, text, _, results = make_report()
    parsed = Parsed(text)
    expected = {"table-summary-head", "table-resolved", "table-building", "table-system", "table-foundation",
                "table-motion", "table-modes", "table-summary", "table-accuracy", "table-criteria",
                "table-provenance", "table-files"}
    for r in results:
        expected |= {f"table-{r.engine}-{r.support}-stories", f"table-{r.engine}-{r.support}-intermediates"}
        if r.support != "rigid":
            expected.add(f"table-{r.engine}-{r.support}-elements")
        if r.engine == "exact":
            expected.add(f"table-{r.engine}-{r.support}-energy")
    assert expected <= set(parsed.tables) == {t.id for t in report.tables()} | {"title-block", "signoff"}
    assert set(parsed.figures) == {f"figure-{name.replace('_', '-')}" for name in specs} == \
        {f.id for f in report.figures()}
    assert set(specs) == {"profiles", "modes", "spectrum", "histories_exact", "moment_rotation_exact", "energy_exact"}
    for src in parsed.figures.values():
        assert src.startswith("data:image/png;base64,")
        assert base64.b64decode(src.split(",", 1)[1]).startswith(PNG)
    sections = re.findall(r'<section id="([a-z]+)"', text)
    assert sections == ["summary", "inputs", "model", "motion", "modes", "results", "accuracy", "warnings",
                        "criteria", "figures", "method", "provenance"]


def test_nothing_external():
    _, _, text, _, _ = make_report()
    parsed = Parsed(text)
    assert not re.search(r"https?:", text, re.IGNORECASE)
    assert "link" not in parsed.tags and "script" not in parsed.tags and "iframe" not in parsed.tags
    assert all(value.startswith(("data:", "#")) for key, value in parsed.attributes if key in ("src", "href"))
    assert "url(" not in text and "@import" not in text
    assert f'content="{CSP}"' in text and "default-src 'none'" in CSP
    assert "@media print" in text and "@page" in text


def test_tables_equal_the_results():
    _, _, text, deck, results = make_report()
    parsed = Parsed(text)
    summary = parsed.tables["table-summary"]
    assert summary[0][:3] == ["engine", "support", "V_b [kN]"]
    for row, r in zip(summary[1:], results, strict=True):
        assert row[:3] == [r.engine, r.support, f"{1e-3 * r.base_shear:.1f}"]
        assert float(row[3]) == pytest.approx(r.base_shear_coefficient, abs=5e-5)
        assert row[-1] == ("yes" if r.uplift else "no")
    exact_uplift = next(r for r in results if r.engine == "exact" and r.support == "uplift")
    stories = parsed.tables["table-exact-uplift-stories"]
    header = stories[0]
    shear = header.index(QUANTITIES["shear"].heading())
    drift = header.index(QUANTITIES["drift_ratio"].heading())
    for row in stories[1:]:  # top story first
        j = int(row[0]) - 1
        assert float(row[shear]) == pytest.approx(1e-3 * exact_uplift.peaks["shear"][j], abs=0.05)
        assert float(row[drift]) == pytest.approx(100 * exact_uplift.peaks["drift_ratio"][j], abs=5e-4)
    assert [int(row[0]) for row in stories[1:]] == list(range(deck.system.building.n_stories, 0, -1))
    modes = parsed.tables["table-modes"]
    assert float(modes[1][1]) == pytest.approx(deck.system.modes.periods[0], rel=1e-4)
    assert sum(float(row[3]) for row in modes[1:]) == pytest.approx(1.0, abs=1e-3)  # m_n*/m_t, massless mat
    resolved = {row[0]: row for row in parsed.tables["table-resolved"][1:]}
    assert resolved["building.stories"][1:4] == ["4", "-", "--set"]
    assert resolved["building.floor_mass"][1:4] == ["350000", "kg", "deck"]
    system = {row[0]: row[1] for row in parsed.tables["table-system"][1:]}
    assert float(system["M_c"]) == pytest.approx(1e-3 * deck.system.critical_base_moment, abs=0.05)  # kN m
    foundation = {row[0]: row[1:3] for row in parsed.tables["table-foundation"][1:]}
    k_f, b = deck.system.foundation.stiffness, deck.system.half_width
    assert foundation["K_theta"][1] == "kN m/rad" and foundation["k_f"][1] == "kN/m"
    assert float(foundation["K_theta"][0]) == pytest.approx(2e-3 * k_f * b**2, rel=1e-4)  # [22]
    assert float(foundation["C_theta"][0]) == pytest.approx(2e-3 * deck.system.foundation.damping * b**2,
                                                            rel=1e-4)  # [25]
    # no large number of the report in E-notation (stiffnesses, N and N m were: 2.686e+07)
    numbers = [cell for rows in parsed.tables.values() for row in rows[1:] for cell in row]
    assert not [cell for cell in numbers if re.fullmatch(r"[-+]?\d+(\.\d+)?e\+\d+", cell)]
    assert "deck-as-given" in text and "floor_mass = 350e3" in text


def test_accuracy_ratios_simplified_over_exact():
    _, _, text, _, results = make_report()
    rows = Parsed(text).tables["table-accuracy"][1:]
    assert len(rows) == 3 * 5 + 2  # every compared value, and with uplift the edge uplift and mat rotation
    for support, label, simplified, exact, ratio, _ in rows:
        if label.split(" [")[0] not in ("base shear V_b", "base overturning moment M_b", "largest story drift ratio",
                                        "roof displacement relative to the mat"):
            continue
        s = next(r for r in results if r.engine == "simplified" and r.support == support)
        e = next(r for r in results if r.engine == "exact" and r.support == support)
        # display units (display.py): kN, kN m, %, mm
        value, factor, digits = {"base shear V_b [kN]": (lambda r: r.base_shear, 1e-3, 0.05),
                                 "base overturning moment M_b [kN m]": (lambda r: r.base_moment, 1e-3, 0.05),
                                 "largest story drift ratio [%]": (lambda r: r.peaks["drift_ratio"].max(), 100, 5e-4),
                                 "roof displacement relative to the mat [mm]": (
                                     lambda r: r.peaks["displacement"][-1], 1e3, 5e-3)}[label]
        assert (float(simplified), float(exact)) == pytest.approx((factor * value(s), factor * value(e)), abs=digits)
        assert float(ratio) == pytest.approx(value(s) / value(e), rel=1e-3)
    # the checks uplift analyze makes (upliftcli/analysis/accuracy.py) are shown instead, as given
    from upliftcli.analysis.accuracy import Check, compare

    exact = {r.support: r for r in results if r.engine == "exact"}
    checks = [compare(r, exact[r.support]) for r in results if r.engine == "simplified"]
    given = Parsed(make_report(checks=checks)[2]).tables["table-accuracy"][1:]
    assert given == rows  # the same numbers as the report's own ratios
    failed = [Check("uplift", "exact engine", error="x")]
    assert Parsed(make_report(checks=failed)[2]).tables["table-accuracy"][1][-2] == "not run: x"


def test_criteria_verdict_and_exit_code_as_analyze():
    report, _, text, deck, results = make_report()
    assert report.exit_code == 0 and "exits with code 0" in report.verdict
    assert not criteria.check_criteria(results, deck.criteria)
    rows = Parsed(text).tables["table-criteria"][1:]
    for row, r in zip(rows, results, strict=True):
        assert row[2] == "drift_ratio" and row[5] == "%"
        assert float(row[3]) == pytest.approx(100 * r.peaks["drift_ratio"].max(), abs=5e-4)
        assert row[-1] == "ok"
    strict = replace(deck, criteria={"drift_ratio": 1e-4, "uplift": False})
    report, _, text, _, _ = make_report(deck=strict)
    violated = criteria.check_criteria(results, strict.criteria)
    assert report.exit_code == 3 and violated
    assert sum(row[-1] == "VIOLATED" for row in Parsed(text).tables["table-criteria"]) == len(violated)
    assert 'class="verdict fail"' in text and "exits with code 3" in text


def test_warnings_listed():
    _, _, text, _, results = make_report()
    given = [[r.engine, r.support, w] for r in results for w in r.details.get("warnings", [])]
    if given:
        assert Parsed(text).tables["table-warnings"][1:] == given
    else:
        assert "No warnings." in text
    warned = [replace(results[0], details={**results[0].details, "warnings": ["V_b above rigid"]}), *results[1:]]
    rows = Parsed(make_report(results=warned)[2]).tables["table-warnings"]
    assert rows[1] == ["exact", "rigid", "V_b above rigid"] and rows[2:] == given


def test_provenance_hashes_and_version():
    deck, _ = small_run()
    info = provenance(deck, ["uplift", "report"], NOW)
    assert info["version"] == tool_version() and info["time_utc"] == "2024-05-01T12:00:00Z"
    files = {f["role"]: f for f in info["files"]}
    assert files["deck"]["sha256"] == hashlib.sha256(EXAMPLE.read_bytes()).hexdigest()
    assert files["record"]["sha256"] == hashlib.sha256(RECORD.read_bytes()).hexdigest()
    assert files["record"]["bytes"] == RECORD.stat().st_size
    text = make_report()[2]
    assert hashlib.sha256(RECORD.read_bytes()).hexdigest() in text and tool_version() in text


def test_method_cites_the_equations_of_the_engines_run():
    report, *_ = make_report()
    (method,) = [s for s in report.sections if s.id == "method"]
    text = " ".join(method.blocks[0].paragraphs)
    for equation in ("[11a-11c]", "[14a]", "[16b]", "[21]", "[28a, 28b]", "[35]"):
        assert equation in text
    assert "Approximate" not in text  # the approximate engine was not run
    deck, _ = small_run()
    assert ("improved procedure" in text) == (deck.analysis.simplified.procedure == "improved")


runner = CliRunner()


def test_report_command(tmp_path):
    out = tmp_path / "report.html"
    args = ["report", str(EXAMPLE), "--out", str(out), "-e", "exact", "--support", "uplift"]
    args += [item for setting in SMALL[1:] for item in ("--set", setting)]
    result = runner.invoke(app, args, env={"CI": "true"})
    assert result.exit_code == 0, result.output
    text = out.read_text()
    parsed = Parsed(text)
    assert "table-exact-uplift-stories" in parsed.tables and len(parsed.figures) == 6
    for src in parsed.figures.values():
        png = base64.b64decode(src.split(",", 1)[1])
        assert png.startswith(PNG) and len(png) > 20_000  # drawn figures
    assert "wrote" in result.stderr
    before = out.read_bytes()
    refused = runner.invoke(app, args, env={"CI": "true"})  # an existing report is replaced only with --overwrite
    assert refused.exit_code == 2 and out.read_bytes() == before
    assert refused.stderr == f"error: --out: {out}: a new file (it exists; pass --overwrite to replace it)\n"
    args.append("--overwrite")
    strict = runner.invoke(app, [*args, "--set", "criteria.drift_ratio=1e-5"], env={"CI": "true"})
    assert strict.exit_code == 3 and "criterion violated" in strict.stderr and "exits with code 3" in out.read_text()
    small = [item for setting in SMALL[1:] for item in ("--set", setting)]
    for flag, rows in (("--check", 3 * 5 + 2), ("--no-check", 0)):  # the simplified engine alone, as the deck says
        result = runner.invoke(app, ["report", str(EXAMPLE), "--out", str(out), *small, flag, "--overwrite"],
                               env={"CI": "true"})
        assert result.exit_code == 0, result.output
        tables = Parsed(out.read_text()).tables
        assert len(tables.get("table-accuracy", [None])[1:]) == rows
    result = runner.invoke(app, ["report", str(EXAMPLE), "--out", str(tmp_path / "r.txt")], env={"CI": "true"})
    assert result.exit_code == 2 and "--out" in result.stderr and ".html" in result.stderr
    np.testing.assert_equal(sorted(p.name for p in tmp_path.iterdir()), ["report.html"])


def test_model_totals():
    _, _, text, deck, _ = make_report()
    system = {row[0]: float(row[1]) for row in Parsed(text).tables["table-system"][1:] if row[1] != "-"
              and row[0] in ("I_b", "L_0", "m_t")}
    building = deck.system.building
    h = 3.5 * np.arange(1, building.n_stories + 1)  # equal 3.5 m stories
    assert system["I_b"] == pytest.approx(350e3 * np.sum(h**2), rel=1e-5)
    assert system["L_0"] == pytest.approx(350e3 * np.sum(h), rel=1e-5)
    assert system["m_t"] == pytest.approx(350e3 * building.n_stories, rel=1e-5)


def test_suite_records_and_accuracy_from_the_suite_result():
    from test_figures_sets import fake_suite

    suite, simplified = fake_suite()
    _, _, text, _, _ = make_report(results=[suite])
    parsed = Parsed(text)
    rows = parsed.tables["table-exact-uplift-records"]
    for row, record, result in zip(rows[1:], suite.records, suite.record_results, strict=False):
        assert row[1] == record.name and float(row[3]) == pytest.approx(1e-3 * result.base_shear, rel=1e-4)
    assert rows[-1][1] == "mean (design value)" and rows[-1][-1] == f"{suite.uplift_count} of 3"
    assert float(rows[-1][3]) == pytest.approx(1e-3 * np.mean([r.base_shear for r in suite.record_results]), rel=1e-4)
    ratios = {row[1]: float(row[4]) for row in parsed.tables["table-accuracy"][1:]}
    assert ratios["base shear V_b [kN]"] == pytest.approx(simplified.base_shear / suite.base_shear, rel=1e-3)


def test_the_foundation_table_is_the_one_the_engines_use():
    """A half-space: K_theta, C_theta and the elements at the frequency every engine uses
    (omega_impedance, the flexible-base w1bar), not at the fixed-base w_1; every row with a unit."""
    from upliftcli.deck.load import load_deck
    from upliftcli.model.interaction import impedance
    from upliftcli.report.inputs import _foundation_rows

    deck = load_deck(ROOT / "inputs" / "frame_halfspace.toml", load_ground_motion=False)
    rows = {row[0]: row for row in _foundation_rows(deck.system)}
    omega = impedance(deck.system)["omega_impedance"]
    foundation, b = deck.system.foundation, deck.system.half_width
    assert rows["K_theta"][2] == "kN m/rad" and rows["C_theta"][2] == "kN m s/rad"  # display units (display.py)
    assert float(rows["K_theta"][1]) == pytest.approx(1e-3 * foundation.rocking_stiffness(b, omega), rel=1e-4)
    assert float(rows["C_theta"][1]) == pytest.approx(1e-3 * foundation.rocking_damping(b, omega), rel=1e-4)
    assert float(rows["omega_impedance"][1]) != pytest.approx(float(deck.system.modes.omega[0]), rel=1e-2)
    assert all(row[2] for row in rows.values()) and rows["shear_modulus"][2] == "MPa"
    us = {row[0]: row for row in _foundation_rows(deck.system, "us")}
    assert us["K_theta"][2] == "kip ft/rad" and us["shear_modulus"][2] == "ksi"
    assert float(us["K_theta"][1]) == pytest.approx(foundation.rocking_stiffness(b, omega) / 1355.8179483314, rel=1e-4)


def test_title_block_signoff_and_project_fields(tmp_path, monkeypatch):
    """The deck's [project] fields fill the title block, the running header and the sign-off
    block; uplift report's options replace them; fields not given are blank lines to fill in."""
    (tmp_path / "decks").mkdir()
    (tmp_path / "records").mkdir()
    (tmp_path / "records" / RECORD.name).write_bytes(RECORD.read_bytes())
    (tmp_path / "decks" / "deck.toml").write_text(EXAMPLE.read_text().replace(
        "[building]", '[project]\nproject = "Harbour St, block B"\njob_number = "24-117"\nengineer = "A. Engineer"\n'
        'revision = "A"\n\n[building]', 1))
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "r.html"
    small = [item for setting in SMALL[1:] for item in ("--set", setting)]
    result = runner.invoke(app, ["report", "decks/deck.toml", "--out", "r.html", *small, "--no-check",
                                 "--checker", "B. Checker", "--revision", "B", "--units", "us"], env={"CI": "true"})
    assert result.exit_code == 0, result.output
    text = out.read_text()
    parsed = Parsed(text)
    assert parsed.tables["table-summary"][0][2] == "V_b [kip]"  # --units us
    block = {row[i]: row[i + 1] for row in parsed.tables["title-block"] for i in (0, 2)}
    assert block["Project"] == "Harbour St, block B" and block["Job number"] == "24-117"
    assert block["Prepared by"] == "A. Engineer" and block["Checked by"] == "B. Checker"
    assert block["Revision"] == "B" and block["Date (UTC)"] == datetime.now(UTC).strftime("%Y-%m-%d")
    assert block["Subject"] == "Ten-story building, El Centro 1940 N-S (Yim & Chopra example)"
    signoff = parsed.tables["signoff"]
    assert signoff[0] == ["", "name", "signature", "date"]
    assert signoff[1] == ["Prepared by", "A. Engineer", "", ""] and signoff[2] == ["Checked by", "B. Checker", "", ""]
    # the running header and the page numbers are in the print CSS (margin boxes of @page)
    assert '"Harbour St, block B \u2014 job 24-117 \u2014 rev. B"' in text
    assert 'counter(page) " of " counter(pages)' in text
    # no absolute path anywhere in the report: files relative to the deck's folder
    assert str(tmp_path) not in text and str(ROOT) not in text
    files = {row[0]: row[1] for row in parsed.tables["table-files"][1:]}
    assert files["deck"] == "deck.toml" and files["record"] == f"../records/{RECORD.name}"


def test_css_strings_cannot_end_the_style_element():
    from upliftcli.report.html import css_string

    assert css_string('a "b" \\ </style>') == '"a \\"b\\" \\\\ \\3C /style>"'


def test_report_in_us_units():
    deck, results = small_run()
    info = provenance(deck, ["uplift", "report"], NOW)
    report, _ = build_report(deck, list(results), Path(deck.source).read_text(), SMALL, info, "us")
    images = {name: PNG for name in report_figure_names(report)}
    parsed = Parsed(render(report, images))
    summary = parsed.tables["table-summary"]
    assert summary[0][2:5] == ["V_b [kip]", "V_b/W", "M_b [kip ft]"]
    for row, r in zip(summary[1:], results, strict=True):
        assert float(row[2]) == pytest.approx(r.base_shear / 4448.2216152605, abs=0.05)
        assert float(row[3]) == pytest.approx(r.base_shear_coefficient, abs=5e-5)  # unchanged
    stories = parsed.tables["table-exact-uplift-stories"]
    assert stories[0][:3] == ["story", "elevation [ft]", "displacement [in]"]
    building = {row[0]: row for row in parsed.tables["table-building"]}
    assert building["story"][4] == "story stiffness k_j [kip/in]"
    assert any("units: US" in line for line in report.subtitle)


def report_figure_names(report):
    return {figure.name for figure in report.figures()}


def test_pdf_without_chromium_is_refused_in_one_line(tmp_path):
    out = tmp_path / "r.pdf"
    result = runner.invoke(app, ["report", str(EXAMPLE), "--out", str(out), "--pdf-engine", "chromium"],
                           env={"CI": "true", "PATH": ""})
    assert result.exit_code == 2
    (line,) = result.stderr.strip().splitlines()
    assert "--out" in line and "Chromium" in line and "apt-get install chromium" in line
    assert not list(tmp_path.iterdir())
