"""Design sweeps and the fuzzy min-max optimal design of seed 004.

:func:`sweep` evaluates any function ``f(**params) -> dict of numbers`` over a grid of design
parameters: serially by default (a tqdm progress bar), in ``processes=N`` local processes
(``concurrent.futures`` with cloudpickled payloads, so notebook-defined functions and unguarded
scripts work), or on a Dask cluster when given a ``dask.distributed.Client`` (install
``imagespace[dask]``). The rows come back in grid order whichever way they ran; a failing design
raises with its parameters named (``on_error="raise"``) or is recorded in the table
(``on_error="record"``), never discarding the finished rows.

:func:`fuzzy_minmax` is Choi's composite index: each index is normalised over the grid to
``u in [0, 1]`` (1 = the best design for that index; ``"max"`` or ``"min"`` says which is better),
weighted to the membership ``z = 1 + g (u - 1)`` (weight ``g in [0, 1]``: ``g = 0`` ignores the
index), and ``W_c = min z`` over the indices; the optimum maximises ``W_c``.

References
----------
Choi (seed 004): kinematic analysis and optimal design of the 3-PPR planar manipulator, KSME 2003.
"""

from __future__ import annotations

import itertools
import sys
import threading
import types
from collections.abc import Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Optional

import numbers

import numpy as np

from .._validate import _short, as_count, as_flag
from ..exceptions import ImageSpaceError, InputError, InputTypeError
from .._validate import as_tolerances as check_tolerances
from .._html import dataclass_html, dataclass_repr, fmt, html_table, summary

__all__ = ["DesignTable", "DesignEvaluationError", "sweep", "fuzzy_minmax", "FuzzyResult"]


@dataclass(frozen=True)
class DesignTable:
    """The result of a sweep: one row per design, in grid order.

    Attributes
    ----------
    params : dict of (n,) arrays
        The design parameters of every row.
    values : dict of (n,) float arrays
        The function's outputs.
    shape : tuple
        The grid's shape (one axis per parameter, in the order given).
    how : str
        ``"serial"``, ``"processes (k)"`` or ``"dask (address)"``.
    errors : (n,) object array of str
        Why each row failed (``""`` for a good row; a failed row's values are NaN). Only a sweep
        with ``on_error="record"`` returns failed rows.
    """

    params: dict
    values: dict
    shape: tuple
    how: str
    errors: Optional[np.ndarray] = None

    def __post_init__(self):
        n = int(np.prod(self.shape))
        errs = np.full(n, "", dtype=object) if self.errors is None else np.asarray(self.errors, dtype=object)
        object.__setattr__(self, "errors", errs)

    @property
    def failed(self):
        """The rows that failed (indices in grid order).

        Examples
        --------
        >>> from imagespace.design.sweep import sweep, _demo_index
        >>> sweep(_demo_index, {"a": [1, 2], "b": [0, 1]}).failed
        []
        """
        return [i for i, e in enumerate(self.errors) if e]

    def grid(self, name):
        """A value reshaped to the grid, ``shape``.

        Raises
        ------
        InputError
            If ``name`` is not one of the table's values.

        Examples
        --------
        >>> from imagespace.design.sweep import sweep, _demo_index
        >>> t = sweep(_demo_index, {"a": [1, 2], "b": [0, 1, 2]}, processes=0)
        >>> t.grid("sum").tolist()
        [[1.0, 2.0, 3.0], [2.0, 3.0, 4.0]]
        """
        try:
            values = self.values[name]
        except (KeyError, TypeError):
            raise InputError(f"name must be one of the table's values {sorted(self.values)}, got {_short(name)}") from None
        return np.asarray(values).reshape(self.shape)

    def equals(self, other):
        """True if both tables hold the same rows and values (exactly)."""
        return (self.shape == other.shape and self.params.keys() == other.params.keys()
                and all(np.array_equal(self.params[k], other.params[k]) for k in self.params)
                and self.values.keys() == other.values.keys()
                and all(np.array_equal(self.values[k], other.values[k], equal_nan=True) for k in self.values)
                and np.array_equal(self.errors, other.errors))

    def _summary_rows(self):
        def span(a):
            a = np.asarray(a)
            if a.size == 0 or a.dtype.kind not in "biuf" or not np.isfinite(a.astype(float)).any():
                return f"{a.size} values"
            return f"[{fmt(np.nanmin(a))}, {fmt(np.nanmax(a))}]"

        rows = [("rows", int(np.prod(self.shape))), ("shape", str(tuple(self.shape))), ("how", self.how),
                ("failed rows", len(self.failed))]
        rows += [(f"param {k}", span(v)) for k, v in self.params.items()]
        rows += [(f"value {k}", span(v)) for k, v in self.values.items()]
        return rows

    def __repr__(self):
        """Rows, grid shape, how it ran, failures and the range of every parameter and value.

        Examples
        --------
        >>> from imagespace.design.sweep import sweep, _demo_index
        >>> sweep(_demo_index, {"a": [1, 2], "b": [0, 1, 2]}, processes=0)
        DesignTable(rows=6, shape=(2, 3), how='serial', failed=0, params={'a': [1, 2], 'b': [0, 2]},
                    values={'sum': [1, 4], 'product': [0, 4]})
        """
        rows = self._summary_rows()
        params = ", ".join(f"{k[6:]!r}: {v}" for k, v in rows[4:4 + len(self.params)])
        values = ", ".join(f"{k[6:]!r}: {v}" for k, v in rows[4 + len(self.params):])
        if len(params) > 2 * 80:
            params = f"{len(self.params)} names"
        if len(values) > 2 * 80:
            values = f"{len(self.values)} names"
        return summary("DesignTable", [("rows", str(rows[0][1])), ("shape", rows[1][1]), ("how", repr(self.how)),
                                       ("failed", str(rows[3][1])), ("params", "{" + params + "}"),
                                       ("values", "{" + values + "}")])

    def _repr_html_(self):
        """The summary as an HTML table (the range ``[min, max]`` of every parameter and value).

        Examples
        --------
        >>> from imagespace.design.sweep import sweep, _demo_index
        >>> "value sum" in sweep(_demo_index, {"a": [1, 2], "b": [0, 1]}, processes=0)._repr_html_()
        True
        """
        return html_table(self._summary_rows(), title="DesignTable")


