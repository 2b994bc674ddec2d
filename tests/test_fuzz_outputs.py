"""Property-based fuzzing (hypothesis) of deck fields and command-line options together (issue 38
item 4): whatever the deck holds (any field of the schema, a hostile title or [project] field) and
whatever the options (engines, formats, units, --out, --name, --plot, --overwrite ...):

- the command ends with exit code 0, 2, 3 or 4, never a traceback;
- nothing is written, changed or removed outside its outputs (--out; the --plot and --histories
  paths, which the examples put under --out): a listing of the temporary working folder (names,
  kinds, sizes, modification times) is compared before and after each run;
- its terminal output holds no control character but line breaks and tabs (errors.printable).

The runs are in-process (typer's CliRunner), in the example's own folder as the working
directory, derandomized (the same examples every run, in CI too) and bounded to about 30 s of
one core (250 examples: 15 s in the commands; UPLIFT_FUZZ_EXAMPLES=N runs N random ones instead,
UPLIFT_FUZZ_SHOW=1 prints each command, its CPU time and how it ended). The values reuse
test_fuzz's strategies (NUMBERS, WORDS, PATHS) and fuzz_cases' TOML writer and records.
"""

from __future__ import annotations

import os
import random
import tempfile
import time
from pathlib import Path

import pytest

hypothesis = pytest.importorskip("hypothesis")
from fuzz_cases import record_text, toml  # noqa: E402
from hypothesis import HealthCheck, event, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from test_fuzz import NUMBERS, PATHS, WORDS, runner  # noqa: E402

from upliftcli.cli import app  # noqa: E402
from upliftcli.errors import printable  # noqa: E402

EXAMPLES = int(os.environ.get("UPLIFT_FUZZ_EXAMPLES", "0"))
FUZZ = settings(max_examples=EXAMPLES or 250, deadline=None, derandomize=not EXAMPLES, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

DECK = {
    "title": "fuzz",
    "building": {"stories": 3, "floor_mass": 2.0e5, "story_height": 3.0, "period": 0.4},
    "foundation": {"slenderness": 3.0, "frequency_ratio": 8, "damping_ratio": 0.1},
    "ground_motion": {"record": "rec.txt"},
    "analysis": {"supports": ["rigid", "uplift"]},
    "criteria": {"drift_ratio": 0.02},
}
RECORD = record_text(random.Random(38), 120)

#: text a terminal would act on, and names that try to leave the folder
HOSTILE = st.sampled_from(["\x1b[2J\x1b[H", "\x1b]0;owned\x07", "\r", "\x9b31m", "\u202e", "\x7f", "\x08",
                           "../x", "/etc/passwd", "a\nb", "\t", "{x}", "[bold]x[/bold]", ":warning:", "%s %d"])
TEXTS = st.one_of(WORDS, st.lists(st.one_of(WORDS, HOSTILE), max_size=4).map("".join))
VALUES = st.one_of(NUMBERS, TEXTS, st.booleans(), st.lists(NUMBERS, max_size=4),
                   st.sampled_from(["two-element", "winkler", "exact", "srss", "g", "rec.txt", "missing.txt", ".",
                                    "..", "/dev/zero", "rec.txt/..", [0, 1], {"a": 1}]))
#: a deck field set to a value (one example in three; the others run the deck as it is, so that
#: most commands get past the deck)
FIELDS = st.one_of(st.none(), st.none(), st.tuples(PATHS, VALUES))
#: --out: a fresh folder, a folder below it, an input file, the working folder itself, names to refuse
OUTS = st.sampled_from(["out"] * 6 + ["out/sub", "out dir", "out\x1b[2J", "deck.toml", "rec.txt", ".", ""])
#: hypothesis draws the simplest value (False, 0) most: these are True one time in 12 and in 4
RARELY, SOMETIMES = st.sampled_from([False] * 11 + [True]), st.sampled_from([False] * 3 + [True])
PROJECT = ("project", "job_number", "engineer", "checker", "revision")


def toml_string(text: str) -> str:
    """A TOML basic string holding any text (its control characters and DEL escaped)."""
    escaped = text.replace("\\", "\\\\").replace('"', '\\"')
    return '"' + "".join(f"\\u{ord(c):04x}" if ord(c) < 0x20 or ord(c) == 0x7F else c for c in escaped) + '"'


def toml_value(value) -> str:
    return toml_string(value) if isinstance(value, str) else toml(value)


def deck_text(deck: dict) -> str:
    """The deck as TOML: its top-level values, then a table per table (a table inside one: inline)."""
    top = [f"{key} = {toml_value(value)}" for key, value in deck.items() if not isinstance(value, dict)]
    tables = [f"\n[{name}]\n" + "".join(f"{key} = {_inline(value)}\n" for key, value in table.items())
              for name, table in deck.items() if isinstance(table, dict)]
    return "\n".join(top) + "\n" + "".join(tables)


def _inline(value) -> str:
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_inline(v)}" for k, v in value.items()) + "}"
    return toml_value(value)


def with_field(path: str, value) -> dict:
    """The deck with the field at a dotted path set (its tables made where missing)."""
    deck = {name: dict(table) if isinstance(table, dict) else table for name, table in DECK.items()}
    *tables, key = path.split(".")
    where = deck
    for name in tables:
        where = where.setdefault(name, {})
        if not isinstance(where, dict):
            return deck
    where[key] = value
    return deck


def listing(folder: Path) -> dict[str, tuple]:
    """Every entry under the folder (symbolic links not followed): kind, size and modification time."""
    found = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            path = Path(root, name)
            info = path.lstat()
            found[str(path.relative_to(folder))] = (info.st_mode >> 12, info.st_size, info.st_mtime_ns)
    return found


