"""`uplift record info` / `uplift record spectrum` end to end through typer's test runner."""

from __future__ import annotations

import csv
import hashlib
from pathlib import Path

import numpy as np
import pytest
import typer
from cli_helpers import invoke, runner

from upliftcli.cli import record as record_cli
from upliftcli.motion.records import read_record
from upliftcli.motion.spectra import response_spectrum
from upliftcli.provenance.record import read_csv_provenance
from upliftcli.units import STANDARD_GRAVITY

RECORD = Path(__file__).resolve().parent.parent / "records" / "elcentro_1940_ns_chopra.txt"



def test_info_prints_the_measures():
    result = invoke("record", "info", RECORD)
    assert result.exit_code == 0, result.output
    text = result.stdout
    for expected in ("dt               0.02 s", "points           1560", "duration         31.18 s",
                     "PGA              0.3188 g = 3.1266 m/s^2", "PGV              360.8 mm/s",
                     "PGD              211.89 mm", "no baseline correction", "Arias intensity  1.724 m/s",
                     "S_a [g] 5 %", "S_d [mm] 5 %", "0.9187", "57.05"):  # 5 %: S_a, S_d at 0.5 s
        assert expected in text, text


def test_info_in_us_display_units_is_the_same_record():
    """--units us (as every command): the values of the SI run in in, in/s, in/s^2 and ft/s
    (1 in = 25.4 mm exactly), g unchanged; S_d of the spectrum table in in."""
    result = invoke("record", "info", RECORD, "--units", "us")
    assert result.exit_code == 0 and result.stderr == "", result.output
    text = result.stdout
    a = read_record(RECORD).acceleration  # Arias: pi/(2 g) times the integral of the piecewise-linear a^2
    arias = np.pi / (2 * STANDARD_GRAVITY) * np.sum(0.02 / 3 * (a[:-1] ** 2 + a[:-1] * a[1:] + a[1:] ** 2))
    assert f"Arias intensity  {arias:.4g} m/s" in invoke("record", "info", RECORD).stdout
    for expected in ("PGA              0.3188 g = 123.09 in/s^2",  # 3.1266 m/s^2 / 0.0254
                     f"PGV              {360.8 / 25.4:.2f} in/s", f"PGD              {211.89 / 25.4:.3f} in",
                     f"Arias intensity  {arias / 0.3048:.4g} ft/s", "S_a [g] 5 %", "S_d [in] 5 %", "0.9187",
                     f"{57.05 / 25.4:.3f}"):
        assert expected in text, text
    refused = invoke("record", "info", RECORD, "--units", "imperial")
    assert refused.exit_code == 2
    assert refused.stderr == ("error: --units: imperial: si or us (display units; the record file's acceleration "
                              "units are --record-units)\n")


def test_spectrum_csv_and_plot(tmp_path):
    out, plot = tmp_path / "sa.csv", tmp_path / "sa.png"
    result = invoke("record", "spectrum", RECORD, "--damping", "0.02,5%", "--periods", "0.05:5:100",
                    "--out", out, "--plot", plot)
    assert result.exit_code == 0, result.output
    text = out.read_text()
    rows = list(csv.DictReader(line for line in text.splitlines() if not line.startswith("#")))
    assert len(rows) == 200
    provenance = read_csv_provenance(text)
    assert provenance["files"][0]["sha256"] == hashlib.sha256(RECORD.read_bytes()).hexdigest()
    assert provenance["files"][0]["format"] == "shared" and provenance["settings"]["dampings"] == [0.02, 0.05]
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    record = read_record(RECORD)
    expected = response_spectrum(record.acceleration, record.dt, np.geomspace(0.05, 5, 100), [0.02, 0.05])
    psa = np.array([float(row["psa_g"]) for row in rows]).reshape(2, 100)
    np.testing.assert_allclose(psa, expected.pseudo_acceleration / STANDARD_GRAVITY, rtol=1e-7)
    assert {row["damping_ratio"] for row in rows} == {"0.02", "0.05"}


def test_spectrum_to_stdout_with_period_list():
    result = invoke("record", "spectrum", RECORD, "--periods", "0.5,1,2")
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader(line for line in result.stdout.splitlines() if not line.startswith("#")))
    np.testing.assert_allclose([float(r["psa_g"]) for r in rows], [0.916, 0.454, 0.137], rtol=0.01)


