"""Result types of the spatial direct kinematics (one pose, and batches with per-row masks)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional, Sequence, overload

import numpy as np
import numpy.typing as npt

from .._html import counts_text, fmt, html_table
from .study import rotation_matrix, translation

if TYPE_CHECKING:
    from ..core.kinematic_map import FloatArray

__all__ = ["SpatialDKResult", "SpatialDKBatch", "METHODS"]

#: how a result was obtained ("reach": no mode, proven by a reach bound, :mod:`imagespace.core.reach`)
METHODS = ("homotopy", "homotopy+krawczyk", "msolve", "reach")


@dataclass(frozen=True)
class SpatialDKResult:
    """The real assembly modes of one spatial direct-kinematics problem.

    Attributes
    ----------
    study_points : (k, 8) float
        Normalised Study points (``x . x = 1``, first non-zero of ``x`` positive), one per real mode.
    residuals : (k,) float
        ``max_j |z^T Q_j z|`` at each mode (the float quadrics, the normalised point).
    aspects : (k,) int8
        Sign of the Jacobian determinant (``0``: not decided in floats, a mode on or very near a
        singularity).
    complex_count : int
        Distinct complex solutions found (40 for a general Gough-Stewart platform); -1 when not
        computed (method ``"reach"``: a reach bound proved that no real mode exists).
    certified : bool
        The count and every mode are proven (Krawczyk boxes in arb, or msolve's exact isolation).
    reliable : bool
        The count is proven by the fast path's compiled Krawczyk test
        (:mod:`imagespace.spatial.fastcert`: rigorous error bounds on the exact quadrics): as many
        distinct solutions as the design's bound (40 Gough-Stewart, 16 for 6-3, 3-3 and 3-RPS) in
        pairwise disjoint boxes, each proven real or not real; for a special design whose start
        system has fewer solutions than the bound, as many as the start system has (then
        complete only as far as that count is). When False the count may be wrong (a warning
        per call). ``certified`` implies ``reliable``.
    method : str
        One of :data:`METHODS`.

    Examples
    --------
    >>> r = SpatialDKResult(np.array([[1.0, 0, 0, 0, 0, 0, 0, 0]]), np.zeros(1), np.ones(1, np.int8),
    ...                     40, False, True, "homotopy")
    >>> r.count, r.translations
    (1, array([[0., 0., 0.]]))
    """

    study_points: np.ndarray
    residuals: np.ndarray
    aspects: np.ndarray
    complex_count: int
    certified: bool
    reliable: bool
    method: str

    @property
    def count(self) -> int:
        """Number of real assembly modes."""
        return int(self.study_points.shape[0])

    @property
    def rotations(self) -> FloatArray:
        """``(k, 3, 3) float`` rotation matrices of the modes."""
        if not self.count:
            return np.zeros((0, 3, 3))
        return rotation_matrix(self.study_points)

    @property
    def translations(self) -> FloatArray:
        """``(k, 3) float`` translations of the modes."""
        if not self.count:
            return np.zeros((0, 3))
        return translation(self.study_points)

    def __len__(self):
        return self.count

    def _repr_html_(self):
        return result_html(self)

    def __repr__(self):
        state = "certified" if self.certified else ("reliable" if self.reliable else "NOT reliable")
        of = f"of {self.complex_count} complex" if self.complex_count >= 0 else "(complex not computed)"
        return f"SpatialDKResult({self.count} real modes {of}, {state}, method={self.method!r})"


class SpatialDKBatch:
    """Real modes of many problems, stored ragged (row ``i`` owns ``offsets[i]:offsets[i+1]``).

    The batch vocabulary of every mechanism (see :mod:`imagespace.solve.front`): ``count``,
    ``row_ok``, ``near_singular``, ``certified``, ``certificate_path``, ``certified_roots``,
    ``errors``; ``batch[i]`` (negative ``i`` from the end, a slice gives a list) is row ``i``'s
    :class:`SpatialDKResult`; padded per-mode arrays ``valid``, ``poses``, ``aspect``.

    Attributes
    ----------
    count : (n,) int
        Real modes per row (``counts`` is the same array, its name before issue [15]).
    offsets : (n + 1,) int
    study_points : (total, 8) float
    residuals : (total,) float
    aspects : (total,) int8
    complex_count : (n,) int
    reliable : (n,) bool
        The row's count is proven by the compiled certificate (see :class:`SpatialDKResult`);
        False marks a row whose count may be wrong.
    certified : (n,) bool
        The row is proven.
    row_ok : (n,) bool
        The row's input was acceptable and solved; invalid rows have no modes and their reason
        in ``errors``.
    errors : dict
        Row -> message, for the rows not solved.
    methods : (n,) str
        How each row was answered (:data:`METHODS`, ``"invalid"`` for a row not solved).

    Examples
    --------
    >>> b = SpatialDKBatch(np.array([1, 0]), np.array([0, 1, 1]), np.eye(1, 8), np.zeros(1),
    ...                    np.ones(1, np.int8), np.array([40, 0]), np.array([True, False]),
    ...                    np.zeros(2, bool), np.array([True, False]))
    >>> b[0].count, len(b), b[-1].count, b.row_ok.tolist()
    (1, 2, 0, [True, False])
    """

    def __init__(self, count: npt.ArrayLike, offsets: npt.ArrayLike, study_points: npt.ArrayLike,
                 residuals: npt.ArrayLike, aspects: npt.ArrayLike, complex_count: npt.ArrayLike,
                 reliable: npt.ArrayLike, certified: npt.ArrayLike, row_ok: npt.ArrayLike,
                 errors: Optional[dict[int, str]] = None, methods: Optional[npt.ArrayLike] = None) -> None:
        self.count = np.array(count, dtype=np.int64)
        self.offsets = np.array(offsets, dtype=np.int64)
        self.study_points = np.asarray(study_points, dtype=float).reshape(-1, 8)
        self.residuals = np.asarray(residuals, dtype=float)
        self.aspects = np.asarray(aspects, dtype=np.int8)
        self.complex_count = np.array(complex_count, dtype=np.int64)
        self.reliable = np.array(reliable, dtype=bool)
        self.certified = np.array(certified, dtype=bool)
        self.row_ok = np.array(row_ok, dtype=bool)
        self.errors = dict(errors or {})
        if methods is None:
            methods = np.where(~self.row_ok, "invalid",
                               np.where(self.complex_count < 0, "reach",
                                        np.where(self.certified, "homotopy+krawczyk", "homotopy")))
        self.methods = np.asarray(methods, dtype=object)

    @classmethod
    def from_results(cls, results: Sequence[Optional[SpatialDKResult]],
                     errors: Optional[dict[int, str]] = None) -> SpatialDKBatch:
        """A batch from per-row :class:`SpatialDKResult` (None for a row not solved).

        Examples
        --------
        >>> r = SpatialDKResult(np.eye(1, 8), np.zeros(1), np.ones(1, np.int8), 40, True, True, "msolve")
        >>> b = SpatialDKBatch.from_results([r, None])
        >>> b.count.tolist(), b.row_ok.tolist(), b[0].method
        ([1, 0], [True, False], 'msolve')
        """
        done = [r for r in results if r is not None]
        count = np.array([r.count if r is not None else 0 for r in results], dtype=np.int64)
        return cls(count, np.concatenate([[0], np.cumsum(count)]),
                   np.vstack([r.study_points for r in done]) if done else np.zeros((0, 8)),
                   np.concatenate([r.residuals for r in done]) if done else np.zeros(0),
                   np.concatenate([r.aspects for r in done]).astype(np.int8) if done else np.zeros(0, np.int8),
                   np.array([r.complex_count if r is not None else 0 for r in results]),
                   np.array([r.reliable if r is not None else False for r in results]),
                   np.array([r.certified if r is not None else False for r in results]),
                   np.array([r is not None for r in results]), errors,
                   np.array([r.method if r is not None else "invalid" for r in results], dtype=object))

    # -- the batch vocabulary ----------------------------------------------------------------------
    @property
    def counts(self) -> npt.NDArray[np.integer]:
        """The same array as :attr:`count` (the name before issue [15])."""
        return self.count

    @property
    def near_singular(self) -> npt.NDArray[np.bool_]:
        """(n,) bool: solved rows whose count is not proven (``row_ok`` and not ``reliable``)."""
        return self.row_ok & ~self.reliable

    @property
    def certified_roots(self) -> npt.NDArray[np.int8]:
        """(n,) int8: the proven count of real modes per row, -1 where not proven."""
        return np.where(self.row_ok & self.certified, self.count, -1).astype(np.int8)

    @property
    def consistent(self) -> npt.NDArray[np.bool_]:
        """(n,) bool: the rows whose modes are proven (as :attr:`certified`, on solved rows)."""
        return self.row_ok & self.certified

    @property
    def certificate_path(self) -> npt.NDArray[np.str_]:
        """(n,) str: what proved each row's count: ``"krawczyk"`` (the compiled certificate or
        Krawczyk boxes in arb), ``"msolve"``, ``"reach"``; ``"uncertified"``, ``"invalid"``."""
        out = np.full(len(self), "uncertified", dtype=object)
        out[~self.row_ok] = "invalid"
        for i in np.flatnonzero(self.row_ok & self.certified):
            m = self.methods[i]
            out[i] = "msolve" if m == "msolve" else ("reach" if m == "reach" else "krawczyk")
        return out.astype(str)

    @property
    def width(self) -> int:
        """The most modes of a row (the padded arrays' second axis)."""
        return int(self.count.max()) if len(self) else 0

    def _padded(self, values, fill, dtype, trailing=()):
        n, w = len(self), self.width
        out = np.full((n, w) + tuple(trailing), fill, dtype=dtype)
        slot = np.arange(w)[None, :] < self.count[:, None]
        out[slot] = values
        return out

    @property
    def valid(self) -> npt.NDArray[np.bool_]:
        """(n, width) bool: which padded slots hold a mode (the planar results' ``valid``)."""
        return np.arange(self.width)[None, :] < self.count[:, None]

    @property
    def poses(self) -> FloatArray:
        """(n, width, 7) float: each mode as translation ``(x, y, z)`` and unit quaternion
        ``(w, x, y, z)`` (``w >= 0``), NaN in unused slots."""
        S = self.study_points
        if len(S):
            x = S[:, :4] / np.linalg.norm(S[:, :4], axis=1, keepdims=True)
            x = x * np.where(x[:, :1] < 0, -1.0, 1.0)
            vals = np.concatenate([translation(S), x], axis=1)
        else:
            vals = np.zeros((0, 7))
        return self._padded(vals, np.nan, float, (7,))

    @property
    def aspect(self) -> npt.NDArray[np.int8]:
        """(n, width) int8: the modes' aspects, 0 in unused slots."""
        return self._padded(self.aspects, 0, np.int8)

    def __len__(self):
        return int(self.count.shape[0])

    @overload
    def __getitem__(self, i: int) -> SpatialDKResult: ...
    @overload
    def __getitem__(self, i: slice) -> list[SpatialDKResult]: ...
    def __getitem__(self, i):
        from ..core.mechanism import index_rows

        def row(k):
            sl = slice(int(self.offsets[k]), int(self.offsets[k + 1]))
            return SpatialDKResult(self.study_points[sl], self.residuals[sl], self.aspects[sl],
                                   int(self.complex_count[k]), bool(self.certified[k]),
                                   bool(self.reliable[k]), str(self.methods[k]))
        return index_rows(self, i, row)

    def _repr_html_(self):
        return batch_html(self)

    def __repr__(self):
        return (f"SpatialDKBatch({len(self)} rows, {int(self.count.sum())} real modes, "
                f"{int(np.sum(self.near_singular))} rows not reliable)")


#: Most modes a result's HTML table lists (Dietmaier's 40 fit; a longer list says how many are left out).
HTML_ROWS = 48


def _state(certified, reliable):
    return "certified" if certified else ("reliable (not proven)" if reliable else "NOT reliable")


def result_html(result: SpatialDKResult) -> str:
    """The modes of a :class:`SpatialDKResult` as a table for Jupyter: translation, rotation (angle
    and axis), aspect and residual of each mode under the count and how sure it is.

    Examples
    --------
    >>> r = SpatialDKResult(np.array([[1.0, 0, 0, 0, 0, 0.5, 0, 0]]), np.zeros(1), np.ones(1, np.int8),
    ...                     40, True, True, "homotopy+krawczyk")
    >>> page = result_html(r)
    >>> "1 real assembly mode of 40 complex solutions, certified" in page, page.count("<tr>")
    (True, 2)
    """
    k = result.count
    title = (f"{k} real assembly mode{'' if k == 1 else 's'} of {result.complex_count} complex solutions, "
             f"{_state(result.certified, result.reliable)} ({result.method})")
    S = np.asarray(result.study_points, dtype=float)[:HTML_ROWS]
    rows = []
    if len(S):
        T = translation(S)
        x = S[:, :4] / np.linalg.norm(S[:, :4], axis=1, keepdims=True)
        vnorm = np.linalg.norm(x[:, 1:], axis=1)
        angle = np.degrees(2 * np.arctan2(vnorm, np.abs(x[:, 0])))
        axis = np.where(vnorm[:, None] > 0, x[:, 1:] * np.sign(x[:, :1] + (x[:, :1] == 0)) / np.where(
            vnorm[:, None] > 0, vnorm[:, None], 1.0), 0.0)
        for i in range(len(S)):
            rows.append([i + 1, "(" + ", ".join(fmt(v, 5) for v in T[i]) + ")", fmt(angle[i], 5),
                         "(" + ", ".join(fmt(v, 4) for v in axis[i]) + ")", f"{int(result.aspects[i]):+d}",
                         f"{float(result.residuals[i]):.1e}"])
    out = html_table(rows, title=title, header=["#", "translation (x, y, z)", "rotation [deg]", "about the axis",
                                                "aspect", "residual"])
    if k > HTML_ROWS:
        out += f"\n<p>... and {k - HTML_ROWS} more modes (result.study_points has all {k})</p>"
    return out


def batch_html(batch: SpatialDKBatch) -> str:
    """A :class:`SpatialDKBatch` for Jupyter: rows, how many are valid, reliable and certified, and
    the real counts seen.

    Examples
    --------
    >>> b = SpatialDKBatch(np.array([1, 0]), np.array([0, 1, 1]), np.eye(1, 8), np.zeros(1),
    ...                    np.ones(1, np.int8), np.array([40, 0]), np.array([True, False]),
    ...                    np.zeros(2, bool), np.array([True, False]))
    >>> "real modes per row" in batch_html(b)
    True
    """
    valid = np.asarray(batch.row_ok, dtype=bool)
    counts = np.asarray(batch.count)[valid]
    rows = [("rows", len(batch)), ("valid rows", int(valid.sum())),
            ("reliable rows (float checks passed)", int(np.sum(np.asarray(batch.reliable) & valid))),
            ("certified rows", int(np.sum(np.asarray(batch.certified) & valid))),
            ("real modes per row", "{" + counts_text(sorted(int(c) for c in counts)) + "}" if len(counts) else "-"),
            ("real modes in all", int(np.sum(counts)))]
    return html_table(rows, title=f"SpatialDKBatch: {len(batch)} rows")
