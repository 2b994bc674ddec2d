"""Issue 36 item 6: an answer that says what it is. The ASCE 7-22 level of every result (design,
11.4.5; MCE_R, 11.4.6 and 16.2) on screen, in the JSON and in the report; one line saying which
number is the design value and which the check; the suite path flags its out-of-band ratios as
the design-spectrum path does; a check suite that cannot be made names what the user gave."""

from __future__ import annotations

import json
import re
from pathlib import Path

from cli_helpers import invoke

from upliftcli.analysis import suite_check
from upliftcli.analysis.level import answer_line, level_text
from upliftcli.analysis.run import run
from upliftcli.deck.load import load_deck
from upliftcli.errors import AnalysisError
from upliftcli.report.document import Text
from upliftcli.report.results import results_section

ROOT = Path(__file__).resolve().parent.parent
SUITE_DECK = ROOT / "inputs" / "ten_story_asce7_suite.toml"
DESIGN_DECK = ROOT / "inputs" / "ten_story_asce7.toml"
MCE_R = "MCE_R level (ASCE 7-22 11.4.6, 16.2)"
DESIGN = "design level (ASCE 7-22 11.4.5)"


def test_the_suite_deck_says_mce_r_flags_its_ratios_and_names_the_design_value():
    """The bundled suite deck (design-level ordinates, records scaled to 1.5 x: MCE_R): the level in
    the tables' titles, the summary and the JSON; mat rotation 0.44 and edge uplift 0.46 against the
    suite, outside [0.5, 2], flagged '!' with a warning each (they went unflagged)."""
    result = invoke("analyze", SUITE_DECK, "--support", "uplift")
    assert result.exit_code == 0, result.output
    assert f"exact engine, uplift support: mean of 11 records (ASCE 7-22 16.2), {MCE_R}" in result.stdout
    flat = " ".join(result.stdout.split())
    assert f"level of every row: {MCE_R}" in flat
    assert re.search(r"mat rotation \[mrad\] +│ +[\d.]+ │ +[\d.]+ │ +0\.4\d\d ! │", result.stdout)
    assert re.search(r"edge uplift \[mm\] +│ +[\d.]+ │ +[\d.]+ │ +0\.4\d\d ! │", result.stdout)
    warnings = [line for line in result.stderr.splitlines() if "against the suite" in line]
    assert len(warnings) == 2 and all("outside [0.5, 2] (analysis.check_band_motion)" in w for w in warnings)
    assert warnings[0].startswith("warning: simplified/uplift on the target spectrum against the suite: edge uplift")
    assert (f"design value: the exact engine's mean of the 11 records (ASCE 7-22 16.2), {MCE_R}; check: the "
            "simplified engine on the target spectrum beside it (simplified / suite), not a design value") in flat
    document = json.loads(invoke("analyze", SUITE_DECK, "--support", "uplift", "--format", "json").stdout)
    assert document["level"] == {"level": "mce_r", "name": "MCE_R", "clause": "ASCE 7-22 11.4.6, 16.2",
                                 "text": MCE_R}
    assert "level" not in document["details"]
    assert document["answer"].startswith("design value: the exact engine's mean of the 11 records")
    assert document["suite"]["check_band_motion"] == [0.5, 2.0]


def test_the_design_deck_says_design_and_names_the_check():
    deck = load_deck(DESIGN_DECK)
    results = run(deck, "simplified", "uplift")
    assert level_text(results[0]) == DESIGN
    (check,) = suite_check.check_deck(deck, results)
    line = answer_line(results, [check])
    assert line == (f"design value: the simplified engine on the design spectrum, {DESIGN}; check: the "
                    f"{check.reference} (simplified / exact), not a design value")
    section = results_section(results, "si", [check])
    assert any(isinstance(block, Text) and block.paragraphs == [line] for block in section.blocks)
    assert f"level of every row: {DESIGN}" in section.blocks[0].note  # the report's summary
    assert all(DESIGN in block.caption for block in section.blocks[2:4])  # the result's tables
    document = json.loads(invoke("analyze", DESIGN_DECK, "--support", "uplift", "--format", "json").stdout)
    assert document["level"]["clause"] == "ASCE 7-22 11.4.5"


def test_a_record_deck_has_no_level_and_no_answer_line():
    deck = load_deck(ROOT / "inputs" / "ten_story_elcentro.toml", ["ground_motion.window=[0, 4]"])
    results = run(deck, "simplified", "uplift")
    assert level_text(results[0]) == "" and answer_line(results) == ""


def test_a_check_suite_that_cannot_be_made_names_the_users_spectrum(monkeypatch, tmp_path):
    """No check suite matched to the spectrum: the check's error names the deck's
    ground_motion.design_spectrum, never the internal 'artificial record 1 (seed 2024)', and the
    run goes on (the design value stands; the check says it could not run)."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))  # no cached check suite

    def unmatched(*args, **kwargs):
        raise AnalysisError("artificial record 1 (seed 2024): no draw of 4 met the tolerance 0.9-1.3 over "
                            "0.05-5 s (S_a/target 0.700 to 1.400); try another seed")

    monkeypatch.setattr("upliftcli.motion.generate.generate_suite", unmatched)
    deck = load_deck(DESIGN_DECK)
    results = run(deck, "simplified", "uplift")
    (check,) = suite_check.check_deck(deck, results)
    assert check.error.startswith(f"{deck.source}: ground_motion.design_spectrum (")
    assert "artificial record" not in check.error and "seed" not in check.error
    assert "S_a/target 0.700 to 1.400" in check.error and check.error.endswith("or --no-check")
    result = invoke("analyze", DESIGN_DECK, "--support", "uplift", env={"XDG_CACHE_HOME": str(tmp_path)})
    assert result.exit_code == 0, result.output
    assert "artificial record 1" not in result.output
