"""`uplift sweep`, `uplift spectra` and `uplift analyze` with several decks, end to end."""

import csv
import io
import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from cli_helpers import invoke

from upliftcli.analysis.run import run_one
from upliftcli.deck.load import load_deck
from upliftcli.provenance.record import rounded
from upliftcli.sweep.store import RowStore

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"
PNG = b"\x89PNG\r\n\x1a\n"




def table_text(path) -> str:
    """A CSV table without its two '#' provenance lines (which hold the time and the command)."""
    lines = Path(path).read_text().splitlines(keepends=True)
    assert lines[0].startswith("# uplift ") and lines[1].startswith("# provenance: {")
    return "".join(lines[2:])


def read_csv(path):
    return list(csv.DictReader(io.StringIO(table_text(path))))


def test_sweep_writes_the_tidy_table_and_prints_the_envelope(tmp_path):
    result = invoke("sweep", EXAMPLE, "--vary", "foundation.k_f=1e8:1e10:3:log", "--vary", "building.period=0.5,1.5",
                    "--support", "bonded,uplift", "--out", tmp_path, "--workers", "1")
    assert result.exit_code == 0, result.output
    for words in ("Varied fields", "Governing cases", "Envelope over foundation.k_f", "ASCE 7-22", "V/W lo"):
        assert words in result.stdout
    assert "sweep: 12 cases to run" in result.stderr and "12/12 cases" in result.stderr  # plain progress (CI)
    rows = read_csv(tmp_path / "ten_story_elcentro.period-k_f.sweep.csv")
    assert len(rows) == 12
    header = list(rows[0])
    assert header[:5] == ["case", "engine", "support", "foundation.k_f", "building.period"]
    assert header.index("base_shear_N") < header.index("status")
    assert {r["status"] for r in rows} == {"ok"}
    doc = json.loads((tmp_path / "ten_story_elcentro.period-k_f.sweep.json").read_text())
    assert doc["units"]["foundation.k_f"] == "N/m" and doc["units"]["base_moment_Nm"] == "N m"
    assert [r["base_shear_N"] for r in doc["rows"]] == [float(r["base_shear_N"]) for r in rows]
    lines = (tmp_path / "ten_story_elcentro.period-k_f.sweep.rows.jsonl").read_text().splitlines()
    assert len(lines) == 13 and "run" in json.loads(lines[0])  # a header line, then one line per case
    # a row equals the single analysis with the same --set values
    row = rows[7]
    deck = load_deck(EXAMPLE, [f"foundation.k_f={row['foundation.k_f']}", f"building.period={row['building.period']}"])
    single = run_one(deck, row["engine"], row["support"])
    assert float(row["base_moment_Nm"]) == rounded(single.base_moment)  # 15 significant digits
    assert (row["uplift"] == "true") is single.uplift


def test_sweep_summary_in_the_display_units(tmp_path):
    """--units us: the varied fields in kip/in, ft ...; drift ratios in % (as the story tables);
    the files' output columns in US units too (tests/test_units_files.py), the ratios unchanged."""
    result = invoke("sweep", EXAMPLE, "--vary", "foundation.k_f=1e8,1e9", "--vary", "foundation.b=2,3",
                    "--support", "uplift", "--out", tmp_path, "--workers", "1", "--units", "us",
                    env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    text = result.stdout
    assert "foundation.k_f [kip/in]" in text and "foundation.b [ft]" in text and "drift ratio [%]" in text
    bar = r"\s*[│|]\s*"
    assert re.search(rf"foundation\.k_f{bar}kip/in{bar}2{bar}list{bar}571\.01{bar}5710\.1", text)  # 1e8, 1e9 N/m
    assert re.search(rf"foundation\.b{bar}ft{bar}2{bar}list{bar}6\.5617{bar}9\.8425", text)  # 2, 3 m
    rows = json.loads((tmp_path / "ten_story_elcentro.b-k_f.sweep.json").read_text())["rows"]
    largest = max(r["max_drift_ratio"] for r in rows)
    governing = next(line for line in text.splitlines() if "drift ratio [%]" in line)
    assert f"{100 * largest:.3f}" in governing
    smallest = min(r["max_drift_ratio"] for r in rows)
    envelope = next(line for line in text.splitlines() if "simplified" in line and "some" in line)
    # drift [%] min, max, in the governing table's format (the two tables once showed 0.066 and 0.0655)
    assert re.search(rf"{bar}{100 * smallest:.3f}{bar}{100 * largest:.3f}{bar}some", envelope)


def test_sweep_json_on_stdout_and_quiet(tmp_path):
    result = invoke("sweep", EXAMPLE, "--vary", "building.period=0.5,1", "--support", "rigid", "--out", tmp_path,
                    "--format", "json", "--quiet", "--table", "csv")
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert [r["building.period"] for r in doc["rows"]] == [0.5, 1.0]
    assert doc["summary"]["governing"]["base_shear_coefficient"]["case"] in (0, 1)
    assert "cases to run" not in result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ten_story_elcentro.period.sweep.csv",
                                                          "ten_story_elcentro.period.sweep.rows.jsonl"]


