"""Input errors: one line naming the file, the field (or line) and what was expected."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any


def printable(text, lines: bool = False) -> str:
    """The one place text is made safe for the terminal: every character a terminal could act on
    (ESC and the other C0/C1 controls, DEL, a carriage return, bidirectional overrides, line and
    paragraph separators: whatever str.isprintable refuses) shown as its visible
    escape ('\\x1b', '\\r', '\\u202e'); `lines`: line breaks and tabs are kept. Every terminal output
    of user-given text goes through it: error and warning lines (one_line), the rich console's
    texts and segments (cli/fitting.py), and every echo (cli/stdout.py)."""
    text = str(text)
    kept = text.replace("\n", "").replace("\t", "") if lines else text
    if kept.isprintable():
        return text
    keep = "\n\t" if lines else ""
    return "".join(ch if ch.isprintable() or ch in keep else _escape(ch) for ch in text)


def _escape(ch: str) -> str:
    """A character as its Python escape: '\\x1b', '\\r', '\\u202e'."""
    return ch.encode("unicode_escape").decode("ascii")


def one_line(text: str) -> str:
    """`text` with line breaks (and other control characters) shown as escapes (printable): a
    message naming a path or value that holds a newline stays on one line."""
    return printable(text)


class InputError(Exception):
    """Bad user input. The CLI prints str(error) on one line and exits with code 2.

    source: the file (or "--set", "--periods", ...) the bad value came from.
    location: the dotted field path or "line N".
    expected: what was expected, in words, with the unit.
    """

    def __init__(self, source: str, location: str | None, expected: str):
        self.source = str(source)
        self.location = location
        self.expected = expected
        where = f"{self.source}: {location}" if location else self.source
        super().__init__(one_line(f"{where}: {expected}"))


class InputErrors(InputError):
    """Several independent input errors found in one pass (a deck with four mistakes): one line
    each, in the order found. source, location and expected are those of the first; `errors`
    holds them all. The CLI prints each line and exits with code 2."""

    def __init__(self, errors):
        self.errors = [item for error in errors for item in getattr(error, "errors", [error])]
        first = self.errors[0]
        self.source, self.location, self.expected = first.source, first.location, first.expected
        Exception.__init__(self, "\n".join(str(error) for error in self.errors))


def lines(error: Exception) -> list[str]:
    """The lines to print for an error: one per InputError of an InputErrors."""
    return [str(item) for item in getattr(error, "errors", [error])]


class AnalysisError(Exception):
    """An analysis that cannot give a trustworthy number (flight unsupported, non-finite state,
    tolerance not met). The CLI prints it on one line and exits with code 4."""

    def __str__(self) -> str:
        return one_line(super().__str__())


def deck_relative_path(given: str, source: str):
    """The file a deck names: relative paths are relative to the deck file's folder; a deck
    that is a symbolic link is read where it points, so its files are found next to the link's
    target (as for a copy of the deck), not next to the link."""
    from pathlib import Path

    path = Path(given)
    if path.is_absolute():
        return path
    deck = Path(source)
    if deck.is_symlink():
        deck = deck.resolve()
    return deck.parent / path


def not_found(path, given: str, source: str, what: str = "record file", folder=None) -> str:
    """What a deck field naming a missing file expected, in words: the file as the deck gives
    it and, for a relative path, the deck's folder it was resolved from (default: the folder
    of `source`) and the absolute path."""
    import os

    if os.path.isabs(given):
        return f"an existing {what}, not found: {str(path)!r}"
    folder = os.path.abspath(folder if folder is not None else deck_relative_path(".", source))
    return (f"an existing {what}, not found: {given!r} (relative to the deck's folder {folder!r}: "
            f"{os.path.abspath(path)!r})")


def gather(errors: list[InputError], check: Callable[..., Any], *args: Any) -> Any:
    """check(*args), or None with its InputError(s) appended to `errors` (to report them all)."""
    try:
        return check(*args)
    except InputError as bad:
        errors.extend(getattr(bad, "errors", [bad]))
        return None


def raise_all(errors: list[InputError]) -> None:
    """Raise the gathered errors: one InputError as it is, several as one InputErrors."""
    if len(errors) == 1:
        raise errors[0]
    if errors:
        raise InputErrors(errors)
