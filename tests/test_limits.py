"""Documented limits: each is refused with the limit, the value and the field, before anything is allocated."""

import io
import os

import numpy as np
import pytest

from upliftcli.errors import InputError
from upliftcli.motion.spectra import response_spectrum, substeps
from upliftcli.runtime import limits


def test_shortest_period_follows_the_record_step_and_length():
    assert limits.shortest_period(0.02, 1560) == pytest.approx(0.02 / limits.MAX_DT_OVER_PERIOD)
    # a long record: the sub-steps of one oscillator over the record bound it instead
    long = limits.shortest_period(0.01, 1_000_000)
    assert long == pytest.approx(4 * 0.01 * 999_999 / limits.MAX_SPECTRUM_STEPS)
    # at the limit an oscillator costs at most MAX_SPECTRUM_STEPS sub-steps (spectra.substeps)
    for dt, samples in ((0.02, 1560), (0.01, 1_000_000), (0.005, 20)):
        t = limits.shortest_period(dt, samples)
        assert int(substeps(dt, [t])[0]) * (samples - 1) <= 1.0001 * max(limits.MAX_SPECTRUM_STEPS,
                                                                          4 * limits.MAX_DT_OVER_PERIOD * samples)


def test_period_problem_names_the_limit_and_the_period():
    assert limits.period_problem([0.0, 0.05, 5.0], 0.02, 1560) is None
    words = limits.period_problem([0.5, 1e-8], 0.02, 1560)
    assert "periods of at least 8e-06 s or 0" in words and "got 1e-08 s" in words


def test_spectrum_at_the_shortest_period_is_quick_and_follows_the_ground():
    """At the limit the ordinate is still computed exactly (and quickly: within the sub-steps of
    the spectrum limit, counted rather than timed on a shared machine): S_a -> PGA as T -> 0."""
    rng = np.random.default_rng(1)
    a = rng.normal(size=200)
    t = limits.shortest_period(0.02, a.size)
    assert limits.spectrum_work([t], 1, 0.02, a.size) <= limits.MAX_SPECTRUM_WORK
    spectrum = response_spectrum(a, 0.02, [t], [0.05])
    assert spectrum.pseudo_acceleration[0, 0] == pytest.approx(np.max(np.abs(a)), rel=1e-3)


def test_step_states_problem():
    assert limits.step_states_problem(1000, 28) is None
    words = limits.step_states_problem(3_741_600, 28)
    assert words.startswith("at most 50,000,000 internal steps x states (about 20 s of stepping on 2 cores), "
                            "got 3,741,600 steps x 30")


def test_steps_problem():
    assert limits.steps_problem(limits.MAX_STEPS, 28) is None
    assert limits.steps_problem(374_160, 28).startswith("at most 250,000 internal steps of one run (about 3 s of "
                                                        "peak search when the mat chatters at every step), got 374,160")
    # steps x (states + 2)^2: 500 stories under El Centro (4,677 steps, 1,008 states) fit, ten times the record not
    assert limits.steps_problem(4_677, 1_008) is None
    assert limits.steps_problem(46_770, 1_008) == ("at most 5,000,000,000 internal steps x states^2 of one run "
                                                   "(about 20 s on 2 cores), got 46,770 steps x 1010^2 = "
                                                   "47,710,077,000")


def test_cases_problem_is_computed_without_expanding():
    assert limits.cases_problem([10, 10], 3) is None
    assert limits.cases_problem([30, 30, 30, 30], 3) == "at most 100,000 cases, got 2,430,000 (30 x 30 x 30 x 30 x 3)"


def test_read_limited_stops_at_the_limit(tmp_path):
    path = tmp_path / "f"
    path.write_bytes(b"x" * 100)
    assert limits.read_limited(path, 100) == b"x" * 100
    with pytest.raises(ValueError, match="at most"):
        limits.read_limited(path, 99)
    with pytest.raises(limits.NotRegularFile, match="a device"):
        limits.read_limited("/dev/zero", 2**20)  # endless: refused before it is opened (else "at most")
    assert isinstance(io.BytesIO(limits.read_limited(path, 1000)).read(), bytes)


