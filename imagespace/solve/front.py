"""The one front end of the direct kinematics, for every mechanism (planar and spatial).

Every direct-kinematics call of imagespace comes through here: a mechanism's methods
(``m.direct_kinematics``, ``m.direct_kinematics_batch`` ...) are these functions, and the engines
(:mod:`imagespace.singular`, :mod:`imagespace.paths`, :mod:`imagespace.design`,
:mod:`imagespace.atlas`) call them with a mechanism. This module does, once for all mechanisms:

* the contract check (:func:`~imagespace.core.mechanism.check_mechanism`);
* validation at the boundary, through :mod:`imagespace._validate` only: flags are booleans,
  ``method`` one of the mechanism's names, a joint vector is checked by the mechanism
  (:meth:`~imagespace.core.mechanism.Mechanism.check_q`: strings never parsed, complex and
  booleans refused, named errors), a batch is a real ``(n, k)`` array whose bad rows are masked
  (:meth:`~imagespace.core.mechanism.Mechanism.joint_rows`), never raised;
* the memory guard of a batch and the split into chunks;
* the ladder: a reach bound (exact, cheap: no real mode) -> the float stage (proven counts or a
  flag per row: ``near_singular``, a :class:`~imagespace.exceptions.NearSingularWarning` per call)
  -> the proof stage (``certify=True``) -> the exact stage (per row, where the float stage does
  not resolve the input, or asked for).

The stages themselves are the mechanism's back ends (:class:`~imagespace.core.mechanism.Backends`):
:mod:`imagespace.solve.planar` for planar designs, :mod:`imagespace.spatial.backends` for the
spatial platforms. Results speak one vocabulary: ``count``, ``row_ok``, ``near_singular``,
``certified``, ``certificate_path``, ``errors``; ``result[i]`` (negative ``i`` too) is row ``i``'s
per-call answer; results pickle and render as HTML tables.
"""

from __future__ import annotations

import warnings
from typing import Any, Iterator

import numpy as np
import numpy.typing as npt

from .._memory import check_memory
from .._validate import as_count, as_flag, as_float_array
from ..core.mechanism import check_mechanism
from ..exceptions import DegenerateDesignError, InputError, InputTypeError, NearSingularWarning

__all__ = ["direct_kinematics", "direct_kinematics_batch", "direct_kinematics_chunks",
           "certified_root_counts", "check_method", "joint_batch"]


def check_method(method: Any, m: Any) -> str:
    """``method`` as one of the mechanism's direct-kinematics methods (``"auto"`` is always
    accepted and means the mechanism's default).

    Raises
    ------
    InputError
        ``method`` is not one of them.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.front import check_method
    >>> check_method("numpy", isp.examples.general_3rpr())
    'numpy'
    """
    names = m.backends.methods
    if isinstance(method, str) and method == "auto":
        return names[0]
    if not isinstance(method, str) or method not in names:
        allowed = [repr(v) for v in ("auto",) + tuple(v for v in names if v != "auto")]
        raise InputError(f"method must be {', '.join(allowed[:-1])} or {allowed[-1]} "
                         f"({type(m).__name__}), got {method!r}")
    return method


def joint_batch(m: Any, Q: npt.ArrayLike, name: Any = None) -> np.ndarray:
    """A batch of joint vectors as a real float array ``(n, k)`` (a single ``(k,)`` becomes one
    row); non-finite entries are kept (their rows are masked later, never raised).

    Raises
    ------
    TypeError
        ``Q`` is not a real array (strings, complex numbers, booleans are refused, never parsed).
    InputError
        ``Q`` is not of shape ``(k,)`` or ``(n, k)``.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.front import joint_batch
    >>> joint_batch(isp.examples.general_3rpr(), [11, 5, 10]).shape
    (1, 3)
    """
    if name is None:                    # the parameter, in the mechanism's words
        name = "Q" if m.image_space == "planar" else "Q (rows of leg lengths)"
    A = as_float_array(Q, name, last=m.joint_count, finite=False)
    return A[None, :] if A.ndim == 1 else A


