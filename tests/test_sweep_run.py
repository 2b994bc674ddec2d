"""sweep/run.py: the driver: --resume, Ctrl-C and stop signals keep every finished row."""

import json
import os

import pytest

from upliftcli.sweep.executors import SerialExecutor
from upliftcli.sweep.run import run_sweep
from upliftcli.sweep.store import RowStore

# ----------------------------------------------------------------------------- parsing


def test_resume_skips_finished_cases_and_gives_the_same_rows(small_plan, serial_rows, tmp_path):
    path = tmp_path / "rows.jsonl"
    path.write_text("".join(json.dumps({**row, "fingerprint": small_plan.fingerprint}) + "\n"
                            for row in serial_rows[:5]))
    seen = []

    class Recording(SerialExecutor):
        def run(self, chunks, on_row):
            chunks = list(chunks)  # made as they are asked for: once
            seen.extend(case.key for chunk in chunks for case in chunk.cases)
            super().run(chunks, on_row)

    outcome = run_sweep(small_plan, Recording(), RowStore(path), resume=True)
    assert outcome.reused == 5 and sorted(seen) == sorted(c.key for c in small_plan.cases[5:])
    assert outcome.rows == serial_rows
    assert len(path.read_text().splitlines()) == len(serial_rows) + 1  # and the header line of the run


def test_resume_reruns_crashed_and_optionally_failed_cases(small_plan, serial_rows, tmp_path):
    path = tmp_path / "rows.jsonl"
    rows = [dict(r) for r in serial_rows]
    rows[0].update(status="crashed", message="worker died")
    rows[1].update(status="failed", message="boom")
    path.write_text("".join(json.dumps({**row, "fingerprint": small_plan.fingerprint}) + "\n" for row in rows))
    outcome = run_sweep(small_plan, SerialExecutor(), RowStore(path), resume=True)
    assert outcome.reused == len(rows) - 1 and outcome.rows[0] == serial_rows[0]
    assert outcome.rows[1]["status"] == "failed"  # deterministic failure: reported, not retried
    outcome = run_sweep(small_plan, SerialExecutor(), RowStore(path), resume=True, retry_failed=True)
    assert outcome.rows == serial_rows


def test_ctrl_c_keeps_the_finished_rows(small_plan, serial_rows, tmp_path):
    class Interrupted(SerialExecutor):
        def run(self, chunks, on_row):
            for row in serial_rows[:3]:
                on_row(row)
            raise KeyboardInterrupt

    path = tmp_path / "rows.jsonl"
    outcome = run_sweep(small_plan, Interrupted(), RowStore(path))
    assert outcome.interrupted and outcome.rows == serial_rows[:3]
    assert len(RowStore(path).read()) == 3


def test_a_run_that_stops_before_its_first_row_leaves_no_rows_file(small_plan, tmp_path):
    class Failing(SerialExecutor):
        def run(self, chunks, on_row):
            raise OSError(111, "Connection refused")

    path = tmp_path / "rows.jsonl"
    with pytest.raises(OSError):
        run_sweep(small_plan, Failing(), RowStore(path))
    assert not path.exists()


@pytest.mark.parametrize("signum", ["SIGTERM", "SIGHUP"])
def test_sigterm_and_sighup_stop_a_sweep_like_ctrl_c(small_plan, serial_rows, tmp_path, signum):
    import signal

    signum = getattr(signal, signum)

    class Terminated(SerialExecutor):
        def run(self, chunks, on_row):
            for row in serial_rows[:4]:
                on_row(row)
            os.kill(os.getpid(), signum)
            for row in serial_rows[4:]:  # never reached: the signal interrupts here
                on_row(row)

    before = signal.getsignal(signum)
    outcome = run_sweep(small_plan, Terminated(), RowStore(tmp_path / "rows.jsonl"))
    assert outcome.interrupted and outcome.signal == signum and outcome.rows == serial_rows[:4]
    assert signal.getsignal(signum) is before  # handlers restored


def test_the_sweep_command_keeps_no_rows_in_memory_and_reads_them_back(tmp_path, monkeypatch):
    """issue 38 item 5: `uplift sweep` runs with keep_rows=False (the outcome holds the cases' keys, not
    their rows) and its summary, tables, figure and exit read the rows back from the rows file: the
    tables hold every case, in case order, and the rows file's rows."""
    import csv

    from cli_helpers import invoke
    from sweep_cases import EXAMPLE

    from upliftcli.sweep import run as run_module

    outcomes, original = [], run_module.run_sweep

    def recording(*args, **kwargs):
        outcomes.append(original(*args, **kwargs))
        return outcomes[-1]

    monkeypatch.setattr(run_module, "run_sweep", recording)
    result = invoke("sweep", EXAMPLE, "--vary", "building.period=0.5,1,2", "--vary", "foundation.b=2,3", "-e",
                    "simplified", "--support", "rigid,uplift", "--out", tmp_path, "--name", "m", "--plot", "--quiet")
    assert result.exit_code == 0, result.output
    (outcome,) = outcomes
    assert outcome.rows == [] and outcome.finished == 12
    with open(tmp_path / "m.csv", encoding="utf-8") as handle:
        table = list(csv.DictReader(line for line in handle if not line.startswith("#")))
    stored = {row["key"]: row for row in RowStore(tmp_path / "m.rows.jsonl").read().values()}
    assert [int(row["case"]) for row in table] == list(range(12)) and set(stored) == {row["key"] for row in table}
    document = json.loads((tmp_path / "m.json").read_text())
    assert [row["case"] for row in document["rows"]] == list(range(12)) and document["summary"]["ok"] == 12
    assert (tmp_path / "m.png").stat().st_size > 0
