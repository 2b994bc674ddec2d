"""Where a result came from: the one provenance record written into every result file.

    record = of_deck(deck)            # a dict, JSON-ready (plain lists, floats, strings)
    csv_comments(record)              # the leading '#' lines of a CSV table
    deck_toml(deck, record)           # <stem>.deck.toml: the resolved deck, a deck that repeats the run

The record holds: the tool and its version (package metadata; "0+unknown" when the package is
not installed), Python, platform and library versions, the command and the UTC time; every
input file with its SHA-256 and size (the deck, each record with its format, units, time step
and samples, a design-spectrum table file); the resolved deck (the TOML mapping after `--set`,
its file paths made absolute) and the fields `--set` changed; the model derived from the deck
(story stiffnesses after the period scaling, the modes, m_t, h_1*, b, the foundation's own
parameters and its rocking stiffness K_theta and damping C_theta at the frequency the engines
use, T1bar and xi1bar [21-25]); the engines, supports and their options. Units: SI, listed
under "units" of the model. docs/provenance.md describes every key.

This module assembles the record and writes it as text; the input files' entries and their
SHA-256 are provenance/files.py (which reads the files to hash them, cached on their path, size
and modification time), the model and options entries provenance/model.py, the plain values and
the text of the numbers provenance/values.py. Knows nothing of the terminal.
"""

from __future__ import annotations

import copy
import json
import os
import platform
import shlex
import sys
from collections.abc import Sequence
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from ..errors import deck_relative_path
from ..runtime import backend
from ..runtime.installed import TOOL, package_version, platform_name, tool_version
from .files import file_entry, motion_files, record_entry
from .model import derived_model, engine_options, spectrum_entry
from .values import DIGITS as DIGITS  # DIGITS, number_text, rounded: re-exported from their home, values.py
from .values import number_text as number_text
from .values import plain, to_text_numbers
from .values import rounded as rounded

#: libraries whose versions are recorded (they decide the numbers)
LIBRARIES = ("numpy", "scipy", "matplotlib")


# ----------------------------------------------------------------------------- small pieces

