"""Fuzzing of the paths of issue 29 with seeded generated cases (tests/fuzz_cases.py): design
spectra of every type (inline and from table files), record-suite entries, `record info`,
`record spectrum` and `record generate` options, and output folders where the deck's record or
an earlier run's files carry the names the outputs would take (--plot, --out, report).

Whatever the case: no traceback; the exit code is 0, 2, 3 or 4; a bad input (exit 2, or the
InputError the command turns into it) is one line naming the option, the deck field or the
file; no input is ever replaced, and no existing file without --overwrite; no NaN in a result.
Most cases run the command's own validation in this process (load_deck: what every command
does first), a few hundred the whole command through the typer app; about 3,000 cases in all.
UPLIFT_FUZZ_SCALE=10 runs ten times as many (other seeds).

Cases marked `item1` hold a deck value of issue 29 item 1 (a wrong type or a magnitude outside
1e-30..1e30 in a design-spectrum key, a suite entry or a table read from a file), which the one
field checker refuses; ITEM1_EXAMPLES are the issue's own examples. A deck with several faults
is refused with one line per fault (every error at once, issue 27), each naming its field.
"""

from __future__ import annotations

import json
import math
import os
import random
import re
import shutil
import time
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import invoke
from fuzz_cases import OUTPUTS, Case, cases, record_text, toml

from upliftcli.deck.load import load_deck
from upliftcli.errors import InputError
from upliftcli.motion.suites import Suite

ROOT = Path(__file__).resolve().parent.parent
SEED = 29
SCALE = int(os.environ.get("UPLIFT_FUZZ_SCALE", "1"))
COUNTS = {"spectrum": 2400, "suite": 250, "record": 220, "generate": 80, "output": 100}
CLI_SPECTRA = 100  # of the spectrum cases, also run as `uplift analyze -e simplified`
FULL_RUNS = {"analyze-plot": 1, "report": 1, "modes": 2}  # expensive commands allowed to run to the end
SECONDS = 60.0  # no single case may take longer


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """The decks and files every case may name: a FIFO, a folder, records."""
    base = tmp_path_factory.mktemp("fuzz")
    (base / "deck.toml").write_text((ROOT / "inputs" / "ten_story_asce7.toml").read_text())
    (base / "suite.toml").write_text((ROOT / "inputs" / "ten_story_asce7_suite.toml").read_text()
                                     .replace('"../records/ten_story_asce7_suite"', '"."'))
    os.mkfifo(base / "fifo.csv")
    os.mkfifo(base / "fifo.txt")
    (base / "folder").mkdir()
    return base


def place(case: Case, base: Path) -> None:
    for name, text in case.files.items():
        (base / name).write_text(text)


def one_line_naming(message: str, sources: tuple[str, ...]) -> None:
    """A bad input: one line per fault, each naming one of the sources (an option, a deck field,
    a file)."""
    assert "Traceback" not in message, message
    for line in message.strip().splitlines():
        assert any(line.startswith(source) for source in sources), (line, sources)


def check_exit(result, sources: tuple[str, ...]) -> None:
    assert result.exit_code in (0, 2, 3, 4), (result.exit_code, result.output, repr(result.exception))
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    assert "Traceback" not in result.output and "RuntimeWarning" not in result.output
    if result.exit_code == 2:
        errors = [line for line in result.stderr.strip().splitlines() if not line.startswith("warning: ")]
        one_line_naming("\n".join(errors), tuple(f"error: {source}" for source in sources))


def finite_results(document: dict) -> None:
    """No NaN (null) among the numbers of the results of a JSON document."""
    for result in document.get("results", [document]):
        for name in ("base_shear", "base_moment", "base_shear_coefficient", "critical_base_shear"):
            assert isinstance(result[name], (int, float)) and math.isfinite(result[name]), (name, result[name])
        for story in result["stories"]:
            assert all(value is not None for value in story.values()), story


# ----------------------------------------------------------------------------- design spectra

SPECTRUM_SOURCES = ("--set: ground_motion.design_spectrum", "--set: ground_motion: ")


def run_spectrum(case: Case, base: Path) -> str:
    """load_deck with the generated design spectrum: a Deck whose S_a is finite and >= 0, or one
    InputError naming the field (or the table file); returns how it ended."""
    place(case, base)
    override = "ground_motion.design_spectrum=" + toml(case.data["spectrum"])
    try:
        loaded = load_deck(base / "deck.toml", [override])
    except InputError as error:  # a table file's own faults (its rows, periods, S_a) name the file
        table = f"{base / 'spectrum.csv'}: "
        one_line_naming(str(error), (*SPECTRUM_SOURCES, table))
        assert not str(error).startswith(tuple(f"{table}{key}:" for key in ("units", "damping", "name"))), error
        return "refused"
    spectrum = loaded.spectrum
    low, high = getattr(spectrum, "period_range", (0.0, 4.0))
    sa = np.asarray(spectrum.sa(np.linspace(low, min(high, 10.0), 25), 0.05), dtype=float)
    assert np.all(np.isfinite(sa)) and np.all(sa >= 0.0), (case.data, sa)
    return "ok"


