"""cli/sweep_options.py: --name is a plain file stem; --workers is capped at the cores unless
--oversubscribe (--workers 1000 started 127 processes and 4 GiB in 14 s); cli/sweep.py: the stale
cases of a sweep in one line."""

from __future__ import annotations

import pytest

from upliftcli.cli import sweep_options
from upliftcli.errors import InputError


def test_workers_are_capped_at_the_cores_unless_oversubscribed(monkeypatch, capsys):
    monkeypatch.setattr("upliftcli.runtime.process.available_cores", lambda: 2)
    assert sweep_options.local_workers(None, False, None) is None
    assert sweep_options.local_workers(2, False, None) == 2
    assert sweep_options.local_workers(1000 // 10, False, None) == 2
    assert "warning: --workers 100 capped at the 2 cores this process may use (--oversubscribe starts 100 " \
           "processes)" in capsys.readouterr().err
    assert sweep_options.local_workers(100, True, "local") == 100
    assert sweep_options.local_workers(1000, False, "tcp://host:8786") == 1000  # a remote cluster's own
    with pytest.raises(InputError, match=r"^--workers: 257: at most 256 worker processes"):
        sweep_options.local_workers(257, True, None)
    with pytest.raises(InputError, match=r"^--workers: 0: an integer >= 1"):
        sweep_options.local_workers(0, True, None)


@pytest.mark.parametrize("name", ["tall_frames", "run-2.v3", "été"])
def test_plain_stems_are_accepted(name):
    sweep_options.check_name(name)


@pytest.mark.parametrize("name, words", [(".", "starts with '.'"), ("..", "starts with '.'"), ("", "is empty"),
                                         ("a/b", "folder separator"), ("a\\b", "folder separator"),
                                         ("a\nb", "control character"), ("x" * 201, "201 characters")])
def test_names_that_are_not_plain_stems_are_refused(name, words):
    with pytest.raises(InputError, match=r"^--name: .*a plain file stem") as error:
        sweep_options.check_name(name)
    assert words in str(error.value) and "\n" not in str(error.value)


def test_stale_cases_are_summed_up_in_one_line(capsys):
    # issue 38: a record replaced during a sweep printed one line per stale case (2,644 lines)
    from upliftcli.cli.sweep_exit import _echo_failures
    from upliftcli.sweep.worker import STALE_TEXT

    def row(case, status, source="/data/el.txt"):
        return {"case": case, "engine": "simplified", "support": "uplift", "status": status,
                "message": f"{source}{STALE_TEXT} (SHA-256 abc... then, def... now): this case was not computed"}

    rows = [row(k, "stale") for k in range(2644)] + [row(2644, "ok"), row(2645, "stale", "/data/b.txt")]
    rows.append({"case": 2646, "engine": "exact", "support": "rigid", "status": "failed", "message": "boom"})
    assert len(_echo_failures(rows)) == 2646
    assert capsys.readouterr().err.splitlines() == [
        "case 2646 (exact/rigid) failed: boom",
        "2645 cases stale (not computed): the record files /data/el.txt, /data/b.txt changed after the sweep read "
        "them; run the same command with --resume --rerun-stale once they are settled"]
    _echo_failures(rows[:1])
    assert capsys.readouterr().err == ("1 case stale (not computed): the record file /data/el.txt changed after the "
                                       "sweep read it; run the same command with --resume --rerun-stale once it is "
                                       "settled\n")