def test_sweep_criteria_exit_3_lists_the_cases(tmp_path):
    result = invoke("sweep", EXAMPLE, "--vary", "building.period=0.5,3", "--support", "rigid", "--out", tmp_path,
                    "--set", "criteria.drift_ratio=0.005", "--quiet")
    assert result.exit_code == 3, result.output
    lines = [line for line in result.stderr.splitlines() if line.startswith("criterion violated")]
    assert len(lines) == 1 and "case 1 (building.period=3): simplified/rigid: drift_ratio" in lines[0]
    rows = read_csv(tmp_path / "ten_story_elcentro.period.sweep.csv")
    assert rows[0]["violations"] == "" and "drift_ratio" in rows[1]["violations"]


def test_failed_case_is_reported_and_exits_4(tmp_path):
    result = invoke("sweep", EXAMPLE, "--engine", "exact", "--support", "rigid", "--out", tmp_path, "--quiet",
                    "--set", "ground_motion.window=[0, 4]", "--vary", "analysis.exact.time_step=[1e-7, 0.005]")
    assert result.exit_code == 4, result.output
    assert "case 0 (exact/rigid) failed:" in result.stderr and "internal steps x states" in result.stderr
    rows = read_csv(tmp_path / "ten_story_elcentro.time_step.sweep.csv")
    assert [r["status"] for r in rows] == ["failed", "ok"]
    assert rows[0]["base_shear_N"] == "" and float(rows[1]["base_shear_N"]) > 0


def test_previous_rows_need_resume_or_overwrite(tmp_path):
    args = ["sweep", EXAMPLE, "--vary", "building.period=0.5,1", "--support", "rigid", "--out", tmp_path, "--quiet"]
    assert invoke(*args).exit_code == 0
    first = table_text(tmp_path / "ten_story_elcentro.period.sweep.csv")
    result = invoke(*args)
    rows = tmp_path / "ten_story_elcentro.period.sweep.rows.jsonl"
    assert result.exit_code == 2 and result.stderr == (
        f"error: --out: {rows}: holds the rows of an earlier run of this sweep (2 cases): pass --resume to continue "
        "that run, or --overwrite to discard them and start again\n")
    assert invoke(*args, "--resume").exit_code == 0
    assert invoke(*args, "--overwrite").exit_code == 0
    assert table_text(tmp_path / "ten_story_elcentro.period.sweep.csv") == first


@pytest.mark.parametrize("args, words", [
    (["--vary", "foundation.bb=1,2"], "--vary: foundation.bb"),
    (["--vary", "foundation.b=-1,2"], "--vary: foundation.b"),
    (["--vary", "building.period=1:2"], "START:STOP:N"),
    (["--engine", "fast"], "--engine: fast"),
    (["--workers", "0"], "--workers"),
    (["--workers", "1000", "--oversubscribe"], "--workers: 1000: at most 256 worker processes"),
    (["--name", "."], "--name: .: a plain file stem"),
    (["--name", "a/b"], "it holds a folder separator"),
    (["--name", ""], "it is empty"),
    (["--name", ".hidden"], "it starts with '.'"),
    (["--dask", "remote"], "--dask"),
    (["--plot", "--plot-format", "jpg"], "--plot-format"),
])
def test_sweep_bad_input_exit_2_no_files(tmp_path, args, words):
    out = tmp_path / "out"
    result = invoke("sweep", EXAMPLE, "--vary", "building.period=0.5,1", "--out", out, *args)
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0] and "Traceback" not in result.output
    assert not out.exists()