def direct_kinematics(m: Any, q: Any, include_complex: bool = False, certify: bool = False,
                      method: str = "auto") -> Any:
    """All real assembly modes of a mechanism for one joint vector.

    Parameters
    ----------
    q : (k,) float or exact numbers
        The actuated joint values (``k = m.joint_count``). Floats are the exact binary rationals
        they store; on the certified path exact entries (sympy, Fraction) are used as given.
    include_complex : bool
        Planar designs: also return the complex solutions (back-substituted, not polished).
    certify : bool
        Prove the answer at the exact input (see the mechanism's back ends: the certified roots
        of the exact kinematic polynomial for planar designs, Krawczyk boxes then msolve for the
        spatial platforms).
    method : str
        One of the mechanism's methods (``"auto"``: its default); ``"exact"`` for a spatial
        platform solves with msolve.

    Returns
    -------
    The mechanism's per-call result: an ``AssemblyModes`` (planar; a ``CertifiedModes`` with
    ``certify``) or a ``SpatialDKResult``.

    Raises
    ------
    TypeError
        ``m`` is not a mechanism with back ends, or a flag is not a boolean.
    InputError
        ``q`` is not one joint vector of the mechanism, or ``method`` is unknown.
    DegenerateDesignError
        The design has infinitely many modes at ``q`` (a continuum).

    Warns
    -----
    NearSingularWarning
        Without ``certify``: the floating-point count is not proven (a double or nearly double
        mode); use ``certify=True``.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.front import direct_kinematics
    >>> m = isp.examples.stigger_husty()
    >>> len(direct_kinematics(m, m.q_example_float))
    6
    >>> direct_kinematics(m, m.q_example, certify=True).certificate.count
    6
    """
    m = check_mechanism(m, image_space=None)
    be = m.backends
    include_complex = as_flag(include_complex, "include_complex")
    certify = as_flag(certify, "certify")
    method = check_method(method, m)
    # exact sympy numbers pass, free symbols are refused by name
    qf = m.check_q(q, "q" if m.image_space == "planar" else "q (leg lengths)")
    if qf.ndim != 1:
        raise InputError(f"q must have shape ({m.joint_count},), got {qf.shape}; use "
                         "direct_kinematics_batch for rows")
    if include_complex and be.complex_modes is None:
        raise InputError(f"include_complex=True is not offered by {type(m).__name__} (its result "
                         "reports the number of complex solutions instead)")
    # a reach bound answers first, except where the caller asked for the exact solver itself (its
    # complex count is part of that answer) on joint values of a sensible size; at absurd sizes
    # (``far``) the bound answers anyway: bounded work, the complex count then unknown (-1)
    far = be.far is not None and bool(be.far(m, qf[None])[0])
    obstruction = (be.reach(m, q if certify else qf)
                   if be.reach is not None and (far or method not in be.exact_methods) else None)
    if obstruction is not None:
        out = be.empty(m, obstruction, certify)
    elif certify or method in be.exact_methods or far:
        out = be.exact(m, q, qf, method, certify)
    else:
        batch = be.solve(m, qf[None, :], np.ones(1, dtype=bool), method, True)
        out = batch[0]
        if batch.near_singular[0]:
            warnings.warn(be.doubt(m, qf, out), NearSingularWarning, stacklevel=2)
    if include_complex:
        if far:
            raise InputError(f"include_complex=True needs joint values within "
                             f"{m.tolerances.far_reach_ratio:g} times the size of {m.name} (the "
                             f"complex modes are computed in floating point), got q = {qf.tolist()}")
        out = be.complex_modes(m, qf, out)
    return out


def direct_kinematics_batch(m: Any, Q: npt.ArrayLike, certify: bool = False, method: str = "auto") -> Any:
    """Direct kinematics of many joint vectors at once, with a validity mask per row.

    Parameters
    ----------
    Q : (n, k) float
        One joint vector per row. Rows with NaN or out-of-domain values are masked
        (``row_ok`` False, the reason in ``errors``), never raised.
    certify : bool
        Prove every row (the mechanism's proof stage); fills ``certified_roots``,
        ``certificate_path`` and ``certified``.
    method : str
        One of the mechanism's methods (``"auto"``: its default).

    Returns
    -------
    The mechanism's batch result (``DKBatchResult`` planar, ``SpatialDKBatch`` spatial):
    ``count``, ``row_ok``, ``near_singular``, ``certified``, ``errors``; ``result[i]`` is row
    ``i``'s per-call result.

    Raises
    ------
    TypeError
        ``Q`` is not a real array, or ``certify`` not a boolean.
    InputError
        ``Q`` is not of shape ``(k,)`` or ``(n, k)``, or ``method`` is unknown.
    MemoryError
        The batch would not fit (use :func:`direct_kinematics_chunks`).

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.solve.front import direct_kinematics_batch
    >>> m = isp.examples.stigger_husty()
    >>> r = direct_kinematics_batch(m, np.array([m.q_example_float, [np.nan, 1, 1]]))
    >>> r.count.tolist(), r.row_ok.tolist(), len(r[-1])
    ([6, 0], [True, False], 0)
    """
    m = check_mechanism(m, image_space=None)
    be = m.backends
    Q = joint_batch(m, Q)
    certify = as_flag(certify, "certify")
    method = check_method(method, m)
    n = Q.shape[0]
    per_row = be.peak_bytes(m, method, certify, n)
    check_memory(n * per_row, f"direct_kinematics_batch of {n:,} rows",
                 f"use direct_kinematics_chunks(Q, chunk_size=...) to solve it chunk by chunk "
                 f"(a chunk of 65,536 rows needs about {65536 * per_row / 1e9:.2g} GB)")
    ok, errors = m.joint_rows(Q)
    far = ok & (be.far(m, Q) if be.far is not None else np.zeros(n, dtype=bool))
    alone = ok.copy() if method in be.exact_methods else far
    rows = ok & ~alone
    res = be.solve(m, Q, rows, method, False)
    if certify:
        res = be.prove(m, Q, res, rows, method)
    if alone.any():
        idx = [int(i) for i in np.flatnonzero(alone)]
        results = []
        for i in idx:
            ob = (be.reach(m, Q[i]) if be.reach is not None and (far[i] or method not in be.exact_methods)
                  else None)
            if ob is not None:
                results.append(be.empty(m, ob, True))
                continue
            try:
                results.append(be.exact(m, Q[i], Q[i], method, certify))
            except (InputError, DegenerateDesignError) as exc:
                results.append(exc)
        res = be.store(res, idx, results, certify)
    for i, msg in errors.items():          # the input's own messages win
        res.errors[i] = msg
    return res


