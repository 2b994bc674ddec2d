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

Knows nothing of the terminal; reads the input files to hash them (cached on their path,
size and modification time).
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import json
import os
import platform
import shlex
import sys
from collections.abc import Sequence
from datetime import UTC, datetime
from functools import lru_cache
from pathlib import Path
from typing import Any

from .installed import TOOL, package_version, platform_name, tool_version

#: libraries whose versions are recorded (they decide the numbers)
LIBRARIES = ("numpy", "scipy", "matplotlib")
#: significant digits of every number written to a result file (DBL_DIG: the digits a double
#: keeps through decimal text; 15.299999999999999 is written 15.3)
DIGITS = 15
#: the foundation's dataclass attributes under their deck names (foundation.<name>)
FOUNDATION_NAMES = {"two-element": {"stiffness": "k_f", "damping": "c_f", "capacity": "element_capacity"},
                    "winkler": {"stiffness": "k_w", "damping": "c_w", "elements": "elements",
                                "capacity": "line_capacity"}}
#: units of the derived model's entries
MODEL_UNITS = {
    "masses": "kg", "elevations": "m", "story_heights": "m", "story_stiffnesses": "N/m", "stiffness_matrix": "N/m",
    "damping": "-", "periods": "s", "effective_masses": "kg", "effective_heights": "m", "total_mass": "kg",
    "mat_mass": "kg", "mat_rotary_inertia": "kg m^2", "half_width": "m", "h1_star": "m", "slenderness": "-",
    "gravity": "m/s^2", "weight": "N", "critical_base_shear": "N", "critical_base_moment": "N m",
    "T1bar": "s", "xi1bar": "-", "K_theta": "N m/rad", "C_theta": "N m s/rad", "omega_impedance": "rad/s",
    "k_element": "N/m", "c_element": "N s/m", "vertical_stiffness": "N/m", "vertical_damping": "N s/m",
    "Q_y": "N", "FS_v": "-",
}


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


@lru_cache(maxsize=512)
def _digest(path: str, size: int, mtime_ns: int) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def sha256(path: str | os.PathLike) -> str | None:
    """SHA-256 (hex) of a file's bytes, None when it cannot be read."""
    try:
        status = os.stat(path)
        return _digest(os.path.abspath(path), status.st_size, status.st_mtime_ns)
    except OSError:
        return None


def file_entry(role: str, path: str | os.PathLike, **extra: Any) -> dict[str, Any]:
    """{role, path (absolute), sha256, bytes, **extra} of an input file."""
    try:
        size = os.stat(path).st_size
    except OSError:
        size = None
    return {"role": role, "path": os.path.abspath(path), "sha256": sha256(path), "bytes": size, **extra}


def command_line(argv: Sequence[str] | None = None) -> str:
    """The command as typed (program name without its folder), shell-quoted."""
    argv = list(sys.argv if argv is None else argv)
    if not argv:
        return ""
    return shlex.join([Path(argv[0]).name, *argv[1:]])


def plain(value: Any) -> Any:
    """numpy arrays and scalars, tuples and paths as plain Python lists, numbers and strings."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if hasattr(value, "tolist") and hasattr(value, "dtype"):  # numpy array or scalar
        return plain(value.tolist())
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    return value


# ----------------------------------------------------------------------------- inputs

def record_sha256(record) -> str | None:
    """The SHA-256 of the bytes a records.Record was parsed from (read once: a file replaced
    since does not change it); for a record made in code without one, its file's now, or None."""
    return getattr(record, "sha256", "") or (sha256(record.source) if record.source else None)


def record_entry(record, role: str = "record", **extra: Any) -> dict[str, Any]:
    """An input-file entry of a records.Record: the SHA-256 of the bytes it was read from
    (record_sha256) and its file's size, the format it was read as, units of the file, name,
    time step dt [s], samples, the scale applied [-]."""
    entry = {**file_entry(role, record.source), "sha256": record_sha256(record)} if record.source else \
        {"role": role, "path": None, "sha256": None, "bytes": None}
    return {**entry, "format": getattr(record, "format", ""), "units": record.units, "name": record.name,
            "dt": float(record.dt), "npts": record.npts, "scale": float(record.scale), **extra}


