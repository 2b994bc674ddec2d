"""Tests of motion/readers.py, one reader per format (PEER .AT2, plain text, CSV, the headered
files of records/), through read_record, and their bad input named by file and line."""

from __future__ import annotations

import numpy as np
import pytest

from upliftcli.errors import InputError
from upliftcli.motion.readers import detect_format, separated
from upliftcli.motion.records import bundled_records_dir, read_record
from upliftcli.units import STANDARD_GRAVITY

G = STANDARD_GRAVITY
VALUES = np.array([0.0, 0.01, -0.02, 0.03, -0.015, 0.005, 0.0, 0.002, -0.001, 0.0, 0.004])


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def at2_text(values, npts=None, dt="0.0100", per_line=5, units_line="ACCELERATION TIME SERIES IN UNITS OF G"):
    rows = [" ".join(f"{value:15.7E}" for value in values[i:i + per_line]) for i in range(0, len(values), per_line)]
    npts = len(values) if npts is None else npts
    header = ["PEER NGA STRONG MOTION DATABASE RECORD", "Test event 2000-01-01, Station X, 090", units_line,
              f"NPTS=  {npts}, DT=   {dt} SEC"]
    return "\n".join(header + rows) + "\n"


def test_bundled_elcentro_in_shared_format():
    path = bundled_records_dir() / "elcentro_1940_ns_chopra.txt"
    assert detect_format(path) == "shared"
    record = read_record(path)
    assert (record.npts, record.dt, record.units) == (1560, 0.02, "g")
    assert record.duration == pytest.approx(31.18)
    assert record.pga / G == pytest.approx(0.31882, abs=1e-12)
    assert record.time[102] == pytest.approx(2.04)
    assert abs(record.acceleration[102]) == pytest.approx(record.pga)
    raw = np.loadtxt(path)
    np.testing.assert_array_equal(record.acceleration, raw[:, 1] * G)


def test_at2_reader(tmp_path):
    path = write(tmp_path, "small.AT2", at2_text(VALUES))
    assert detect_format(path) == "at2"
    record = read_record(path)
    assert record.dt == 0.01 and record.npts == VALUES.size and record.units == "g"
    np.testing.assert_allclose(record.acceleration, VALUES * G, rtol=1e-7, atol=1e-12)
    assert record.name.startswith("Test event")
    # the old header layout "npts dt NPTS, DT" and a .txt extension with format given
    old = at2_text(VALUES).replace(f"NPTS=  {VALUES.size}, DT=   0.0100 SEC", f"{VALUES.size}   0.0100   NPTS, DT")
    record = read_record(write(tmp_path, "old.txt", old), format="at2")
    assert record.dt == 0.01 and record.npts == VALUES.size


def test_at2_npts_mismatch_and_bad_dt(tmp_path):
    with pytest.raises(InputError, match=r"bad\.AT2: line 4: NPTS = 12 .* found 11"):
        read_record(write(tmp_path, "bad.AT2", at2_text(VALUES, npts=12)))
    with pytest.raises(InputError, match=r"line 4: a time step dt: a number > 0 and at most 10 \[s\]"):
        read_record(write(tmp_path, "zero.AT2", at2_text(VALUES, dt="0.0")))
    with pytest.raises(InputError, match=r"line 4"):
        read_record(write(tmp_path, "noheader.AT2", at2_text(VALUES).replace("NPTS=", "N=").replace("DT=", "T=")))


def test_text_single_and_multi_column(tmp_path):
    single = "# test record\n# dt = 0.005 s\n# units: cm/s2\n" + "\n".join(str(v) for v in VALUES) + "\n"
    record = read_record(write(tmp_path, "single.txt", single))
    assert record.dt == 0.005 and record.units == "cm/s2"
    np.testing.assert_allclose(record.acceleration, VALUES * 0.01)
    multi = "\n".join("  ".join(str(v) for v in VALUES[i:i + 4]) for i in range(0, VALUES.size, 4)) + "\n"
    record = read_record(write(tmp_path, "multi.dat", multi), units="in/s2", dt=0.02)
    np.testing.assert_allclose(record.acceleration, VALUES * 0.0254)
    assert record.npts == VALUES.size and record.dt == 0.02
    with pytest.raises(InputError, match=r"multi\.dat: dt: a time step"):
        read_record(tmp_path / "multi.dat", units="g")
    with pytest.raises(InputError, match=r"multi\.dat: units: acceleration units"):
        read_record(tmp_path / "multi.dat", dt=0.01)


