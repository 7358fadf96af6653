"""The numba import with its fallback: ``njit`` and ``prange`` become no-ops where numba is
missing (the compiled paths, :mod:`imagespace.solve.kernel`, are then not used).

``njit(cache=True)`` falls back to uncached compilation where numba finds no writable place for
its cache (a read-only install with ``HOME`` unset or unwritable: numba raises
``RuntimeError: cannot cache function ...: no locator available``), so ``import imagespace``
works when nothing is writable.
"""

from __future__ import annotations

import itertools
import os
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


#: Parts per thread a batch is cut into by :func:`run_parts` (a speed knob: the balance of the
#: threads' loads against the cost of handing a part to a thread, tens of microseconds)
PARTS_PER_THREAD = 4
#: Rows below which a part is not split further (a speed knob: ~0.15 ms of planar kernel work)
MIN_PART_ROWS = 64


_POOLS: dict[tuple[int, int], Any] = {}   # thread pools per (process, threads): a forked child makes its own


def _pool(threads):
    """This process's pool of ``threads`` helper threads for :func:`run_parts`."""
    from concurrent.futures import ThreadPoolExecutor

    key = (os.getpid(), threads)
    if key not in _POOLS:
        _POOLS[key] = ThreadPoolExecutor(max_workers=threads, thread_name_prefix="imagespace-kernel")
    return _POOLS[key]


def run_parts(loop, items, *args, rows_per_item=1):
    """Run a compiled loop over ``items`` (blocks or rows) on numba's number of threads.

    The loops are serial functions of a range ``[a, b)`` of their items, compiled with
    ``nogil``; the items are cut into at most :data:`PARTS_PER_THREAD` parts per thread, which
    this thread and a pool of ``threads - 1`` Python threads take one by one. (A
    ``parallel=True`` loop over the same parts computes the same answers, but numba's parallel
    lowering compiles the whole inlined pipeline of the loop's body once more: ~30 s for the
    planar lockstep loop, once per installation, in front of a user's first batch.)
    ``numba.set_num_threads`` and ``NUMBA_NUM_THREADS`` set the number of threads, as for
    numba's own parallel loops.

    Parameters
    ----------
    loop : callable
        A compiled loop ``loop(*args, a, b)``.
    items : int
    *args
        The loop's other arguments.
    rows_per_item : int
        Rows of an item (a block's rows for the lockstep loops): parts hold at least
        :data:`MIN_PART_ROWS` rows.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core._numba import run_parts
    >>> out = np.zeros(10)
    >>> def fill(o, a, b):
    ...     o[a:b] = np.arange(a, b)
    >>> run_parts(fill, 10, out, rows_per_item=1000)
    >>> out.tolist() == list(range(10))
    True
    """
    threads = _threads()
    parts = min(items // max(1, MIN_PART_ROWS // rows_per_item), threads * PARTS_PER_THREAD)
    if parts > threads:               # whole rounds of parts: no thread left with one part more
        parts -= parts % threads
    if threads == 1 or parts <= 1:
        loop(*args, 0, items)
        return
    cuts = [items * k // parts for k in range(parts + 1)]
    taken = itertools.count()          # next() of a count is atomic: each part is run once

    def work():
        k = next(taken)
        while k < parts:
            loop(*args, cuts[k], cuts[k + 1])
            k = next(taken)

    helpers = [_pool(threads - 1).submit(work) for _ in range(threads - 1)]
    work()                             # this thread takes parts too (no wait for a helper's start)
    for f in helpers:
        f.result()


def _threads():
    """numba's number of threads (1 without numba)."""
    if _numba_njit is None:  # pragma: no cover - exercised only where numba is missing
        return 1
    import numba

    return max(1, int(numba.get_num_threads()))


__all__ = ["njit", "prange", "HAVE_NUMBA", "run_parts", "PARTS_PER_THREAD", "MIN_PART_ROWS"]