def test_missing_extras_are_named(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyarrow", None)
    result = invoke("sweep", EXAMPLE, "--vary", "building.period=0.5,1", "--out", tmp_path, "--table", "parquet")
    assert result.exit_code == 2 and "pip install 'upliftcli[parquet]'" in result.stderr
    monkeypatch.setitem(sys.modules, "distributed", None)
    result = invoke("sweep", EXAMPLE, "--vary", "building.period=0.5,1", "--out", tmp_path, "--dask", "local")
    assert result.exit_code == 2 and "pip install 'upliftcli[dask]'" in result.stderr
    assert not list(tmp_path.iterdir())


def test_parquet_table_matches_the_csv(tmp_path):
    pyarrow_parquet = pytest.importorskip("pyarrow.parquet")
    result = invoke("sweep", EXAMPLE, "--vary", "building.period=0.5,1,2", "--support", "uplift", "--out", tmp_path,
                    "--table", "parquet", "--quiet")
    assert result.exit_code == 0, result.output
    table = pyarrow_parquet.read_table(tmp_path / "ten_story_elcentro.period.sweep.parquet")
    rows = read_csv(tmp_path / "ten_story_elcentro.period.sweep.csv")
    assert [rounded(v) for v in table.column("base_shear_N").to_pylist()] == [float(r["base_shear_N"]) for r in rows]
    assert table.column("uplift").to_pylist() == [r["uplift"] == "true" for r in rows]
    assert json.loads(table.schema.metadata[b"units"])["building.period"] == "s"


def test_sweep_plot_is_written(tmp_path):
    result = invoke("sweep", EXAMPLE, "--vary", "foundation.k_f=1e8:1e10:3:log", "--out", tmp_path, "--plot",
                    "--quiet")
    assert result.exit_code == 0, result.output
    data = (tmp_path / "ten_story_elcentro.k_f.sweep.png").read_bytes()
    assert data.startswith(PNG) and len(data) > 10_000


def test_killed_sweep_resumes_to_the_same_table(deck_dir):
    """Kill the process (SIGKILL) after a few rows, tear the last line, resume: the final table is
    the one of an uninterrupted run (which here runs on 2 local worker processes)."""
    deck = deck_dir / "inputs" / "deck.toml"
    common = ["sweep", str(deck), "--engine", "exact", "--support", "uplift", "--set", "ground_motion.window=[0, 8]",
              "--vary", "building.period=0.3:2:100", "--quiet"]
    killed = deck_dir / "killed"
    process = subprocess.Popen([sys.executable, "-c", "from upliftcli.cli import console; console()", *common,
                                "--out", str(killed), "--workers", "1"], stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE)
    rows_path = killed / "deck.period.sweep.rows.jsonl"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and process.poll() is None:
        if rows_path.exists() and len(rows_path.read_bytes().splitlines()) >= 3:
            process.send_signal(signal.SIGKILL)
            break
        time.sleep(0.005)
    process.wait()
    assert process.returncode == -signal.SIGKILL, process.stderr.read().decode()
    kept = len(rows_path.read_text().splitlines())
    assert 3 <= kept < 100
    assert not (killed / "deck.period.sweep.csv").exists()
    with open(rows_path, "a") as handle:
        handle.write('{"case": 99, "key": "torn')
    resumed = invoke(*common, "--out", killed, "--resume", "--workers", "1")
    assert resumed.exit_code == 0, resumed.output
    whole = invoke(*common, "--out", deck_dir / "whole", "--workers", "2")
    assert whole.exit_code == 0, whole.output
    assert table_text(killed / "deck.period.sweep.csv") == table_text(deck_dir / "whole" / "deck.period.sweep.csv")
    assert len(read_csv(killed / "deck.period.sweep.csv")) == 100


def test_spectra_writes_data_and_paper_figures(tmp_path):
    result = invoke("spectra", EXAMPLE, "--periods", "0.2:2:4", "--out", tmp_path, "--plot-format", "png,svg",
                    "--workers", "1")
    assert result.exit_code == 0, result.output
    assert "uplift for T_1 [s]" in result.stdout
    rows = read_csv(tmp_path / "ten_story_elcentro.spectra.csv")
    assert len(rows) == 4 * 3
    periods = sorted({float(r["building.period"]) for r in rows})
    assert periods == pytest.approx([0.2, 0.2 * 10 ** (1 / 3), 0.2 * 10 ** (2 / 3), 2.0])
    row = next(r for r in rows if r["support"] == "uplift" and float(r["building.period"]) == 2.0)
    single = run_one(load_deck(EXAMPLE, ["building.period=2.0"]), "simplified", "uplift")
    assert float(row["base_shear_coefficient"]) == rounded(single.base_shear_coefficient)
    for name in ("base_shear_simplified", "base_moment_simplified", "modal_simplified"):
        png = (tmp_path / f"ten_story_elcentro.spectra.{name}.png").read_bytes()
        assert png.startswith(PNG) and len(png) > 10_000
        svg = (tmp_path / f"ten_story_elcentro.spectra.{name}.svg").read_text()
        assert "<svg" in svg and "critical b/h" in svg and "fixed-base fundamental period T" in svg
    assert not list(tmp_path.glob("*engines*"))  # one engine: no comparison figure


@pytest.mark.parametrize(("workers", "scheduler", "cores", "started"), [
    (None, None, 2, True), (3, None, 1, True), (None, None, 1, False), (1, None, 4, False),
    (None, "tcp://127.0.0.1:1", 4, False)])
def test_spectra_starts_the_warm_server_early_when_local_workers_are_likely(monkeypatch, workers, scheduler,
                                                                            cores, started):
    from upliftcli.cli import sweep_execute as cli_sweep
    from upliftcli.sweep.executors import ProcessExecutor

    calls = []
    monkeypatch.setattr(ProcessExecutor, "prestart", lambda self: calls.append(self.workers))
    monkeypatch.setattr("upliftcli.runtime.process.available_cores", lambda: cores)
    cli_sweep.warm_workers_early(workers, scheduler, None)
    assert calls == ([workers or 2] if started else [])


def test_spectra_bad_periods(tmp_path):
    result = invoke("spectra", EXAMPLE, "--periods", "0:2:4", "--out", tmp_path)
    assert result.exit_code == 2 and "--periods" in result.stderr


# ----------------------------------------------------------------------------- analyze, several decks

def test_analyze_several_decks_one_summary(deck_dir):
    second = deck_dir / "inputs" / "second.toml"
    second.write_text((deck_dir / "inputs" / "deck.toml").read_text().replace("period = 0.5", "period = 2.0"))
    decks = [deck_dir / "inputs" / "deck.toml", second]
    result = invoke("analyze", *decks)
    assert result.exit_code == 0, result.output
    assert "Summary of 2 decks" in result.stdout and "second.toml" in result.stdout
    assert "rigid support" not in result.stdout  # no per-deck story tables
    doc = json.loads(invoke("analyze", *decks, "--format", "json", "--support", "rigid").stdout)
    assert [d["periods"][0] for d in doc["decks"]] == pytest.approx([0.5, 2.0])
    out = deck_dir / "results"
    result = invoke("analyze", *decks, "--out", out, "--set", "criteria.drift_ratio=0.004", "--support", "rigid")
    assert result.exit_code == 3
    violated = [line for line in result.stderr.splitlines() if line.startswith("criterion violated")]
    assert len(violated) == 1 and "second.toml: simplified/rigid: drift_ratio" in violated[0]
    assert sorted(p.name for p in out.iterdir()) == sorted(f"{s}.{e}" for s in ("deck", "second")
                                                           for e in ("csv", "json", "deck.toml"))


def test_analyze_several_decks_bad_one_stops_before_output(deck_dir):
    bad = deck_dir / "inputs" / "bad.toml"
    bad.write_text((deck_dir / "inputs" / "deck.toml").read_text().replace("floor_mass", "flor_mass"))
    out = deck_dir / "results"
    result = invoke("analyze", deck_dir / "inputs" / "deck.toml", bad, "--out", out)
    assert result.exit_code == 2 and result.stdout == "" and "building.flor_mass" in result.stderr
    assert not out.exists()
    twice = invoke("analyze", EXAMPLE, deck_dir / "inputs" / "deck.toml", EXAMPLE, "--out", out)
    assert twice.exit_code == 2 and "given twice" in twice.stderr


def test_progress_displays():
    from rich.console import Console

    from upliftcli.cli.sweep_render import PlainProgress, RichProgress

    stream = io.StringIO()
    plain = PlainProgress("sweep", interval=0.0, stream=stream)
    plain.start(4, 1)
    for status in ("ok", "failed", "ok"):
        plain.advance({"status": status})
    plain.stop()
    lines = stream.getvalue().splitlines()
    assert lines[0] == "sweep: 3 cases to run (1 kept from the previous run)"
    assert lines[1].startswith("sweep: 2/4 cases, ") and "ETA" in lines[1]
    assert lines[-1].startswith("sweep: 4/4 cases (1 failed), ") and "cases/s" in lines[-1] and "ETA" not in lines[-1]
    screen = io.StringIO()
    bar = RichProgress(Console(file=screen, force_terminal=True, width=100), "spectra")
    bar.start(3, 0)
    for status in ("ok", "failed", "ok"):
        bar.advance({"status": status})
    bar.stop()
    assert "spectra" in screen.getvalue() and "3/3" in screen.getvalue() and "1 failed" in screen.getvalue()


# ----------------------------------------------------------------------------- nothing lost, no hang (issue 13)

LONG_SWEEP = ["sweep", str(EXAMPLE), "--vary", "foundation.frequency_ratio=4:16:6000", "--workers", "2", "--quiet"]


def _start_long_sweep(out: Path) -> tuple[subprocess.Popen, list[int]]:
    """A sweep of 18,000 simplified cases on 2 local workers, once it has written 5 rows;
    returns the process and its descendants (multiprocessing's helpers: the resource tracker and
    the warm server, and the workers it forked)."""
    process = subprocess.Popen([sys.executable, "-c", "from upliftcli.cli import console; console()", *LONG_SWEEP,
                                "--out", str(out)], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                               env={**os.environ, "PYTHONFAULTHANDLER": "1"})  # SIGABRT: its stacks
    rows_path = out / "ten_story_elcentro.frequency_ratio.sweep.rows.jsonl"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and process.poll() is None:
        if rows_path.exists() and len(rows_path.read_bytes().splitlines()) >= 6:
            break
        time.sleep(0.01)
    assert process.poll() is None, process.stderr.read().decode()
    children = subprocess.run(["ps", "-o", "pid=", "--ppid", str(process.pid)], capture_output=True,
                              text=True).stdout.split()
    below = [subprocess.run(["ps", "-o", "pid=", "--ppid", pid], capture_output=True, text=True).stdout.split()
             for pid in children]  # the workers, forked from the warm server
    return process, [int(pid) for pid in children + [p for pids in below for p in pids]]


def _gone(pids: list[int], seconds: float = 15.0) -> bool:
    def alive(pid: int) -> bool:
        try:
            return "\nState:\tZ" not in Path(f"/proc/{pid}/status").read_text()
        except FileNotFoundError:
            return False

    deadline = time.monotonic() + seconds
    while any(alive(pid) for pid in pids) and time.monotonic() < deadline:
        time.sleep(0.1)
    return not any(alive(pid) for pid in pids)


@pytest.mark.parametrize(("signals", "code", "name"), [
    ((signal.SIGTERM,), 143, "SIGTERM"),  # SIGHUP takes the same path (tests/test_sweep_run.py)
    ((signal.SIGINT, signal.SIGINT, signal.SIGINT), 130, "SIGINT"),  # a double (triple) Ctrl-C
])
def test_stop_signals_keep_the_rows_and_stop_the_workers(tmp_path, signals, code, name):
    process, children = _start_long_sweep(tmp_path)
    assert len(children) >= 2
    for signum in signals:
        process.send_signal(signum)
        time.sleep(0.02)
    try:
        _, stderr = process.communicate(timeout=60)
    except subprocess.TimeoutExpired:  # a hang: fail with the stacks of its threads
        process.send_signal(signal.SIGABRT)
        pytest.fail("the sweep did not exit after the signal:\n" + process.communicate(timeout=30)[1].decode()[-8000:])
    stderr = stderr.decode()
    assert process.returncode == code, stderr
    assert stderr.strip().splitlines() == [line for line in stderr.strip().splitlines() if line.startswith(
        f"interrupted ({name}): ")] and "Traceback" not in stderr and "Exception ignored" not in stderr
    kept = len(RowStore(tmp_path / "ten_story_elcentro.frequency_ratio.sweep.rows.jsonl").read())
    assert kept >= 5 and f"{kept} of 18000 cases are kept" in stderr
    assert _gone(children)


def test_killed_sweep_takes_its_workers_along(tmp_path):
    process, children = _start_long_sweep(tmp_path)
    process.send_signal(signal.SIGKILL)
    process.wait(timeout=60)
    assert _gone(children), "workers left behind with parent 1"


def test_a_second_sweep_on_the_same_stem_is_refused(tmp_path):
    from upliftcli.sweep.store import stem_lock

    with stem_lock(tmp_path, "ten_story_elcentro.period.sweep"):  # as a sweep in another process holds it
        result = invoke("sweep", EXAMPLE, "--vary", "building.period=0.5,1", "--out", tmp_path, "--quiet")
    assert result.exit_code == 2
    stem = tmp_path / "ten_story_elcentro.period.sweep"
    assert result.stderr.strip() == (f"error: --out: {stem}: an output stem no other "
                                     "sweep is writing (another `uplift sweep` with the same --out and --name is "
                                     "running: wait for it to end or choose another --name)")
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_an_unreachable_scheduler_fails_fast_and_writes_nothing(tmp_path, monkeypatch):
    """Refused before a Dask client is made (its connection would wait 20 s): counted, not timed."""
    import socket

    distributed = pytest.importorskip("distributed")
    clients = []
    monkeypatch.setattr(distributed, "Client", lambda *args, **kwargs: clients.append(args))
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]  # closed again: nothing listens there
    result = invoke("sweep", EXAMPLE, "--vary", "building.period=0.5,1", "--out", tmp_path / "out", "--quiet",
                    "--scheduler", f"tcp://127.0.0.1:{port}")
    assert clients == []
    assert result.exit_code == 2 and result.stderr.startswith(f"error: --scheduler: tcp://127.0.0.1:{port}: a "
                                                              "reachable Dask scheduler")
    assert not (tmp_path / "out").exists()


