"""Long exact computations that Ctrl-C can stop.

python-flint holds Python's global interpreter lock inside a FLINT call, so neither a signal
handler nor another thread runs until the call returns: a root isolation on numbers of thousands
of digits ignores Ctrl-C for as long as it takes. :func:`call_interruptibly` runs such a call in
a forked child process instead; the parent waits on a pipe in slices of
:data:`WAIT_SLICE_SECONDS`, so a ``KeyboardInterrupt`` (or the optional deadline) reaches it at
once, kills the child and is raised in the caller. Small calls run inline (a fork costs a few
milliseconds); callers decide which calls are large from the size of their input.

The child runs only the given function on already-imported modules and leaves through
``os._exit``; it never takes a lock another thread of the parent may hold (python-flint's
precision lock included: pass the precision as an argument). Where ``fork`` is not available (or
not on Linux) the call runs inline.
"""

from __future__ import annotations

import os
import pickle
import select
import signal
import sys
import time
import warnings
from typing import Any, Callable, Optional

from ..exceptions import ImageSpaceError, InputError

__all__ = ["WAIT_SLICE_SECONDS", "ComputationTimeoutError", "call_interruptibly", "can_fork"]

#: Seconds between two looks of the waiting parent at its signals: the bound on how late a
#: Ctrl-C arrives while a child computes. A responsiveness knob, decides nothing.
WAIT_SLICE_SECONDS = 0.05


class ComputationTimeoutError(ImageSpaceError, TimeoutError):
    """A computation run by :func:`call_interruptibly` passed its deadline (the child is killed)."""


def can_fork() -> bool:
    """True where :func:`call_interruptibly` runs calls in a child process (Linux with fork).

    Examples
    --------
    >>> from imagespace.core.interruptible import can_fork
    >>> can_fork() in (True, False)
    True
    """
    return hasattr(os, "fork") and sys.platform.startswith("linux")


def _child(fn, args, w):
    """In the forked child: compute, send ``(ok, value)`` pickled through ``w``, leave."""
    code = 0
    try:
        signal.signal(signal.SIGINT, signal.SIG_DFL)        # the parent owns Ctrl-C
        try:
            payload = pickle.dumps((True, fn(*args)), protocol=pickle.HIGHEST_PROTOCOL)
        except BaseException as exc:                        # noqa: BLE001 - sent to the parent
            try:
                payload = pickle.dumps((False, exc), protocol=pickle.HIGHEST_PROTOCOL)
            except Exception:                               # an exception that does not pickle
                payload = pickle.dumps((False, RuntimeError(f"{type(exc).__name__}: {exc}")))
        view = memoryview(payload)
        while view:
            view = view[os.write(w, view):]
    except BaseException:                                   # noqa: BLE001 - never return
        code = 1
    finally:
        os._exit(code)


def _reap(pid, kill):
    if kill:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    while True:
        try:
            os.waitpid(pid, 0)
            return
        except ChildProcessError:
            return
        except InterruptedError:
            continue


def call_interruptibly(fn: Callable, args: tuple = (), *, in_child: bool = True,
                       timeout: Optional[float] = None) -> Any:
    """``fn(*args)``, computed where Ctrl-C and a deadline can stop it.

    Parameters
    ----------
    fn : callable
        A module-level function; its result (and any exception it raises) must pickle.
    args : tuple
        Its arguments.
    in_child : bool
        Run in a forked child process (default). False runs ``fn(*args)`` inline: for calls the
        caller knows to be short.
    timeout : float, optional
        Seconds before the child is killed and :class:`ComputationTimeoutError` raised (None: no
        deadline). Only for calls in a child.

    Returns
    -------
    The value of ``fn(*args)``.

    Raises
    ------
    KeyboardInterrupt
        Ctrl-C while the child computes: the child is killed first.
    ComputationTimeoutError
        The deadline passed.
    Exception
        Whatever ``fn`` raised (re-raised in the caller).

    Examples
    --------
    >>> from imagespace.core.interruptible import call_interruptibly
    >>> call_interruptibly(pow, (3, 4))
    81
    >>> call_interruptibly(divmod, (7, 2), in_child=False)
    (3, 1)
    """
    if timeout is not None and not (isinstance(timeout, (int, float)) and timeout > 0):
        raise InputError(f"timeout must be a positive number of seconds or None, got {timeout!r}")
    if not in_child or not can_fork():
        return fn(*args)
    r, w = os.pipe()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)   # fork in a threaded process
        pid = os.fork()
    if pid == 0:                                               # pragma: no cover - the child
        os.close(r)
        _child(fn, args, w)
    os.close(w)
    chunks, done = [], False
    deadline = None if timeout is None else time.monotonic() + timeout
    try:
        while True:
            if deadline is not None and time.monotonic() > deadline:
                raise ComputationTimeoutError(
                    f"{getattr(fn, '__name__', 'the computation')} did not finish within "
                    f"timeout={timeout} s; it was stopped")
            ready, _, _ = select.select([r], [], [], WAIT_SLICE_SECONDS)
            if not ready:
                continue
            data = os.read(r, 1 << 20)
            if not data:
                break
            chunks.append(data)
        done = True
    finally:
        os.close(r)
        _reap(pid, kill=not done)
    if not chunks:
        raise RuntimeError(f"the child process computing {getattr(fn, '__name__', fn)} died "
                           "without an answer")
    ok, value = pickle.loads(b"".join(chunks))
    if ok:
        return value
    raise value
