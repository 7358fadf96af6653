"""Result types of the spatial direct kinematics (one pose, and batches with per-row masks)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._html import counts_text, fmt, html_table
from .study import rotation_matrix, translation

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
    def count(self):
        """Number of real assembly modes."""
        return int(self.study_points.shape[0])

    @property
    def rotations(self):
        """``(k, 3, 3) float`` rotation matrices of the modes."""
        if not self.count:
            return np.zeros((0, 3, 3))
        return rotation_matrix(self.study_points)

    @property
    def translations(self):
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


@dataclass(frozen=True)
class SpatialDKBatch:
    """Real modes of many problems, stored ragged (row ``i`` owns ``offsets[i]:offsets[i+1]``).

    Attributes
    ----------
    counts : (n,) int
        Real modes per row.
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
    valid : (n,) bool
        The row's input was acceptable (positive finite lengths); invalid rows have no modes.

    Examples
    --------
    >>> b = SpatialDKBatch(np.array([1, 0]), np.array([0, 1, 1]), np.eye(1, 8), np.zeros(1),
    ...                    np.ones(1, np.int8), np.array([40, 0]), np.array([True, False]),
    ...                    np.zeros(2, bool), np.array([True, False]))
    >>> b[0].count, len(b)
    (1, 2)
    """

    counts: np.ndarray
    offsets: np.ndarray
    study_points: np.ndarray
    residuals: np.ndarray
    aspects: np.ndarray
    complex_count: np.ndarray
    reliable: np.ndarray
    certified: np.ndarray
    valid: np.ndarray

    def __len__(self):
        return int(self.counts.shape[0])

    def __getitem__(self, i):
        i = int(i)
        sl = slice(int(self.offsets[i]), int(self.offsets[i + 1]))
        method = ("reach" if self.complex_count[i] < 0 else
                  "homotopy+krawczyk" if self.certified[i] else "homotopy")
        return SpatialDKResult(self.study_points[sl], self.residuals[sl], self.aspects[sl],
                               int(self.complex_count[i]), bool(self.certified[i]),
                               bool(self.reliable[i]), method)

    def _repr_html_(self):
        return batch_html(self)

    def __repr__(self):
        return (f"SpatialDKBatch({len(self)} rows, {int(self.counts.sum())} real modes, "
                f"{int(np.sum(~self.reliable & self.valid))} rows not reliable)")


#: Most modes a result's HTML table lists (Dietmaier's 40 fit; a longer list says how many are left out).
HTML_ROWS = 48


def _state(certified, reliable):
    return "certified" if certified else ("reliable (not proven)" if reliable else "NOT reliable")


def result_html(result):
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


def batch_html(batch):
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
    valid = np.asarray(batch.valid, dtype=bool)
    counts = np.asarray(batch.counts)[valid]
    rows = [("rows", len(batch)), ("valid rows", int(valid.sum())),
            ("reliable rows (float checks passed)", int(np.sum(np.asarray(batch.reliable) & valid))),
            ("certified rows", int(np.sum(np.asarray(batch.certified) & valid))),
            ("real modes per row", "{" + counts_text(sorted(int(c) for c in counts)) + "}" if len(counts) else "-"),
            ("real modes in all", int(np.sum(counts)))]
    return html_table(rows, title=f"SpatialDKBatch: {len(batch)} rows")