def test_every_input_file_is_read_within_its_limit(tmp_path):
    """Decks, records and spectrum tables share one bounded read of regular files: a device such as
    /dev/zero or a FIFO is refused before it is opened (a FIFO blocked for ever), a directory or a
    missing file named as such."""
    from upliftcli.motion.design_spectra import from_mapping
    from upliftcli.runtime.limits import read_input

    with pytest.raises(InputError, match=r"^/dev/zero: a regular deck file \(this is a device\)$"):
        read_input("/dev/zero", limits.MAX_DECK_BYTES, "/dev/zero", None, "deck file")
    fifo = tmp_path / "fifo.toml"
    os.mkfifo(fifo)
    with pytest.raises(InputError, match=r"fifo.toml: a regular deck file \(this is a FIFO\)$"):
        read_input(fifo, limits.MAX_DECK_BYTES, str(fifo), None, "deck file")
    big = tmp_path / "big.toml"
    big.write_bytes(b"#" * 2000)
    with pytest.raises(InputError, match=r"big.toml: a deck file of at most 0.000976562 MiB"):
        read_input(big, 1024, str(big), None, "deck file")
    with pytest.raises(InputError, match=r": a record file \(this is a directory\)$"):
        read_input(tmp_path, limits.MAX_RECORD_BYTES, str(tmp_path), None, "record file")
    with pytest.raises(InputError, match=r"an existing record file \(file not found\)$"):
        read_input(tmp_path / "none.txt", limits.MAX_RECORD_BYTES, "r.txt", None, "record file")
    deck = str(tmp_path / "deck.toml")
    with pytest.raises(InputError, match=r"spectrum\.file: a regular spectrum table .* \(this is a device\)"):
        from_mapping({"type": "table", "file": "/dev/zero", "damping": 0.05}, deck)


@pytest.mark.parametrize("text", [
    "[" + ".".join(["a"] * 1000) + "]\n",  # parsed by tomllib, then too deep for the deck's walks
    "x = " + "[" * 1000 + "]" * 1000 + "\n",  # too deep for the parser itself
    "x = " + "{a=" * 1000 + "}" * 1000 + "\n",
    "[" + ".".join(["a"] * (limits.MAX_NESTING + 1)) + "]\n",  # just past the limit
])
def test_tables_nested_too_deeply_are_one_line_naming_the_deck(tmp_path, text):
    from cli_helpers import invoke

    deck = tmp_path / "n.toml"
    deck.write_text(text)
    for command in (["analyze", deck], ["sweep", deck, "--vary", "foundation.slenderness=5,6", "--out",
                                        tmp_path / "o"]):
        result = invoke(*command)
        assert result.exit_code == 2, result.output
        assert result.stderr == f"error: {deck}: valid TOML (arrays or tables nested too deeply: at most " \
                                f"{limits.MAX_NESTING} levels)\n"
        assert "Traceback" not in result.output


def test_nesting_is_measured_without_recursion():
    deep: list = []
    for _ in range(100_000):
        deep = [deep]
    assert limits.too_deeply_nested(deep)
    assert not limits.too_deeply_nested({"a": {"b": [[1, 2], [3]]}, "c": 1.0})
    assert limits.too_deeply_nested({"a": {"b": [[1]]}}, limit=3) and not limits.too_deeply_nested({"a": [[1]]}, 3)


def test_a_deck_mapping_or_a_set_value_nested_too_deeply_is_refused():
    from upliftcli.deck.load import build_deck
    from upliftcli.deck.overrides import toml_value

    deep: dict = {}
    for _ in range(2000):
        deep = {"a": deep}
    with pytest.raises(InputError, match="nested too deeply"):
        build_deck(deep, "m.toml")
    text = "[" * 500 + "]" * 500
    assert toml_value(text) == text  # kept as the string: the field check refuses it with one line