def test_design_spectra_of_every_type(folder):
    ended = {"ok": 0, "refused": 0}
    clean = cases("spectrum", COUNTS["spectrum"] * SCALE, SEED)
    assert sum(case.item1 for case in clean) > 0.1 * len(clean)
    for case in clean:
        start = time.monotonic()
        ended[run_spectrum(case, folder)] += 1
        assert time.monotonic() - start < SECONDS
    assert ended["ok"] > 0.1 * len(clean) and ended["refused"] > 0.1 * len(clean), ended
    for case in clean[:CLI_SPECTRA]:  # the whole command: exit codes, one line, finite results
        place(case, folder)
        result = invoke("analyze", folder / "deck.toml", "--set",
                        "ground_motion.design_spectrum=" + toml(case.data["spectrum"]), "-e", "simplified",
                        "--format", "json", "--no-check")
        check_exit(result, (*SPECTRUM_SOURCES, f"{folder / 'spectrum.csv'}: "))
        if result.exit_code in (0, 3):
            finite_results(json.loads(result.stdout))


# ----------------------------------------------------------------------------- suites

def suite_overrides(case: Case) -> list[str]:
    return [f"ground_motion.{key}={toml(value)}" for key, value in case.data.items()]


def run_suite(case: Case, base: Path) -> str:
    place(case, base)
    try:
        loaded = load_deck(base / "suite.toml", suite_overrides(case))
    except InputError as error:  # a record file's own faults name the file
        one_line_naming(str(error), ("--set: ground_motion", str(base)))
        location = str(error).split(": ")[1] if str(error).startswith(str(base)) else ""
        assert location not in ("dt", "units", "scale", "format"), error  # deck values: the deck field
        return "refused"
    suite = loaded.ground_motion
    assert isinstance(suite, Suite)
    assert all(math.isfinite(f) and f > 0.0 for f in suite.factors), suite.factors
    assert np.all(np.isfinite(suite.spectra())) and np.all(np.isfinite(suite.mean_ratio()))
    return "ok"


def test_suite_entries(folder):
    ended = {"ok": 0, "refused": 0}
    for case in cases("suite", COUNTS["suite"] * SCALE, SEED):
        start = time.monotonic()
        ended[run_suite(case, folder)] += 1
        assert time.monotonic() - start < SECONDS
    assert ended["ok"] > 10 and ended["refused"] > 10, ended


# ----------------------------------------------------------------------------- record commands

def test_record_info_and_spectrum_options(folder):
    codes = set()
    for case in cases("record", COUNTS["record"] * SCALE, SEED):
        place(case, folder)
        path = folder / case.data["file"]
        args = [item for option, value in case.data["options"].items() for item in (option, value)]
        start = time.monotonic()
        result = invoke("record", case.data["command"], path, *args)
        assert time.monotonic() - start < SECONDS
        check_exit(result, (*case.data["options"], "--out/--plot", str(path)))
        codes.add(result.exit_code)
        if result.exit_code == 0:  # no NaN in the table (numbers) nor in the CSV
            assert not re.search(r"\bnan\b|\binf\b", result.stdout, re.IGNORECASE), result.stdout
            if case.data["command"] == "spectrum":
                rows = [line.split(",") for line in result.stdout.splitlines()[3:]]
                assert rows and all(math.isfinite(float(value)) for row in rows for value in row)
    assert {0, 2} <= codes


def test_record_generate_options_never_replace_the_manifest(folder):
    out = folder / "generated"
    out.mkdir()
    (out / "manifest.json").write_text("{}")
    for case in cases("generate", COUNTS["generate"] * SCALE, SEED):
        args = [item for option, value in case.data["options"].items() for item in (option, value)]
        start = time.monotonic()
        result = invoke("record", "generate", folder / "suite.toml", *args, "--out", out)
        assert time.monotonic() - start < SECONDS
        # a valid command is refused too: its manifest.json exists (before anything is generated)
        assert result.exit_code == 2, (case.data, result.output)
        check_exit(result, (*case.data["options"], "--out", "--set"))
        assert sorted(p.name for p in out.iterdir()) == ["manifest.json"]
        assert (out / "manifest.json").read_text() == "{}"


# ----------------------------------------------------------------------------- outputs

COMMANDS = {
    "modes": lambda d, rec: ["modes", d / "deck.toml", "--plot", d],
    "analyze-out": lambda d, rec: ["analyze", d / "deck.toml", "--out", d, *SIMPLE],
    "analyze-plot": lambda d, rec: ["analyze", d / "deck.toml", "--plot", d, *SIMPLE],
    "report": lambda d, rec: ["report", d / "deck.toml", "--out", d / "report.html", *SIMPLE],
    "spectrum": lambda d, rec: ["record", "spectrum", d / rec, "--periods", "0.5,1", "--out", d / "spectrum.csv"],
}
SIMPLE = ["-e", "simplified", "--support", "rigid", "--no-check"]


