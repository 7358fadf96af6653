"""Paths in image space: ``t -> X(t)`` made of polynomial pieces (segments, polylines, polynomial
and rational curves, exact rational coefficients) or of pose segments. Checked against the
singularity surface by :mod:`imagespace.paths.check`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import sympy as sp

from .._validate import as_float_array
from ..core.exact_roots import fmpq_of, roots_in_unit_interval
from ..exceptions import InputError, InputTypeError
from .._html import html_table, summary

__all__ = ["ImagePath", "segment", "polyline", "polynomial_curve", "rational_curve", "pose_segment"]


def _exact(v):
    """A coordinate as an exact Fraction: floats as the binary rationals they are, sympy rationals as such."""
    if isinstance(v, Fraction):
        return v
    if isinstance(v, (str, bytes, bool, np.bool_, complex)) or v is None:
        raise InputTypeError(f"path coefficients must be real numbers, got {type(v).__name__} {v!r}; "
                             "strings are never parsed")
    if isinstance(v, sp.Basic):
        r = sp.Rational(v) if isinstance(v, sp.Float) else v      # a Float is its binary rational
        if not r.is_Rational:
            raise InputError(f"path coefficients must be rational, got {v}")
        return Fraction(int(r.p), int(r.q))
    if isinstance(v, (int, np.integer)):
        return Fraction(int(v))
    return Fraction(float(v))


@dataclass(frozen=True)
class ImagePath:
    """A path ``t -> X(t)`` in image space made of pieces, each over ``t in [0, 1]``.

    Build with :func:`segment`, :func:`polyline`, :func:`polynomial_curve`, :func:`rational_curve`
    or :func:`pose_segment`.

    Attributes
    ----------
    pieces : tuple
        For polynomial pieces: ``(deg + 1, 4)`` exact rational coefficient arrays (object dtype;
        row ``k`` multiplies ``t**k``). For pose segments: ``(2, 3)`` float endpoint poses.
    kind : str
        ``"polynomial"`` or ``"pose"``.
    """

    pieces: tuple
    kind: str = "polynomial"

    def __len__(self):
        return len(self.pieces)

    @property
    def start(self):
        """The first point, ``(4,)`` float."""
        return self.evaluate(0, np.array([0.0]))[0]

    @property
    def end(self):
        """The last point, ``(4,)`` float."""
        return self.evaluate(len(self.pieces) - 1, np.array([1.0]))[0]

    def evaluate(self, piece, t):
        """Points of one piece at parameters ``t``: ``(n, 4)`` float (homogeneous).

        Examples
        --------
        >>> from imagespace.paths.check import segment
        >>> segment([1, 0, 0, 0], [1, 0, 2, 0]).evaluate(0, [0.5]).tolist()
        [[1.0, 0.0, 1.0, 0.0]]
        """
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if self.kind == "pose":
            from ..core.kinematic_map import image_point

            p0, p1 = self.pieces[piece]
            return image_point(p0[None, :] + t[:, None] * (p1 - p0)[None, :])
        B = _bernstein_floats(self.pieces[piece])
        # de Casteljau on the Bernstein coefficients (computed exactly, rounded once): stable where
        # the monomial form cancels, e.g. (1 - t) a + t b with |a| >> |b| at t = 1
        pts = np.broadcast_to(B[None, :, :], (len(t), *B.shape)).copy()
        tt = t[:, None]
        for r in range(1, B.shape[0]):
            pts[:, : B.shape[0] - r, :] = (1 - tt[:, :, None]) * pts[:, : B.shape[0] - r, :] \
                + tt[:, :, None] * pts[:, 1: B.shape[0] - r + 1, :]
        return pts[:, 0, :]

    def sample(self, per_piece=64):
        """Points along the whole path: ``(len(self) * per_piece + 1, 4)`` float, and their
        global parameters ``s in [0, len(self)]``.

        Examples
        --------
        >>> from imagespace.paths.check import polyline
        >>> X, s = polyline([[1, 0, 0, 0], [1, 0, 1, 0], [1, 0, 1, 1]]).sample(4)
        >>> X.shape, float(s[-1])
        ((9, 4), 2.0)
        """
        out, ss = [], []
        for k in range(len(self.pieces)):
            t = np.linspace(0, 1, per_piece + 1)[: -1 if k < len(self.pieces) - 1 else None]
            out.append(self.evaluate(k, t))
            ss.append(k + t)
        return np.concatenate(out), np.concatenate(ss)

    def poses(self, per_piece=64):
        """Poses along the path: ``(n, 3)`` float, ``phi`` unwrapped to be continuous.

        Examples
        --------
        >>> from imagespace.paths.check import pose_segment
        >>> pose_segment([0, 0, 0], [1, 0, 0.5]).poses(2)[:, 2].tolist()
        [0.0, 0.25, 0.5]
        """
        from ..core.kinematic_map import pose_of

        X, _ = self.sample(per_piece)
        P = pose_of(X)
        P[:, 2] = np.unwrap(P[:, 2])
        return P

    def _summary_items(self):
        items = [("kind", repr(self.kind)), ("pieces", str(len(self.pieces)))]
        if self.kind == "polynomial":
            items.append(("degrees", str(tuple(int(np.shape(p)[0]) - 1 for p in self.pieces[:8]))
                          .replace(")", ", ...)" if len(self.pieces) > 8 else ")")))
        return items

    def __repr__(self):
        """The kind, the number of pieces and their degrees, never the exact coefficients.

        Examples
        --------
        >>> from imagespace.paths.check import polyline
        >>> polyline([[1, 0, 0, 0], [1, 0, 1, 0], [1, 0, 1, 1]])
        ImagePath(kind='polynomial', pieces=2, degrees=(1, 1))
        """
        return summary("ImagePath", self._summary_items())

    def _repr_html_(self):
        """The summary as an HTML table.

        Examples
        --------
        >>> from imagespace.paths.check import segment
        >>> "polynomial" in segment([1, 0, 0, 0], [1, 0, 1, 0])._repr_html_()
        True
        """
        return html_table(self._summary_items(), title="ImagePath")


def _bernstein_floats(C):
    """Bernstein coefficients ``(deg + 1, 4)`` on ``[0, 1]`` of the exact monomial rows ``C``,
    computed in rational arithmetic and rounded once to float:
    ``b_i = sum_{k <= i} binom(i, k) / binom(n, k) c_k``."""
    n = len(C) - 1
    out = np.empty((n + 1, 4))
    for i in range(n + 1):
        for j in range(4):
            out[i, j] = float(sum(Fraction(math.comb(i, k), math.comb(n, k)) * _exact(C[k][j])
                                  for k in range(i + 1)))
    return out


def _point(v, name):
    a = as_float_array(v, name, last=4, allow_batch=False)
    if a[0] == 0 and a[1] == 0:
        raise InputError(f"{name} has x0 = x1 = 0, a point of the absolute line, not a displacement; got {a.tolist()}")
    return a


def segment(a, b):
    """The straight segment ``(1 - t) a + t b`` between two image points (the representatives given).

    Parameters
    ----------
    a, b : (4,) float
        Image points; ``X`` and ``-X`` are the same point but give different segments: the one
        through the representatives given is taken.

    Returns
    -------
    ImagePath

    Raises
    ------
    InputError
        ``a`` or ``b`` not an image point of shape ``(4,)``; for a pose ``(x, y, phi)`` the
        message points to :func:`~imagespace.paths.check.pose_segment` (the segment between two
        poses) and :func:`~imagespace.image_point` (a pose's image point).

    Examples
    --------
    >>> from imagespace.paths.check import segment
    >>> len(segment([1, 0, 0, 0], [1, 0.5, 1, 2]))
    1
    """
    for v, name in ((a, "a"), (b, "b")):
        try:
            as_float_array(v, name, last=4, allow_batch=False)
        except InputError as e:
            pose = np.shape(v) == (3,) if not isinstance(v, (str, bytes)) else False
            hint = (f"{name} looks like a pose (x, y, phi): segment joins image points (x0, x1, x2, x3); "
                    "use isp.pose_segment(pose_a, pose_b) for the path between two poses, or "
                    "isp.image_point(pose) for a pose's image point") if pose else (
                    "segment joins image points (x0, x1, x2, x3): isp.image_point(pose) gives a pose's, and "
                    "isp.pose_segment(pose_a, pose_b) the path between two poses")
            raise InputError(f"{e}; {hint}") from None
    return polyline([a, b])


def polyline(points):
    """A polyline through image points (one straight segment per consecutive pair).

    Parameters
    ----------
    points : (k, 4) float, k >= 2

    Returns
    -------
    ImagePath

    Raises
    ------
    InputError
        Fewer than two points, a zero-length segment, a non-finite point, or a segment through
        the absolute line ``x0 = x1 = 0``.

    Examples
    --------
    >>> from imagespace.paths.check import polyline
    >>> len(polyline([[1, 0, 0, 0], [1, 0, 1, 0], [1, 0.2, 1, 1]]))
    2
    """
    P = as_float_array(points, "points", last=4)
    if P.ndim != 2 or len(P) < 2:
        raise InputError(f"points must be (k, 4) with k >= 2, got shape {P.shape}")
    pieces = []
    for k in range(len(P) - 1):
        a, b = _point(P[k], f"points[{k}]"), _point(P[k + 1], f"points[{k + 1}]")
        if np.array_equal(a, b):
            raise InputError(f"points[{k}] and points[{k + 1}] are equal: a zero-length segment")
        sa, sb = a / np.max(np.abs(a)), b / np.max(np.abs(b))      # signs only: no overflow
        if sa[0] * sb[1] - sa[1] * sb[0] == 0 and sa[0] * sb[0] + sa[1] * sb[1] < 0:
            raise InputError(f"the segment from points[{k}] to points[{k + 1}] passes through x0 = x1 = 0 "
                             "(not a displacement); flip the sign of one representative")
        C = np.empty((2, 4), dtype=object)
        for j in range(4):
            C[0, j] = _exact(a[j])
            C[1, j] = _exact(b[j]) - C[0, j]
        pieces.append(C)
    return ImagePath(tuple(pieces))


def polynomial_curve(coefficients):
    """A polynomial curve ``X(t) = sum_k c_k t**k``, ``t in [0, 1]``.

    Parameters
    ----------
    coefficients : (deg + 1, 4) numbers
        Row ``k`` multiplies ``t**k``; exact sympy rationals are kept exact, floats are taken as
        the binary rationals they are.

    Returns
    -------
    ImagePath

    Raises
    ------
    TypeError
        Non-numeric coefficients.
    InputError
        Coefficients not ``(deg + 1, 4)``, or a constant curve.

    Examples
    --------
    >>> from imagespace.paths.check import polynomial_curve
    >>> polynomial_curve([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]).evaluate(0, [1.0]).tolist()
    [[1.0, 1.0, 1.0, 0.0]]
    """
    rows = np.array(coefficients, dtype=object)
    if rows.ndim != 2 or rows.shape[1] != 4 or rows.shape[0] < 1:
        raise InputError(f"coefficients must be (deg + 1, 4), got shape {rows.shape}")
    flo = as_float_array(rows, "coefficients", last=4)
    if flo.shape[0] == 1 or not np.any(flo[1:]):
        raise InputError("coefficients describe a constant curve (a zero-length path)")
    C = np.empty(rows.shape, dtype=object)
    for i in range(rows.shape[0]):
        for j in range(4):
            C[i, j] = _exact(rows[i, j])
    return ImagePath((C,))


def rational_curve(numerators, denominator):
    """A rational curve ``X(t) = N(t) / d(t)``: as a point of image space it is ``N(t)``.

    Parameters
    ----------
    numerators : (deg + 1, 4) numbers
    denominator : (m + 1,) numbers
        Must not vanish on ``[0, 1]`` (checked exactly); it does not change the points.

    Returns
    -------
    ImagePath

    Raises
    ------
    TypeError
        Non-numeric coefficients or denominator.
    InputError
        As :func:`polynomial_curve`; a denominator vanishing on ``[0, 1]``.

    Examples
    --------
    >>> from imagespace.paths.check import rational_curve
    >>> len(rational_curve([[1, 0, 0, 0], [0, 1, 1, 0]], [1, 1]))
    1
    """
    from flint import fmpq_poly

    d = [_exact(v) for v in np.ravel(np.array(denominator, dtype=object))]
    dp = fmpq_poly([fmpq_of(c) for c in d])
    if dp.is_zero() or roots_in_unit_interval(dp):
        raise InputError(f"denominator must not vanish on [0, 1], got {denominator!r}")
    return polynomial_curve(numerators)


def pose_segment(p0, p1):
    """The straight segment in pose space from ``p0`` to ``p1`` (``phi`` linear in ``t``).

    Parameters
    ----------
    p0, p1 : (3,) float

    Returns
    -------
    ImagePath
        ``kind == "pose"``; checked by interval arithmetic.

    Raises
    ------
    TypeError
        ``p0`` or ``p1`` not numeric.
    InputError
        ``p0`` or ``p1`` not ``(3,)`` or not finite; ``p0 == p1``.

    Examples
    --------
    >>> from imagespace.paths.check import pose_segment
    >>> pose_segment([0, 0, 0], [1, 2, 0.3]).kind
    'pose'
    """
    a = as_float_array(p0, "p0", last=3, allow_batch=False)
    b = as_float_array(p1, "p1", last=3, allow_batch=False)
    if np.array_equal(a, b):
        raise InputError("p0 and p1 are equal: a zero-length segment")
    return ImagePath(((a, b),), kind="pose")
