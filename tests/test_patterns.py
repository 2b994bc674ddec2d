"""runtime/patterns.py: a regular expression compiled on first use behaves as the compiled one."""

from __future__ import annotations

import re

from upliftcli.runtime.patterns import LazyPattern, lazy


def test_a_lazy_pattern_is_compiled_on_first_use_and_answers_as_re():
    source = r"(?P<number>[-+]?\d+)\s*(?P<unit>[a-z]+)?-lazy-test"
    pattern = lazy(source, re.IGNORECASE)
    assert isinstance(pattern, LazyPattern) and "search" not in vars(pattern)  # nothing compiled yet
    compiled = re.compile(source, re.IGNORECASE)
    for text in ("12 KN-lazy-test", "x -3-LAZY-TEST y", "none"):
        for method in ("fullmatch", "search"):
            found, expected = getattr(pattern, method)(text), getattr(compiled, method)(text)
            assert (found and found.groupdict()) == (expected and expected.groupdict())
        assert pattern.sub("#", text) == compiled.sub("#", text)
    assert "search" in vars(pattern)  # looked up once, then kept
    assert (pattern.pattern, pattern.flags) == (compiled.pattern, compiled.flags)