def direct_kinematics_chunks(m: Any, Q: npt.ArrayLike, chunk_size: int = 65536, certify: bool = False,
                             method: str = "auto") -> Iterator[tuple[int, Any]]:
    """Direct kinematics of a large batch, chunk by chunk (memory bounded by the chunk).

    Parameters
    ----------
    Q : (n, k) float array (a numpy memmap works: it is read chunk by chunk)
    chunk_size : int
        Rows per chunk.
    certify, method
        As in :func:`direct_kinematics_batch`.

    Yields
    ------
    (start, batch result)
        The rows ``start : start + len(result)`` of ``Q``.

    Raises
    ------
    InputError
        ``Q`` is not of shape ``(n, k)``, ``chunk_size`` is not a positive count, or ``method``
        is unknown.
    TypeError
        ``Q`` is not a real float or integer array, or ``certify`` is not a bool.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> m = isp.examples.general_3rpr()
    >>> Q = np.tile(m.q_example_float, (5, 1))
    >>> [(s, r.count.tolist()) for s, r in m.direct_kinematics_chunks(Q, chunk_size=2)]
    [(0, [6, 6]), (2, [6, 6]), (4, [6])]
    """
    m = check_mechanism(m, image_space=None)
    chunk_size = as_count(chunk_size, "chunk_size")
    certify = as_flag(certify, "certify")
    method = check_method(method, m)
    if not isinstance(Q, np.ndarray):               # a memmap is validated chunk by chunk
        Q = as_float_array(Q, "Q", last=m.joint_count, finite=False)
    elif Q.dtype.kind not in "iuf":
        raise InputTypeError(f"Q must be a real float or integer array, got dtype {Q.dtype}")
    if Q.ndim != 2 or Q.shape[-1] != m.joint_count:
        raise InputError(f"Q must have shape (n, {m.joint_count}), got {Q.shape}")
    return _chunks(m, Q, chunk_size, certify, method)    # validated now, solved lazily


def _chunks(m, Q, chunk_size, certify, method):
    """The generator behind :func:`direct_kinematics_chunks` (its arguments already checked)."""
    for start in range(0, Q.shape[0], chunk_size):
        yield start, direct_kinematics_batch(m, Q[start:start + chunk_size], certify, method)


def certified_root_counts(m: Any, Q: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Proven numbers of real assembly modes for a batch of joint vectors, without the modes.

    Each row is decided at its exact input (floats are the binary rationals they store) by the
    mechanism's counting back end; rows the float stage does not resolve are answered one by
    one (a reach bound, else the exact stage). Bad rows get -1 and a path saying why.

    Parameters
    ----------
    Q : (n, k) float

    Returns
    -------
    counts : (n,) int8
        -1 for invalid rows, continua and the rare rows nothing could certify (see ``path``).
    path : (n,) str
        How each count was proven (the mechanism's names: ``"kernel"``, ``"flint"``, ``"arb"``,
        ``"reach"``, ``"krawczyk"``, ``"msolve"`` ...), or ``"uncertified"``, ``"continuum"``,
        ``"invalid"``.

    Raises
    ------
    InputError
        ``Q`` is not of shape ``(k,)`` or ``(n, k)``.
    TypeError
        ``Q`` is not a real float or integer array.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> m = isp.examples.stigger_husty()
    >>> counts, path = m.certified_root_counts(np.array([m.q_example_float, [np.nan, 1, 1]]))
    >>> counts.tolist(), path.tolist()[1]
    ([6, -1], 'invalid')
    """
    m = check_mechanism(m, image_space=None)
    be = m.backends
    Q = joint_batch(m, Q)
    n = Q.shape[0]
    # the float stage's working set per row (the solve's), plus the outputs (a count and a path name)
    per_row = be.peak_bytes(m, be.methods[0], False, n) + 64
    check_memory(n * per_row, f"certified_root_counts of {n:,} rows",
                 f"count it in chunks of rows (a chunk of 65,536 rows needs about "
                 f"{65536 * per_row / 1e9:.2g} GB)")
    ok, _ = m.joint_rows(Q)
    counts = np.full(n, -1, dtype=np.int8)
    path = np.full(n, "invalid", dtype=object)
    far = ok & (be.far(m, Q) if be.far is not None else np.zeros(n, dtype=bool))
    for i in np.flatnonzero(far):           # beyond the float stage: a reach bound, else exact
        ob = be.reach(m, Q[i]) if be.reach is not None else None
        if ob is not None:
            counts[i], path[i] = 0, "reach"
    rows = ok & ~(far & (path == "reach"))
    c, p = be.counts(m, Q, rows)
    counts[rows], path[rows] = c[rows], p[rows]
    return counts, path.astype(str)
