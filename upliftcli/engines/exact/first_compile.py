"""The first run after an install: the compiled loops are compiled in two processes at once.

numba compiles a loop on its first call and keeps the machine code in its cache (__pycache__
beside the module, or numba's user cache directory); later processes load it. One process
compiles serially (numba holds a global lock): about 2.5 s for the stepping loop
(stepping_kernels.integrate) and 3 s for the three post-processing loops on 2 cores. When the
post-processing loops are not in the cache, `start` launches a child process that compiles
them from their signatures while this process compiles the stepping loop and steps; `join`,
before the first post-processing call, waits for the child, and the loops are then loaded from
the cache. If the child fails, this process compiles them itself: the same machine code either
way, so results do not depend on it. See docs/exact-engine.md ("Compiled loops").
"""

from __future__ import annotations

import multiprocessing
import os
import subprocess
import sys
from pathlib import Path

from numba import types

from . import response_kernels

_F1, _F2, _F3 = types.float64[::1], types.float64[:, ::1], types.float64[:, :, ::1]
_I1, _B2, _INT = types.int64[::1], types.bool_[:, ::1], types.int64

#: the signature each post-processing loop is called with (response.py, energy.py); a test
#: checks that a run after the child finds every one of them in the cache
SIGNATURES = {
    "evaluate_signals": (_F2, _I1, _F3, _F2, _F2, _F2),
    "hermite_peaks": (_F2, _F2, _F2, _F2, _I1, _I1, _I1, _I1, _F2, _F1, _F1),
    "work_integrals": (_F2, _F2, _I1, _F2, _F2, _F1, _B2, *(_INT,) * 8, _F1, _F1, _F1),
}

#: the child waits at most this long [s] before this process compiles the loops itself
TIMEOUT = 300.0

_child: subprocess.Popen | None = None
_started = False
#: the loops this process asked a child to compile (empty: none was started)
launched: tuple[str, ...] = ()


def _cached(name: str) -> bool:
    """Whether the cache holds an index for the loop (numba's internals: when they differ,
    the loop counts as cached and compiles on its first call, as without this module)."""
    try:
        return os.path.exists(getattr(response_kernels, name)._cache._cache_file._index_path)
    except (AttributeError, TypeError):
        return True


def start() -> None:
    """Launch the child compiling the post-processing loops that are not cached, once per
    process and only in a main process: `uplift analyze`, or the warm server of local sweep
    workers (sweep/warm.py); the workers themselves (multiprocessing or Dask children) start none."""
    global _child, _started, launched
    if _started:
        return
    _started = True
    missing = [name for name in SIGNATURES if not _cached(name)]
    if not missing or multiprocessing.parent_process() is not None:
        return
    try:
        # the child imports this very package (its cache is keyed by the source files)
        package_root = str(Path(__file__).resolve().parents[3])
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, (package_root, os.environ.get("PYTHONPATH"))))}
        code = f"from {__name__} import compile_loops; compile_loops({missing!r})"
        _child = subprocess.Popen([sys.executable, "-c", code], env=env, stdin=subprocess.DEVNULL,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except OSError:
        return
    launched = tuple(missing)


def join() -> None:
    """Wait for the child, if one was started (after it the loops load from the cache)."""
    global _child
    child, _child = _child, None
    if child is None:
        return
    try:
        child.wait(timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        child.kill()
        child.wait()


def compile_loops(names: list[str]) -> None:
    """Compile (and cache) the named post-processing loops from their signatures."""
    for name in names:
        getattr(response_kernels, name).compile(SIGNATURES[name])