def test_sweep_refuses_engine_names_as_analyze_does(tmp_path):
    result = invoke("sweep", EXAMPLE, "--engine", "EXACT", "--out", tmp_path, "--quiet")
    assert result.exit_code == 2
    assert result.stderr.strip() == ("error: --engine: EXACT: one of simplified, approximate, exact or all (names are "
                                     "lower case: 'exact')")


@pytest.mark.parametrize(("args", "line"), [
    (["--workers", "abc"], "error: --workers: 'abc' is not a valid int."),
    (["--table", "xls"], "error: --table: 'xls' is not one of 'json', 'parquet', 'csv'."),
    (["--format", "xml"], "error: --format: 'xml' is not one of 'table', 'json'."),
])
def test_bad_option_values_give_one_line(tmp_path, args, line):
    result = invoke("sweep", EXAMPLE, "--out", tmp_path, *args)
    assert result.exit_code == 2 and result.stderr.strip().splitlines() == [line]


def test_spectra_refuses_periods_the_record_cannot_resolve(tmp_path, monkeypatch):
    """Refused before any case runs (counted, not timed)."""
    from upliftcli.sweep import run

    runs = []
    monkeypatch.setattr(run, "run_sweep", lambda *args, **kwargs: runs.append(args))
    result = invoke("spectra", EXAMPLE, "--periods", "1e-9:1e-8:3", "--out", tmp_path, "--quiet")
    assert runs == []
    assert result.exit_code == 2
    assert result.stderr.strip().startswith("error: --periods: 1e-9:1e-8:3: periods of at least 8e-06 s or 0")
    assert list(tmp_path.iterdir()) == []


