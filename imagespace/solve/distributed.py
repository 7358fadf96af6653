"""Direct kinematics of a ``dask.array`` of joint vectors, block by block (on a cluster or locally).

:func:`direct_kinematics_dask` (bound as :meth:`PlanarParallel.direct_kinematics_dask`) maps
:func:`~imagespace.solve.front.direct_kinematics_batch` over the row blocks of an ``(n, 3)``
dask array. Each block is solved exactly once, into one structured numpy array (a record per
row: count, poses, masks); the result's arrays (:class:`DKDaskResult`) are lazy field views of
that one array, so computing any or all of them solves each block once.

The manipulator enters the task graph once, as its own key, not once per task: on a
``dask.distributed`` cluster each worker process receives one copy and builds its compiled
kernel on that copy once, on the first block it solves (a pickled manipulator carries its design,
not its caches: the numba kernel loads from the on-disk numba cache, about 2.5 s for seed 002,
instead of being recompiled from a pickled dispatcher, about 22 s). The worker keeps that copy
for later computations on the same design (:func:`kept_design`). Nothing of size ``n`` is materialised
unless the caller computes it: reductions such as ``da.bincount(result.count)`` stream.

``dask`` is an optional dependency (``pip install imagespace[dask]``), imported inside the
functions only.
"""

from __future__ import annotations

import sys
import threading
from collections import OrderedDict
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any, Optional

import numpy as np
import numpy.typing as npt

from .._html import html_table, summary
from .._validate import as_flag, as_float_array
from ..core.mechanism import check_mechanism
from ..exceptions import InputError, InputTypeError
from .front import check_method, direct_kinematics_batch
from .results import MAX_MODES

if TYPE_CHECKING:  # pragma: no cover
    import dask.array

__all__ = ["direct_kinematics_dask", "DKDaskResult", "DEFAULT_CHUNK_ROWS"]

#: Rows per block when ``Q`` is not a dask array (a numpy array, a memmap, a list): the default
#: chunk of :meth:`PlanarParallel.direct_kinematics_chunks`, about 26 MB of batch result and
#: 10 MB of records per block. Layout only (decides nothing about the answers).
DEFAULT_CHUNK_ROWS = 65536

_METHODS = ("auto", "kernel", "numpy")

#: How many designs a ``dask.distributed`` worker process keeps between computations (the most
#: recently used ones), with their compiled kernels. Memory management only, decides nothing.
KEPT_DESIGNS_MAX = 4

#: The designs kept by this worker process: dask token -> the worker's copy of the design. A
#: worker receives a fresh copy of the design with every computation (the graph's key is released
#: when the computation ends); solving with the copy it already holds reuses that copy's compiled
#: kernel (building it again costs 2-3 s per worker). Filled on ``dask.distributed`` workers only
#: (a local scheduler passes the caller's own object, which keeps its kernel anyway).
KEPT_DESIGNS: "OrderedDict[str, Any]" = OrderedDict()
_KEPT_LOCK = threading.Lock()


def _on_dask_worker() -> bool:
    """Whether this code runs in a task on a ``dask.distributed`` worker."""
    if "distributed" not in sys.modules:
        return False
    from distributed import get_worker

    try:
        get_worker()
    except ValueError:
        return False
    return True


def kept_design(token: str, m: Any) -> Any:
    """The design to solve with: on a ``dask.distributed`` worker the copy of the design with
    this token kept from an earlier computation (with its compiled kernel), else ``m``.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.distributed import kept_design
    >>> m = isp.examples.general_3rpr()
    >>> kept_design("token", m) is m          # not on a worker: the design as given
    True
    """
    if not _on_dask_worker():
        return m
    with _KEPT_LOCK:
        kept = KEPT_DESIGNS.setdefault(token, m)
        KEPT_DESIGNS.move_to_end(token)
        while len(KEPT_DESIGNS) > KEPT_DESIGNS_MAX:
            KEPT_DESIGNS.popitem(last=False)
    return kept


