"""cli/sweep_options.py: --name is a plain file stem; --workers is capped at the cores unless
--oversubscribe (--workers 1000 started 127 processes and 4 GiB in 14 s)."""

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