def test_csv_reader_and_units_from_column_name(tmp_path):
    rows = "\n".join(f"{i * 0.01:.2f},{v}" for i, v in enumerate(VALUES))
    record = read_record(write(tmp_path, "rec.csv", "time,acc (g)\n" + rows + "\n"))
    assert record.dt == pytest.approx(0.01) and record.units == "g"
    np.testing.assert_allclose(record.acceleration, VALUES * G)
    record = read_record(write(tmp_path, "rec2.csv", "time_s,accel_m/s2\n" + rows + "\n"))
    assert record.units == "m/s2"
    np.testing.assert_allclose(record.acceleration, VALUES)


@pytest.mark.parametrize("content, line", [
    ("# dt = 0.01\n# units: g\n0.1\n0.2\nnan\n", 5),
    ("# dt = 0.01\n# units: g\n0.1 0.2\n0.3 inf\n", 4),
    ("# dt = 0.01\n# units: g\n0.1\n0.2\n0.3 abc\n", 5),
    ("# dt = 0.01\n# units: g\n# npts = 4\n0.1\n0.2\n0.3\n", 3),
    ("# dt = -0.01\n# units: g\n0.1\n0.2\n", 1),
])
def test_bad_text_names_the_line(tmp_path, content, line):
    path = write(tmp_path, "bad.txt", content)
    with pytest.raises(InputError, match=rf"bad\.txt: line {line}: "):
        read_record(path)


def test_bad_csv_time_column(tmp_path):
    path = write(tmp_path, "nonuniform.csv", "t,a\n0.0,0.1\n0.01,0.2\n0.025,0.3\n0.03,0.1\n")
    with pytest.raises(InputError, match=r"nonuniform\.csv: line 4: a uniform time step"):
        read_record(path, units="g")
    path = write(tmp_path, "backwards.csv", "0.03,0.1\n0.02,0.2\n0.01,0.3\n")
    with pytest.raises(InputError, match=r"backwards\.csv: line 2: increasing times"):
        read_record(path, units="g")


def test_csv_times_rounded_in_print_are_accepted(tmp_path):
    rows = "\n".join(f"{i / 300:.4f},{v}" for i, v in enumerate(VALUES))  # steps 0.0033 / 0.0034
    record = read_record(write(tmp_path, "rounded.csv", rows + "\n"), units="g")
    assert record.dt == pytest.approx(1 / 300, rel=1e-3)


def test_at2_units_from_header_other_than_g(tmp_path):
    path = write(tmp_path, "cm.AT2", at2_text(VALUES, units_line="ACCELERATION TIME SERIES IN UNITS OF CM/SEC/SEC"))
    record = read_record(path)
    assert record.units == "cm/s2"
    np.testing.assert_allclose(record.acceleration, VALUES * 0.01, rtol=1e-7, atol=1e-14)


# ----------------------------------------------------------------------------- nonsense refused (issue 13)


def test_a_byte_order_mark_is_accepted_in_text_and_csv_records(tmp_path):
    text = write(tmp_path, "bom.txt", "\ufeff# dt = 0.01\n# units: g\n0.1\n-0.2\n0.3\n")
    record = read_record(text)
    np.testing.assert_allclose(record.acceleration, np.array([0.1, -0.2, 0.3]) * G)
    csv = write(tmp_path, "bom.csv", "\ufefftime,acc\n0,0.1\n0.01,0.2\n")
    assert read_record(csv, units="g").npts == 2


def test_a_decimal_comma_is_refused_not_split_in_two(tmp_path):
    path = write(tmp_path, "comma.txt", "# dt = 0.01\n# units: g\n0,05\n0,07\n")
    with pytest.raises(InputError, match=r"comma.txt: line 3: numbers with a decimal point, got '0,05'"):
        read_record(path)
    # commas between numbers with decimal points still separate values
    assert read_record(write(tmp_path, "list.txt", "# dt = 0.01\n# units: g\n0.05,0.07, 0.1\n")).npts == 3


def test_devices_directories_and_binary_files_are_refused_quickly(tmp_path):
    with pytest.raises(InputError, match=r"^/dev/zero: a regular record file \(this is a device\)"):
        read_record("/dev/zero", units="g", dt=0.01)  # refused before it is read: it never ends
    with pytest.raises(InputError, match="this is a directory"):
        read_record(tmp_path, units="g", dt=0.01)
    binary = tmp_path / "b.txt"
    binary.write_bytes(b"0.1\n\x00\x00\n")
    with pytest.raises(InputError, match="NUL bytes found"):
        read_record(binary, units="g", dt=0.01)


