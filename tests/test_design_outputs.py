"""The design values of [design] (engines/design.py) in the terminal and the report: a table per result
that carries them (cli/render_design.py, report/design.py), none for one without them."""

from __future__ import annotations

from test_design_linear import mapping

from upliftcli.analysis.run import run
from upliftcli.cli.render import print_results
from upliftcli.cli.render_design import design_table as terminal_table
from upliftcli.deck.load import build_deck
from upliftcli.report import design
from upliftcli.report.results import result_tables


def _result(design_fields=None):
    (result,) = run(build_deck(mapping(design_fields or {"R": 8, "Cd": 15, "risk_category": "IV"}), "d.toml"))
    return result


def test_the_report_has_a_design_table_with_every_story_and_its_verdict():
    """Story 1: elastic 0.619 % x 15/8 = 1.160 % > 1.000 % (risk category IV): exceeds; stories 2, 3 ok."""
    (table,) = [t for t in result_tables(_result()) if t.id == "table-simplified-rigid-design"]
    assert table.headers == ["story", "design shear [kN]", "elastic drift ratio [%]", "design drift ratio [%]",
                             "allowable [%]", "verdict"]
    assert [row[0] for row in table.rows] == ["3", "2", "1"]
    assert [row[-1] for row in table.rows] == ["ok", "ok", "exceeds"]
    assert table.rows[-1][3:5] == ["1.160", "1.000"]
    assert table.caption.startswith("ASCE 7-22 design values (simplified, rigid): R = 8, C_d = 15, I_e = 1.5, "
                                    "risk category IV, all-other; design base shear V = ")
    assert "12.9.1.4" in table.note


def test_a_result_without_design_values_has_no_design_table():
    (plain,) = run(build_deck(mapping(None), "d.toml"))
    assert design.design_table(plain) is None and terminal_table(plain) is None
    assert not [t for t in result_tables(plain) if t.id.endswith("-design")]


def test_the_terminal_prints_the_design_table_in_us_units():
    from rich.console import Console

    out = Console(width=200, record=True)
    print_results(out, [_result()], units="us")
    text = out.export_text()
    assert "ASCE 7-22 design values (simplified, rigid)" in text
    assert "design shear [kip]" in text and "exceeds" in text


def test_the_json_under_us_units_gives_the_design_forces_in_kip():
    """design_base_shear and design_shear follow base_shear into kip (output.file_units with DESIGN_UNITS)."""
    import json

    from upliftcli.output import to_json

    result = _result({"R": 8, "Cd": 5.5, "risk_category": "II"})
    document = json.loads(to_json([result], system="us"))
    assert document["units"]["design_base_shear"] == "kip" and document["units"]["design_shear"] == "kip"
    assert abs(document["design_base_shear"] * 8 / document["base_shear"] - 1) < 1e-12
    assert abs(document["stories"][0]["design_shear"] * 8 / document["stories"][0]["shear"] - 1) < 1e-12


def test_the_reports_criteria_section_judges_the_design_drift_without_criteria():
    """A deck with [design] and no [criteria]: the report's criteria table has the design drift row, its
    source Table 12.12-1, the verdict names [design], and the exit code is 3 when a story exceeds the
    allowable drift (0 when none does)."""
    from upliftcli.deck.criteria import Criteria
    from upliftcli.report.checks import criteria_section

    section, verdict, code = criteria_section([_result()], Criteria())
    (table,) = [block for block in section.blocks if hasattr(block, "rows")]
    assert code == 3
    assert verdict == "1 acceptance limit of the deck's [design] exceeded: `uplift analyze` exits with code 3."
    assert table.rows == [["simplified", "rigid", "design_drift_ratio", "1.160", "1.000", "%", "VIOLATED",
                           "ASCE 7-22 Table 12.12-1, all-other, risk category IV; C_d = 15, R = 8"]]
    assert criteria_section([_result({"R": 8, "Cd": 5.5, "risk_category": "IV"})], Criteria())[2] == 0
    (plain,) = run(build_deck(mapping(None), "d.toml"))
    assert criteria_section([plain], Criteria())[2] == 0


def test_the_batch_tables_verdict_judges_the_design_drift():
    from upliftcli.cli.render_batch import _criteria_verdict

    assert _criteria_verdict(_result(), {}, ()) == "violated"
    (plain,) = run(build_deck(mapping(None), "d.toml"))
    assert _criteria_verdict(plain, {}, ()) == "-"