@pytest.mark.parametrize("content, name, message", [
    ("# dt = 0.01\n# units: g\n0.1\nnan\n", "nan.txt", "nan.txt: line 4: a finite number"),
    ("# dt = 0.01\n# units: g\n0.1\n0.2 x\n", "text.txt", "text.txt: line 4: a number"),
    ("t,a\n0,0.1\n0.01,0.2\n0.03,0.1\n", "step.csv", "step.csv: line 4: a uniform time step"),
    ("", "empty.txt", "empty.txt: acceleration values (the file is empty)"),
    ("# dt = 0\n# units: g\n0.1\n0.2\n", "zero.txt",
     "zero.txt: line 1: a time step dt: a number > 0 and at most 10 [s]"),
    ("# dt = 0.01\n# units: furlongs\n0.1\n0.2\n", "unit.txt", "unit.txt: units: acceleration units"),
    ("PEER NGA STRONG MOTION DATABASE RECORD\nx\nACCELERATION IN UNITS OF G\nNPTS=   3, DT=   .0100 SEC\n"
     "0.1 0.2\n", "short.AT2", "short.AT2: line 4: NPTS = 3"),
])
def test_bad_input_one_line_exit_2(tmp_path, content, name, message):
    path = tmp_path / name
    path.write_text(content)
    for command in ("info", "spectrum"):
        result = invoke("record", command, path)
        assert result.exit_code == 2, (command, result.output)
        assert result.stdout == ""
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1 and message in lines[0], result.stderr


def test_bad_options_exit_2_without_output_files(tmp_path):
    out = tmp_path / "x.csv"
    for args, message in ((["--periods", "5:0.05:100"], "--periods"), (["--damping", "1.5"], "--damping"),
                          (["--plot", tmp_path / "x.bmp"], "--plot"), (["--window", "3"], "--window")):
        result = invoke("record", "spectrum", RECORD, "--out", out, *args)
        assert result.exit_code == 2 and message in result.stderr, result.output
        assert not out.exists()


def test_register_on_a_fresh_app():
    fresh = typer.Typer()
    record_cli.register(fresh)
    result = runner.invoke(fresh, ["record", "spectrum", str(RECORD), "--periods", "1"])
    assert result.exit_code == 0 and "damping_ratio,period_s" in result.stdout


@pytest.fixture()
def spectrum_work(monkeypatch):
    """The response spectra the commands compute and the period arrays they make (geomspace), as
    counted calls: a refused input must cost neither (no clock: a count of the work guarded)."""
    from upliftcli.motion import spectra

    calls = {"spectra": 0, "periods": 0}
    compute, geomspace = spectra.response_spectrum, np.geomspace

    def counted(name, function):
        def call(*args, **kwargs):
            calls[name] += 1
            return function(*args, **kwargs)
        return call

    monkeypatch.setattr(spectra, "response_spectrum", counted("spectra", compute))
    monkeypatch.setattr(np, "geomspace", counted("periods", geomspace))
    return calls


def test_the_work_counter_sees_a_spectrum(spectrum_work):
    result = invoke("record", "spectrum", RECORD, "--periods", "0.1:1:3")
    assert result.exit_code == 0 and spectrum_work == {"spectra": 1, "periods": 1}


def test_periods_shorter_than_the_record_resolves_are_refused_at_once(spectrum_work):
    """It ran for minutes (time grows as 1/T): refused before any oscillator is integrated."""
    result = invoke("record", "spectrum", RECORD, "--periods", "1e-8")
    assert spectrum_work["spectra"] == 0
    assert result.exit_code == 2
    assert result.stderr.strip() == ("error: --periods: 1e-8: periods of at least 8e-06 s or 0 (limit for the "
                                     "record's dt = 0.02 s and 1,560 samples: T >= dt/2,500), got 1e-08 s")


def test_spectrum_work_is_limited_before_anything_is_allocated(spectrum_work):
    """--periods 0.1:5:10000000 ran for 299 s; the periods are counted before the array is made,
    and the oscillator sub-steps of all periods and dampings are bounded (limits.MAX_SPECTRUM_WORK):
    no period array made for the count refused, no spectrum computed for any of them."""
    result = invoke("record", "spectrum", RECORD, "--periods", "0.1:5:10000000")
    assert spectrum_work["periods"] == 0
    assert result.stderr.strip() == "error: --periods: 0.1:5:10000000: at most 10,000 periods (limit of the tool), " \
                                    "got 10,000,000"
    result = invoke("record", "spectrum", RECORD, "--periods", ",".join(["1"] * 10_001))
    assert result.exit_code == 2 and "at most 10,000 periods" in result.stderr
    result = invoke("record", "spectrum", RECORD, "--periods", "0.0001:5:1000")
    assert result.exit_code == 2 and "at most 100,000,000 oscillator sub-steps" in result.stderr
    result = invoke("record", "info", RECORD, "--damping", ",".join(["0.05"] * 8000))
    assert result.exit_code == 2 and result.stderr.startswith("error: --damping: ") and "sub-steps" in result.stderr
    assert spectrum_work["spectra"] == 0