class DesignEvaluationError(ImageSpaceError, RuntimeError):
    """A design of a :func:`sweep` failed (``on_error="raise"``).

    The message names the failing design's parameters and the original exception is chained
    (``__cause__``). Nothing finished is lost: ``table`` holds every row computed before the
    sweep stopped (see :class:`DesignTable` ``errors`` for the rows that failed or did not run).

    Attributes
    ----------
    params : dict
        The failing design's parameters.
    index : int
        Its row in grid order.
    table : DesignTable
        The finished rows (the others NaN, with their ``errors`` entry set).
    """

    def __init__(self, message, params=None, index=None, table=None):
        super().__init__(message)
        self.params = params
        self.index = index
        self.table = table


class _RemoteTraceback(Exception):
    """The traceback of an exception raised in a worker process (chained as its cause)."""

    def __init__(self, tb):
        super().__init__(tb)
        self.tb = tb

    def __str__(self):
        return self.tb


def _demo_index(a, b):
    """A tiny index function for examples and tests (module level: picklable)."""
    return {"sum": float(a + b), "product": float(a * b)}


def _as_number(v):
    """``float(v)`` for a real scalar; None for anything else (strings, complex, arrays, None)."""
    if isinstance(v, (str, bytes)) or v is None:
        return None
    try:
        a = np.asarray(v)
        if a.ndim != 0 or np.iscomplexobj(a):
            return None
        return float(v)
    except (TypeError, ValueError, OverflowError):
        return None


def _check_output(out):
    """``(dict of floats, None)`` for a valid task output, else ``(None, what is wrong)``."""
    if not isinstance(out, Mapping):
        return None, f"returned {type(out).__name__} {out!r:.80}, not a dict of numbers"
    values = {}
    for k, v in out.items():
        x = _as_number(v)
        if x is None:
            return None, f"returned a non-number for {k!r}: {type(v).__name__} {v!r:.80}"
        values[k] = x
    return values, None


