"""`--set PATH=VALUE` overrides of a deck: the value read as TOML, the path checked against the
deck's schema (deck/schema.TABLES), and the raw deck with each override applied, a member of a
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
from ..runtime.limits import too_deeply_nested
from . import schema
from .schema import set_by_override  # noqa: F401 - part of this module's interface

#: groups of mutually exclusive fields: a `--set` of one member removes the others
ALTERNATIVES: list[tuple[str, list[set[str]]]] = [
    ("building", [{"floor_mass"}, {"masses"}]),
    ("building", [{"story_height"}, {"story_heights"}]),
    ("building", [{"story_stiffness"}, {"story_stiffnesses"}, {"stiffness_matrix"}]),
    ("building", [{"story_strengths"}, {"strength_coefficient"}]),
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
    path, value_text = _split_override(text)
    _check_known_path(path)
    if not _one_line(value_text):
        raise InputError("--set", path, "a value on one line (without line breaks or control characters)")
    return path, toml_value(value_text)


def _split_override(text: str) -> tuple[str, str]:
    """'a.b = value' -> ('a.b', 'value')."""
    path, sep, value_text = text.partition("=")
    path = path.strip()
    if not sep or not path:
        raise InputError("--set", text, "PATH=VALUE, e.g. building.period=0.5")
    return path, value_text.strip()


def _check_known_path(path: str) -> None:
    """A dotted path of a deck field (schema.known_path), else the closest one suggested."""
    if not schema.known_path(path):
        candidates = schema.all_paths()
        raise InputError("--set", path, f"a known deck field{schema.suggestion(path, candidates)}")


def _one_line(text: str) -> bool:
    """No line break or control character (a tab is allowed)."""
    return all(ch.isprintable() or ch == "\t" for ch in text)


def toml_value(text: str) -> Any:
    """A command-line value read as a TOML value, else the bare string; nesting too deep
    for the parser (RecursionError) or for the deck (runtime/limits.MAX_NESTING) is kept as the
    string, which the field check refuses."""
    try:
        value = tomllib.loads(f"value = {text}")["value"]
    except (tomllib.TOMLDecodeError, RecursionError):
        return text
    return text if too_deeply_nested(value) else value


def apply_overrides(raw: dict, overrides: Iterable[tuple[str, Any]]) -> tuple[dict, frozenset[str]]:
    """Copy of `raw` with each (dotted path, value) set; members of the same group of
    alternatives (e.g. foundation.b vs foundation.slenderness) are removed, and setting
    foundation.type removes the fields of the other foundation types."""
    result = copy.deepcopy(raw)
    paths = []
    for path, value in overrides:
        _apply(result, path, value)
        paths.append(path)
    return result, frozenset(paths)


def _apply(result: dict, path: str, value: Any) -> None:
    """One override set in `result`, after the fields it replaces are removed."""
    table = _table_of(result, path)
    parent, _, name = path.rpartition(".")
    _drop_alternatives(table, parent, name)
    if _is_foundation_type(path, value):
        _drop_other_types(table, value)
    table[name] = value


def _table_of(result: dict, path: str) -> dict:
    """The table that holds the field at `path` (created, or replacing a value that is not a table, on the way)."""
    table = result
    for part in path.split(".")[:-1]:
        if not isinstance(table.get(part), dict):
            table[part] = {}
        table = table[part]
    return table


def _drop_alternatives(table: dict, parent: str, name: str) -> None:
    """Remove the other members of each group of alternatives of `parent` that `name` is in."""
    for group_table, groups in ALTERNATIVES:
        if group_table == parent and _in_groups(name, groups):
            _drop_other_groups(table, group_table, groups, name)


def _in_groups(name: str, groups: list[set[str]]) -> bool:
    """Whether `name` is a member of one of the groups."""
    return any(name in group for group in groups)


def _drop_other_groups(table: dict, group_table: str, groups: list[set[str]], name: str) -> None:
    """Remove the members of the groups `name` is not in; of [foundation], with their companions (a bearing
    capacity's, model/bearing.COMPANIONS)."""
    for other in _other_members(groups, name):
        table.pop(other, None)
        for companion in _companions(group_table, other):
            table.pop(companion, None)


def _other_members(groups: list[set[str]], name: str) -> list[str]:
    """The members of the groups `name` is not in."""
    return [other for group in groups if name not in group for other in group]


def _companions(group_table: str, name: str) -> tuple[str, ...]:
    """The fields that go with the foundation field `name` (none elsewhere)."""
    return COMPANIONS.get(name, ()) if group_table == "foundation" else ()


def _is_foundation_type(path: str, value: Any) -> bool:
    """A --set of foundation.type to a known type."""
    return path == "foundation.type" and isinstance(value, str) and value in FOUNDATION_FIELDS


def _drop_other_types(table: dict, kind: str) -> None:
    """Remove the fields of the foundation types other than `kind`."""
    for other, names in FOUNDATION_FIELDS.items():
        if other != kind:
            for name in names:
                table.pop(name, None)
