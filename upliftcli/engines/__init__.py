"""Analysis engines: simplified (response spectrum), exact and approximate (response history)."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import TypeVar

from threadpoolctl import ThreadpoolController

F = TypeVar("F", bound=Callable)
_controller: ThreadpoolController | None = None


def single_threaded_blas(function: F) -> F:
    """Run `function` with BLAS limited to one thread.

    The engines multiply many small matrices; OpenBLAS threads on them cost up to 100x
    on a loaded 2-core machine. Parallelism belongs to the batch (sweep workers) instead.
    """

    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        global _controller
        if _controller is None:
            _controller = ThreadpoolController()
        with _controller.limit(limits=1, user_api="blas"):
            return function(*args, **kwargs)

    return wrapper  # type: ignore[return-value]
