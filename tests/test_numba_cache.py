"""Where numba's compiled code goes (upliftcli.numba_cache): next to the sources when the package
is writable, else a per-user cache directory (the first writable one), never over the user's choice."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from upliftcli import numba_cache


def only(*allowed: Path):
    """A writability test that allows only these directories (root writes everywhere)."""
    return lambda directory: any(directory == a for a in allowed)


def test_writable_package_keeps_numbas_default(tmp_path):
    environ = {"HOME": str(tmp_path)}
    assert numba_cache.configure(environ, tmp_path / "pkg", only(tmp_path / "pkg" / "__pycache__")) is None
    assert "NUMBA_CACHE_DIR" not in environ


def test_read_only_package_caches_under_the_users_cache_directory(tmp_path):
    environ = {"HOME": str(tmp_path / "home")}
    chosen = numba_cache.configure(environ, tmp_path / "pkg", only(tmp_path / "home" / ".cache" / "uplift" / "numba"))
    assert chosen == tmp_path / "home" / ".cache" / "uplift" / "numba"
    assert environ["NUMBA_CACHE_DIR"] == str(chosen)
    environ = {"HOME": str(tmp_path / "home"), "XDG_CACHE_HOME": str(tmp_path / "xdg")}
    assert numba_cache.configure(environ, tmp_path / "pkg", only(tmp_path / "xdg" / "uplift" / "numba"))


def test_no_home_falls_back_to_the_temporary_directory(tmp_path):
    environ = {"HOME": "/nonexistent", "TMPDIR": str(tmp_path)}
    candidates = numba_cache.candidates(environ)
    chosen = numba_cache.configure(environ, tmp_path / "pkg", only(candidates[-1]))
    assert chosen == candidates[-1] and chosen.is_relative_to(tmp_path)


def test_the_users_setting_wins_and_nothing_writable_changes_nothing(tmp_path):
    environ = {"NUMBA_CACHE_DIR": "/mine", "HOME": str(tmp_path)}
    assert numba_cache.configure(environ, tmp_path / "pkg", only()) is None
    assert environ["NUMBA_CACHE_DIR"] == "/mine"
    environ = {"HOME": str(tmp_path)}
    assert numba_cache.configure(environ, tmp_path / "pkg", only()) is None and "NUMBA_CACHE_DIR" not in environ


def test_writable_creates_the_directory(tmp_path):
    assert numba_cache.writable(tmp_path / "a" / "b")
    assert (tmp_path / "a" / "b").is_dir()
    (tmp_path / "file").write_text("x")
    assert not numba_cache.writable(tmp_path / "file" / "below")


def test_numba_compiles_into_the_chosen_directory(tmp_path):
    """End to end in a fresh interpreter: the package taken as read-only, the chosen per-user
    directory receives numba's cache of a compiled function (and importing the package loads no numba)."""
    probe = """
import os, sys
from pathlib import Path
import upliftcli
from upliftcli import numba_cache
assert "numba" not in sys.modules
os.environ.pop("NUMBA_CACHE_DIR", None)
os.environ.pop("XDG_CACHE_HOME", None)
os.environ["HOME"] = sys.argv[1]
read_only = numba_cache.PACKAGE / "__pycache__"
chosen = numba_cache.configure(can_write=lambda d: d != read_only and numba_cache.writable(d))
import numpy as np
from upliftcli.motion.spectra import sdof_history
sdof_history(np.zeros(3), 0.01, 1.0, 0.05)
print(chosen, len(list(Path(chosen).rglob("*.nbi"))))
"""
    done = subprocess.run([sys.executable, "-c", probe, str(tmp_path)], capture_output=True, text=True, check=True)
    chosen, count = done.stdout.split()
    assert Path(chosen) == tmp_path / ".cache" / "uplift" / "numba"
    assert int(count) >= 1