def test_outputs_never_replace_an_input_nor_an_earlier_file_without_overwrite(tmp_path):
    full = dict.fromkeys(COMMANDS, 0)
    for k, case in enumerate(cases("output", COUNTS["output"] * SCALE, SEED)):
        data = case.data
        d = tmp_path / f"d{k}"
        d.mkdir()
        runs = data["record"] not in OUTPUTS[data["command"]] and (data["overwrite"] or not data["existing"])
        if runs and full[data["command"]] >= FULL_RUNS.get(data["command"], 10**9):  # keep it cheap: refused
            data = {**data, "record": "rec.txt", "existing": OUTPUTS[data["command"]][:1], "overwrite": False}
        (d / data["record"]).write_text(record_text(random.Random(k), 400))
        (d / "deck.toml").write_text((ROOT / "inputs" / "ten_story_elcentro.toml").read_text()
                                     .replace("../records/elcentro_1940_ns_chopra.txt", data["record"]))
        for name in data["existing"]:
            (d / name).write_text("earlier")
        before = {p.name: p.read_bytes() for p in d.iterdir()}
        result = invoke(*COMMANDS[data["command"]](d, data["record"]), *(["--overwrite"] * data["overwrite"]))
        check_exit(result, ("--out", "--plot", "--out/--plot", str(d / data["record"])))  # a record misread
        full[data["command"]] += result.exit_code in (0, 3)
        assert (d / data["record"]).read_bytes() == before[data["record"]], "an input was replaced"
        assert (d / "deck.toml").read_bytes() == before["deck.toml"]
        if not (data["overwrite"] and result.exit_code in (0, 3)):
            for name in data["existing"]:
                assert (d / name).read_text() == "earlier", (data, name)
        if result.exit_code in (0, 3) and data["command"] == "analyze-out":
            finite_results(json.loads((d / "deck.json").read_text()))
        assert not [p for p in d.iterdir() if ".uplift-tmp-" in p.name]
        shutil.rmtree(d)
    assert full["analyze-out"] > 0 and full["spectrum"] > 0, full


# ----------------------------------------------------------------------------- issue 29 item 1

def _deck_value(folder, deck: str, override: str, sources: tuple[str, ...]) -> None:
    try:
        load_deck(folder / deck, [override])
    except InputError as error:
        one_line_naming(str(error), sources)
    else:
        raise AssertionError(f"{override} accepted")


#: the examples of issue 29 item 1
ITEM1_EXAMPLES = {
    "table damping '5%'": ("deck.toml", 'ground_motion.design_spectrum={type="table", periods=[0, 1, 8], '
                                        'sa=[1, 1, 1], damping="5%"}'),
    "sds = true": ("deck.toml", "ground_motion.design_spectrum={type='asce7', sds=true, sd1=0.6, tl=8}"),
    "sds = 1e300": ("deck.toml", "ground_motion.design_spectrum={type='asce7', sds=1e300, sd1=0.6, tl=8}"),
    "spectrum name of a date": ("deck.toml", "ground_motion.design_spectrum={type='table', periods=[0, 8], "
                                             "sa=[1, 1], damping=0.05, name=1979-05-27}"),
    "suite dt = 'x'": ("suite.toml", 'ground_motion.suite=[{file="r1.txt", dt="x"}]'),
    "suite dt = true": ("suite.toml", 'ground_motion.suite=[{file="r1.txt", dt=true}]'),
}


#: record files of item 1: values the field checker refuses (a header dt below 1e-30 s, '1_000')
ITEM1_RECORDS = {"header dt = 1e-300": "# dt = 1e-300\n# units: g\n0.1\n0.2\n0.1\n",
                      "a value 1_000": "# dt = 0.01\n# units: g\n0.1\n1_000\n0.1\n"}


@pytest.mark.parametrize("name", sorted(ITEM1_EXAMPLES))
def test_item1_examples_are_refused_naming_the_field(folder, name):
    (folder / "r1.txt").write_text(record_text(random.Random(1), 600))
    deck, override = ITEM1_EXAMPLES[name]
    _deck_value(folder, deck, override, ("--set: ground_motion",))


@pytest.mark.parametrize("name", sorted(ITEM1_RECORDS))
def test_item1_record_values_are_refused_naming_the_line(tmp_path, name):
    path = tmp_path / "r.txt"
    path.write_text(ITEM1_RECORDS[name])
    result = invoke("record", "info", path)
    assert result.exit_code == 2
    one_line_naming(result.stderr.strip(), (f"error: {path}: line ",))