def utc_now(now: datetime | None = None) -> str:
    """ISO 8601 UTC time to the second: 2026-12-01T10:00:00Z."""
    return (now or datetime.now(UTC)).astimezone(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def command_line(argv: Sequence[str] | None = None) -> str:
    """The command as typed (program name without its folder), shell-quoted."""
    argv = list(sys.argv if argv is None else argv)
    if not argv:
        return ""
    return shlex.join([Path(argv[0]).name, *argv[1:]])


# ----------------------------------------------------------------------------- the deck

def _absolute(path: Any, source: str, relative_to: str | os.PathLike | None) -> Any:
    """A file path a deck gives, as errors.deck_relative_path resolves it: absolute, or relative to
    the folder relative_to; anything but text as it is."""
    if not isinstance(path, str):
        return path
    found = os.path.abspath(deck_relative_path(path, source))
    return found if relative_to is None else os.path.relpath(found, os.path.abspath(relative_to))


def _absolute_suite(suite: Any, source: str, relative_to: str | os.PathLike | None) -> Any:
    """ground_motion.suite with its paths resolved (_absolute): the folder, or each file of its
    list (text or a table whose `file` is resolved)."""
    if not isinstance(suite, list):
        return _absolute(suite, source, relative_to)
    return [{**item, "file": _absolute(item.get("file"), source, relative_to)} if isinstance(item, dict)
            else _absolute(item, source, relative_to) for item in suite]


def absolute_paths(raw: dict, source: str, relative_to: str | os.PathLike | None = None) -> dict:
    """A copy of a deck mapping with its file paths (ground_motion.record, the suite's folder or
    files, design_spectrum.file) absolute: relative paths joined to the deck's folder; with
    relative_to (a folder), relative to that folder instead (the folder of a resolved deck file)."""
    raw = copy.deepcopy(raw)
    motion = raw.get("ground_motion")
    if not isinstance(motion, dict):
        return raw
    if "record" in motion:
        motion["record"] = _absolute(motion["record"], source, relative_to)
    if "suite" in motion:
        motion["suite"] = _absolute_suite(motion["suite"], source, relative_to)
    spectrum = motion.get("design_spectrum")
    if isinstance(spectrum, dict) and "file" in spectrum:
        spectrum["file"] = _absolute(spectrum["file"], source, relative_to)
    return raw


def resolved_deck(deck, relative_to: str | os.PathLike | None = None) -> dict:
    """The deck a run used: its mapping after `--set`, every number in bare SI (a value given
    with a unit or under `units = "us"` converted: Deck.resolved), file paths absolute
    (relative_to: relative to that folder), its title stated (a copy of it under another name
    keeps the title)."""
    raw = absolute_paths(plain(deck.resolved or deck.raw), deck.source, relative_to)
    return {"title": deck.title, **raw}


def _field(table: Any, path: str) -> Any:
    """The value at a dotted path of a deck mapping (None where there is none)."""
    for part in path.split("."):
        table = table.get(part) if isinstance(table, dict) else None
    return table


def overrides(deck) -> dict[str, Any]:
    """The fields `--set` (or --engine / --support) gave: dotted path -> value."""
    return {path: plain(_field(deck.raw, path)) for path in sorted(deck.overridden)}


# ----------------------------------------------------------------------------- records

def base(command: str | None = None, now: datetime | None = None) -> dict[str, Any]:
    """Tool, version, Python, platform, libraries, the loops in use (backend.in_use), command and
    UTC time."""
    return {"tool": TOOL, "version": tool_version(), "python": platform.python_version(),
            "platform": platform_name(), "libraries": {name: package_version(name) for name in LIBRARIES},
            "loops": backend.in_use(),
            "command": command_line() if command is None else command, "time_utc": utc_now(now)}


def of_deck(deck, command: str | None = None, now: datetime | None = None) -> dict[str, Any]:
    """The provenance of a run of a deck.Deck (module docstring): base(), files, deck
    {source, title, set, resolved}, model (derived_model) and options (engine_options)."""
    deck_file = [file_entry("deck", deck.source)] if Path(deck.source).is_file() else []
    files = deck_file + motion_files(deck.ground_motion)
    described = {"source": deck.source, "title": deck.title, "set": overrides(deck), "resolved": resolved_deck(deck)}
    return {**base(command, now), "files": files, "deck": described,
            "model": derived_model(deck.system, deck.analysis.simplified.effective_properties),
            "spectrum": spectrum_entry(deck.spectrum), "options": engine_options(deck.analysis)}


def of_record(record, command: str | None = None, now: datetime | None = None, **settings: Any) -> dict[str, Any]:
    """The provenance of a result computed from one record alone (uplift record spectrum):
    base(), the record's file entry and the settings (periods, dampings ...)."""
    return {**base(command, now), "files": [record_entry(record)], "settings": plain(settings)}


def summary(record: dict[str, Any]) -> str:
    """One line: tool, version, UTC time, the deck (or first input) and its SHA-256."""
    first = _first_input(record.get("files", []))
    where = f"; {first['role']} {first['path']} (sha256 {first['sha256']})" if first else ""
    return f"{record['tool']} {record['version']}, {record['time_utc']}{where}"


def _first_input(files: list[dict[str, Any]]) -> dict[str, Any] | None:
    """The deck's file entry, else the first input's (None without inputs)."""
    for entry in files:
        if entry["role"] == "deck":
            return entry
    return files[0] if files else None


def csv_comments(record: dict[str, Any] | None) -> str:
    """The two '#' lines that open every CSV result: a summary, then the whole provenance as
    one line of JSON after '# provenance: '. pandas.read_csv(path, comment="#") skips them.
    No record: no lines."""
    if record is None:
        return ""
    text = json.dumps(to_text_numbers(record), separators=(",", ":"), allow_nan=False)
    return (f"# {summary(record)}; read with pandas.read_csv(path, comment='#'); provenance as JSON on the next "
            f"line\n# provenance: {text}\n")


def read_csv_provenance(text: str) -> dict[str, Any] | None:
    """The provenance of a CSV result's text (the '# provenance: ' line), None if it has none."""
    for line in text.splitlines():
        if not line.startswith("#"):
            return None
        if line.startswith("# provenance: "):
            return json.loads(line.removeprefix("# provenance: "))
    return None


def deck_toml(deck, record: dict[str, Any] | None = None, directory: str | os.PathLike = ".") -> str:
    """<stem>.deck.toml: the resolved deck (resolved_deck) with '#' lines saying where it came
    from, its file paths (and the deck's) relative to `directory`, the folder it is written into
    (no absolute path: the folder of results and inputs may move together); `uplift analyze
    <stem>.deck.toml` repeats the run (same engines, supports, options)."""
    import tomli_w

    record = record or of_deck(deck)
    source = os.path.relpath(os.path.abspath(deck.source), os.path.abspath(directory))
    lines = [f"# The deck of a run of {record['tool']} {record['version']} at {record['time_utc']}:",
             f"# {source}{_with_overrides(record['deck']['set'])}",
             "# after the overrides, file paths relative to this file. `uplift analyze` on this file repeats the run.",
             "# Every number is bare SI (kg, m, s, N; design-spectrum ordinates in g), whatever units the deck used.",
             f"# command: {record['command']}"]
    return ("".join(line.replace("\n", " ") + "\n" for line in lines) + "\n"
            + tomli_w.dumps(resolved_deck(deck, directory)))


def _with_overrides(changed: dict[str, Any]) -> str:
    """' with path=value, ...': the fields `--set` changed, as JSON values ('' when none)."""
    if not changed:
        return ""
    return " with " + ", ".join(f"{k}={json.dumps(v)}" for k, v in changed.items())
