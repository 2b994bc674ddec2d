"""The Python API (upliftcli.__all__, api.py): cheap to import, every name documented and
resolvable, numpy arrays in decks, engines on a model built in code equal to the deck's run,
dicts and DataFrames equal to the written files, a sweep equal to single analyses, and the
worked example of docs/api.md executed."""

from __future__ import annotations

import io
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import upliftcli
from upliftcli.analysis import run as analysis
from upliftcli.output import result_to_dict, to_csv

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
API_DOC = ROOT / "docs" / "api.md"
RAW = {
    "building": {"stories": 3, "floor_mass": 2.0e5, "story_height": 3.0, "story_stiffness": 3.0e8},
    "foundation": {"b": 3.0, "k_f": 5.0e8, "c_f": 4.0e6},
    "ground_motion": {"design_spectrum": {"type": "asce7", "sds": 1.0, "sd1": 0.5, "tl": 8.0}},
}


def test_import_loads_no_numerical_library():
    code = ("import sys, upliftcli; upliftcli.__version__; sorted(upliftcli.__all__); dir(upliftcli); "
            "print([m for m in ('numpy', 'scipy', 'matplotlib', 'rich', 'typer') if m in sys.modules])")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True)
    assert done.stdout.strip() == "[]"


def test_every_public_name_resolves_and_is_documented():
    from upliftcli.runtime.installed import tool_version

    documented = API_DOC.read_text()
    assert upliftcli.__version__ == tool_version()  # the distribution upliftcli's (tests/test_installed.py)
    for name in upliftcli.__all__:
        assert getattr(upliftcli, name) is not None
        assert f"`{name}" in documented, name
    assert set(upliftcli.__all__) <= set(dir(upliftcli))
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        upliftcli.nothing  # noqa: B018


def test_build_deck_takes_numpy_arrays_and_scalars():
    with_lists = upliftcli.build_deck({**RAW, "building": {"masses": [2e5, 2e5, 1e5], "story_heights": [3.0] * 3,
                                                           "story_stiffnesses": [3e8, 2e8, 1e8]}})
    with_arrays = upliftcli.build_deck({**RAW, "building": {
        "masses": np.array([2e5, 2e5, 1e5]), "story_heights": np.full(3, 3.0),
        "story_stiffnesses": np.array([3e8, 2e8, 1e8]), "damping": np.float64(0.05)}},
        overrides=[("analysis.modes", np.int64(2))])
    first, second = with_lists.system.building, with_arrays.system.building
    assert np.array_equal(first.stiffness, second.stiffness) and np.array_equal(first.masses, second.masses)
    assert with_arrays.analysis.n_modes == 2 and isinstance(with_arrays.raw["building"]["masses"], list)
    stories = upliftcli.build_deck({**RAW, "building": {**RAW["building"], "stories": np.int64(3)}})
    assert stories.system.building.n_stories == 3
    negative = {"masses": np.array([2e5, -1.0, 1e5]), "story_height": 3.0, "story_stiffness": 3e8}
    with pytest.raises(upliftcli.InputError, match=r"<mapping>: building.masses: every entry a number > 0 \[kg\]"):
        upliftcli.build_deck({**RAW, "building": negative})


@pytest.mark.parametrize("support", ["rigid", "bonded", "uplift"])
def test_analyze_a_system_built_in_code_equals_the_deck(support):
    deck = upliftcli.build_deck(RAW)
    building = upliftcli.uniform_building(3, 2.0e5, 3.0, story_stiffness=3.0e8)
    system = upliftcli.System(building, upliftcli.TwoElement(5.0e8, 4.0e6), half_width=3.0)
    spectrum = upliftcli.design_spectrum(RAW["ground_motion"]["design_spectrum"])
    in_code = upliftcli.analyze(system, spectrum, support)
    (from_deck,) = analysis.run(deck, "simplified", support)
    assert in_code.base_shear == from_deck.base_shear and in_code.uplift == from_deck.uplift
    assert in_code.drift_ratio.tolist() == from_deck.drift_ratio.tolist()


def test_analyze_any_engine_on_a_record():
    deck = upliftcli.load_deck(EXAMPLE, ["ground_motion.window=[0, 4]", "analysis.exact.n_modes=2"])
    (from_deck,) = analysis.run(deck, "exact", "uplift")
    options = upliftcli.ExactOptions(n_modes=2)
    in_code = upliftcli.analyze(deck.system, deck.ground_motion, "uplift", "exact", options)
    assert in_code.base_shear == from_deck.base_shear and in_code.uplift == from_deck.uplift
    simplified = upliftcli.analyze(deck.system, deck.ground_motion, "rigid")  # the record's spectrum
    (expected,) = analysis.run(deck, "simplified", "rigid")
    assert simplified.base_shear == expected.base_shear


def test_analyze_refuses_what_the_engine_cannot_take():
    deck = upliftcli.build_deck(RAW)
    with pytest.raises(ValueError, match="engine must be one of"):
        upliftcli.analyze(deck.system, deck.spectrum, "uplift", "fast")
    with pytest.raises(ValueError, match="support must be one of"):
        upliftcli.analyze(deck.system, deck.spectrum, "floating")
    with pytest.raises(ValueError, match="the exact engine needs a record"):
        upliftcli.analyze(deck.system, deck.spectrum, "uplift", "exact")


