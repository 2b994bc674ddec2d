"""ASCE 7-22's linear procedure on the simplified engine (engines/design.py, docs/theory.md 16): the design
forces elastic x Ie/R, the design drift ratios C_d/R x the elastic ones (12.9.1.2, 12.8.6), the allowable
drift of Table 12.12-1, exit 3 when a story exceeds it (exit 0 when none does), no design values at MCE_R,
and a deck without [design] written as before."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import invoke

from upliftcli.analysis.run import run
from upliftcli.deck.load import build_deck
from upliftcli.engines.design import MCE_R_WARNING, NO_FACTORS_WARNING, with_design
from upliftcli.output import to_csv, to_json

#: a three-story building of 100 t floors on a rigid base, T_1 = 0.4 s, under S_DS = 1.0 g, S_D1 = 0.6 g
BUILDING = {"stories": 3, "floor_mass": 1.0e5, "story_height": 3.5, "period": 0.4}
DESIGN = {"R": 8, "Cd": 5.5, "Omega0": 3, "risk_category": "III"}


def mapping(design: dict | None = DESIGN, level: str = "design", supports=("rigid",)) -> dict:
    spectrum = {"type": "asce7", "sds": 1.0, "sd1": 0.6, "tl": 8.0, "level": level}
    return {"building": dict(BUILDING), "foundation": {"type": "two-element", "b": 10.0, "frequency_ratio": 4.0},
            "ground_motion": {"design_spectrum": spectrum},
            "analysis": {"engine": "simplified", "supports": list(supports)},
            **({"design": dict(design)} if design else {})}


def test_the_design_values_are_the_elastic_ones_times_ie_over_r_and_cd_over_r():
    """Closed form: V_design = V_elastic Ie/R in every story (Ie = 1.25, risk category III), the design drift
    ratio C_d/R x the elastic one ((Ie/R)(C_d/Ie), 12.9.1.2), the allowable 0.015 (Table 12.12-1, all other
    structures, III), on every support."""
    for result in run(build_deck(mapping(supports=("rigid", "bonded", "uplift")), "d.toml")):
        shear, drift = result.peaks["shear"], result.peaks["drift_ratio"]
        np.testing.assert_allclose(result.peaks["design_shear"], shear * 1.25 / 8, rtol=1e-15)
        np.testing.assert_allclose(result.peaks["design_drift_ratio"], drift * 5.5 / 8, rtol=1e-15)
        assert result.peaks["design_base_shear"][0] == pytest.approx(result.base_shear * 1.25 / 8, rel=1e-15)
        assert result.peaks["allowable_drift_ratio"][0] == 0.015
        assert result.details["design"] == {"R": 8.0, "Cd": 5.5, "Ie": 1.25, "risk_category": "III",
                                            "structure": "all-other", "Omega0": 3.0}


def test_the_json_and_csv_carry_the_design_values_in_si():
    (result,) = run(build_deck(mapping(), "d.toml"))
    document = json.loads(to_json([result]))
    assert document["design_base_shear"] == pytest.approx(result.base_shear * 1.25 / 8, rel=1e-14)
    assert document["allowable_drift_ratio"] == 0.015
    assert [s["design_drift_ratio"] for s in document["stories"]] == pytest.approx(
        list(result.peaks["drift_ratio"] * 5.5 / 8), rel=1e-14)
    assert document["units"]["design_shear"] == "N" and document["units"]["design_drift_ratio"] == "-"
    header = to_csv([result]).splitlines()[0].split(",")
    assert header[-2:] == ["design_shear_N", "design_drift_ratio"]


def test_at_mce_r_no_design_values_are_given_and_a_warning_says_why():
    (result,) = run(build_deck(mapping(level="mce_r"), "d.toml"))
    assert not any(name.startswith(("design", "allowable")) for name in result.peaks)
    assert MCE_R_WARNING in result.details["warnings"]


def test_without_r_and_cd_no_design_values_are_given_and_a_warning_says_why():
    (result,) = run(build_deck(mapping({"risk_category": "II"}), "d.toml"))
    assert not any(name.startswith(("design", "allowable")) for name in result.peaks)
    assert NO_FACTORS_WARNING in result.details["warnings"]


def _strip(document):
    """A results document without the design values."""
    if isinstance(document, dict):
        return {k: _strip(v) for k, v in document.items()
                if not k.startswith(("design", "allowable")) and k != "design"}
    return [_strip(v) for v in document] if isinstance(document, list) else document


def test_a_deck_without_design_is_written_as_before_and_design_only_adds():
    """Without [design] no result carries a design value (with_design gives the result itself) and the
    JSON and CSV are those of the results as the engine gave them; with it, the documents are the same
    once the design values are taken out."""
    (plain,) = run(build_deck(mapping(None), "d.toml"))
    assert with_design(plain, None) is plain
    assert not any(k.startswith(("design_", "allowable")) for k in json.loads(to_json([plain])))
    assert '"design_' not in to_json([plain]) and '"allowable' not in to_json([plain])
    (designed,) = run(build_deck(mapping(), "d.toml"))
    assert _strip(json.loads(to_json([designed]))) == json.loads(to_json([plain]))
    assert [line.rsplit(",", 2)[0] for line in to_csv([designed]).splitlines()] == to_csv([plain]).splitlines()


def _deck_file(tmp_path, **design) -> str:
    lines = ["[building]", "stories = 3", "floor_mass = 1.0e5", "story_height = 3.5", "period = 0.4",
             "[foundation]", 'type = "two-element"', "b = 10.0", "frequency_ratio = 4.0",
             "[ground_motion]", 'design_spectrum = {type = "asce7", sds = 1.0, sd1 = 0.6, tl = 8.0}',
             "[analysis]", 'engine = "simplified"', 'supports = ["rigid"]', "[design]",
             *(f"{k} = {json.dumps(v)}" for k, v in design.items())]
    path = tmp_path / "d.toml"
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def test_a_design_drift_above_the_allowable_exits_3_naming_the_story_and_the_values(tmp_path):
    """Elastic drift ratio of story 1: 0.619 %; x C_d/R = 15/8: 1.16 % > 1.0 % (risk category IV)."""
    deck = _deck_file(tmp_path, R=8, Cd=15, risk_category="IV")
    outcome = invoke("analyze", deck, "--no-check", "--format", "json")
    assert outcome.exit_code == 3
    (line,) = [line for line in outcome.stderr.splitlines() if line.startswith("criterion violated")]
    assert line == ("criterion violated: simplified/rigid: design_drift_ratio = 0.0116 exceeds the limit 0.01 [-] "
                    "(source: ASCE 7-22 Table 12.12-1, all-other, risk category IV; C_d = 15, R = 8) (story 1)")


def test_a_design_drift_within_the_allowable_exits_0(tmp_path):
    """The same building at C_d = 5.5: 0.43 % <= 1.0 %."""
    outcome = invoke("analyze", _deck_file(tmp_path, R=8, Cd=5.5, risk_category="IV"), "--no-check",
                     "--format", "json")
    assert outcome.exit_code == 0, outcome.stderr
    assert json.loads(outcome.stdout)["allowable_drift_ratio"] == 0.01


def test_a_bad_design_field_exits_2_with_one_line(tmp_path):
    outcome = invoke("analyze", _deck_file(tmp_path, R=8, Cd=5.5, risk_category="II", Ie=1.5), "--no-check")
    assert outcome.exit_code == 2
    assert outcome.stderr.strip().endswith("d.toml: design.Ie: 1.0, the importance factor of risk category II "
                                           "(ASCE 7-22 11.5.1, Table 1.5-2), got 1.5 (or leave it out)")


def test_a_sweep_of_cd_names_the_case_whose_design_drift_exceeds_the_allowable(tmp_path):
    """The sweep's violations follow deck/criteria.py: C_d = 15 violates (1.16 % > 1.0 %), C_d = 5 does not."""
    deck = _deck_file(tmp_path, R=8, Cd=5.5, risk_category="IV")
    outcome = invoke("sweep", deck, "--vary", "design.Cd=5,15", "-o", tmp_path)
    assert outcome.exit_code == 3
    violated = [line for line in outcome.stderr.splitlines() if line.startswith("criterion violated")]
    assert len(violated) == 1 and violated[0].startswith("criterion violated: case 1 (design.Cd=15): simplified/rigid: "
                                                          "design_drift_ratio = 0.0116 exceeds the limit 0.01")


