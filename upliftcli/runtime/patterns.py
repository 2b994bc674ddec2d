"""Regular expressions compiled when first used, not when their module is imported: Python's re
compiles a pattern in Python code (0.1-0.3 ms each), and a command uses few of the package's
(`uplift modes` reads no record: none of the record readers' patterns)."""

from __future__ import annotations

import re


class LazyPattern:
    """A re.Pattern compiled on first use: its methods and attributes (search, fullmatch, sub,
    pattern ...) are the compiled pattern's, each looked up once and then kept on this object."""

    def __init__(self, pattern: str, flags: int = 0) -> None:
        self._source = (pattern, flags)

    def __getattr__(self, name: str):
        value = getattr(re.compile(*self._source), name)  # re caches the compiled pattern itself
        setattr(self, name, value)
        return value


def lazy(pattern: str, flags: int = 0) -> LazyPattern:
    """The pattern, compiled when first used (LazyPattern)."""
    return LazyPattern(pattern, flags)
