"""Where numba keeps the compiled engine: next to the sources (numba's default, __pycache__) when
the installed package is writable, else a per-user cache directory, so that the compiled code
survives between runs of an installation the user cannot write to.

Numba falls back to its own user-wide directory (~/.cache/numba) in that case, and raises
"cannot cache function ... no locator available" at import when that is not writable either (a
service account without a home, a read-only container). configure() runs when the package is
imported, before anything imports numba, and sets NUMBA_CACHE_DIR only when the package
directory is not writable and the variable is not set: to $XDG_CACHE_HOME/uplift/numba (or
~/.cache/uplift/numba), else to a per-user directory under the temporary directory.
"""

from __future__ import annotations

import os
from collections.abc import Callable, MutableMapping
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent


def writable(directory: Path) -> bool:
    """Whether files can be created in `directory` (made if missing)."""
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError:
        return False
    return os.access(directory, os.W_OK | os.X_OK)


def candidates(environ: MutableMapping[str, str]) -> list[Path]:
    """Per-user cache directories, preferred first."""
    found = []
    home = environ.get("XDG_CACHE_HOME") or (str(Path(environ["HOME"]) / ".cache") if environ.get("HOME") else "")
    if home:
        found.append(Path(home) / "uplift" / "numba")
    user = os.getuid() if hasattr(os, "getuid") else environ.get("USERNAME", "user")
    temporary = environ.get("TMPDIR") or environ.get("TEMP") or environ.get("TMP") or "/tmp"
    found.append(Path(temporary) / f"uplift-{user}" / "numba")
    return found


def configure(environ: MutableMapping[str, str] | None = None, package: Path = PACKAGE,
              can_write: Callable[[Path], bool] = writable) -> Path | None:
    """Set NUMBA_CACHE_DIR in `environ` (os.environ) if the package directory is not writable
    and it is not set; return the directory chosen (None: numba's default is kept)."""
    environ = os.environ if environ is None else environ
    if environ.get("NUMBA_CACHE_DIR") or can_write(package / "__pycache__"):
        return None
    for directory in candidates(environ):
        if can_write(directory):
            environ["NUMBA_CACHE_DIR"] = str(directory)
            return directory
    return None
