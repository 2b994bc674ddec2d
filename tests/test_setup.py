"""setup.py: the compiled loops use Python 3.11's limited API only (one cp311-abi3 wheel per
platform), and where no compiler works the wheel is a pure one (py3-none-any) without them.

The cp311-abi3 wheel itself is built, audited (abi3audit), repaired to manylinux, installed
without a compiler and run by tools/check_wheel.sh, a step of .ci/run (8 s of compiling: not
repeated here)."""

from __future__ import annotations

import ast
import importlib.util
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
COMPILER = shutil.which(os.environ.get("CC", "cc"))


def _setup_constant(name: str) -> str:
    """A constant of setup.py, read without running it."""
    tree = ast.parse((ROOT / "setup.py").read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == name for t in node.targets):
            return ast.literal_eval(node.value)
    raise LookupError(name)


def _extensions() -> list[tuple[str, Path]]:
    """(module name, C source) of every extension setup.py builds."""
    tree = ast.parse((ROOT / "setup.py").read_text(encoding="utf-8"))
    return [(call.args[0].value, ROOT / call.args[1].value) for call in ast.walk(tree)
            if isinstance(call, ast.Call) and getattr(call.func, "id", None) == "module"]


def test_every_c_file_is_an_extension_built_against_the_limited_api():
    assert _setup_constant("LIMITED_API") == "0x030B0000"  # Python 3.11, the oldest the package supports
    sources = {source for _, source in _extensions()}
    assert sources == set(ROOT.joinpath("upliftcli").rglob("_*.c"))


@pytest.mark.skipif(COMPILER is None, reason="no C compiler here")
@pytest.mark.parametrize(("name", "source"), _extensions(), ids=lambda item: str(item).rsplit(".", 1)[-1])
def test_each_loop_compiles_under_the_limited_api(name, source):
    """Under Py_LIMITED_API the headers declare only the stable ABI: a call outside it is an
    implicit declaration, an error here (the built wheel is audited too: tools/build_wheel.sh)."""
    command = [COMPILER, "-fsyntax-only", "-std=c99", "-Wall", "-Werror=implicit-function-declaration",
               f"-DPy_LIMITED_API={_setup_constant('LIMITED_API')}", f"-I{sysconfig.get_paths()['include']}",
               f"-I{ROOT / 'upliftcli' / 'compiled'}", str(source)]
    done = subprocess.run(command, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and not done.stderr, done.stderr


def test_the_built_loops_are_stable_abi_modules():
    """The loops of this install (built in place by `pip install -e .`, or by a wheel) carry the
    stable ABI's suffix, which every CPython from 3.11 on imports."""
    from upliftcli.runtime import backend

    built = backend.built()
    if not built:
        pytest.skip("the compiled loops are not built in this install (UPLIFT_BACKEND=numpy runs their twins)")
    for name in built:
        spec = importlib.util.find_spec(name)
        assert spec.origin.endswith((".abi3.so", ".pyd")), spec.origin


def test_without_a_compiler_the_wheel_is_pure_and_says_what_it_costs(tmp_path):
    """CC=/bin/false: every extension fails, the build says so in one line, and the wheel is
    py3-none-any with every module at its root and no extension (it was a cp311-cp311-linux
    wheel without them, claiming a platform and an ABI it does not need), and with the example
    decks and records (setup.py's BuildWithExamples). 3-4 s with pip's cache."""
    source = tmp_path / "source"
    shutil.copytree(ROOT, source, ignore=shutil.ignore_patterns(".venv", ".git", "build", "dist", "*.so", "*.pyd",
                                                                  "__pycache__", "*.egg-info", "tests", "benchmarks"))
    environment = {**os.environ, "CC": "/bin/false", "CXX": "/bin/false"}
    done = subprocess.run([sys.executable, "-m", "pip", "wheel", "-v", "--no-deps", "-w", str(tmp_path / "dist"),
                           str(source)], capture_output=True, text=True, env=environment, timeout=600)
    if done.returncode != 0 and "satisfies the requirement setuptools" in done.stdout + done.stderr:
        pytest.skip("pip cannot get the build requirement setuptools>=77 (offline, empty cache)")
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    output = (done.stdout + done.stderr).splitlines()
    said = [line for line in output if "uplift: the compiled loops were not built" in line]
    assert len(said) == 1 and "their numpy twins run instead" in said[0]
    wheels = list((tmp_path / "dist").glob("*.whl"))
    assert [wheel.name for wheel in wheels] == ["upliftcli-0.1.0-py3-none-any.whl"]
    with zipfile.ZipFile(wheels[0]) as wheel:
        names = wheel.namelist()
        metadata = wheel.read("upliftcli-0.1.0.dist-info/WHEEL").decode()
    assert "Root-Is-Purelib: true" in metadata and "Tag: py3-none-any" in metadata
    assert not [name for name in names if name.endswith((".so", ".pyd"))]
    assert "upliftcli/engines/exact/stepping_numpy.py" in names and "upliftcli/cli/__init__.py" in names
    assert not [name for name in names if ".data/" in name]
    # the example decks and records, as `uplift examples` writes them from a source checkout
    from upliftcli.runtime.examples import bundled_files

    packaged = sorted(name.removeprefix("upliftcli/examples/") for name in names
                      if name.startswith("upliftcli/examples/"))
    assert packaged == sorted(bundled_files(ROOT)) and "records/README.md" in packaged
    with zipfile.ZipFile(wheels[0]) as wheel:
        assert wheel.read("upliftcli/examples/inputs/ten_story_elcentro.toml") == \
            (ROOT / "inputs" / "ten_story_elcentro.toml").read_bytes()
