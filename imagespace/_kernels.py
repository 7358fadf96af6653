"""The numba import with its fallback: ``njit`` and ``prange`` become no-ops where numba is
missing (the compiled paths, :mod:`imagespace.fastdk`, are then not used)."""

from __future__ import annotations

try:  # numba is optional: without it the decorators leave plain Python functions
    from numba import njit, prange
    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - exercised only where numba is missing
    HAVE_NUMBA = False
    prange = range

    def njit(*args, **kwargs):
        def wrap(f):
            return f
        return wrap(args[0]) if args and callable(args[0]) else wrap

__all__ = ["njit", "prange", "HAVE_NUMBA"]
