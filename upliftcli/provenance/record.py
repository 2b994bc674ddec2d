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
and modification time), the model and options entries provenance/model.py. Knows nothing of
the terminal.
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

from ..runtime import backend
from ..runtime.installed import TOOL, package_version, platform_name, tool_version
from .files import file_entry, motion_files, record_entry

#: libraries whose versions are recorded (they decide the numbers)
LIBRARIES = ("numpy", "scipy", "matplotlib")
#: significant digits of every number written to a result file (DBL_DIG: the digits a double
#: keeps through decimal text; 15.299999999999999 is written 15.3)
DIGITS = 15


# ----------------------------------------------------------------------------- small pieces

def utc_now(now: datetime | None = None) -> str:
    """ISO 8601 UTC time to the second: 2026-12-01T10:00:00Z."""
    return (now or datetime.now(UTC)).astimezone(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def rounded(value: float) -> float:
    """value rounded to DIGITS significant digits (its shortest text then has no noise digits)."""
    return float(f"{float(value):.{DIGITS}g}")


def number_text(value: float) -> str:
    """The text of a number in a result file: the shortest text of `rounded(value)`; '' for NaN
    and infinities (no value)."""
    value = float(value)
    return repr(rounded(value)) if value == value and abs(value) != float("inf") else ""


def command_line(argv: Sequence[str] | None = None) -> str:
    """The command as typed (program name without its folder), shell-quoted."""
    argv = list(sys.argv if argv is None else argv)
    if not argv:
        return ""
    return shlex.join([Path(argv[0]).name, *argv[1:]])


def plain(value: Any) -> Any:
    """numpy arrays and scalars, tuples and paths as plain Python lists, numbers and strings (the
    deck's mapping built in code, as TOML would give it, and every provenance entry)."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if hasattr(value, "tolist") and hasattr(value, "dtype"):  # numpy array or scalar
        return plain(value.tolist())
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    return value


# ----------------------------------------------------------------------------- the deck

def absolute_paths(raw: dict, source: str, relative_to: str | os.PathLike | None = None) -> dict:
    """A copy of a deck mapping with its file paths (ground_motion.record, the suite's folder or
    files, design_spectrum.file) absolute: relative paths joined to the deck's folder; with
    relative_to (a folder), relative to that folder instead (the folder of a resolved deck file)."""
    from ..errors import deck_relative_path

    raw = copy.deepcopy(raw)
    motion = raw.get("ground_motion")
    if not isinstance(motion, dict):
        return raw

    def absolute(path: Any) -> Any:  # as errors.deck_relative_path resolves it
        if not isinstance(path, str):
            return path
        found = os.path.abspath(deck_relative_path(path, source))
        return found if relative_to is None else os.path.relpath(found, os.path.abspath(relative_to))

    if "record" in motion:
        motion["record"] = absolute(motion["record"])
    suite = motion.get("suite")
    if isinstance(suite, str):
        motion["suite"] = absolute(suite)
    elif isinstance(suite, list):
        motion["suite"] = [absolute(item) if isinstance(item, str)
                           else {**item, "file": absolute(item.get("file"))} if isinstance(item, dict) else item
                           for item in suite]
    spectrum = motion.get("design_spectrum")
    if isinstance(spectrum, dict) and "file" in spectrum:
        spectrum["file"] = absolute(spectrum["file"])
    return raw


def resolved_deck(deck, relative_to: str | os.PathLike | None = None) -> dict:
    """The deck a run used: its mapping after `--set`, every number in bare SI (a value given
    with a unit or under `units = "us"` converted: Deck.resolved), file paths absolute
    (relative_to: relative to that folder), its title stated (a copy of it under another name
    keeps the title)."""
    raw = absolute_paths(plain(deck.resolved or deck.raw), deck.source, relative_to)
    return {"title": deck.title, **raw}


def overrides(deck) -> dict[str, Any]:
    """The fields `--set` (or --engine / --support) gave: dotted path -> value."""
    values = {}
    for path in sorted(deck.overridden):
        table = deck.raw
        for part in path.split("."):
            table = table.get(part) if isinstance(table, dict) else None
        values[path] = plain(table)
    return values


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
    from .model import derived_model, engine_options, spectrum_entry  # it imports plain from here

    files = [file_entry("deck", deck.source)] if Path(deck.source).is_file() else []
    if deck.ground_motion is not None:
        files += motion_files(deck.ground_motion)
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
    files = record.get("files", [])
    first = next((f for f in files if f["role"] == "deck"), files[0] if files else None)
    where = f"; {first['role']} {first['path']} (sha256 {first['sha256']})" if first else ""
    return f"{record['tool']} {record['version']}, {record['time_utc']}{where}"


def csv_comments(record: dict[str, Any]) -> str:
    """The two '#' lines that open every CSV result: a summary, then the whole provenance as
    one line of JSON after '# provenance: '. pandas.read_csv(path, comment="#") skips them."""
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


def to_text_numbers(value: Any) -> Any:
    """Every float rounded to DIGITS significant digits (non-finite -> None), recursively."""
    if isinstance(value, dict):
        return {k: to_text_numbers(v) for k, v in value.items()}
    if isinstance(value, list):
        return [to_text_numbers(v) for v in value]
    if isinstance(value, float):
        return rounded(value) if value == value and abs(value) != float("inf") else None
    return value


def deck_toml(deck, record: dict[str, Any] | None = None, directory: str | os.PathLike = ".") -> str:
    """<stem>.deck.toml: the resolved deck (resolved_deck) with '#' lines saying where it came
    from, its file paths (and the deck's) relative to `directory`, the folder it is written into
    (no absolute path: the folder of results and inputs may move together); `uplift analyze
    <stem>.deck.toml` repeats the run (same engines, supports, options)."""
    import tomli_w

    record = record or of_deck(deck)
    changed = record["deck"]["set"]
    source = os.path.relpath(os.path.abspath(deck.source), os.path.abspath(directory))
    lines = [f"# The deck of a run of {record['tool']} {record['version']} at {record['time_utc']}:",
             f"# {source}" + (" with " + ", ".join(f"{k}={json.dumps(v)}" for k, v in changed.items())
                              if changed else ""),
             "# after the overrides, file paths relative to this file. `uplift analyze` on this file repeats the run.",
             "# Every number is bare SI (kg, m, s, N; design-spectrum ordinates in g), whatever units the deck used.",
             f"# command: {record['command']}"]
    return ("".join(line.replace("\n", " ") + "\n" for line in lines) + "\n"
            + tomli_w.dumps(resolved_deck(deck, directory)))