def test_spectrum_out_never_replaces_the_record(tmp_path):
    record = tmp_path / "rec.txt"
    record.write_bytes(RECORD.read_bytes())
    result = invoke("record", "spectrum", record, "--out", tmp_path / "." / "rec.txt")
    assert result.exit_code == 2 and "--out/--plot" in result.stderr and "does not replace an input" in result.stderr
    assert record.read_bytes() == RECORD.read_bytes()


def test_info_of_a_one_sample_record_is_one_line(tmp_path):
    path = tmp_path / "one.txt"
    path.write_text("# dt = 0.01\n# units: g\n0.05\n")
    result = invoke("record", "info", path)
    assert result.exit_code == 2
    assert result.stderr.strip() == f"error: {path}: at least two acceleration samples, found 1"


def test_units_contradicting_the_header_need_the_override_option():
    refused = invoke("record", "info", RECORD, "--record-units", "gal")
    assert refused.exit_code == 2 and refused.stderr.count("\n") == 1
    assert "declares, g, got 'gal'" in refused.stderr and "--override-header-units" in refused.stderr
    meant = invoke("record", "info", RECORD, "--record-units", "gal", "--override-header-units")
    assert meant.exit_code == 0 and "units cm/s2" in meant.stdout
    bad = invoke("record", "info", RECORD, "--record-units", "furlongs")
    assert bad.exit_code == 2 and bad.stderr.startswith("error: --record-units: furlongs: acceleration units g, ")


def test_the_old_units_spelling_of_the_file_units_still_works_with_a_warning(monkeypatch):
    """--units named the record file's units; it is the display units now (si, us), as in every
    command. The two sets of values do not overlap: an acceleration unit is still read as
    --record-units, with one warning line naming it, and gives the same output (the clock of the
    provenance lines held, so that a second boundary between the two runs changes nothing)."""
    monkeypatch.setattr("upliftcli.provenance.record.utc_now", lambda now=None: "2026-01-02T03:04:05Z")
    for command in (["record", "info", RECORD], ["record", "spectrum", RECORD, "--periods", "0.5,1"]):
        new = invoke(*command, "--record-units", "gal", "--override-header-units")
        old = invoke(*command, "--units", "gal", "--override-header-units")
        assert new.exit_code == old.exit_code == 0 and old.stdout == new.stdout
        assert new.stderr == ""
        assert old.stderr == ("warning: --units gal: the record file's units are --record-units now (--units is the "
                              "display units, si or us, as in the other commands); read as --record-units gal\n")
    both = invoke("record", "info", RECORD, "--units", "g", "--record-units", "g")
    assert both.exit_code == 2 and both.stderr.startswith("error: --units: g: si or us with --record-units g")


def test_spectrum_out_and_plot_replace_a_file_only_with_overwrite(tmp_path):
    out, plot = tmp_path / "s.csv", tmp_path / "s.png"
    out.write_text("mine")
    result = invoke("record", "spectrum", RECORD, "--periods", "0.5,1", "--out", out)
    assert result.exit_code == 2 and out.read_text() == "mine"
    assert result.stderr == f"error: --out: {out}: a new file (it exists; pass --overwrite to replace it)\n"
    plot.write_text("mine")
    result = invoke("record", "spectrum", RECORD, "--periods", "0.5,1", "--plot", plot)
    assert result.exit_code == 2 and plot.read_text() == "mine" and result.stderr.startswith("error: --plot: ")
    assert invoke("record", "spectrum", RECORD, "--periods", "0.5,1", "--out", out, "--overwrite").exit_code == 0
    assert out.read_text().count("\n") == 5  # two '#' lines, the header and two rows


def test_the_record_file_format_is_input_format_and_the_old_spelling_is_refused(tmp_path):
    """--format is the output format everywhere; under `record` the file's format is --input-format,
    and --format is refused in one line naming the new option (never read as something else)."""
    good = invoke("record", "info", RECORD, "--input-format", "shared")
    assert good.exit_code == 0 and "units g" in good.stdout
    for command in (["record", "info", RECORD], ["record", "spectrum", RECORD]):
        result = invoke(*command, "--format", "text")
        assert result.exit_code == 2
        (line,) = result.stderr.strip().splitlines()
        assert line.startswith("error: --format:") and "--input-format text" in line
    assert "--input-format" in invoke("record", "scale", "--help").stdout


def test_every_csv_file_names_its_columns_quantity_unit(tmp_path):
    """The spectrum CSV as the results' and the sweeps' (shear_N, floor_acceleration_m_s2)."""
    text = invoke("record", "spectrum", RECORD, "--periods", "0.5,1").stdout
    header = next(line for line in text.splitlines() if not line.startswith("#"))
    assert header == "damping_ratio,period_s,sd_m,psv_m_s,psa_m_s2,psa_g,abs_acc_m_s2"