def test_dicts_and_dataframes_hold_what_the_files_hold():
    deck = upliftcli.build_deck(RAW)
    results = upliftcli.run(deck)
    assert upliftcli.to_dict(results[0]) == result_to_dict(results[0])
    document = upliftcli.to_dict(results, deck)
    assert [r["support"] for r in document["results"]] == ["rigid", "bonded", "uplift"]
    assert document["provenance"]["deck"]["resolved"]["building"]["story_stiffness"] == 3.0e8
    json.dumps(document, allow_nan=False)  # plain, JSON-ready
    pandas = pytest.importorskip("pandas")
    frame = upliftcli.to_dataframe(results)
    written = pandas.read_csv(io.StringIO(to_csv(results)))
    assert list(frame.columns) == list(written.columns) and len(frame) == 9
    np.testing.assert_allclose(frame["shear_N"], written["shear_N"], rtol=5e-15)  # written with 15 significant digits
    assert frame.attrs["units"]["shear_N"] == "N" and frame.attrs["units"]["drift_ratio"] == "-"
    elements = upliftcli.elements_dataframe(results)
    assert elements["position_m"].tolist() == [-3.0, 3.0, -3.0, 3.0]


def test_dataframes_without_pandas_say_how_to_install_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="pip install pandas"):
        upliftcli.to_dataframe(upliftcli.run(upliftcli.build_deck(RAW), supports="rigid"))


def test_run_sweep_rows_equal_single_analyses(tmp_path):
    rows_file = tmp_path / "rows.jsonl"
    sweep = upliftcli.run_sweep(EXAMPLE, ["building.period=0.5,1.5"], ["analysis.modes=3"], supports=["uplift"],
                                rows_file=rows_file)
    assert [row["building.period"] for row in sweep.rows] == [0.5, 1.5]
    for row in sweep.rows:
        deck = upliftcli.load_deck(EXAMPLE, ["analysis.modes=3", f"building.period={row['building.period']}"])
        (single,) = upliftcli.run(deck, supports="uplift")
        assert row["base_shear_N"] == single.base_shear and row["status"] == "ok"
    from upliftcli.sweep.store import RowStore

    assert len(RowStore(rows_file).read()) == 2
    before = rows_file.read_text()
    again = upliftcli.run_sweep(EXAMPLE, ["building.period=0.5,1.5"], ["analysis.modes=3"], supports=["uplift"],
                                rows_file=rows_file, resume=True)
    assert again.rows == sweep.rows and rows_file.read_text().startswith(before)
    assert len(RowStore(rows_file).read()) == 2  # nothing run again
    assert sweep.provenance["sweep"]["cases"] == 2 and sweep.document()["rows"][0]["case"] == 0


def code_blocks(text: str) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", text, re.S | re.M)


def test_the_worked_example_of_docs_api_runs(monkeypatch, capsys):
    pytest.importorskip("pandas")
    blocks = code_blocks(API_DOC.read_text())
    assert len(blocks) >= 5
    monkeypatch.chdir(ROOT)
    namespace: dict = {}
    for number, block in enumerate(blocks, 1):
        exec(compile(block, f"docs/api.md block {number}", "exec"), namespace)
    printed = capsys.readouterr().out
    assert "--set: building.period: a number > 0 [s], got -1" in printed
    assert namespace["exact"].engine == "exact" and namespace["frame"].shape[0] == 8


def test_figures_are_matplotlib_figures_of_their_descriptions():
    from matplotlib.figure import Figure

    from upliftcli.figures.histories import moment_rotation_figure
    from upliftcli.figures.modes import mode_shape_figure

    deck = upliftcli.load_deck(EXAMPLE, ["ground_motion.window=[0, 3]"])
    modes = upliftcli.mode_shape_figure(deck.system, 3)
    assert isinstance(modes, Figure) and len(modes.axes) == len(mode_shape_figure(deck.system, 3).panels)
    run = upliftcli.analyze(deck.system, deck.ground_motion, "uplift", "exact", upliftcli.ExactOptions(histories=True))
    rotation = upliftcli.moment_rotation_figure(run)
    assert isinstance(rotation, Figure) and len(rotation.axes) == len(moment_rotation_figure([run]).panels)


def test_a_per_record_sweep_lists_each_record_once():
    """per_record: each case's row, then one row per record of its suite, in the table, the
    document and the DataFrame alike (3 records x 2 periods: 2 + 6 rows)."""
    suite = ROOT / "inputs" / "ten_story_ec8_suite.toml"
    three = [f'"../records/ten_story_asce7_suite/artificial_2024_0{k}.txt"' for k in (1, 2, 3)]
    sweep = upliftcli.run_sweep(suite, ["building.period=0.5,1.0"],
                                [f"ground_motion.suite=[{', '.join(three)}]"],
                                engines=["exact"], supports=["uplift"], per_record=True)
    assert len(sweep.case_rows) == 2 and len(sweep.rows) == 8
    assert len(sweep.document()["rows"]) == 8
    assert sweep.rows[1]["base_shear_N"] == sweep.case_rows[0]["record_rows"][0]["base_shear_N"]