def record_dtype(certify: bool, width: int = MAX_MODES, pose_dim: int = 3) -> np.dtype:
    """The per-row record one block solve writes: the fields of :class:`DKDaskResult`.

    ``count`` uint8, ``poses`` (width, pose_dim) float64, ``valid`` (width,) bool, ``aspect``
    (width,) int8, ``row_ok`` bool, ``near_singular`` bool; with ``certify`` also
    ``certified_roots`` int8 (-1 where the row is not valid) and ``consistent`` bool. A planar
    design: width 6, poses ``(x, y, phi)``, 159 bytes a row (161 certified); a spatial platform:
    width its number of complex solutions, poses translation and unit quaternion (7 numbers).

    Examples
    --------
    >>> from imagespace.solve.distributed import record_dtype
    >>> record_dtype(False).names
    ('count', 'poses', 'valid', 'aspect', 'row_ok', 'near_singular')
    >>> record_dtype(False).itemsize, record_dtype(True).itemsize
    (159, 161)
    """
    spec: list[Any] = [("count", np.uint8), ("poses", np.float64, (width, pose_dim)),
                       ("valid", np.bool_, (width,)), ("aspect", np.int8, (width,)),
                       ("row_ok", np.bool_), ("near_singular", np.bool_)]
    if certify:
        spec += [("certified_roots", np.int8), ("consistent", np.bool_)]
    return np.dtype(spec)


def solve_block(block: np.ndarray, m: Any, certify: bool, method: str, token: str = "",
                width: int = MAX_MODES, pose_dim: int = 3) -> np.ndarray:
    """Solve one row block: :func:`direct_kinematics_batch` on it, packed into records.

    The task function of :func:`direct_kinematics_dask` (runs on the workers; ``token`` names
    the design for :func:`kept_design`). Reads only the public attributes of the batch result.

    Examples
    --------
    >>> import imagespace as isp
    >>> import numpy as np
    >>> from imagespace.solve.distributed import solve_block
    >>> m = isp.examples.general_3rpr()
    >>> rec = solve_block(np.array([m.q_example_float]), m, False, "auto")
    >>> rec["count"].tolist(), rec["valid"].sum(axis=1).tolist()
    ([6], [6])
    """
    out = np.zeros(block.shape[0], dtype=record_dtype(certify, width, pose_dim))
    if block.shape[0] == 0:
        return out
    res = direct_kinematics_batch(kept_design(token, m) if token else m, block, certify=certify,
                                  method=method)
    out["count"] = res.count
    w = min(width, np.shape(res.valid)[1])
    out["poses"] = np.nan
    out["poses"][:, :w] = np.asarray(res.poses)[:, :w]
    out["valid"][:, :w] = np.asarray(res.valid)[:, :w]
    out["aspect"][:, :w] = np.asarray(res.aspect)[:, :w]
    out["row_ok"] = res.row_ok
    if res.near_singular is not None:
        out["near_singular"] = res.near_singular
    if certify:
        out["certified_roots"] = res.certified_roots
        out["consistent"] = res.consistent
    return out