@st.composite
def commands(draw) -> tuple[list[str], list[str]]:
    """(the arguments after the command's name, the outputs it may write: paths relative to the folder)."""
    command = draw(st.sampled_from(["analyze"] * 4 + ["modes", "sweep", "sweep", "sweep", "spectra", "spectra",
                                                      "record spectrum", "record info"]))
    out = draw(OUTS)
    if command in ("record spectrum", "record info"):
        return _record_command(draw, command, out)
    args, outputs = [*command.split(), "deck.toml", *([] if command == "modes" else ["--out", out])], [out]
    if command == "analyze":
        engine = draw(st.sampled_from(["simplified"] * 6 + ["exact", "approximate", "all", "x"]))
        args += ["--engine", engine, *draw(st.sampled_from([["--no-check"]] * 3 + [[]]))]
        if engine in ("exact", "approximate") and draw(st.booleans()):
            args += ["--histories", f"{out}/h.csv"]
            outputs.append(f"{out}/h.csv")
    if command in ("analyze", "modes"):
        args += ["--format", draw(st.sampled_from(["table"] * 4 + ["json"] * 3 + ["xml"]))]
        if command == "modes" or draw(RARELY):  # figures cost most: few of them
            args += ["--plot", out]
    if command == "sweep":
        args += ["--vary", draw(st.sampled_from(["foundation.slenderness=3,4", "building.period=0.3:0.5:2",
                                                 "building.stories=2,3", "foundation.slenderness=x"])),
                 "--workers", "1", "--table", draw(st.sampled_from(["csv", "json"])), "--quiet"]
    if command == "spectra":
        args += ["--periods", draw(st.sampled_from(["0.2,1", "0.1:1:3", "x"])), "--workers", "1", "--quiet"]
    if command in ("sweep", "spectra") and draw(SOMETIMES):
        args += ["--name", draw(st.one_of(st.sampled_from(["s", "../escape", "a/b", "/tmp/escape", ".", ".."]),
                                          TEXTS))]
    args += draw(st.sampled_from([[], [], ["--overwrite"]])) + draw(st.sampled_from([[], ["--units", "us"]]))
    return args, outputs


def _record_command(draw, command: str, out: str) -> tuple[list[str], list[str]]:
    """record spectrum (its --out a file) or record info (no output)."""
    args = [*command.split(), draw(st.sampled_from(["rec.txt", "rec.txt", "deck.toml", "missing.txt", "."]))]
    if command == "record info":
        return args + draw(st.sampled_from([[], ["--units", "us"], ["--damping", "0.02,0.05"]])), []
    target = draw(st.sampled_from([f"{out}/s.csv", f"{out}/s.csv", out]))
    args += ["--periods", draw(st.sampled_from(["0.1,1", "0.1:2:4", "1e-9"])), "--out", target]
    return args + draw(st.sampled_from([[], ["--overwrite"]])), [target]


def allowed(entry: str, outputs: list[str], folder: Path) -> bool:
    """An entry of the listing that is one of the outputs, under one, or a folder made on the way to one
    (record spectrum --out out/s.csv makes out)."""
    path = (folder / entry).resolve()
    return any(path == target or target in path.parents or (path in target.parents and path.is_dir())
               for target in ((folder / out).resolve() for out in outputs))


@pytest.fixture(scope="module")
def base():
    with tempfile.TemporaryDirectory(prefix="uplift-fuzz-") as folder:
        yield Path(folder)


@pytest.mark.filterwarnings("ignore:Glyph:UserWarning")  # a title's control characters drawn in a figure
@FUZZ
@given(field=FIELDS, title=TEXTS, project=st.dictionaries(st.sampled_from(PROJECT), TEXTS, max_size=2),
       command=commands())
def test_no_traceback_and_nothing_written_outside_the_outputs(base, field, title, project, command):
    args, outputs = command
    folder = Path(tempfile.mkdtemp(dir=base))
    deck = {**(with_field(*field) if field else DECK), "title": title, **({"project": project} if project else {})}
    (folder / "deck.toml").write_text(deck_text(deck), encoding="utf-8")
    (folder / "rec.txt").write_text(RECORD)
    before, everything = listing(folder), listing(base)
    previous = os.getcwd()
    os.chdir(folder)  # relative outputs land in the example's folder (a CliRunner has no cwd of its own)
    start = time.process_time()
    try:
        result = runner.invoke(app, args, env={"CI": "true", "COLUMNS": "120"})
    finally:
        os.chdir(previous)
    event(f"{args[0]} exit {result.exit_code}")
    if os.environ.get("UPLIFT_FUZZ_SHOW"):
        print(f"{time.process_time() - start:.2f}", args, result.exit_code, result.stderr[:150].replace("\n", " | "))
    assert result.exit_code in (0, 2, 3, 4), (args, result.exit_code, result.output, result.exception)
    assert result.exception is None or isinstance(result.exception, SystemExit), (args, repr(result.exception))
    assert "Traceback" not in result.stderr and "Traceback" not in result.stdout, (args, result.stderr)
    for text in (result.stdout, result.stderr):
        assert printable(text, lines=True) == text, (args, text[:300])
    after = listing(folder)
    changed = {entry for entry in before.keys() | after.keys() if before.get(entry) != after.get(entry)}
    outside = sorted(entry for entry in changed if not allowed(entry, outputs, folder))
    assert not outside, (args, outside)
    others = {entry: kind for entry, kind in listing(base).items() if not entry.startswith(folder.name)}
    assert others == {e: k for e, k in everything.items() if not e.startswith(folder.name)}, args
