"""Names chosen from a fixed set: the closest name suggested for a mistake (`suggestion`, in every
error about an unknown key, field or choice) and the names of a command-line option
(`parse_choices`: repeated, comma-separated or 'all'). Imported from deck/fields.py, whose
names they are."""

from __future__ import annotations

import difflib

from ..errors import InputError


def suggestion(name: str, candidates) -> str:
    """' (did you mean 'x'?)' for the closest candidate, or ''."""
    close = difflib.get_close_matches(name, list(candidates), n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


def parse_choices(texts, choices, option: str) -> list[str]:
    """Repeated and/or comma-separated names of a command-line option ('all' = every
    choice), in the order given; names are matched exactly, as in a deck (InputError naming
    `option` otherwise)."""
    names: list[str] = []
    for name in _option_names(texts):
        names.extend(_choice(name, choices, option))
    return list(dict.fromkeys(names))


def _option_names(texts) -> list[str]:
    """The non-empty comma-separated names of the texts, in order."""
    parts = (part.strip() for part in ",".join(texts).split(","))
    return [name for name in parts if name]


def _choice(name: str, choices, option: str) -> list[str]:
    """The choices one name stands for: every one for 'all', else itself."""
    if name == "all":
        return list(choices)
    if name in choices:
        return [name]
    hint = f" (names are lower case: {name.lower()!r})" if name.lower() in choices else suggestion(name, choices)
    raise InputError(option, name, f"one of {', '.join(choices)} or all{hint}")