def _evaluate(func, kw):
    """One design: ``(values, None, None)``, or ``(None, message, exception or None)``."""
    try:
        out = func(**kw)
    except (Exception, SystemExit) as e:  # noqa: BLE001 -- reported per design, chained when raised
        # a design calling sys.exit() is that design's failure, not the sweep's end
        return None, f"{type(e).__name__}: {e}", e
    values, problem = _check_output(out)
    return values, problem, None


def _evaluate_remote(func_blob, kws_blob):
    """Worker side: a chunk of designs from cloudpickled payloads; exceptions travel as data."""
    import traceback

    import cloudpickle

    func = cloudpickle.loads(func_blob)
    out = []
    for kw in cloudpickle.loads(kws_blob):
        values, message, exc = _evaluate(func, kw)
        if exc is None:
            out.append((values, message, None, None))
            continue
        tb = "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))
        try:
            blob = cloudpickle.dumps(exc)
        except Exception:  # noqa: BLE001 -- an unpicklable exception still reports its text
            blob = None
        out.append((None, message, blob, tb))
    return out


def _revive(blob, message, tb):
    """The worker's exception (its remote traceback chained), or a RuntimeError with its text."""
    import cloudpickle

    exc = None
    if blob is not None:
        try:
            exc = cloudpickle.loads(blob)
        except Exception:  # noqa: BLE001
            exc = None
    if not isinstance(exc, BaseException):
        exc = RuntimeError(message)
    if tb:
        exc.__cause__ = _RemoteTraceback(tb)
    return exc


@contextmanager
def _main_not_reimported():
    """Start spawned workers without re-running the user's ``__main__`` (script or notebook).

    ``spawn`` re-imports the main script in every worker, which runs an unguarded script's
    top level again (multiprocessing's bootstrapping error). Payloads are cloudpickled by value,
    so the workers never need ``__main__``: it is hidden while they start.
    """
    main = sys.modules.get("__main__")
    stub = types.ModuleType("__main__")
    with _MAIN_LOCK:
        sys.modules["__main__"] = stub
        try:
            yield
        finally:
            if sys.modules.get("__main__") is stub:
                sys.modules["__main__"] = main


_MAIN_LOCK = threading.Lock()


def _plain(v):
    return v.item() if isinstance(v, np.generic) else v


MAX_PROCESSES = 1024
"""The largest number of local worker processes :func:`sweep` starts."""


