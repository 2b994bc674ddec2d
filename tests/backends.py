"""Run a call on both backends of the loops (upliftcli.runtime.backend) in one process."""

from __future__ import annotations

import pytest

from upliftcli.runtime import backend


def compiled_or_skip() -> None:
    """Skip the test where the C extensions were not built (nothing to compare the twins with)."""
    missing = sorted(set(backend.EXTENSIONS) - set(backend.built()))
    if missing:
        pytest.skip(f"the C extensions were not built: {', '.join(missing)}")


def on_both(call):
    """(call() on the compiled loops, call() on the numpy twins)."""
    compiled_or_skip()
    with backend.use("compiled"):
        compiled = call()
    with backend.use("numpy"):
        twin = call()
    return compiled, twin
