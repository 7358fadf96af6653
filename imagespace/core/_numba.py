"""The numba import with its fallback: ``njit`` and ``prange`` become no-ops where numba is
missing (the compiled paths, :mod:`imagespace.solve.kernel`, are then not used).

``njit(cache=True)`` falls back to uncached compilation where numba finds no writable place for
its cache (a read-only install with ``HOME`` unset or unwritable: numba raises
``RuntimeError: cannot cache function ...: no locator available``), so ``import imagespace``
works when nothing is writable.
"""

from __future__ import annotations

from typing import Any, Callable, Optional

_numba_njit: Optional[Callable[..., Any]]  # numba's njit, or None without numba
prange: Callable[..., Any]  # numba's prange, or range without numba
try:  # numba is optional: without it the decorators leave plain Python functions
    from numba import njit as _numba_njit, prange
    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - exercised only where numba is missing
    HAVE_NUMBA = False
    prange = range
    _numba_njit = None

# the start of numba's message when no cache locator is available for a function's file
_NO_LOCATOR = "cannot cache function"


def njit(*args, **kwargs):
    """numba's ``njit``; with ``cache=True``, uncached where numba has nowhere to cache.

    Without numba the decorated function is returned unchanged.

    Examples
    --------
    >>> from imagespace.core._numba import njit
    >>> @njit(cache=True)
    ... def twice(x):
    ...     return 2 * x
    >>> twice(21)
    42
    """
    if _numba_njit is None:  # pragma: no cover - exercised only where numba is missing
        def plain(f):
            return f
        return plain(args[0]) if args and callable(args[0]) else plain
    if not kwargs.get("cache"):
        return _numba_njit(*args, **kwargs)

    def wrap(f):
        try:
            return _numba_njit(**kwargs)(f)
        except RuntimeError as exc:
            if _NO_LOCATOR not in str(exc):
                raise
            return _numba_njit(**dict(kwargs, cache=False))(f)

    return wrap(args[0]) if args and callable(args[0]) else wrap


__all__ = ["njit", "prange", "HAVE_NUMBA"]