def sweep(func, grid, client=None, processes=None, progress=None, chunksize=1, on_error="raise"):
    """Evaluate ``func(**params)`` over every combination of the grid's parameter values.

    Serial by default. Parallelism is opt-in: ``processes=N`` local worker processes, or a Dask
    ``client``. Functions are shipped by value (cloudpickle), so a function defined in a notebook
    cell, a closure, or a script without an ``if __name__ == "__main__"`` guard works in both.
    One failing design never discards the others.

    Parameters
    ----------
    func : callable
        ``func(**params)`` returns a dict name -> real number, with the same names for every
        design.
    grid : dict of name -> sequence
        Each parameter's values; the grid is their Cartesian product (row-major).
    client : dask.distributed.Client, optional
        Run on this cluster (install ``imagespace[dask]``); takes precedence over ``processes``.
    processes : int or None
        ``None`` or ``0`` (default): serial in this process; ``N >= 1``: ``N`` local worker
        processes (spawned; workers do not re-run the caller's ``__main__``).
    progress : bool or None
        tqdm bar (``None``: shown after a second).
    chunksize : int
        Designs per task sent to a worker.
    on_error : {"raise", "record"}
        What a failing design does. A design fails when ``func`` raises, or returns something
        other than a dict of real numbers (a string, None, complex, an array...), or returns
        other names than most designs do (a missing or an extra key; ties go to the names of the
        first such design in grid order).

        - ``"raise"`` (default): stop at the first failure found (pending designs are cancelled)
          and raise :class:`DesignEvaluationError`, whose message names the design's parameters,
          with the original exception chained and the finished rows in its ``table``.
        - ``"record"``: evaluate every design and return the table with every finished row;
          a failed row has NaN values and its error text in ``table.errors`` (``""`` for good
          rows).

    Returns
    -------
    DesignTable
        Rows in grid order whichever way they ran.

    Raises
    ------
    TypeError
        A ``func`` that is not callable, a ``grid`` that is not a dict (or whose keys are not
        identifiers), a ``client`` that is not a dask Client, or non-integer ``processes``/
        ``chunksize`` or a non-boolean ``progress``.
    InputError
        An empty grid, a parameter with no values, a grid of a single design, or a bad
        ``processes``, ``chunksize`` or ``on_error``.
    DesignEvaluationError
        A design failed and ``on_error="raise"``.

    Examples
    --------
    >>> from imagespace.design.sweep import sweep, _demo_index
    >>> t = sweep(_demo_index, {"a": [1.0, 2.0], "b": [10.0, 20.0]})
    >>> t.values["sum"].tolist(), t.how
    ([11.0, 21.0, 12.0, 22.0], 'serial')

    A failing design is recorded instead of losing the sweep:

    >>> def f(a, b):
    ...     if a == 2.0 and b == 20.0:
    ...         raise ValueError("no design here")
    ...     return {"sum": a + b}
    >>> t = sweep(f, {"a": [1.0, 2.0], "b": [10.0, 20.0]}, on_error="record")
    >>> t.values["sum"].tolist(), t.errors.tolist()
    ([11.0, 21.0, 12.0, nan], ['', '', '', 'ValueError: no design here'])
    >>> sweep(f, {"a": [1.0, 2.0], "b": [10.0, 20.0]})
    Traceback (most recent call last):
    ...
    imagespace.design.sweep.DesignEvaluationError: design 3 {'a': 2.0, 'b': 20.0} failed: ValueError: no design here
    """
    if not callable(func):
        raise InputTypeError(f"func must be callable (func(**params) -> dict of numbers), got "
                             f"{type(func).__name__} {_short(func)}")
    if not isinstance(grid, dict):
        raise InputTypeError(f"grid must be a dict of parameter name -> values, got {type(grid).__name__} {_short(grid)}")
    if not grid:
        raise InputError("grid must be a non-empty dict of parameter name -> values, got {}")
    for k in grid:
        if not isinstance(k, str) or not k.isidentifier():
            raise InputTypeError(f"grid keys must be parameter names (identifiers, passed as func(**params)), "
                                 f"got {_short(k)}")
    if not isinstance(on_error, str) or on_error not in ("raise", "record"):
        raise InputError(f"on_error must be 'raise' or 'record', got {on_error!r}")
    if client is not None and not all(hasattr(client, a) for a in ("submit", "scheduler", "cancel")):
        raise InputTypeError(f"client must be a dask.distributed.Client (or None), got {type(client).__name__} "
                             f"{_short(client)}")
    if processes is not None:
        processes = as_count(processes, "processes", 0)
        if processes > MAX_PROCESSES:
            raise InputError(f"processes must be at most MAX_PROCESSES = {MAX_PROCESSES}, got {_short(processes)}")
    if progress is not None:
        progress = as_flag(progress, "progress")
    chunksize = as_count(chunksize, "chunksize")
    names = list(grid)
    axes = []
    for k in names:
        vals = list(np.atleast_1d(np.asarray(grid[k], dtype=object)))
        if len(vals) == 0:
            raise InputError(f"grid[{k!r}] has no values")
        axes.append(vals)
    shape = tuple(len(a) for a in axes)
    if int(np.prod(shape)) < 2:
        raise InputError(f"the grid has a single design {dict(zip(names, [a[0] for a in axes]))}; "
                         "a sweep needs at least two")
    rows = [dict(zip(names, combo)) for combo in itertools.product(*axes)]
    n = len(rows)
    params = {k: np.array([r[k] for r in rows]) for k in names}
    results = [None] * n          # values dict per finished row
    errors = [""] * n             # error text per failed row
    causes = [None] * n           # the exception behind a failure, if any
    done = [False] * n

    def table(not_run=""):
        keys = list(dict.fromkeys(k for r in results if r is not None for k in r))
        vals = {k: np.array([r[k] if r is not None and k in r else np.nan for r in results], dtype=float)
                for k in keys}
        errs = [e if e or done[i] else not_run for i, e in enumerate(errors)]
        return DesignTable(params, vals, shape, how, np.array(errs, dtype=object))

    def fail(i):
        p = {k: _plain(v) for k, v in rows[i].items()}
        err = DesignEvaluationError(f"design {i} {p} failed: {errors[i]}", p, i,
                                    table("not run: the sweep stopped at a failing design"))
        raise err from causes[i]

    def finish(i, values, message, cause):
        done[i] = True
        if message is None:
            results[i] = values
            return False
        errors[i], causes[i] = message, cause
        return on_error == "raise"

    from tqdm.auto import tqdm

    bar = tqdm(total=n, delay=1.0, desc="design sweep", leave=False, disable=progress is False)
    chunks = [list(range(s, min(s + chunksize, n))) for s in range(0, n, chunksize)]
    try:
        if client is None and not processes:
            how = "serial"
            for i in range(n):
                try:
                    outcome = _evaluate(func, rows[i])
                except KeyboardInterrupt as e:
                    # Ctrl-C stops the sweep; the designs already finished travel with it
                    e.partial_table = table("not run: the sweep was interrupted (KeyboardInterrupt)")
                    raise
                if finish(i, *outcome):
                    fail(i)
                bar.update()
        else:
            import cloudpickle

            func_blob = cloudpickle.dumps(func)
            blobs = [cloudpickle.dumps([rows[i] for i in c]) for c in chunks]
            if client is not None:
                from distributed import as_completed

                how = f"dask ({getattr(client.scheduler, 'address', 'cluster')})"
                futures = [client.submit(_evaluate_remote, func_blob, b, pure=False) for b in blobs]
                ex = None
            else:
                import concurrent.futures as cf
                import multiprocessing as mp

                how = f"processes ({int(processes)})"
                ex = cf.ProcessPoolExecutor(max_workers=int(processes), mp_context=mp.get_context("spawn"))
                with _main_not_reimported():
                    futures = [ex.submit(_evaluate_remote, func_blob, b) for b in blobs]
                as_completed = cf.as_completed
            chunk_of = {id(f): c for f, c in zip(futures, chunks)}
            stop = None
            try:
                for f in as_completed(futures):
                    c = chunk_of[id(f)]
                    try:
                        out = f.result()
                    except Exception as e:  # noqa: BLE001 -- the pool or the cluster lost the task
                        out = [(None, f"{type(e).__name__}: {e}", e, None)] * len(c)
                    else:
                        out = [(v, m, None if b is None and tb is None else _revive(b, m, tb), None)
                               for v, m, b, tb in out]
                    for i, (v, m, cause, _) in zip(c, out):
                        if finish(i, v, m, cause) and stop is None:
                            stop = i
                    bar.update(len(c))
                    if stop is not None:
                        break
            finally:
                if ex is not None:
                    ex.shutdown(wait=True, cancel_futures=True)
                elif stop is not None:
                    client.cancel([f for f in futures if not f.done()])
            if stop is not None:
                fail(stop)
    finally:
        bar.close()
    # every design returns the same names: those most designs return (ties: the first in grid order)
    sets = [frozenset(r) for r in results if r is not None]
    keys = max(sets, key=lambda k: (sets.count(k), -sets.index(k))) if sets else frozenset()
    order = next((list(r) for r in results if r is not None and frozenset(r) == keys), [])
    for i, r in enumerate(results):
        if r is not None and frozenset(r) != keys:
            missing, extra = sorted(keys - set(r)), sorted(set(r) - keys)
            errors[i] = ("returned " + (f"no value for {missing}" if missing else "")
                         + (" and " if missing and extra else "") + (f"unexpected {extra}" if extra else "")
                         + f" (the other designs return {order})")
            results[i] = None
            if on_error == "raise":
                fail(i)
    return table()