def test_sweep_outputs_never_replace_an_input(tmp_path):
    record = tmp_path / "rec.csv"
    record.write_bytes(RECORD.read_bytes())
    deck = tmp_path / "deck.toml"
    deck.write_text(EXAMPLE.read_text().replace("../records/elcentro_1940_ns_chopra.txt", "rec.csv")
                    .replace('units = "g"', 'units = "g"\nformat = "shared"'))
    result = invoke("sweep", deck, "--vary", "building.period=0.5,1", "--out", tmp_path, "--name", "rec", "--quiet")
    assert result.exit_code == 2 and "does not replace an input of the run" in result.stderr
    assert record.read_bytes() == RECORD.read_bytes()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.toml", "rec.csv"]


def test_sweep_files_follow_the_umask(tmp_path):
    import os
    import stat

    saved = os.umask(0o002)
    try:
        result = invoke("sweep", EXAMPLE, "--vary", "building.period=0.5,1", "--out", tmp_path, "--quiet")
    finally:
        os.umask(saved)
    assert result.exit_code == 0
    assert {p.name: stat.S_IMODE(p.stat().st_mode) for p in tmp_path.iterdir()} == {
        "ten_story_elcentro.period.sweep.rows.jsonl": 0o664, "ten_story_elcentro.period.sweep.csv": 0o664,
        "ten_story_elcentro.period.sweep.json": 0o664}