def motion_files(motion) -> list[dict[str, Any]]:
    """Input-file entries of a ground motion: a record, each record of a suite (with its
    amplitude factor), or a design spectrum read from a table file."""
    from .motion.records import Record

    if isinstance(motion, Record):
        return [record_entry(motion)]
    records = getattr(motion, "records", None)
    if records is not None:  # a motion.suites.Suite
        notes = tuple(motion.provenance) + ("",) * (len(records) - len(motion.provenance))
        entries = [record_entry(record, f"suite record {k + 1}", factor=float(factor), note=note)
                   for k, (record, factor, note) in enumerate(zip(records, motion.factors, notes, strict=True))]
        return entries + motion_files(motion.target)
    source = getattr(motion, "source", "")
    if source and Path(str(source)).is_file():
        return [file_entry("design spectrum table", source)]
    return []


def absolute_paths(raw: dict, source: str, relative_to: str | os.PathLike | None = None) -> dict:
    """A copy of a deck mapping with its file paths (ground_motion.record, the suite's folder or
    files, design_spectrum.file) absolute: relative paths joined to the deck's folder; with
    relative_to (a folder), relative to that folder instead (the folder of a resolved deck file)."""
    from .errors import deck_relative_path

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


# ----------------------------------------------------------------------------- model

def foundation_entry(system) -> dict[str, Any]:
    """The foundation's type and own parameters under their deck names (SI), its rocking
    stiffness K_theta [N m/rad] and damping C_theta [N m s/rad] at the frequency omega_impedance
    [rad/s] every engine uses (model/interaction.py), the equivalent edge elements and the
    vertical stiffness [N/m] and damping [N s/m] at that frequency."""
    from .model.interaction import impedance

    foundation = system.foundation
    names = FOUNDATION_NAMES.get(foundation.kind, {})
    entry: dict[str, Any] = {"type": foundation.kind}
    for item in dataclasses.fields(foundation):
        if getattr(foundation, item.name) is not None:  # no bearing capacity: not an entry
            entry[names.get(item.name, item.name)] = plain(getattr(foundation, item.name))
    if getattr(foundation, "capacity", None) is not None:  # each element's Q_y and FS_v (docs/theory.md 14)
        entry["Q_y"] = plain(foundation.contact_elements(system.half_width).capacity)
        entry["FS_v"] = foundation.total_capacity(system.half_width) / system.weight
    if hasattr(foundation, "shear_wave_velocity"):
        entry["shear_wave_velocity"] = float(foundation.shear_wave_velocity)
    rocking = impedance(system)
    omega = rocking["omega_impedance"]
    b = system.half_width
    return {**entry, **rocking, "vertical_stiffness": float(foundation.vertical_stiffness(b, omega)),
            "vertical_damping": float(foundation.vertical_damping(b, omega))}


def foundation_units(system) -> dict[str, str]:
    """Units of the foundation's own parameters (from its deck fields)."""
    cls = type(system.foundation)
    names = FOUNDATION_NAMES.get(cls.kind, {})
    units = {names.get(item.name, item.name): cls.deck_fields[names.get(item.name, item.name)].unit
             for item in dataclasses.fields(cls) if names.get(item.name, item.name) in cls.deck_fields
             and getattr(system.foundation, item.name) is not None}
    if "shear_wave_velocity" in cls.deck_fields:
        units["shear_wave_velocity"] = "m/s"
    return units


