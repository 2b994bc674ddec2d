"""A reader that closes the output early (`uplift analyze deck | head`): the output stops quietly,
the command runs to its end (files written) and exits with its own code (cli/stdout.py)."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "inputs" / "ten_story_elcentro.toml"
RECORD = ROOT / "records" / "elcentro_1940_ns_chopra.txt"


def closed_pipe(*args: str) -> subprocess.CompletedProcess:
    """`uplift ARGS` with its standard output a pipe whose reader has gone before the first write."""
    process = subprocess.Popen([sys.executable, "-c", "from upliftcli.cli import console; console()", *args],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT,
                               env={"PATH": "/usr/bin:/bin", "CI": "true"})
    process.stdout.close()
    stderr = process.stderr.read()
    process.wait(timeout=300)
    return subprocess.CompletedProcess(args, process.returncode, "", stderr)


@pytest.mark.parametrize("output", ["table", "json"])
def test_analyze_into_a_closed_pipe_finishes_quietly(tmp_path, output):
    result = closed_pipe("analyze", str(EXAMPLE), "--no-check", "--format", output, "--out", str(tmp_path))
    assert result.returncode == 0, result.stderr
    assert "Error" not in result.stderr and "Traceback" not in result.stderr and "Broken pipe" not in result.stderr
    assert (tmp_path / "ten_story_elcentro.json").exists()  # the run went on after its output stopped


def test_the_exit_code_stays_the_runs():
    result = closed_pipe("analyze", str(EXAMPLE), "--no-check", "--set", "criteria.drift_ratio=1e-5")
    assert result.returncode == 3 and "criterion violated" in result.stderr


def test_record_spectrum_csv_into_a_closed_pipe():
    result = closed_pipe("record", "spectrum", str(RECORD))
    assert result.returncode == 0 and "Traceback" not in result.stderr
