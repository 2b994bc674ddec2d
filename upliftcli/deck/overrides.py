"""`--set PATH=VALUE` overrides of a deck: the value read as TOML, the path checked against the
deck's schema (deck_schema.TABLES), and the raw deck with each override applied, a member of a
group of alternatives (foundation.b or foundation.slenderness ...) replacing the others.
Pure functions of the parsed TOML; errors are InputError("--set", field, expected).
"""

from __future__ import annotations

import copy
import tomllib
from collections.abc import Iterable
from typing import Any

from ..errors import InputError
from ..model.bearing import COMPANIONS
from ..model.foundations import FOUNDATIONS
from . import schema
from .schema import set_by_override  # noqa: F401 - part of this module's interface

#: groups of mutually exclusive fields: a `--set` of one member removes the others
ALTERNATIVES: list[tuple[str, list[set[str]]]] = [
    ("building", [{"floor_mass"}, {"masses"}]),
    ("building", [{"story_height"}, {"story_heights"}]),
    ("building", [{"story_stiffness"}, {"story_stiffnesses"}, {"stiffness_matrix"}]),
    ("foundation", [{"b"}, {"slenderness"}]),
    *[("foundation", groups) for kind in FOUNDATIONS.values() for groups in kind.deck_alternatives],
    ("analysis", [{"modes"}, {"mass_participation"}]),
    ("ground_motion", [{"record", "format", "units", "override_header_units", "dt", "window", "scale"},
                       {"design_spectrum", "suite", "scaling", "suite_factor", "period_range", "statistics"}]),
]

#: foundation type -> its own fields of the [foundation] table
FOUNDATION_FIELDS = {kind: set(cls.deck_fields) for kind, cls in FOUNDATIONS.items()}



def parse_override(text: str) -> tuple[str, Any]:
    """'a.b=value' -> ('a.b', value); the value is read as a TOML value, else as a bare string."""
    path, sep, value_text = text.partition("=")
    path = path.strip()
    if not sep or not path:
        raise InputError("--set", text, "PATH=VALUE, e.g. building.period=0.5")
    if not schema.known_path(path):
        candidates = schema.all_paths()
        raise InputError("--set", path, f"a known deck field{schema.suggestion(path, candidates)}")
    value_text = value_text.strip()
    if any(not (ch.isprintable() or ch == "\t") for ch in value_text):
        raise InputError("--set", path, "a value on one line (without line breaks or control characters)")
    return path, toml_value(value_text)


def toml_value(text: str) -> Any:
    """A command-line value read as a TOML value, else the bare string; nesting too deep
    for the parser (RecursionError) is kept as the string, which the field check refuses."""
    try:
        return tomllib.loads(f"value = {text}")["value"]
    except (tomllib.TOMLDecodeError, RecursionError):
        return text


def apply_overrides(raw: dict, overrides: Iterable[tuple[str, Any]]) -> tuple[dict, frozenset[str]]:
    """Copy of `raw` with each (dotted path, value) set; members of the same group of
    alternatives (e.g. foundation.b vs foundation.slenderness) are removed, and setting
    foundation.type removes the fields of the other foundation types."""
    result = copy.deepcopy(raw)
    paths = []
    for path, value in overrides:
        parts = path.split(".")
        table = result
        for part in parts[:-1]:
            if not isinstance(table.get(part), dict):
                table[part] = {}
            table = table[part]
        parent, name = ".".join(parts[:-1]), parts[-1]
        for group_table, groups in ALTERNATIVES:
            if group_table == parent and any(name in group for group in groups):
                for group in groups:
                    if name not in group:
                        for other in group:
                            table.pop(other, None)
                            for companion in COMPANIONS.get(other, ()) if group_table == "foundation" else ():
                                table.pop(companion, None)
        if path == "foundation.type" and isinstance(value, str) and value in FOUNDATION_FIELDS:
            for kind, names in FOUNDATION_FIELDS.items():  # fields of the replaced type go
                if kind != value:
                    for other in names:
                        table.pop(other, None)
        table[name] = value
        paths.append(path)
    return result, frozenset(paths)
