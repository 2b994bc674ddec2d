"""The choice of the loops (upliftcli.runtime.backend): compiled where built, else the numpy twins, as
UPLIFT_BACKEND asks; a source tree without built extensions runs on the twins."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from upliftcli.errors import InputError
from upliftcli.runtime import backend

ROOT = Path(__file__).resolve().parents[1]
MISSING = "upliftcli.engines.exact._never_built"
TWIN = "upliftcli.engines.exact.stepping_numpy"


def test_the_variable_chooses_and_use_overrides_it(monkeypatch):
    monkeypatch.delenv(backend.VARIABLE, raising=False)
    assert backend.choice() == "auto"
    monkeypatch.setenv(backend.VARIABLE, " NumPy ")
    assert backend.choice() == "numpy"
    with backend.use("compiled"):
        assert backend.choice() == "compiled"
        with backend.use("auto"):
            assert backend.choice() == "auto"
        assert backend.choice() == "compiled"
    assert backend.choice() == "numpy"
    with pytest.raises(ValueError, match="backend"):
        backend.use("fortran").__enter__()


def test_an_unknown_value_is_one_input_error(monkeypatch):
    monkeypatch.setenv(backend.VARIABLE, "fast")
    with pytest.raises(InputError, match=r"UPLIFT_BACKEND: one of auto, compiled, numpy .* got 'fast'"):
        backend.choice()


def test_a_missing_extension_falls_back_to_its_twin_unless_compiled_is_asked_for():
    with backend.use("auto"):
        assert backend.loops(MISSING, TWIN).__name__ == TWIN
    with backend.use("numpy"):
        assert backend.loops("upliftcli.engines.exact._stepping", TWIN).__name__ == TWIN
    with backend.use("compiled"), pytest.raises(InputError, match="_never_built, which was not built"):
        backend.loops(MISSING, TWIN)


def test_built_finds_the_extensions_on_disk_and_describe_says_what_runs(monkeypatch):
    present = backend.built()
    assert set(present) <= set(backend.EXTENSIONS)
    # found on disk exactly where they import (a wrong package root found none after a move)
    importable = [name for name in backend.EXTENSIONS if not isinstance(backend._module(name), ImportError)]
    assert present == importable
    with backend.use("numpy"):
        assert backend.describe() == "loops: numpy twins (UPLIFT_BACKEND=numpy)"
    monkeypatch.setattr(backend, "built", lambda: list(backend.EXTENSIONS))
    with backend.use("auto"):
        assert backend.describe() == "loops: compiled (C extensions)"
    monkeypatch.setattr(backend, "built", lambda: list(backend.EXTENSIONS[1:]))
    with backend.use("auto"):
        assert backend.describe().startswith("loops: numpy twins for _stepping (the C extensions were not built")
    with backend.use("compiled"):
        assert backend.describe() == "loops: compiled asked for, but not built: _stepping"


def test_a_source_tree_without_built_extensions_runs_on_the_twins(tmp_path):
    """The package copied without its compiled modules (a checkout that was never built): the exact
    engine and the spectra run on the twins; --version says so; UPLIFT_BACKEND=compiled is refused
    in one line with exit code 2."""
    shutil.copytree(ROOT / "upliftcli", tmp_path / "upliftcli",
                    ignore=shutil.ignore_patterns("*.so", "*.pyd", "__pycache__"))
    environment = dict(os.environ, PYTHONPATH=str(tmp_path))
    environment.pop(backend.VARIABLE, None)
    command = [sys.executable, "-c", "from upliftcli.cli import main; main()"]
    deck = str(ROOT / "inputs" / "ten_story_elcentro.toml")

    def uplift(*arguments, **extra):
        return subprocess.run([*command, *arguments], capture_output=True, text=True, timeout=300, cwd=tmp_path,
                              env=dict(environment, **extra))

    version = uplift("--version")
    assert version.returncode == 0 and version.stdout.splitlines()[1].startswith(
        "loops: numpy twins (the C extensions were not built")
    done = uplift("analyze", deck, "--engine", "exact", "--support", "uplift", "--format", "json")
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["uplift"] is True
    refused = uplift("analyze", deck, "--engine", "exact", UPLIFT_BACKEND="compiled")
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1
    assert refused.stderr.startswith("error: UPLIFT_BACKEND: 'compiled' needs the C extension upliftcli.")