@dataclass(frozen=True, repr=False)
class DKDaskResult:
    """Lazy direct kinematics of an ``(n, 3)`` dask array of joint vectors.

    Every array is a dask array whose blocks follow the row blocks of ``Q``; all of them are
    field views of ``records``, so each block is solved once however many of them are computed
    together (:meth:`compute`, ``dask.compute(...)``). Computing them in separate calls solves
    again: :meth:`persist` first on a cluster, or compute them together.

    Attributes
    ----------
    records : (n,) structured dask array
        One record per row (:func:`record_dtype`): the one task per block.
    count : (n,) uint8 dask array
        Number of real assembly modes per row.
    poses : (n, 6, 3) float64 dask array
        ``(x, y, phi)`` of the modes, NaN in unused slots.
    valid : (n, 6) bool dask array
        Which slots hold a mode.
    aspect : (n, 6) int8 dask array
        Sign of ``det J`` per mode, 0 in unused slots.
    row_ok : (n,) bool dask array
        False for rows that could not be solved (NaN, out of domain, degenerate).
    near_singular : (n,) bool dask array
        As :attr:`DKBatchResult.near_singular`.
    certified_roots : (n,) int8 dask array or None
        With ``certify=True``: the proven number of distinct real roots per row (-1 where the row
        is not valid).
    consistent : (n,) bool dask array or None
        With ``certify=True``: as :attr:`DKBatchResult.consistent`.
    """

    records: Any
    count: Any
    poses: Any
    valid: Any
    aspect: Any
    row_ok: Any
    near_singular: Any
    certified_roots: Optional[Any] = None
    consistent: Optional[Any] = None

    @classmethod
    def from_records(cls, records: Any) -> "DKDaskResult":
        """The result whose arrays are the fields of the structured dask array ``records``.

        Examples
        --------
        >>> import dask.array as da
        >>> import numpy as np
        >>> from imagespace.solve.distributed import DKDaskResult, record_dtype
        >>> rec = da.from_array(np.zeros(4, dtype=record_dtype(False)), chunks=2)
        >>> DKDaskResult.from_records(rec).poses.shape
        (4, 6, 3)
        """
        names = records.dtype.names
        return cls(records, *(records[f.name] if f.name in names else None
                              for f in fields(cls)[1:]))

    def arrays(self) -> dict[str, Any]:
        """The dask arrays by name (``records`` left out, the certified ones only when present).

        Examples
        --------
        >>> import imagespace as isp
        >>> import numpy as np
        >>> m = isp.examples.general_3rpr()
        >>> list(m.direct_kinematics_dask(np.array([m.q_example_float])).arrays())
        ['count', 'poses', 'valid', 'aspect', 'row_ok', 'near_singular']
        """
        return {f.name: getattr(self, f.name) for f in fields(self)[1:]
                if getattr(self, f.name) is not None}

    def compute(self, **kwargs: Any) -> dict[str, np.ndarray]:
        """Compute every array in one pass (each block solved once): a dict of numpy arrays.

        Parameters
        ----------
        **kwargs
            Passed to ``dask.compute`` (``scheduler="synchronous"``, ...); on a
            ``dask.distributed`` client the default scheduler is the client.

        Examples
        --------
        >>> import imagespace as isp
        >>> import numpy as np
        >>> m = isp.examples.general_3rpr()
        >>> out = m.direct_kinematics_dask(np.array([m.q_example_float])).compute(scheduler="synchronous")
        >>> out["count"].tolist(), out["poses"].shape
        ([6], (1, 6, 3))
        """
        import dask

        arrays = self.arrays()
        return dict(zip(arrays, dask.compute(*arrays.values(), **kwargs)))

    def persist(self, **kwargs: Any) -> "DKDaskResult":
        """The same result with its records computed and kept in (cluster) memory.

        Parameters
        ----------
        **kwargs
            Passed to ``dask.persist``.

        Examples
        --------
        >>> import imagespace as isp
        >>> import numpy as np
        >>> m = isp.examples.general_3rpr()
        >>> r = m.direct_kinematics_dask(np.array([m.q_example_float])).persist(scheduler="synchronous")
        >>> int(r.count.sum().compute())
        6
        """
        import dask

        (records,) = dask.persist(self.records, **kwargs)
        return DKDaskResult.from_records(records)

    @property
    def nrows(self) -> float:
        """Number of rows (NaN when the row blocks of ``Q`` have unknown sizes).

        Examples
        --------
        >>> import imagespace as isp
        >>> import numpy as np
        >>> m = isp.examples.general_3rpr()
        >>> m.direct_kinematics_dask(np.zeros((5, 3))).nrows
        5
        """
        return self.records.shape[0]

    def _summary_rows(self) -> list[tuple[str, Any]]:
        blocks = self.records.chunks[0]
        known = all(np.isfinite(b) for b in blocks)
        lo, hi = (int(min(blocks)), int(max(blocks))) if known and blocks else (0, 0)
        rows: list[tuple[str, Any]] = [
            ("rows", int(self.nrows) if known else "unknown"), ("blocks", len(blocks)),
            ("rows per block", ("unknown" if not known else str(lo) if lo == hi else f"{lo}..{hi}")),
            ("certified", self.certified_roots is not None),
            ("arrays", ", ".join(self.arrays())),
            ("computed", "no (lazy)")]
        return rows

    def __repr__(self) -> str:
        """A summary of the lazy result (rows, blocks, arrays); computes nothing.

        Examples
        --------
        >>> import imagespace as isp
        >>> import numpy as np
        >>> m = isp.examples.general_3rpr()
        >>> print(m.direct_kinematics_dask(np.zeros((5, 3))))  # doctest: +ELLIPSIS
        DKDaskResult(rows=5, blocks=1, rows_per_block=5, certified=False,
                     arrays=count, poses, valid, aspect, row_ok, near_singular, computed=no (lazy))
        """
        return summary("DKDaskResult", [(k.replace(" ", "_"), str(v)) for k, v in self._summary_rows()])

    def _repr_html_(self) -> str:
        """A summary table for Jupyter; computes nothing.

        Examples
        --------
        >>> import imagespace as isp
        >>> import numpy as np
        >>> m = isp.examples.general_3rpr()
        >>> "<table" in m.direct_kinematics_dask(np.zeros((5, 3)))._repr_html_()
        True
        """
        return html_table([(k, str(v)) for k, v in self._summary_rows()],
                          title=f"DKDaskResult: {self._summary_rows()[0][1]} rows")