def test_sample_limit(tmp_path, monkeypatch):
    from upliftcli.motion import readers

    monkeypatch.setattr(readers, "MAX_RECORD_SAMPLES", 5)
    assert read_record(write(tmp_path, "five.txt", "# dt = 0.01\n# units: g\n1 2 3 4 5\n")).npts == 5
    with pytest.raises(InputError, match=r"six.txt: line 3: at most 5 samples"):
        read_record(write(tmp_path, "six.txt", "# dt = 0.01\n# units: g\n1 2 3 4 5 6\n"))
    with pytest.raises(InputError, match=r"six.csv: line 7: at most 5 samples"):
        read_record(write(tmp_path, "six.csv", "t,a\n" + "".join(f"{0.01 * i},{i}\n" for i in range(6))), units="g")


@pytest.mark.parametrize(("name", "line", "what"), [
    ("RSN1_VEL.VT2", "VELOCITY TIME SERIES IN UNITS OF CM/S", "velocity"),
    ("RSN1_DIS.DT2", "DISPLACEMENT TIME SERIES IN UNITS OF CM", "displacement"),
    ("renamed.AT2", "VELOCITY TIME SERIES IN UNITS OF CM/S", "velocity"),
    ("RSN1_VEL.VT2", "ACCELERATION TIME SERIES IN UNITS OF G", "velocity"),  # the extension says so
])
def test_peer_velocity_and_displacement_files_are_named_for_what_they_are(tmp_path, name, line, what):
    path = write(tmp_path, name, at2_text(VALUES, units_line=line))
    assert detect_format(path) == "at2"
    with pytest.raises(InputError) as info:
        read_record(path)
    message = str(info.value)
    assert message.startswith(f"{path}: line 3: an acceleration history (PEER .AT2); this is a {what} history")
    assert "\n" not in message


def test_fixed_width_values_that_touch_are_two_values(tmp_path):
    rows = ["1.71300E-02-3.43000E-03 2.00000E-02", "-1.00000E-02-2.50000D-03+4.00000E-04", "0.5-0.25"]
    expected = [1.713e-2, -3.43e-3, 2e-2, -1e-2, -2.5e-3, 4e-4, 0.5, -0.25]
    header = ["PEER NGA STRONG MOTION DATABASE RECORD", "event", "ACCELERATION TIME SERIES IN UNITS OF G",
              f"NPTS=  {len(expected)}, DT=   0.0100 SEC"]
    record = read_record(write(tmp_path, "touch.AT2", "\n".join(header + rows) + "\n"))
    np.testing.assert_array_equal(record.acceleration, np.array(expected) * G)
    text = read_record(write(tmp_path, "touch.txt", "# dt = 0.01\n# units: g\n" + "\n".join(rows) + "\n"))
    np.testing.assert_array_equal(text.acceleration, record.acceleration)
    assert separated("1.0E-05 2.0D+03") == "1.0E-05 2.0D+03"  # exponents are not split


def test_values_are_plain_numbers_not_python_literals(tmp_path):
    """A record value 1_000 was read as 1000 (Python's float accepts digit separators)."""
    with pytest.raises(InputError, match=r"line 4: a number, got '1_000'$"):
        read_record(write(tmp_path, "r.txt", "# dt = 0.01\n# units: g\n0.1\n1_000\n0.2\n"))


def test_a_header_time_step_below_the_magnitude_limit_is_refused(tmp_path):
    with pytest.raises(InputError, match=r"r\.txt: line 1: a time step dt: a number > 0 and at most 10 of magnitude "
                                         r"1e-30 to 1e\+30 \[s\], got 1e-300$"):
        read_record(write(tmp_path, "r.txt", "# dt = 1e-300\n# units: g\n0.1\n0.2\n0.3\n"))


def test_a_fifo_is_refused_before_it_is_opened(tmp_path):
    """A FIFO as a record blocked the reader for ever (open() waits for a writer): it is refused
    from os.stat, whatever the format, and detect_format does not open it either."""
    import os

    fifo = tmp_path / "fifo.txt"
    os.mkfifo(fifo)
    with pytest.raises(InputError, match=r"fifo.txt: a regular record file \(this is a FIFO\)"):
        read_record(fifo, units="g", dt=0.01)
    with pytest.raises(InputError, match="this is a FIFO"):
        read_record(fifo, format="text", units="g", dt=0.01)
    assert detect_format(fifo) == "text"