def test_the_sweep_rows_carry_the_design_values_of_each_case(tmp_path):
    """sweep/table.DESIGN_COLUMNS: each case's row has the largest design drift ratio, the design base shear and
    the allowable drift ratio of its own analysis (the JSON of `uplift analyze` with the case's values); a sweep
    of a deck without [design] has no such columns."""
    deck = _deck_file(tmp_path, R=8, Cd=5.5, risk_category="II")
    outcome = invoke("sweep", deck, "--vary", "design.Cd=4,5.5", "-o", tmp_path, "--format", "json")
    assert outcome.exit_code == 0, outcome.stderr
    rows = json.loads(outcome.stdout)["rows"]
    for row, cd in zip(rows, (4, 5.5), strict=True):
        single = json.loads(invoke("analyze", deck, "--set", f"design.Cd={cd}", "--format", "json").stdout)
        result = single.get("results", [single])[0]
        assert row["max_design_drift_ratio"] == pytest.approx(max(s["design_drift_ratio"] for s in result["stories"]),
                                                               rel=1e-12)
        assert row["design_base_shear_N"] == pytest.approx(result["design_base_shear"], rel=1e-12)
        assert row["allowable_drift_ratio"] == pytest.approx(0.02)
    assert rows[1]["max_design_drift_ratio"] == pytest.approx(rows[0]["max_design_drift_ratio"] * 5.5 / 4, rel=1e-12)
    plain_deck = tmp_path / "plain.toml"
    plain_deck.write_text(Path(deck).read_text().split("[design]")[0])
    plain = invoke("sweep", plain_deck, "--vary", "building.period=0.4,0.5", "-o", tmp_path / "plain", "--format",
                   "json")
    assert "max_design_drift_ratio" not in json.loads(plain.stdout)["rows"][0]