def test_resume_from_another_folder_is_the_same_sweep(tmp_path, monkeypatch):
    """The files a sweep reads are fingerprinted by absolute path: the same deck named from
    another working folder resumes its rows (nothing is run again)."""
    args = ["--vary", "building.period=0.5,1", "--support", "rigid", "--out", tmp_path, "--quiet"]
    monkeypatch.chdir(ROOT)
    assert invoke("sweep", "inputs/ten_story_elcentro.toml", *args).exit_code == 0
    rows = tmp_path / "ten_story_elcentro.period.sweep.rows.jsonl"
    before = rows.read_text()
    monkeypatch.chdir(ROOT / "inputs")
    result = invoke("sweep", "ten_story_elcentro.toml", *args, "--resume")
    assert result.exit_code == 0, result.stderr
    added = rows.read_text()[len(before):].splitlines()
    assert rows.read_text().startswith(before) and all(line.startswith('{"run"') for line in added)  # no case again


def test_a_full_disk_under_the_figures_of_spectra_is_one_line(tmp_path, monkeypatch):
    """An OSError writing a figure ended in a traceback: one line naming the figure and what was
    written, exit 2; --resume then writes the tables and figures again."""
    import errno

    from upliftcli.figures import draw as plots

    def full_disk(figures, option="--plot"):
        raise OSError(errno.ENOSPC, "No space left on device", str(figures[0][1]))

    monkeypatch.setattr(plots, "plot_figures", full_disk)
    args = ["spectra", EXAMPLE, "--periods", "0.5,1", "--out", tmp_path, "--workers", "1", "--quiet",
            "--support", "rigid"]
    result = invoke(*args)
    figure = tmp_path / "ten_story_elcentro.spectra.base_shear_simplified.png"
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert result.stderr == (f"error: --out: {figure}: a writable directory (No space left on device); the figures "
                             "were not all written, the tables were (ten_story_elcentro.spectra.csv, "
                             "ten_story_elcentro.spectra.json): run the same command with --resume once there is "
                             "room\n")
    monkeypatch.undo()
    assert invoke(*args).exit_code == 2  # the rows of that run: --resume or --overwrite
    assert invoke(*args, "--resume").exit_code == 0 and figure.exists()