def derived_model(system, effective_properties: str = "formula") -> dict[str, Any]:
    """What the engines analyse, derived from the deck (SI, see MODEL_UNITS and
    "foundation_units"): floors, story stiffnesses after the period scaling (a frame: its
    stiffness matrix), modal damping, the fixed-base modes (T_n, m_n*, h_n*), m_t, h_1*, b,
    h_1*/b, V_c, M_c [16a, 16b], the foundation (foundation_entry) and T1bar, xi1bar of the
    bonded system [21-25] by the deck's analysis.effective_properties."""
    from .errors import AnalysisError
    from .model.interaction import effective_properties as properties

    building, modes = system.building, system.modes
    model: dict[str, Any] = {
        "stories": building.n_stories, "masses": plain(building.masses), "elevations": plain(building.heights),
        "story_heights": plain(building.story_heights),
    }
    if building.story_stiffness is not None:
        model["story_stiffnesses"] = plain(building.story_stiffness)
    else:
        model["stiffness_matrix"] = plain(building.stiffness)
    model.update({
        "damping": plain(building.damping), "periods": plain(modes.periods),
        "effective_masses": plain(modes.effective_mass), "effective_heights": plain(modes.effective_height),
        "total_mass": system.total_mass, "mat_mass": system.mat_mass, "mat_rotary_inertia": system.mat_rotary_inertia,
        "half_width": system.half_width, "h1_star": system.effective_height,
        "slenderness": system.effective_height / system.half_width, "gravity": system.gravity, "weight": system.weight,
        "critical_base_shear": system.critical_base_shear, "critical_base_moment": system.critical_base_moment,
        "foundation": foundation_entry(system),
    })
    try:
        bonded = properties(system, effective_properties)
        model.update(T1bar=float(bonded["T1bar"]), xi1bar=float(bonded["xi1bar"]))
    except AnalysisError:  # an overdamped bonded system has no T1bar: the engines say so
        pass
    model["units"] = {**{name: unit for name, unit in MODEL_UNITS.items() if name in model},
                      "foundation": {**foundation_units(system),
                                     **{name: MODEL_UNITS[name] for name in MODEL_UNITS
                                        if name in model["foundation"]}}}
    return model


def spectrum_entry(spectrum) -> dict[str, Any] | None:
    """A design spectrum's name and, for a table, its damping [-], the damping correction used
    for other dampings and its period range [s] (None for a record's own spectrum)."""
    if spectrum is None or hasattr(spectrum, "record"):
        return None
    entry: dict[str, Any] = {"name": getattr(spectrum, "name", type(spectrum).__name__)}
    for name in ("damping", "damping_correction", "units"):
        if hasattr(spectrum, name):
            entry[name] = plain(getattr(spectrum, name))
    if hasattr(spectrum, "period_range"):
        entry["period_range"] = plain(spectrum.period_range)
    return entry


def engine_options(analysis) -> dict[str, Any]:
    """The engines and supports of a deck and every option of the simplified and the
    response-history engines (engines/options.py), with the units of the options (their deck fields)."""
    from .engines.options import deck_fields

    simplified = dataclasses.asdict(analysis.simplified)
    exact = {k: v for k, v in dataclasses.asdict(analysis.exact).items() if k != "histories"}
    units = {table: {name: field.unit for name, field in deck_fields(type(options)).items() if name in values}
             for table, options, values in (("simplified", analysis.simplified, simplified),
                                            ("exact", analysis.exact, exact))}
    return {"engines": list(analysis.engines), "supports": list(analysis.supports), "n_modes": analysis.n_modes,
            "simplified": plain(simplified), "exact": plain(exact), "units": units}


# ----------------------------------------------------------------------------- records

def base(command: str | None = None, now: datetime | None = None) -> dict[str, Any]:
    """Tool, version, Python, platform, libraries, command and UTC time."""
    return {"tool": TOOL, "version": tool_version(), "python": platform.python_version(),
            "platform": platform_name(), "libraries": {name: package_version(name) for name in LIBRARIES},
            "command": command_line() if command is None else command, "time_utc": utc_now(now)}


def of_deck(deck, command: str | None = None, now: datetime | None = None) -> dict[str, Any]:
    """The provenance of a run of a deck.Deck (module docstring): base(), files, deck
    {source, title, set, resolved}, model (derived_model) and options (engine_options)."""
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
