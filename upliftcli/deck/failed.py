"""Which checks of a deck still run once some fields have failed theirs (deck/load.build_deck): a
check that rests on a field with an error is skipped (its message would follow from that error,
not name a mistake of its own: a floor mass that is not a number is not also "missing"); every
other check runs, so that one run reports every mistake of the deck.

    failed = Failed.of(errors)        # the InputErrors gathered so far
    failed.clear("building")          # no error at or inside [building], nor at the top level

An error at the top level (`units`, whose system every number is read in, or an unknown key, which
may be a misspelt table) leaves every table unclear; one with no field named, too.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass

from ..errors import InputError
from .schema import TABLES

#: the top-level fields whose errors leave the other fields meaningful
HARMLESS_TOP = frozenset(TABLES[""]) - {"units"}


@dataclass(frozen=True)
class Failed:
    """The dotted fields (locations) of the errors gathered so far."""

    locations: frozenset[str]

    @classmethod
    def of(cls, errors: Iterable[InputError]) -> Failed:
        return cls(frozenset(error.location or "" for error in errors))

    def clear(self, *paths: str) -> bool:
        """Whether no failed field lies at or inside one of `paths` (dotted fields or tables), and
        none at the top level that every table rests on."""
        return not any(_blocks(location, paths) for location in self.locations)


def _blocks(location: str, paths: tuple[str, ...]) -> bool:
    """Whether an error at `location` leaves the fields at `paths` unclear."""
    return _everywhere(location) or any(_inside(location, path) for path in paths)


def _everywhere(location: str) -> bool:
    """An error at the top level (units, an unknown table or key), or of no field."""
    head = re.split(r"[.\[]", location, maxsplit=1)[0]
    return not head or (head not in TABLES and head not in HARMLESS_TOP)


def _inside(location: str, path: str) -> bool:
    """Whether the field at `location` is `path` or lies in it (a.b inside a, a[1].c inside a)."""
    return location == path or location.startswith((f"{path}.", f"{path}["))
