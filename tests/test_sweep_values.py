"""sweep/values.py: the values of --vary and --periods parsed and checked against the deck's schema."""

import numpy as np
import pytest

from upliftcli.deck.fields import parse_choices
from upliftcli.errors import InputError
from upliftcli.sweep.values import parse_values, parse_vary


def test_parse_values_ranges_and_lists():
    values, spacing = parse_values("1e7:1e10:4:log", "--vary")
    assert spacing == "log" and values == [1e7, 1e8, 1e9, 1e10]
    values, spacing = parse_values("0.2:3:15", "--vary")
    assert spacing == "linear" and len(values) == 15 and values[0] == 0.2 and values[-1] == 3.0
    assert values[1] == 0.4  # rounded to 12 digits, not 0.39999999999999997
    np.testing.assert_allclose(np.diff(values), 0.2, rtol=1e-12)
    assert parse_values("1:5:5", "--vary") == ([1, 2, 3, 4, 5], "linear")  # integers stay integers
    assert parse_values("srss,cqc", "--vary") == (["srss", "cqc"], "list")
    assert parse_values("[0.5, 1]", "--vary") == ([0.5, 1], "list")
    assert parse_values("0.05:5:3", "--periods", "log")[0] == [0.05, 0.5, 5.0]
    for bad in ("1:2", "0:10:5:log", "a:b:3", "1:2:0", "1:2:3:cubic", "[]"):
        with pytest.raises(InputError):
            parse_values(bad, "--vary")


def test_parse_vary_checks_the_path():
    vary = parse_vary("foundation.k_f=1e7:1e9:3:log")
    assert vary.path == "foundation.k_f" and vary.unit == "N/m" and vary.values == (1e7, 1e8, 1e9)
    with pytest.raises(InputError, match=r"did you mean 'foundation\.k_f'"):
        parse_vary("foundation.kf=1:2:2")
    with pytest.raises(InputError, match="--engine"):
        parse_vary("analysis.engine=exact,simplified")
    with pytest.raises(InputError):
        parse_vary("building.period")
    assert parse_choices(["exact,simplified", "all"], ("simplified", "approximate", "exact"), "--engine") == \
        ["exact", "simplified", "approximate"]
    with pytest.raises(InputError, match="--support"):
        parse_choices(["rigid,flying"], ("rigid", "bonded", "uplift"), "--support")


@pytest.mark.parametrize(("text", "line"), [
    ("0.5,1,0.5", "--vary building.period: 0.5,1,0.5: each value once (0.5 is given 2 times)"),
    ("1:1:3", "--vary building.period: 1:1:3: each value once (1 is given 3 times)"),
    ("1:1.0000000000001:3", "--vary building.period: 1:1.0000000000001:3: each value once (1.0 is given 3 times)"),
])
def test_a_value_given_twice_is_refused(text, line):
    """Two cases with one value had one case key: the table listed cases 0-2 twice and never 3-5
    (`--vary building.period=0.5,0.5`)."""
    with pytest.raises(InputError) as info:
        parse_vary(f"building.period={text}")
    assert str(info.value) == line
    assert parse_vary("building.period=1:1:1").values == (1,)


def test_a_field_whose_value_is_an_array_is_varied_as_an_array_of_arrays():
    """Fuzzing found `--vary analysis.check_band=[0.9,1.1]` read as two cases, 0.9 and 1.1, and
    refused as 'got 0.9': a field whose value is an array (a pair, numbers, a matrix) takes one
    array per case, and the error says so, naming the field and showing the form."""
    vary = parse_vary("analysis.check_band=[[0.9, 1.1], [0.8, 1.25]]")
    assert vary.values == ([0.9, 1.1], [0.8, 1.25]) and vary.spacing == "list"
    assert parse_vary("ground_motion.window=[[0, 10], [0, 20]]").values == ([0, 10], [0, 20])
    for text, single in (("[0.9,1.1]", "0.9"), ("0.9,1.1", "0.9"), ("[[0.9,1.1],0.8]", "0.8")):
        with pytest.raises(InputError) as raised:
            parse_vary(f"analysis.check_band={text}")
        assert str(raised.value) == (
            "--vary: analysis.check_band: a TOML array of arrays, one array per case (the field's value is itself an "
            f"array), e.g. analysis.check_band=[[0.9, 1.1], [0.8, 1.25]]; got '{text}', whose case {single} is not an "
            "array")
    with pytest.raises(InputError, match=r"building\.masses: a TOML array of arrays"):
        parse_vary("building.masses=1e5,2e5")
    assert parse_vary("building.damping=0.02,0.05").values == (0.02, 0.05)  # one value or an array: scalars vary
