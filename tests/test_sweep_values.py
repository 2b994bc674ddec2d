"""sweep/values.py: the values of --vary and --periods parsed and checked against the deck's schema."""

import numpy as np
import pytest

from upliftcli.errors import InputError
from upliftcli.fields import parse_choices
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
