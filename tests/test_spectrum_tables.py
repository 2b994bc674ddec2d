"""spectrum_tables: the checks every design spectrum shares (a number > 0, a damping ratio) and
the spectrum table files (two columns of plain numbers, an optional header row)."""

import pytest

from upliftcli.errors import InputError
from upliftcli.motion.design_spectra import ASCE7Spectrum, from_mapping
from upliftcli.motion.spectrum_tables import TabulatedSpectrum, check_damping, positive, read_spectrum_table

G = 9.80665


def test_spectra_built_in_code_refuse_booleans_and_texts():
    with pytest.raises(InputError, match="sds: a number > 0 of magnitude"):
        ASCE7Spectrum(True, 0.6, 8.0)
    with pytest.raises(InputError, match="damping: a damping ratio between 0 and 1"):
        TabulatedSpectrum([0.0, 1.0], [1.0, 1.0], "5%")
    assert positive(0.4, "s", "sds", "g") == 0.4 and check_damping(0.05, "s") == 0.05
    with pytest.raises(InputError, match="a number > 0 of magnitude 1e-30 to 1e"):
        positive(1e300, "s", "sds", "g")


def test_a_spectrum_table_file_holds_plain_numbers(tmp_path):
    deck = str(tmp_path / "deck.toml")
    (tmp_path / "t.csv").write_text("period_s,sa_g\n0,0.4\n1,1_000\n")
    with pytest.raises(InputError, match=r"t\.csv: line 3: two numbers \(period \[s\], S_a\), got '1,1_000'$"):
        from_mapping({"type": "table", "file": "t.csv", "damping": 0.05}, deck)
    (tmp_path / "u.csv").write_text("period_s,sa_g\n0,0.4\n1,0.5\n")
    assert from_mapping({"type": "table", "file": "u.csv", "damping": 0.05}, deck).sa_values[1] == 0.5 * G


def test_a_header_row_is_names_and_a_row_of_numbers_is_data(tmp_path):
    (tmp_path / "t.csv").write_text("# a comment\nT [s], Sa [g]\n0 0.4\n1, 0.5 # a comment\n")
    periods, sa = read_spectrum_table(tmp_path / "t.csv", "deck.toml")
    assert periods.tolist() == [0.0, 1.0] and sa.tolist() == [0.4, 0.5]


def test_a_spectrum_table_with_two_header_rows_is_refused(tmp_path):
    """Issue 38: a second header row was read silently; its rows are quoted only once data was read."""
    (tmp_path / "t.csv").write_text("# comment\nT [s], Sa [g]\nperiod, sa\n0 0.4\n1 0.5\n")
    with pytest.raises(InputError, match=r"t\.csv: line 3: one header row of names before the \(period \[s\], S_a\) "
                                         r"rows, found a second one \(a comment starts with '#'\)$"):
        read_spectrum_table(tmp_path / "t.csv", "deck.toml")
    (tmp_path / "s.csv").write_text("T, Sa\n1 x_secret\n")
    with pytest.raises(InputError, match=r"s\.csv: line 2: two numbers \(period \[s\], S_a\) \(the text is not "
                                         r"quoted: nothing before it read as a spectrum table\)$"):
        read_spectrum_table(tmp_path / "s.csv", "deck.toml")