@pytest.mark.parametrize(("options", "line"), [
    (["--dt", "0"], "--dt: {r}: a time step dt: a number > 0 and at most 10 [s], got 0.0"),
    (["--dt", "0.01"], "--dt: {r}: dt = 0.02 s as in the file, got 0.01 s"),
    (["--window", "5:2"], "--window: {r}: 0 <= start < end [s], got (5, 2)"),
    (["--window", "100:200"], "--window: {r}: a start time within the record (0 to 31.18 s), got 100"),
    (["--input-format", "xx"], "--input-format: {r}: one of at2, text, csv, shared, got 'xx'"),
])
def test_an_option_that_does_not_suit_the_record_names_the_option(options, line):
    """A value of --dt, --scale, --window or --input-format that does not suit the record is the
    option's mistake, named with the file (it named the file alone: `{file}: dt: ...`)."""
    for command in ("info", "spectrum"):
        result = invoke("record", command, RECORD, *options)
        assert result.exit_code == 2 and result.stdout == ""
        assert result.stderr == f"error: {line.format(r=RECORD)}\n"


@pytest.mark.parametrize(("value", "line"), [
    ("-1", "--scale: a number > 0, got -1.0"),
    ("0", "--scale: a number > 0, got 0.0"),
    ("nan", "--scale: a number > 0, got nan"),
    ("1e300", "--scale: a number > 0 of magnitude 1e-30 to 1e+30, got 1e+300"),
])
def test_a_scale_is_refused_by_the_rule_of_the_decks_ground_motion_scale(value, line):
    """Fuzzing found `--scale -1` accepted where a deck refuses ground_motion.scale <= 0: the
    option is checked by that field (records.RECORD_FIELDS), on info and spectrum alike."""
    deck = invoke("analyze", RECORD.parents[1] / "inputs" / "ten_story_elcentro.toml",
                  "--set", "ground_motion.scale=-1")
    assert deck.exit_code == 2 and deck.stderr == "error: --set: ground_motion.scale: a number > 0, got -1\n"
    for command in ("info", "spectrum"):
        result = invoke("record", command, RECORD, "--scale", value)
        assert result.exit_code == 2 and result.stdout == ""
        assert result.stderr == f"error: {line}\n"


@pytest.mark.parametrize("value", ["5%,", ",", "5%,,2%"])
def test_a_damping_list_with_an_empty_item_is_refused(value):
    """Fuzzing found `--damping 5%,` accepted (the empty item dropped): one line naming the option."""
    for command in ("info", "spectrum"):
        result = invoke("record", command, RECORD, "--damping", value)
        assert result.exit_code == 2 and result.stdout == ""
        assert result.stderr == (f"error: --damping: {value}: damping ratios separated by single commas, e.g. "
                                 "0.02,0.05 (or 2%,5%), without an empty item\n")
    blank = invoke("record", "spectrum", RECORD, "--damping", " ")
    assert blank.exit_code == 2 and blank.stderr == "error: --damping:  : at least one damping ratio, e.g. 0.05\n"


def test_record_units_that_contradict_the_header_name_the_option():
    """--record-units (or the old --units g spelling) that contradict the header: the option is named."""
    result = invoke("record", "info", RECORD, "--record-units", "m/s2")
    assert result.exit_code == 2
    assert result.stderr.startswith(f"error: --record-units: {RECORD}: the units that the header of ")
    old = invoke("record", "info", RECORD, "--units", "m/s2")
    assert old.exit_code == 2 and old.stderr.splitlines()[1].startswith(f"error: --record-units: {RECORD}: ")


def test_a_record_without_dt_still_names_the_file(tmp_path):
    """Without --dt the missing time step is the file's (no option was given)."""
    path = tmp_path / "plain.txt"
    path.write_text("0.1\n0.2\n-0.1\n")
    result = invoke("record", "info", path)
    assert result.exit_code == 2
    assert result.stderr == f"error: {path}: dt: a time step dt [s] (give dt, or a 'dt = ...' header line)\n"


@pytest.mark.parametrize("value", ["0.5,,1", "0.5,1,", ",0.5"])
def test_a_period_list_with_an_empty_item_is_refused(value):
    """`record spectrum --periods "0.5,,1,"` was accepted, its empty items dropped (as --damping
    was): one line naming the option."""
    result = invoke("record", "spectrum", RECORD, "--periods", value)
    assert result.exit_code == 2 and result.stdout == ""
    assert result.stderr == (f"error: --periods: {value}: START:STOP:N with 0 < START < STOP and N >= 2 "
                             "(log-spaced, s) or a comma list of periods >= 0 s without an empty item\n")
