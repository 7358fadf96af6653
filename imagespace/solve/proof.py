"""Proven real-root counts for the float paths to answer to: the design's batch kernel, the
proven counts and isolating intervals of a batch of joint vectors, and the test that a row's
float modes account for them.

A float path (the numpy path, the per-call float path, the kernel's careful rows) returns a
count it has not proven; :func:`proven_roots` proves the number of distinct real roots of the
kinematic polynomial at the exact input and isolates each root (inside the compiled kernel, or
on the rigorous enclosure of the general-q polynomial for designs the kernel does not take),
and :func:`modes_match_roots` says whether the float modes sit one per proven root. A row that
fails it is flagged ``near_singular``: its count may be wrong. A row that passes has the proven
count.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

__all__ = ["batch_kernel", "proven_roots", "modes_match_roots"]


def have_numba() -> bool:
    """Whether numba is installed, without importing it (its import alone takes ~0.3 s).

    Examples
    --------
    >>> from imagespace.solve.proof import have_numba
    >>> isinstance(have_numba(), bool)
    True
    """
    import importlib.util

    return importlib.util.find_spec("numba") is not None


def batch_kernel(m: Any) -> Any:
    """The batch kernel of the design ``m`` (the generic compiled loops bound to the design's
    tables; built once, cached on it), or None where it does not apply (numba missing, free
    symbols in the design, a PP dyad, a Cramer denominator vanishing identically).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.proof import batch_kernel
    >>> from imagespace.solve.kernel import HAVE_NUMBA
    >>> (batch_kernel(isp.examples.general_3rpr()) is not None) == HAVE_NUMBA
    True
    """
    return m.cached("kernel", lambda: _build_batch_kernel(m))


def _build_batch_kernel(m):
    """Build the compiled kernel of ``m`` (None where it does not apply): the factory behind
    :func:`batch_kernel`."""
    if not m.is_numeric or not have_numba():
        return None
    from .kernel import build_kernel          # numba is imported on the first kernel only

    return build_kernel(m)


def proven_roots(m: Any, Q: np.ndarray) -> Optional[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """Proven numbers of distinct real roots of the kinematic polynomial, with an isolating
    interval for each, for joint vectors ``Q`` (n, 3) (finite, in the joints' domains; floats
    taken as the binary rationals they are).

    With the design's compiled kernel the proof runs inside it
    (:meth:`~imagespace.solve.kernel.BatchKernel.certified_counts`); otherwise the rigorous
    enclosure of the general-q polynomial (:meth:`~imagespace.core.mechanism.Mechanism.enclosure`)
    goes through the same Bernstein isolation (:func:`imagespace.core.isolate.certified_root_counts`).
    Nothing here is exact: rows the bounds cannot decide get -1.

    Returns
    -------
    (counts, lo, hi, chart) or None
        ``counts`` (n,) int, -1 where undecided; ``lo``, ``hi`` (n, 6) the isolating
        intervals, in ``t = x1/x0`` where ``chart`` (n, 6) is 0 and in ``s = x0/x1`` where it is
        1 (-1 in unused slots). None when the design has neither a kernel nor an enclosure of
        degree <= 6.

    Examples
    --------
    >>> import numpy as np
    >>> import imagespace as isp
    >>> from imagespace.solve.proof import proven_roots
    >>> m = isp.examples.collinear_3rpr()          # no kernel (Cramer case (a)): the enclosure
    >>> counts, lo, hi, chart = proven_roots(m, np.array([m.q_example_float]))
    >>> counts.tolist(), int((chart[0] >= 0).sum())
    ([2], 2)
    """
    n = Q.shape[0]
    kernel = batch_kernel(m)
    if kernel is not None:
        counts, lo, hi, chart = kernel.certified_counts(Q)
        return counts.astype(int), lo, hi, chart
    from ..core.isolate import MAX_DEGREE, certified_root_counts

    enc = m.enclosure()
    if enc.degree > MAX_DEGREE:
        return None
    lo = np.full((n, 6), np.nan)
    hi = np.full((n, 6), np.nan)
    chart = np.full((n, 6), -1, dtype=np.int8)
    if not n:
        return np.zeros(0, dtype=int), lo, hi, chart
    F, E = enc.evaluate(Q)
    counts, iv, ch = certified_root_counts(F, E)
    d = iv.shape[1]
    lo[:, :d], hi[:, :d], chart[:, :d] = iv[..., 0], iv[..., 1], ch
    return counts.astype(int), lo, hi, chart


def _inside(x0, x1, lo, hi, chart):
    """(n, k, r) bool: the orientation ``(x0 : x1)`` (n, k) lies in root interval ``r``."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (x1 / x0)[:, :, None]
        s = (x0 / x1)[:, :, None]
    L, H, c = lo[:, None, :], hi[:, None, :], chart[:, None, :]
    return ((c == 0) & (t >= L) & (t <= H)) | ((c == 1) & (s >= L) & (s <= H))


