"""Property-based fuzzing of the command line (hypothesis): deck fields through --set, --vary
values and record files, run in-process.

Whatever the input: the exit code is 0, 2, 3 or 4; nothing ends in a traceback; a bad input
(exit 2) is one line on stderr naming the right source (the option, the deck or the record
file); a failed run leaves no file under --out; no run takes longer than a bound. The
examples are derandomized (the same ones every run) and bounded to keep the suite fast.
"""

from __future__ import annotations

import math
import os
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from upliftcli.deck import schema as deck_schema

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, event, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from upliftcli.cli import app  # noqa: E402

runner = CliRunner()
SECONDS = 60.0  # no single run may take longer
#: UPLIFT_FUZZ_EXAMPLES=5000 runs a longer, random (not derandomized) campaign
LONG = int(os.environ.get("UPLIFT_FUZZ_EXAMPLES", "0"))
FUZZ = settings(max_examples=LONG or 120, deadline=None, derandomize=not LONG, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

RECORD_TEXT = "# dt = 0.02\n# units: g\n" + "\n".join(
    f"{0.3 * math.sin(0.7 * i) * math.exp(-0.05 * i):.5f}" for i in range(60)) + "\n"
DECK_TEXT = """title = "fuzz"
[building]
stories = 3
floor_mass = 2.0e5
story_height = 3.0
period = 0.4
[foundation]
slenderness = 3.0
frequency_ratio = 8
damping_ratio = 0.1
[ground_motion]
record = "rec.txt"
[analysis]
supports = ["rigid", "bonded", "uplift"]
[criteria]
drift_ratio = 0.02
"""


@pytest.fixture()
def workdir(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fuzz")
    (folder / "rec.txt").write_text(RECORD_TEXT)
    (folder / "deck.toml").write_text(DECK_TEXT)
    return folder


# ----------------------------------------------------------------------------- values

NUMBERS = st.one_of(
    st.floats(min_value=1e-3, max_value=1e3),  # plausible magnitudes: the analyses run
    st.floats(min_value=1e-3, max_value=1e3),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1e308, -1e308, 1e-300, 1e-320, 1e30, 1e-30, 1e31, 5e-324, 1.0, 0.5, 2.0, 1e4]),
    st.integers(min_value=-2**70, max_value=2**70),
    st.sampled_from([0, 1, 2, 3, 10, 500, 501, 10**6, 2**63 - 1]),
)


def toml_number(value) -> str:
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    return str(value)


WORDS = st.text(alphabet=st.characters(codec="utf-8", exclude_categories=("Cs",)), max_size=12)
VALUE_TEXTS = st.one_of(
    NUMBERS.map(toml_number),
    st.lists(NUMBERS.map(toml_number), max_size=5).map(lambda items: "[" + ", ".join(items) + "]"),
    st.lists(st.lists(NUMBERS.map(toml_number), min_size=1, max_size=3), min_size=1, max_size=3).map(
        lambda rows: "[" + ", ".join("[" + ", ".join(row) + "]" for row in rows) + "]"),
    st.sampled_from(['"two-element"', '"winkler"', '"halfspace"', '"exact"', '["exact", "simplified"]', "true",
                     '"g"', '"m/s2"', '"furlong"', '"/dev/zero"', '"rec.txt"', '"missing.txt"', '"."', "[0, 1]",
                     "[0, 1e308]", "{ a = 1 }", "[" * 3000 + "]" * 3000, '"srss"', '"cqc"', '"text"', '"at2"']),
    WORDS,
    WORDS.map(lambda text: f'"{text}"'),
)
PATHS = st.sampled_from([path for path in deck_schema.all_paths() if path != "ground_motion.design_spectrum"])


def check(result, seconds: float, sources: tuple[str, ...], out: Path | None = None) -> None:
    """The properties every run must have."""
    event(f"exit {result.exit_code}")  # pytest --hypothesis-show-statistics: how the examples ended
    assert seconds < SECONDS, f"took {seconds:.1f} s"
    assert result.exit_code in (0, 2, 3, 4), (result.exit_code, result.output, result.exception)
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    assert "Traceback" not in result.output
    if result.exit_code == 2:
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1, result.stderr
        assert any(lines[0].startswith(f"error: {source}") for source in sources), (lines[0], sources)
    if out is not None and result.exit_code not in (0, 3):
        assert not out.exists() or not any(out.iterdir()), sorted(out.iterdir())


