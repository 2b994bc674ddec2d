"""The `uplift` entry point: commands that run no history engine load no scipy, and the exact
engine no scipy.linalg (each run in a fresh interpreter, its sys.modules inspected after the command)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

INPUTS = Path(__file__).resolve().parent.parent / "inputs"
#: scipy.linalg (0.15-0.2 s to import: issues 10, 14), any of scipy (scipy.special or scipy.fft alone: 0.1-0.2 s),
#: and matplotlib
HEAVY = ("scipy.linalg", "scipy", "matplotlib")

PROBE = """
import json, sys
args, heavy = json.loads(sys.argv[1]), json.loads(sys.argv[2])
sys.argv = ["uplift", *args]
from upliftcli.cli import main
try:
    main()
except SystemExit as end:
    code = end.code
else:
    code = 0
print(json.dumps({"code": code, "loaded": [name for name in heavy if name in sys.modules]}), file=sys.stderr)
"""


def loaded_after(*args: str) -> tuple[int, list[str]]:
    """(exit code, heavy modules loaded) after `uplift args...` in a fresh interpreter."""
    done = subprocess.run([sys.executable, "-c", PROBE, json.dumps(list(args)), json.dumps(HEAVY)],
                          capture_output=True, text=True, timeout=120)
    report = json.loads(done.stderr.strip().splitlines()[-1])
    return report["code"], report["loaded"]


@pytest.mark.parametrize("args", [
    ("--help",),
    ("modes", str(INPUTS / "ten_story_elcentro.toml")),
    ("analyze", str(INPUTS / "ten_story_asce7.toml")),  # design spectrum: the simplified engine only
    # the README's deck, simplified on a record (numpy S_a), its check by the exact engine switched off
    ("analyze", str(INPUTS / "ten_story_elcentro.toml"), "--no-check"),
], ids=["help", "modes", "analyze-design-spectrum", "analyze-record-simplified"])
def test_commands_without_history_engine_load_no_scipy(args):
    """A design spectrum's check suite, generated once per spectrum and cached (analysis/suite_check.py),
    is made with scipy's inverse incomplete gamma function (motion/envelopes.py): a first run makes it
    where another test has not, the second is the one probed."""
    if args[-1].endswith("ten_story_asce7.toml"):
        loaded_after(*args)
    code, loaded = loaded_after(*args)
    assert code == 0
    assert loaded == []


def test_readme_command_loads_no_scipy():
    """The README's first command, with the exact engine's check (step operators by engines/exact/expm.py)."""
    code, loaded = loaded_after("analyze", str(INPUTS / "ten_story_elcentro.toml"))
    assert code == 0
    assert loaded == []


def loaded_modules(*args: str, names: list[str]) -> tuple[int, list[str]]:
    """(exit code, those of `names` loaded) after `uplift args...` in a fresh interpreter."""
    done = subprocess.run([sys.executable, "-c", PROBE, json.dumps(list(args)), json.dumps(names)],
                          capture_output=True, text=True, timeout=120)
    report = json.loads(done.stderr.strip().splitlines()[-1])
    return report["code"], report["loaded"]


COMMAND_MODULES = [f"upliftcli.cli.{name}" for name in ("analyze", "modes", "record", "sweep", "report", "examples")]


@pytest.mark.parametrize(("args", "expected"), [
    (("modes", str(INPUTS / "ten_story_elcentro.toml")), ["upliftcli.cli.modes"]),
    (("analyze", "--help"), ["upliftcli.cli.analyze"]),
    (("record", "info", "--help"), ["upliftcli.cli.record"]),
    (("spectra", "--help"), ["upliftcli.cli.sweep"]),
    (("--version",), []),
    (("--help",), COMMAND_MODULES),  # the top-level help lists every command
    (("nonsense",), COMMAND_MODULES),  # click's "No such command" from the whole app
], ids=["modes", "analyze", "record", "spectra", "version", "help", "unknown"])
def test_a_command_line_imports_only_its_commands_module(args, expected):
    """Start-up (issue 34): a command registers only the module of its command (cli.COMMANDS)."""
    code, loaded = loaded_modules(*args, names=COMMAND_MODULES)
    assert code == (2 if args == ("nonsense",) else 0)
    assert loaded == expected


def test_every_command_is_named_in_commands():
    """cli.COMMANDS names every command the command modules register, and only those."""
    import typer.main

    from upliftcli.cli import COMMANDS, app

    assert set(typer.main.get_command(app).commands) == set(COMMANDS)


def test_probe_sees_what_a_command_loads(tmp_path):
    """The probe is not blind: drawing the figures loads matplotlib."""
    code, loaded = loaded_after("analyze", str(INPUTS / "ten_story_elcentro.toml"), "--no-check", "--plot",
                                str(tmp_path))
    assert code == 0
    assert loaded == ["matplotlib"]


def test_version_is_the_installed_distributions_and_names_the_loops_in_use(tmp_path):
    """The version of the distribution upliftcli (here a stand-in's metadata, first on the path;
    tools/check_wheel.sh checks a wheel's own), `python -m upliftcli` the same command."""
    (tmp_path / "upliftcli-7.1.2.dist-info").mkdir()
    (tmp_path / "upliftcli-7.1.2.dist-info" / "METADATA").write_text("Name: upliftcli\nVersion: 7.1.2\n")
    path = os.pathsep.join([str(tmp_path), str(INPUTS.parent), os.environ.get("PYTHONPATH", "")])
    for command in ([sys.executable, "-c", "from upliftcli.cli import main; main()", "--version"],
                    [sys.executable, "-m", "upliftcli", "--version"]):
        done = subprocess.run(command, capture_output=True, text=True, timeout=120,
                              env={**os.environ, "PYTHONPATH": path})
        assert done.returncode == 0 and done.stdout.splitlines()[0] == "7.1.2", done.stderr
    command = [sys.executable, "-c", "from upliftcli.cli import main; main()", "--version"]
    assert done.stdout.splitlines()[1].startswith("loops: ") and len(done.stdout.splitlines()) == 2
    twins = subprocess.run(command, capture_output=True, text=True, timeout=120,
                           env=dict(os.environ, UPLIFT_BACKEND="numpy"))
    assert twins.stdout.splitlines()[1] == "loops: numpy twins (UPLIFT_BACKEND=numpy)"


def test_python_m_upliftcli_is_the_command(tmp_path):
    """`python -m upliftcli` runs the `uplift` command: its output and its exit codes."""
    missing = subprocess.run([sys.executable, "-m", "upliftcli", "analyze", str(tmp_path / "none.toml")],
                             capture_output=True, text=True, timeout=120)
    assert missing.returncode == 2 and missing.stderr.count("\n") == 1 and "file not found" in missing.stderr
    modes = subprocess.run([sys.executable, "-m", "upliftcli", "modes", str(INPUTS / "ten_story_elcentro.toml")],
                           capture_output=True, text=True, timeout=120)
    assert modes.returncode == 0 and "m_n*/m_t" in modes.stdout, modes.stderr


def test_console_script_exits_with_the_command_code_and_its_whole_output(tmp_path):
    """The `uplift` script (cli.console): the exit code and the output of main(), without the teardown."""
    command = [sys.executable, "-c", "from upliftcli.cli import console; console()"]
    missing = subprocess.run([*command, "analyze", str(tmp_path / "none.toml")], capture_output=True, text=True)
    assert missing.returncode == 2
    assert missing.stderr.count("\n") == 1 and "file not found" in missing.stderr
    deck = str(INPUTS / "ten_story_elcentro.toml")
    fast = subprocess.run([*command, "analyze", deck, "--no-check", "--format", "json"], capture_output=True,
                          text=True)
    assert fast.returncode == 0
    slow = subprocess.run([sys.executable, "-c", "from upliftcli.cli import main; main()", "analyze", deck,
                           "--no-check", "--format", "json"], capture_output=True, text=True)
    ours, theirs = json.loads(fast.stdout), json.loads(slow.stdout)  # whole documents: flushed
    for document in (ours, theirs):
        document["provenance"].pop("time_utc")
    assert ours == theirs


def test_numpy_runtime_warnings_never_reach_the_terminal():
    """A command's numpy RuntimeWarnings (overflow in exp, 0/0) are not printed (they reached
    stderr); other warnings and the command's own output are."""
    import warnings

    import numpy as np
    import typer
    from typer.testing import CliRunner

    from upliftcli.cli import UpliftGroup

    app = typer.Typer(cls=UpliftGroup)

    @app.command()
    def noisy() -> None:
        with np.errstate(all="warn"):
            np.exp(np.array([1000.0]))
            np.array([0.0]) / np.array([0.0])
        warnings.warn("a user warning", UserWarning, stacklevel=1)
        typer.echo("done", err=True)

    @app.command()
    def other() -> None: ...

    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        result = CliRunner().invoke(app, ["noisy"])
    assert result.exit_code == 0 and "done" in result.stderr
    assert [type(w.message) for w in shown if issubclass(w.category, Warning)] == [UserWarning]


#: the command modules of the CLI whose imports must run one way (the record commands' circle, issue 34)
ONE_WAY = ("analyze", "analyze_batch", "analyze_deck", "analyze_steps", "modes", "options", "record",
           "record_options", "record_output", "record_select", "record_suite", "report", "sweep", "sweep_execute",
           "sweep_options")


def cli_imports() -> dict[str, set[str]]:
    """Module of upliftcli/cli -> the modules of upliftcli/cli it imports (at module level or in a function)."""
    import ast

    folder = Path(__file__).resolve().parent.parent / "upliftcli" / "cli"
    names = {path.stem for path in folder.glob("*.py")}
    graph = {}
    for name in names:
        found = set()
        for node in ast.walk(ast.parse((folder / f"{name}.py").read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level == 1:
                found |= {node.module} if node.module else {alias.name for alias in node.names}
        graph[name] = found & names - {name}
    return graph


def test_command_modules_import_one_way():
    """No import circle passes through the command modules (record <-> record_select <-> record_suite was one)."""
    graph = cli_imports()

    def reaches(start: str, goal: str, seen: set[str]) -> bool:
        return any(step == goal or (step not in seen and reaches(step, goal, seen | {step}))
                   for step in graph[start])

    assert [name for name in ONE_WAY if reaches(name, name, set())] == []
    assert not graph["record_options"] & {"record", "record_select", "record_suite"}
    assert not graph["record_output"] & {"record", "record_select", "record_suite"}