def test_the_checksum_is_that_of_the_bytes_parsed(tmp_path):
    """read_record reads the file once: its sha256 is of the bytes its values came from."""
    import hashlib

    path = write(tmp_path, "r.txt", "# dt = 0.01\n# units: g\n0.1\n-0.2\n")
    record = read_record(path)
    assert record.sha256 == hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.parametrize("header, units", [("time_s,acc_m_s2", "m/s2"), ("time_s,accel_g", "g"),
                                           ("t_s,acc_cm_s2", "cm/s2"), ("time,acceleration_in_s2", "in/s2"),
                                           ("time (s),acceleration (m/s^2)", "m/s2")])
def test_a_csv_record_headed_in_the_csv_style_of_the_tool(tmp_path, header, units):
    path = tmp_path / "a.csv"
    path.write_text(f"{header}\n0,0\n0.01,0.5\n0.02,-1\n0.03,0.25\n")
    record = read_record(path)
    assert record.units == units and record.dt == pytest.approx(0.01)
    factor = {"m/s2": 1.0, "g": STANDARD_GRAVITY, "cm/s2": 0.01, "in/s2": 0.0254}[units]
    np.testing.assert_allclose(record.acceleration, factor * np.array([0, 0.5, -1, 0.25]))


SYSTEM_LIKE = "root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1::/usr/sbin:/usr/sbin/nologin\n_apt:x:42:65534::/x:/no\n"


@pytest.mark.parametrize(("name", "options", "location"), [
    ("passwd", {"units": "g", "dt": 0.01}, "line 3"),  # text: the header is the lines of words, then '_apt...'
    ("passwd", {"units": "g", "format": "csv"}, "line 2"),  # a second row of names
    ("accounts.csv", {"units": "g"}, "line 1"),  # a first row that starts with a digit
    ("list.txt", {"units": "g", "dt": 0.01}, "line 1"),
])
def test_a_file_that_is_no_record_is_never_quoted(tmp_path, name, options, location):
    """Issue 38, I1: `--record /etc/passwd` quoted the line it could not read. Until the file
    reads as a record (a value read, or a record header), the message names the line only."""
    text = {"accounts.csv": "1secret,token_abc\n", "list.txt": "4,5,secret_token\n"}.get(name, SYSTEM_LIKE)
    path = write(tmp_path, name, text)
    with pytest.raises(InputError) as info:
        read_record(path, **options)
    message = str(info.value)
    assert message.startswith(f"{path}: {location}: ") and "\n" not in message
    said = message[len(str(path)):]
    assert not any(word in said for word in ("x:42", "_apt", "secret", "token", "root")), said


def test_a_record_quotes_a_short_printable_excerpt_of_a_bad_value(tmp_path):
    """In a file read as a record (values read before), the bad value is quoted: at most 24
    characters, any character that is not printable ASCII as '?' (no terminal escape)."""
    bad = "\x1b[2J" + "A" * 100
    path = write(tmp_path, "r.txt", f"0.1\n0.2\n{bad}\n")
    with pytest.raises(InputError) as info:
        read_record(path, units="g", dt=0.01)
    assert str(info.value) == f"{path}: line 3: a number, got '?[2J{'A' * 20}...'"
    headed = write(tmp_path, "h.txt", f"# dt = 0.01\n{bad}\n")  # a record header: recognised at once
    with pytest.raises(InputError, match=r"h\.txt: line 2: a number, got '\?\[2JA+\.\.\.'$"):
        read_record(headed, units="g")
    csv = write(tmp_path, "c.csv", "time,acc\n0,0.1\n0.01,\u00e9t\u00e9\n")
    with pytest.raises(InputError, match=r"c\.csv: line 3: a number, got '\?t\?'$"):
        read_record(csv, units="g")


@pytest.mark.parametrize(("text", "line"), [("time,acc\nt,a\n0,0.1\n0.01,0.2\n", 2),
                                           ("# a comment\ntime,acc\n\n\"t\",\"a\"\n0,0.1\n", 4)])
def test_a_csv_record_with_two_header_rows_is_refused(tmp_path, text, line):
    """Issue 38: a CSV record with two rows of names was read silently (the second taken as a header too)."""
    path = write(tmp_path, "two.csv", text)
    with pytest.raises(InputError, match=rf"^{path}: line {line}: one row of column names before the data, found a "
                                         r"second one \(a comment starts with '#'\)$"):
        read_record(path, units="g")
    assert read_record(write(tmp_path, "one.csv", "# t, a\ntime,acc\n0,0.1\n0.01,0.2\n"), units="g").npts == 2
