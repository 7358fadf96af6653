"""Design sweeps and the fuzzy min-max optimal design of seed 004.

:func:`sweep` evaluates any module-level function ``f(**params) -> dict of numbers`` over a grid of
design parameters: in local processes by default (``concurrent.futures``, a tqdm progress bar),
serially with ``processes=0``, or on a Dask cluster when given a ``dask.distributed.Client``
(install ``imagespace[dask]``). The rows come back in grid order whichever way they ran.

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
from dataclasses import dataclass

import numpy as np

from .exceptions import InputError

__all__ = ["DesignTable", "sweep", "fuzzy_minmax", "FuzzyResult"]


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
    """

    params: dict
    values: dict
    shape: tuple
    how: str

    def grid(self, name):
        """A value reshaped to the grid, ``shape``.

        Examples
        --------
        >>> from imagespace.design import sweep, _demo_index
        >>> t = sweep(_demo_index, {"a": [1, 2], "b": [0, 1, 2]}, processes=0)
        >>> t.grid("sum").tolist()
        [[1.0, 2.0, 3.0], [2.0, 3.0, 4.0]]
        """
        return np.asarray(self.values[name]).reshape(self.shape)

    def equals(self, other):
        """True if both tables hold the same rows and values (exactly)."""
        return (self.shape == other.shape and self.params.keys() == other.params.keys()
                and all(np.array_equal(self.params[k], other.params[k]) for k in self.params)
                and self.values.keys() == other.values.keys()
                and all(np.array_equal(self.values[k], other.values[k], equal_nan=True) for k in self.values))


def _demo_index(a, b):
    """A tiny index function for examples and tests (module level: picklable)."""
    return {"sum": float(a + b), "product": float(a * b)}


def _call(args):
    func, kw = args
    return func(**kw)


def sweep(func, grid, client=None, processes=None, progress=None, chunksize=1):
    """Evaluate ``func(**params)`` over every combination of the grid's parameter values.

    Parameters
    ----------
    func : callable
        Returns a dict of numbers. Must be picklable (defined at module level) for processes
        and Dask.
    grid : dict of name -> sequence
        Each parameter's values; the grid is their Cartesian product (row-major).
    client : dask.distributed.Client, optional
        Run on this cluster.
    processes : int or None
        Local worker processes (``None``: ``os.cpu_count()``; ``0``: serial in this process).
    progress : bool or None
        tqdm bar (``None``: shown after a second).

    Returns
    -------
    DesignTable

    Raises
    ------
    InputError
        An empty grid, a parameter with no values, or a grid of a single design.

    Examples
    --------
    >>> from imagespace.design import sweep, _demo_index
    >>> t = sweep(_demo_index, {"a": [1.0, 2.0], "b": [10.0, 20.0]}, processes=0)
    >>> t.values["sum"].tolist(), t.how
    ([11.0, 21.0, 12.0, 22.0], 'serial')
    """
    if not isinstance(grid, dict) or not grid:
        raise InputError(f"grid must be a non-empty dict of parameter name -> values, got {grid!r}")
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
    tasks = [(func, r) for r in rows]
    from tqdm import tqdm

    bar = tqdm(total=len(rows), delay=1.0, desc="design sweep", leave=False,
               disable=progress is False)
    if client is not None:
        futures = client.map(_call, tasks, pure=False)
        results = []
        for f in futures:
            results.append(f.result())
            bar.update()
        how = f"dask ({getattr(client.scheduler, 'address', 'cluster')})"
    elif processes == 0:
        results = []
        for t in tasks:
            results.append(_call(t))
            bar.update()
        how = "serial"
    else:
        import concurrent.futures as cf
        import multiprocessing as mp
        import os

        n = processes or os.cpu_count() or 1
        ctx = mp.get_context("spawn")
        with cf.ProcessPoolExecutor(max_workers=n, mp_context=ctx) as ex:
            results = []
            for r in ex.map(_call, tasks, chunksize=chunksize):
                results.append(r)
                bar.update()
        how = f"processes ({n})"
    bar.close()
    keys = list(results[0])
    values = {k: np.array([float(r[k]) for r in results]) for k in keys}
    params = {k: np.array([r[k] for r in rows]) for k in names}
    return DesignTable(params, values, shape, how)


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
        Rows with the largest ``W_c`` (ties within 1e-12 all listed).
    """

    composite: np.ndarray
    memberships: dict
    best: list


def fuzzy_minmax(table, criteria):
    """The fuzzy min-max composite index.

    Parameters
    ----------
    table : DesignTable
    criteria : dict of index name -> (weight, "max" or "min")
        ``"max"``: larger is better; weights in ``[0, 1]``.

    Returns
    -------
    FuzzyResult

    Examples
    --------
    >>> from imagespace.design import sweep, fuzzy_minmax, _demo_index
    >>> t = sweep(_demo_index, {"a": [1.0, 2.0, 3.0], "b": [1.0, 2.0]}, processes=0)
    >>> res = fuzzy_minmax(t, {"sum": (1.0, "max"), "product": (1.0, "min")})
    >>> [(float(t.params["a"][i]), float(t.params["b"][i])) for i in res.best]
    [(3.0, 1.0)]
    """
    if not isinstance(criteria, dict) or not criteria:
        raise InputError("criteria must be a non-empty dict name -> (weight, 'max'|'min')")
    z = {}
    for name, spec in criteria.items():
        if name not in table.values:
            raise InputError(f"criteria names {name!r}, not an index of the table ({sorted(table.values)})")
        try:
            g, sense = spec
        except (TypeError, ValueError):
            raise InputError(f"criteria[{name!r}] must be (weight, 'max'|'min'), got {spec!r}") from None
        g = float(g)
        if not 0 <= g <= 1:
            raise InputError(f"the weight of {name!r} must be in [0, 1], got {g}")
        if sense not in ("max", "min"):
            raise InputError(f"criteria[{name!r}] sense must be 'max' or 'min', got {sense!r}")
        v = np.asarray(table.values[name], dtype=float)
        lo, hi = np.nanmin(v), np.nanmax(v)
        u = np.ones_like(v) if hi == lo else (v - lo) / (hi - lo)
        if sense == "min":
            u = 1 - u
        z[name] = 1 + g * (u - 1)
    W = np.min(np.stack(list(z.values())), axis=0)
    best = np.flatnonzero(W >= np.nanmax(W) - 1e-12).tolist()
    return FuzzyResult(W, z, best)
