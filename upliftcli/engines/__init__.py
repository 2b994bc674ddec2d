"""Analysis engines: simplified (response spectrum), exact and approximate (response history)."""

from __future__ import annotations

from threadpoolctl import ThreadpoolController

_controller: ThreadpoolController | None = None


def one_blas_thread():
    """Context manager limiting BLAS to one thread.

    The engines multiply many small matrices; OpenBLAS threads on them cost up to 100x
    on a loaded 2-core machine. Parallelism belongs to the batch (sweep workers) instead.
    """
    global _controller
    if _controller is None:
        _controller = ThreadpoolController()
    return _controller.limit(limits=1, user_api="blas")