def _as_row_blocks(Q: Any, k: int = 3) -> "dask.array.Array":
    """``Q`` as a float or integer dask array of shape ``(n, k)`` with full rows in every block."""
    import dask.array as da

    if isinstance(Q, da.Array):
        if Q.dtype.kind not in "iuf":
            raise InputTypeError(f"Q must be a real float or integer array, got a dask array of dtype {Q.dtype}")
    elif isinstance(Q, np.ndarray) and Q.dtype.kind in "iuf":
        pass                                    # a memmap stays on disk; da.from_array reads blocks
    elif isinstance(Q, np.ndarray) and Q.dtype.kind != "O":
        raise InputTypeError(f"Q must be a real float or integer array, got dtype {Q.dtype}")
    else:
        Q = as_float_array(Q, "Q", last=k, finite=False)
    if Q.ndim != 2 or not Q.shape[1] == k:
        raise InputError(f"Q must have shape (n, {k}) (one joint vector per row), got shape {Q.shape}")
    if not isinstance(Q, da.Array):
        Q = da.from_array(Q, chunks=(DEFAULT_CHUNK_ROWS, k))
    if len(Q.chunks[1]) != 1:                   # chunked along the joints: whole rows per block
        Q = Q.rechunk({1: k})
    return Q


def _layout(m: Any) -> tuple[int, int]:
    """Mode slots and pose size of a record: 6 planar modes ``(x, y, phi)``; a spatial platform's
    complex solution count (its start system) and translation + quaternion."""
    if m.image_space == "planar":
        return MAX_MODES, 3
    return int(len(m.start_system.solutions)), 7


