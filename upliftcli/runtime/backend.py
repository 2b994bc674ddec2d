"""Which implementation runs the compiled loops: the C extension modules where they were built at
install, else their numpy twins (docs/exact-engine.md, "Compiled loops").

Each C module has a twin module with the same functions taking the same arguments (outputs
written in place the same way); the two agree to round-off (tests/test_backend_agreement.py).
A module that calls a loop asks for the module that runs it at the call:

    backend.loops("upliftcli.engines.exact._stepping", "upliftcli.engines.exact.stepping_numpy").integrate(...)

so that both backends are served and a test can switch between them in one process (`use`).
$UPLIFT_BACKEND chooses: unset or "auto" (the C loop where it imports, else the twin),
"compiled" (the C loops; an error naming the missing module where one was not built), "numpy"
(the twins, whatever was built).
"""

from __future__ import annotations

import importlib
import importlib.machinery
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from types import ModuleType

from ..errors import InputError

VARIABLE = "UPLIFT_BACKEND"
CHOICES = ("auto", "compiled", "numpy")
#: the C extension modules of the package (setup.py builds them)
EXTENSIONS = ("upliftcli.engines.exact._stepping", "upliftcli.engines.exact._signals",
              "upliftcli.engines.exact._peaks", "upliftcli.engines.exact._contact",
              "upliftcli.engines.exact._energy", "upliftcli.engines.exact._levels",
              "upliftcli.engines.exact._soil_states", "upliftcli.engines.exact._soil_operators",
              "upliftcli.motion._spectra")

_chosen: list[str] = []  # the choice of `use`, innermost last
_imported: dict[str, ModuleType | ImportError] = {}


def choice() -> str:
    """The backend asked for: that of `use`, else $UPLIFT_BACKEND, else "auto"."""
    if _chosen:
        return _chosen[-1]
    wanted = os.environ.get(VARIABLE, "").strip().lower() or "auto"
    if wanted not in CHOICES:
        raise InputError(VARIABLE, None, f"one of {', '.join(CHOICES)} (or unset), got {wanted!r}")
    return wanted


def _module(name: str) -> ModuleType | ImportError:
    if name not in _imported:
        try:
            _imported[name] = importlib.import_module(name)
        except ImportError as error:
            _imported[name] = error
    return _imported[name]


def loops(extension: str, twin: str) -> ModuleType:
    """The module that runs a loop: the C extension `extension` or its numpy twin module `twin`,
    as choice() says. "compiled" with `extension` not importable raises InputError (exit code 2)."""
    wanted = choice()
    if wanted != "numpy":
        found = _module(extension)
        if isinstance(found, ModuleType):
            return found
        if wanted == "compiled":
            raise InputError(VARIABLE, None, f"'compiled' needs the C extension {extension}, which was not built "
                             f"({found}): reinstall upliftcli where a C compiler works, or unset {VARIABLE}")
    twin_module = _module(twin)
    if isinstance(twin_module, ImportError):
        raise twin_module
    return twin_module


def built() -> list[str]:
    """The C extension modules present next to the package's sources (found on disk, not imported)."""
    root = Path(__file__).resolve().parents[2]
    suffixes = importlib.machinery.EXTENSION_SUFFIXES
    return [name for name in EXTENSIONS
            if any((root / (name.replace(".", os.sep) + suffix)).is_file() for suffix in suffixes)]


def in_use() -> str:
    """The loops a run uses now, in one word for the provenance record: "compiled" (every C
    extension), "numpy" (the twins) or "compiled, numpy for <modules>" (some not built)."""
    present = built()
    if choice() == "numpy" or not present:
        return "numpy"
    missing = _missing(present)
    return "compiled" if not missing else f"compiled, numpy for {', '.join(missing)}"


def _missing(present: list[str]) -> list[str]:
    """The short names of the C extensions that are not among those built (present)."""
    return [name.rsplit(".", 1)[1] for name in EXTENSIONS if name not in present]


def describe() -> str:
    """One line for `uplift --version`: the backend in use and why."""
    wanted = choice()
    present = built()
    if wanted == "numpy":
        return f"loops: numpy twins ({VARIABLE}=numpy)"
    if len(present) == len(EXTENSIONS):
        return "loops: compiled (C extensions)"
    missing = _missing(present)
    if wanted == "compiled":
        return f"loops: compiled asked for, but not built: {', '.join(missing)}"
    which = "" if not present else f" for {', '.join(missing)}"
    return (f"loops: numpy twins{which} (the C extensions were not built: the same results to round-off in "
            "1.5-6x the time; reinstall where a C compiler works to build them)")


@contextmanager
def use(name: str) -> Iterator[None]:
    """Run the loops on backend `name` ("auto", "compiled", "numpy") inside the block (tests,
    benchmarks: both backends in one process)."""
    if name not in CHOICES:
        raise ValueError(f"backend must be one of {', '.join(CHOICES)}, got {name!r}")
    _chosen.append(name)
    try:
        yield
    finally:
        _chosen.pop()