def invoke(args, cwd: Path):
    start = time.monotonic()
    result = runner.invoke(app, [str(a) for a in args], env={"CI": "true", "COLUMNS": "120"})
    return result, time.monotonic() - start


# ----------------------------------------------------------------------------- properties

@FUZZ
@given(path=PATHS, value=VALUE_TEXTS, engine=st.sampled_from(["simplified"] * 4 + ["exact", "approximate"]))
def test_set_any_field_to_any_value(workdir, path, value, engine):
    deck, out = workdir / "deck.toml", workdir / f"out_{time.monotonic_ns()}"
    result, seconds = invoke(["analyze", deck, "--set", f"{path}={value}", "--engine", engine, "--out", out], workdir)
    check(result, seconds, ("--set", str(deck), str(workdir), "/dev/zero", "missing.txt", "."), out)


LINES = st.one_of(
    NUMBERS.map(toml_number),
    st.lists(NUMBERS.map(toml_number), min_size=1, max_size=4).map(" ".join),
    st.sampled_from(["0,05", "1,5 2,5", "\ufeff0.1", "# dt = 0.01", "# dt = 1e300", "# units: furlong", "", "\x00",
                     "dt=0", "NPTS= 3, DT= 0.01 SEC", "time,acc", "0.0,0.1", "nan", "1e308", "abc", "0.1\r"]),
    WORDS,
)


@FUZZ
@given(lines=st.lists(LINES, max_size=12), header=st.booleans(), suffix=st.sampled_from([".txt", ".csv", ".AT2"]),
       command=st.sampled_from(["info", "spectrum", "analyze"]))
def test_any_record_file(workdir, lines, header, suffix, command):
    record = workdir / f"fuzz{suffix}"
    text = ("# dt = 0.02\n# units: g\n" if header else "") + "\n".join(lines) + "\n"
    record.write_text(text, encoding="utf-8", errors="surrogatepass")
    if command == "analyze":
        deck = workdir / "fuzzdeck.toml"
        deck.write_text(DECK_TEXT.replace('record = "rec.txt"', f'record = "{record.name}"'))
        out = workdir / f"out_{time.monotonic_ns()}"
        result, seconds = invoke(["analyze", deck, "--out", out, "--engine", "simplified,exact"], workdir)
        check(result, seconds, (str(record), str(deck)), out)
    else:
        result, seconds = invoke(["record", command, record, "--periods", "0.1,1"] if command == "spectrum"
                                 else ["record", command, record], workdir)
        check(result, seconds, (str(record), "--periods"))


RANGES = st.one_of(
    # counts within the bounded run time, or beyond the limit of one range (refused before expanding)
    st.tuples(NUMBERS, NUMBERS, st.integers(min_value=-5, max_value=12) | st.sampled_from([10_001, 10**6, 10**9]),
              st.sampled_from(["", ":log", ":lin", ":cubic"])).map(
        lambda t: f"{toml_number(t[0])}:{toml_number(t[1])}:{t[2]}{t[3]}"),
    st.lists(NUMBERS.map(toml_number), min_size=1, max_size=4).map(",".join),
    VALUE_TEXTS,
)


@settings(FUZZ, max_examples=LONG or 60)
@given(path=PATHS, values=RANGES, second=st.booleans())
def test_vary_any_field_over_any_range(workdir, path, values, second):
    deck, out = workdir / "deck.toml", workdir / f"out_{time.monotonic_ns()}"
    args = ["sweep", deck, "--vary", f"{path}={values}", "--out", out, "--quiet", "--workers", "1", "--table", "csv"]
    if second:
        args += ["--vary", "building.period=0.3:0.5:3"]
    result, seconds = invoke(args, workdir)
    # a sweep whose cases fail exits 4 with the rows it has: only bad input (exit 2) leaves nothing
    check(result, seconds, ("--vary", "--set", str(deck), str(workdir), "/dev/zero", "missing.txt", "."),
          out if result.exit_code == 2 else None)