def direct_kinematics_dask(m: Any, Q: "dask.array.Array | npt.ArrayLike", certify: bool = False,
                           method: str = "auto") -> DKDaskResult:
    """Direct kinematics of a ``dask.array`` of joint vectors, lazily, block by block.

    Each row block of ``Q`` is one task that runs :meth:`direct_kinematics_batch` on it (the
    compiled kernel for blocks of 2,000 rows or more with ``method="auto"``). Nothing is
    computed until asked; on a ``dask.distributed`` cluster the blocks run on the workers, each
    worker building the design's compiled kernel once.

    Parameters
    ----------
    Q : (n, k) dask array, or array_like
        One joint vector per row (``k = m.joint_count``: 3 planar, the legs of a spatial
        platform), float or integer. Blocks split along the joints are
        rechunked to whole rows; anything else (a numpy array, a memmap, a list) is wrapped
        into blocks of :data:`DEFAULT_CHUNK_ROWS` rows. Rows with NaN or out-of-domain values
        are masked (``row_ok`` False), not raised.
    certify : bool
        Prove the number of real roots per row, as in :meth:`direct_kinematics_batch`; fills
        ``certified_roots`` and ``consistent``.
    method : {"auto", "kernel", "numpy"}
        As in :meth:`direct_kinematics_batch`, per block.

    Returns
    -------
    DKDaskResult
        Lazy dask arrays ``count``, ``poses``, ``valid``, ``aspect``, ``row_ok``,
        ``near_singular`` (and ``certified_roots``, ``consistent``), one solve per block;
        :meth:`DKDaskResult.compute` computes them together.

    Raises
    ------
    TypeError
        ``Q`` is not a real float or integer array (booleans, complex, strings, objects), or
        ``certify`` is not a bool.
    InputError
        ``Q`` is not of shape ``(n, 3)``, or ``method`` is not ``'auto'``, ``'kernel'`` or
        ``'numpy'``. Errors of a block (``method='kernel'`` on a design the kernel does not take,
        a block too large for the memory) are raised when it is computed.

    Notes
    -----
    The dask graph holds ``m`` once, as its own key: the worker processes each receive one copy
    (pickled without its caches) and keep it for every block they solve, and for the next
    computations (:data:`KEPT_DESIGNS_MAX` designs per worker), so a worker builds the
    design's compiled kernel once. Reductions stream:
    ``da.bincount(r.count, minlength=7).compute()`` holds a few blocks per worker at a time,
    never an array of ``n`` rows.

    Examples
    --------
    >>> import dask.array as da
    >>> import numpy as np
    >>> import imagespace as isp
    >>> m = isp.examples.general_3rpr()
    >>> q = m.q_example_float
    >>> Q = da.from_array(np.array([q, [np.nan, 1, 1], q]), chunks=(2, 3))
    >>> r = m.direct_kinematics_dask(Q)
    >>> r.count.chunks
    ((2, 1),)
    >>> out = r.compute(scheduler="synchronous")
    >>> out["count"].tolist(), out["row_ok"].tolist(), out["poses"].shape
    ([6, 0, 6], [True, False, True], (3, 6, 3))
    >>> da.bincount(r.count, minlength=7).compute(scheduler="synchronous").tolist()
    [1, 0, 0, 0, 0, 0, 2]
    """
    import dask
    import dask.array as da
    from dask.base import tokenize

    m = check_mechanism(m, image_space=None)
    certify = as_flag(certify, "certify")
    method = check_method(method, m)
    Q = _as_row_blocks(Q, m.joint_count)
    width, pose_dim = _layout(m)
    dtype = record_dtype(certify, width, pose_dim)
    # the manipulator as one key of the graph (not copied into every task): a worker receives it
    # once and its compiled kernel, cached on that copy, serves every block the worker solves;
    # the token (of the design without its caches) finds the copy a worker kept from before
    token = tokenize(m)
    design = dask.delayed(m, name=f"{type(m).__name__}-{token}")
    records = da.map_blocks(solve_block, Q, design, certify, method, token, width, pose_dim,
                            dtype=dtype, drop_axis=1,
                            chunks=(Q.chunks[0],), meta=np.empty((0,), dtype=dtype),
                            token="direct-kinematics-dask")
    return DKDaskResult.from_records(records)