@dataclass(frozen=True)
class FuzzyResult:
    """Choi's fuzzy min-max over a design table.

    Attributes
    ----------
    composite : (n,) float
        ``W_c = min z`` per design.
    memberships : dict of (n,) float
        ``z`` per index.
    best : list of int
        Rows with the largest ``W_c`` (ties within ``Tolerances.fuzzy_tie``, default 1e-12, all
        listed).
    """

    composite: np.ndarray
    memberships: dict
    best: list

    # short summaries (arrays as shape and dtype) for the terminal and Jupyter; see imagespace._html
    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html


def fuzzy_minmax(table, criteria, tolerances=None):
    """The fuzzy min-max composite index.

    Parameters
    ----------
    table : DesignTable
    criteria : dict of index name -> (weight, "max" or "min")
        ``"max"``: larger is better; weights in ``[0, 1]``.
    tolerances : Tolerances, optional
        ``fuzzy_tie``: rows within it of the best composite are all best (``None``: the defaults).

    Returns
    -------
    FuzzyResult

    Raises
    ------
    TypeError
        For a ``table`` that is not a DesignTable, ``criteria`` that is not a dict, a
        non-numeric weight, or a ``tolerances`` that is not a Tolerances.
    InputError
        For empty ``criteria``, a name that is not an index of the table (or has no finite
        value), a malformed ``(weight, sense)``, a weight outside ``[0, 1]`` or an unknown sense.

    Examples
    --------
    >>> from imagespace.design.sweep import sweep, fuzzy_minmax, _demo_index
    >>> t = sweep(_demo_index, {"a": [1.0, 2.0, 3.0], "b": [1.0, 2.0]}, processes=0)
    >>> res = fuzzy_minmax(t, {"sum": (1.0, "max"), "product": (1.0, "min")})
    >>> [(float(t.params["a"][i]), float(t.params["b"][i])) for i in res.best]
    [(3.0, 1.0)]
    """
    if not isinstance(table, DesignTable):
        raise InputTypeError(f"table must be a DesignTable (the result of sweep), got {type(table).__name__} "
                             f"{_short(table)}")
    if not isinstance(criteria, Mapping):
        raise InputTypeError(f"criteria must be a dict name -> (weight, 'max'|'min'), got "
                             f"{type(criteria).__name__} {_short(criteria)}")
    if not criteria:
        raise InputError("criteria must be a non-empty dict name -> (weight, 'max'|'min'), got {}")
    tol = check_tolerances(tolerances)
    z = {}
    for name, spec in criteria.items():
        if name not in table.values:
            raise InputError(f"criteria names {name!r}, not an index of the table ({sorted(table.values)})")
        if isinstance(spec, (str, bytes)) or not isinstance(spec, (tuple, list)) or len(spec) != 2:
            raise InputError(f"criteria[{name!r}] must be (weight, 'max'|'min'), got {_short(spec)}")
        g, sense = spec
        if isinstance(g, (bool, np.bool_)) or not isinstance(g, numbers.Real):
            raise InputTypeError(f"the weight of {name!r} (criteria[{name!r}][0]) must be a number in [0, 1], "
                                 f"got {type(g).__name__} {_short(g)}")
        g = float(g)
        if not 0 <= g <= 1:
            raise InputError(f"the weight of {name!r} must be in [0, 1], got {g}")
        if not isinstance(sense, str) or sense not in ("max", "min"):
            raise InputError(f"criteria[{name!r}] sense must be 'max' or 'min', got {sense!r}")
        v = np.asarray(table.values[name], dtype=float)
        if not np.any(np.isfinite(v)):
            raise InputError(f"criteria names {name!r}, which has no finite value in the table")
        lo, hi = np.nanmin(v), np.nanmax(v)
        u = np.ones_like(v) if hi == lo else (v - lo) / (hi - lo)
        if sense == "min":
            u = 1 - u
        z[name] = 1 + g * (u - 1)
    W = np.min(np.stack(list(z.values())), axis=0)
    best = np.flatnonzero(W >= np.nanmax(W) - tol.fuzzy_tie).tolist()
    return FuzzyResult(W, z, best)
