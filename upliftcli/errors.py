"""Input errors: one line naming the file, the field (or line) and what was expected."""

from __future__ import annotations


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
        super().__init__(f"{where}: {expected}")


class AnalysisError(Exception):
    """An analysis that cannot give a trustworthy number (flight unsupported, non-finite state,
    tolerance not met). The CLI prints it on one line and exits with code 4."""
