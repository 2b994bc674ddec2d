"""Error messages stay on one line whatever the path or value holds."""

from upliftcli.errors import AnalysisError, InputError, one_line


def test_one_line_escapes_line_breaks():
    assert one_line("a\nb\r\tc") == "a\\nb\\r\\tc"
    assert one_line("plain text, 5 % [m/s^2]") == "plain text, 5 % [m/s^2]"
    error = InputError("dir\nname/deck.toml", "line 3", "a number, got 'x\ny'")
    assert "\n" not in str(error) and str(error) == "dir\\nname/deck.toml: line 3: a number, got 'x\\ny'"
    assert error.source == "dir\nname/deck.toml"  # the attributes keep the real values
    assert str(AnalysisError("two\nlines")) == "two\\nlines"


def test_several_errors_are_one_line_each():
    from upliftcli.errors import InputErrors, lines

    first = InputError("deck.toml", "building.period", "a number > 0 [s], got -1")
    second = InputError("--set", "foundation.b", "a number > 0 [m], got 'x\ny'")
    both = InputErrors([first, InputErrors([second])])  # nested: flattened
    assert lines(both) == ["deck.toml: building.period: a number > 0 [s], got -1",
                           "--set: foundation.b: a number > 0 [m], got 'x\\ny'"]
    assert (both.source, both.location, both.expected) == (first.source, first.location, first.expected)
    assert isinstance(both, InputError) and lines(first) == [str(first)]