def test_tables_of_an_earlier_run_are_replaced_only_with_resume_or_overwrite(tmp_path):
    args = ["sweep", EXAMPLE, "--vary", "building.period=0.5,1", "--out", tmp_path, "--workers", "1", "--quiet",
            "--table", "csv"]
    assert invoke(*args).exit_code == 0
    (tmp_path / "ten_story_elcentro.period.sweep.rows.jsonl").unlink()
    before = (tmp_path / "ten_story_elcentro.period.sweep.csv").read_text()
    result = invoke(*args)
    assert result.exit_code == 2 and (tmp_path / "ten_story_elcentro.period.sweep.csv").read_text() == before
    table = tmp_path / "ten_story_elcentro.period.sweep.csv"
    assert result.stderr == (f"error: --out: {table}: a new file (it exists: "
                             "written by an earlier run; --resume continues that run; pass --overwrite to replace "
                             "it)\n")
    assert not (tmp_path / "ten_story_elcentro.period.sweep.rows.jsonl").exists()
    assert invoke(*args, "--overwrite").exit_code == 0


def test_a_simplified_error_limit_needs_check(tmp_path):
    """A sweep judges [criteria] simplified_error on the ratios --check adds: without --check (the
    limit in the deck, by --set or varied) every case passed it unchecked; refused before any run."""
    line = ("error: --check: criteria.simplified_error: needed by this limit of the deck (a sweep judges it on the "
            "ratios simplified / exact that --check adds): add --check or drop the limit\n")
    for limit in (["--set", "criteria.simplified_error=0.25"], ["--vary", "criteria.simplified_error=0.01,1"]):
        result = invoke("sweep", EXAMPLE, "--vary", "building.period=0.5,1.0", *limit, "--out", tmp_path,
                        "--workers", "1", "-q")
        assert (result.exit_code, result.stderr) == (2, line)
    assert sorted(tmp_path.iterdir()) == []


