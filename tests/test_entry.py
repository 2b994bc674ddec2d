"""The `uplift` entry point (upliftcli/__main__.py): a Ctrl-C during start-up (the imports of typer,
rich and the commands: most of the first second) ends the process with exit 130 and no traceback,
as a Ctrl-C during a command does.

No timing: the child is held inside the import named, by an import hook that says "ready" and
waits; the SIGINT is sent once that line is read, so it always lands inside that import."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: held here until the SIGINT comes (a fail-safe against a signal that never comes, not a timing)
HOLD_SECONDS = 300

HOOK = """
import sys, time

class Hold:
    def find_spec(self, name, path=None, target=None):
        if name == {module!r}:
            sys.meta_path.remove(self)
            print("ready", flush=True)
            time.sleep({hold})  # the SIGINT raises KeyboardInterrupt here, inside the import
        return None

sys.meta_path.insert(0, Hold())
"""


def console_script() -> str:
    """The console script pip writes for pyproject.toml's `uplift` entry point."""
    entry = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]["uplift"]
    module, function = entry.split(":")
    return (f"import re\nimport sys\nfrom {module} import {function}\nif __name__ == '__main__':\n"
            f"    sys.argv[0] = re.sub(r'(-script\\.pyw|\\.exe)?$', '', sys.argv[0])\n    sys.exit({function}())\n")


def test_the_entry_point_imports_nothing_heavy():
    """Only the entry module itself stands between the interpreter's start and the guarded imports."""
    code = f"{console_script().split('if __name__')[0]}\nprint(sorted(m for m in ('typer', 'rich', 'click', " \
           "'numpy', 'upliftcli.cli') if m in sys.modules))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.returncode == 0 and done.stdout.strip() == "[]", done.stdout + done.stderr


@pytest.mark.parametrize(("module", "args"), [
    ("typer", ["--help"]),  # the first heavy import
    ("upliftcli.runtime.atomic", ["--help"]),  # deep in the imports of the command line
    ("upliftcli.cli.sweep", ["--help"]),  # the commands registered
    ("numpy", ["analyze", str(ROOT / "inputs" / "ten_story_elcentro.toml")]),  # in a command: typer's Exit(130)
])
def test_ctrl_c_during_start_up_exits_130_without_a_traceback(module, args):
    code = HOOK.format(module=module, hold=HOLD_SECONDS) + console_script()
    process = subprocess.Popen([sys.executable, "-c", code, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True, env={**os.environ, "PYTHONPATH": str(ROOT)})
    try:
        line = process.stdout.readline()  # "ready" once held inside the import; '' if it ended first
        assert line == "ready\n", (line, process.communicate(timeout=HOLD_SECONDS)[1])
        process.send_signal(signal.SIGINT)
        stdout, stderr = process.communicate(timeout=HOLD_SECONDS)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert process.returncode == 130, (process.returncode, stderr)
    assert "Traceback" not in stderr and "KeyboardInterrupt" not in stderr, stderr
    assert stdout == ""


def test_python_m_upliftcli_runs_the_command():
    done = subprocess.run([sys.executable, "-m", "upliftcli", "--version"], capture_output=True, text=True,
                          timeout=120, env={**os.environ, "PYTHONPATH": str(ROOT)}, cwd=ROOT)
    assert done.returncode == 0 and done.stdout.splitlines()[1].startswith("loops: "), done.stderr
