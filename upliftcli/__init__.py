"""uplift: earthquake response of multistory buildings whose foundation mat may lift off
(Yim & Chopra). See README.md; the command line is upliftcli.cli."""

from .numba_cache import configure as _configure_numba_cache

_configure_numba_cache()  # before anything imports numba: a writable compile cache (numba_cache.py)
