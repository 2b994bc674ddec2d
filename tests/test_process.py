"""runtime/process.py: freed blocks of a few megabytes are reused instead of being mapped (and
page-faulted) again; the cores a process may use."""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
from pathlib import Path

import pytest

LOOP = """
import resource, sys
import numpy as np
from upliftcli.runtime.process import keep_freed_memory
if sys.argv[1] == "keep":
    assert keep_freed_memory()
if sys.argv[1] == "import":  # what a program using the Python API imports
    import upliftcli.api, upliftcli.cli, upliftcli.sweep.executors
def chunk():  # the arrays of one exact-engine chunk, about 6-8 MB each
    arrays = [np.ones(1_000_000), np.ones(800_000), np.ones(900_000)]
    return sum(float(a[-1]) for a in arrays)
chunk()
before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(20):
    chunk()
print(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
"""


def _faults(mode: str) -> int:
    done = subprocess.run([sys.executable, "-c", LOOP, mode], capture_output=True, text=True, check=True)
    return int(done.stdout)


@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="the setting is glibc's")
def test_kept_memory_is_not_faulted_in_again_and_importing_keeps_the_default():
    default, kept, imported = _faults("default"), _faults("keep"), _faults("import")
    assert default > 5_000  # chunks of 21 MB: glibc maps most of them again each time
    assert kept < default / 20
    assert imported > default / 2  # the package changes the allocator only where it runs the process


def test_available_cores_are_those_the_process_may_run_on():
    from upliftcli.runtime.process import available_cores

    assert 1 <= available_cores() <= (os.cpu_count() or 1)


EXIT = """
import atexit, sys, threading, time
from upliftcli.runtime.process import exit_now
atexit.register(lambda: print("handler ran", file=sys.stderr))
def late():
    time.sleep(0.2)
    print("thread done", file=sys.stderr)
threading.Thread(target=late).start()
sys.stdout.write("x" * 100_000)  # buffered: only a flush writes it
exit_now(eval(sys.argv[1]))
print("not reached", file=sys.stderr)
"""


@pytest.mark.parametrize(("code", "expected"), [("3", 3), ("None", 0), ("'failed'", 1)])
def test_exit_now_ends_as_a_normal_exit_would(code, expected):
    done = subprocess.run([sys.executable, "-c", EXIT, code], capture_output=True, text=True)
    assert done.returncode == expected
    assert done.stdout == "x" * 100_000  # flushed
    lines = done.stderr.splitlines()
    assert lines[-2:] == ["thread done", "handler ran"]  # threads waited for, then the atexit handlers
    assert ("failed" in lines) == (code == "'failed'")
    assert "not reached" not in done.stderr


ANALYZE = """
import json, platform, sys
if sys.argv[1] == "not-glibc":  # as on macOS, Windows or musl
    platform.libc_ver = lambda *args, **kwargs: ("", "")
from upliftcli.cli import main
from upliftcli.runtime.process import keep_freed_memory
print(json.dumps({"kept": keep_freed_memory()}))
sys.argv = ["uplift", "analyze", sys.argv[2], "--engine", "exact", "--support", "uplift", "--format", "json"]
main()
"""


def _analysis(libc: str) -> tuple[bool, dict]:
    deck = str(Path(__file__).resolve().parents[1] / "inputs" / "ten_story_elcentro.toml")
    done = subprocess.run([sys.executable, "-c", ANALYZE, libc, deck], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    first, _, rest = done.stdout.partition("\n")
    return json.loads(first)["kept"], json.loads(rest)


def test_without_glibc_the_allocator_is_left_alone_and_the_results_are_the_same():
    """keep_freed_memory changes nothing where the C library is not glibc (no mallopt call); the
    exact engine's uplift response of the README deck is the same to the bit either way."""
    kept, default = _analysis("default")
    skipped, elsewhere = _analysis("not-glibc")
    assert kept == (platform.libc_ver()[0] == "glibc") and not skipped
    for field in ("base_shear", "base_moment", "stories", "elements", "uplift"):
        assert elsewhere[field] == default[field], field