def modes_match_roots(half: np.ndarray, valid: np.ndarray, proof: tuple, spurious: Optional[np.ndarray] = None,
                      special: Optional[np.ndarray] = None, examined: Optional[np.ndarray] = None) -> np.ndarray:
    """Whether each row's float modes account for its proven real roots.

    Parameters
    ----------
    half : (n, k) float
        Half-angles ``phi / 2`` of the modes (NaN where not valid).
    valid : (n, k) bool
    proof : tuple
        :func:`proven_roots` of the rows.
    spurious : (n, p) float, optional
        Half-angles of the spurious orientations of PP dyads (NaN where none): a root interval
        holding one of them may hold no mode.
    special : (n,) bool, optional
        Rows solved orientation by orientation (Cramer cases), where a root may carry 0, 1 or 2
        modes: where the proof decided the row, every mode must lie in a root interval, no root
        may hold more than two, and a root holding none must hold one of the ``examined``
        orientations; where it did not, the row passes here and is left to the float path's
        own criteria (merging positions, clusters, conditioning).
    examined : (n, e) float, optional
        Half-angles of the orientations the float path solved on special rows (NaN padded).

    Returns
    -------
    (n,) bool
        True where the count is proven: the proof decided the row and every proven real root
        holds exactly one mode, no mode outside them (special rows: as above). False rows are
        ``near_singular``.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.solve.proof import modes_match_roots
    >>> proof = (np.array([2]), np.array([[-0.5, 0.1]]), np.array([[-0.4, 0.2]]), np.array([[0, 0]]))
    >>> half = np.arctan(np.array([[-0.45, 0.15]]))
    >>> modes_match_roots(half, np.array([[True, True]]), proof).tolist()
    [True]
    >>> modes_match_roots(half[:, :1], np.array([[True]]), proof).tolist()      # a root without a mode
    [False]
    """
    counts, lo, hi, chart = proof
    real_slot = chart >= 0
    h = np.where(valid, half, 0.0)
    inside = _inside(np.cos(h), np.sin(h), lo, hi, chart) & valid[:, :, None]
    per_root = inside.sum(axis=1)
    per_mode = inside.sum(axis=2)
    exempt = np.zeros_like(real_slot)
    if spurious is not None and spurious.size:
        sp_ok = np.isfinite(spurious)
        hs = np.where(sp_ok, spurious, 0.0)
        exempt = np.any(_inside(np.cos(hs), np.sin(hs), lo, hi, chart) & sp_ok[:, :, None], axis=1)
    modes_in = np.all(np.where(valid, per_mode == 1, True), axis=1)
    one_each = np.all(np.where(real_slot, (per_root == 1) | ((per_root == 0) & exempt), per_root == 0), axis=1)
    ok = (counts >= 0) & modes_in & one_each
    if special is not None and np.any(special):
        seen = np.zeros_like(real_slot)
        if examined is not None and examined.size:
            ex_ok = np.isfinite(examined)
            he = np.where(ex_ok, examined, 0.0)
            seen = np.any(_inside(np.cos(he), np.sin(he), lo, hi, chart) & ex_ok[:, :, None], axis=1)
        loose = np.all(np.where(real_slot, (per_root <= 2) & ((per_root > 0) | seen | exempt), per_root == 0),
                       axis=1)
        # an undecided proof says nothing on a Cramer-case row: a nearly vanishing Cramer
        # denominator makes two well-separated modes of one orientation a pair of roots the
        # bounds cannot separate; such rows are judged by the float path's own criteria
        ok = np.where(special, (counts < 0) | (modes_in & loose), ok)
    return ok