@pytest.mark.parametrize("mode", ["--overwrite", "--resume"])
def test_sweep_never_writes_through_a_symlinked_rows_file(tmp_path, mode):
    # issue 38 S1: the rows file a symbolic link to a file outside --out
    out, outside = tmp_path / "o", tmp_path / "outside"
    out.mkdir()
    outside.mkdir()
    (outside / "v.txt").write_text("keep\n")
    rows = out / "ten_story_elcentro.slenderness.sweep.rows.jsonl"
    rows.symlink_to("../outside/v.txt")
    result = invoke("sweep", EXAMPLE, "--vary", "foundation.slenderness=5,6", "-e", "simplified", "--out", out, mode)
    assert result.exit_code == 2
    assert result.stderr == (f"error: --out: {rows}: a path that is not a symbolic link (an output is never written "
                             "through one; remove the link or choose another output folder)\n")
    assert (outside / "v.txt").read_text() == "keep\n"
    assert rows.is_symlink() and sorted(p.name for p in out.iterdir()) == [rows.name]


def test_spectra_whose_every_case_fails_draws_no_figure_and_says_so(tmp_path):
    """Every case failing (a step limit each case exceeds) left figures of no data, whose log axis
    raised a traceback; now: the failures, one line that no figure was drawn, exit code 4."""
    result = invoke("spectra", EXAMPLE, "--periods", "0.5,1", "--engine", "exact", "--support", "uplift",
                    "--set", "analysis.exact.steps_per_period=100000", "--out", tmp_path, "--quiet")
    assert result.exit_code == 4, result.output
    assert "Traceback" not in result.output and "warning: no figure drawn: no case finished" in result.stderr
    assert not list(tmp_path.glob("*.png"))
