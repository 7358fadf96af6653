r"""Study's kinematic map: spatial displacements <-> points of Study's quadric in P^7.

Convention. A displacement with rotation quaternion ``x = x0 + x1 i + x2 j + x3 k`` and
translation ``t = (tx, ty, tz)`` has the Study parameters ``(x0 : x1 : x2 : x3 : y0 : y1 : y2 : y3)``
with the dual part ``y = (1/2) t x`` (quaternion product, ``t`` as the pure quaternion
``tx i + ty j + tz k``). A platform point ``p`` lands at ``X = R p + t`` with

.. math::

    R p = \frac{x\,p\,\tilde x}{x \tilde x}, \qquad t = \frac{2\,y\,\tilde x}{x \tilde x},

``~`` the quaternion conjugate. Every displacement lies on Study's quadric
``x0 y0 + x1 y1 + x2 y2 + x3 y3 = 0`` and has ``x != 0``; the points of the quadric with
``x = 0`` (the exceptional generator) are not displacements and are refused. Any non-zero multiple
is the same displacement; the normalised representative has ``x . x = 1`` and the first non-zero
of ``(x0, x1, x2, x3)`` positive. Half-turns (``x0 = 0``) are ordinary displacements.

The planar image space of :mod:`imagespace.core.kinematic_map` is the subspace
``x1 = x2 = y0 = y3 = 0``: a planar pose ``(x, y, phi)`` (rotation about ``z`` by ``phi``,
translation ``(x, y, 0)``) with planar image point ``(p0, p1, p2, p3)`` has the Study point
``(p0, 0, 0, p1, 0, p3, -p2, 0)``.

Every function has a numeric face (numpy, a point ``(8,)`` or a batch ``(n, 8)``) and works on
sympy objects too (a list or ``sympy.Matrix`` of 8 expressions in, a ``sympy.Matrix`` out).

References
----------
E. Study, *Geometrie der Dynamen*, Teubner 1903.
M. L. Husty, A. Karger, H. Sachs, W. Steinhilper, *Kinematik und Robotik*, Springer 1997,
doi:10.1007/978-3-642-59029-0.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Optional, Union, overload

import numpy as np
import numpy.typing as npt
import sympy as sp

from .._validate import as_float_array, as_sympy_vector, as_tolerances, is_symbolic
from ..exceptions import InputError
from ..tolerances import TOLERANCES

if TYPE_CHECKING:
    from ..core.kinematic_map import FloatArray, NumericInput
    from ..tolerances import Tolerances

__all__ = [
    "study_symbols",
    "quaternion_multiply",
    "quaternion_conjugate",
    "quaternion_from_matrix",
    "matrix_from_quaternion",
    "study_point",
    "rotation_matrix",
    "translation",
    "transform_matrix",
    "transform_points",
    "study_condition",
    "normalize_study",
    "compose_study",
    "inverse_study",
    "planar_to_study",
    "study_to_planar",
]


def study_symbols() -> tuple[sp.Symbol, ...]:
    """The eight Study parameters as sympy symbols ``x0, x1, x2, x3, y0, y1, y2, y3``.

    Returns
    -------
    tuple of 8 sympy.Symbol

    Examples
    --------
    >>> study_symbols()
    (x0, x1, x2, x3, y0, y1, y2, y3)
    """
    return tuple(sp.symbols("x0:4")) + tuple(sp.symbols("y0:4"))


# --------------------------------------------------------------------------- quaternions

def _qmul(p, q):
    """Hamilton product on the last axis (works for numpy arrays and lists of sympy objects)."""
    a0, a1, a2, a3 = p[..., 0], p[..., 1], p[..., 2], p[..., 3]
    b0, b1, b2, b3 = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
                     a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
                     a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
                     a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0], axis=-1)


def _batch_shape(a, b, names):
    """The broadcast batch shape of two arrays' leading axes, or an InputError naming both."""
    try:
        return np.broadcast_shapes(a.shape[:-1], b.shape[:-1])
    except ValueError:
        raise InputError(f"{names[0]} and {names[1]} must have the same batch size, got "
                         f"{a.shape[:-1]} and {b.shape[:-1]}") from None


def _sym(value, n, name):
    """A vector of ``n`` sympy entries as an object array (strings refused, never parsed)."""
    return np.array(as_sympy_vector(value, name, n), dtype=object)


def _max_abs(v):
    """The largest absolute entry on the last axis (keepdims), 1 where a row is zero: dividing by it
    brings any finite vector to entries in ``[-1, 1]`` without overflow or underflow."""
    m = np.abs(v).max(axis=-1, keepdims=True)
    return np.where(m > 0, m, 1.0)


# squared norms inside (_SAFE_LO, _SAFE_HI): products of two entries of such vectors neither
# overflow nor lose digits to underflow, so the plain formulas are exact to rounding there (the
# fast path); outside, the same formulas run on copies scaled to max |entry| = 1
_SAFE_LO, _SAFE_HI = 1e-150, 1e150


def _safe(sq, zero_ok=False):
    """True when every squared norm in ``sq`` lies in the fast path's range (or is 0, if allowed)."""
    ok = (sq > _SAFE_LO) & (sq < _SAFE_HI)
    if zero_ok:
        ok |= sq == 0
    return bool(np.all(ok))


def _sq(v):
    return np.einsum("...i,...i->...", v, v)


def vector_norm(v):
    """Euclidean norms on the last axis without overflow or underflow (scaled by the largest entry
    first): ``numpy.linalg.norm`` squares the entries, so a vector of ``1e200`` has norm ``inf``
    there and one of ``1e-200`` norm 0.

    Shared by the spatial modules (not public API: not in ``__all__``).

    Parameters
    ----------
    v : (..., k) float
        Finite entries.

    Returns
    -------
    (...) float

    Examples
    --------
    >>> from imagespace.spatial.study import vector_norm
    >>> float(vector_norm(np.array([3e200, 4e200]))), float(vector_norm(np.array([3e-200, 4e-200])))
    (5e+200, 5e-200)
    """
    sq = _sq(v)
    if _safe(sq, zero_ok=True) and not np.any((sq == 0) & np.any(v != 0, axis=-1)):
        return np.sqrt(sq)
    m = _max_abs(v)
    with np.errstate(over="ignore"):
        return np.linalg.norm(v / m, axis=-1) * m[..., 0]


def _not_finite(name, what):
    return InputError(f"{name} is too large: {what} is outside the float range (about 1.8e308); "
                      "expected magnitudes whose result a float can hold")


def _scaled_study(z, name):
    """``z / max|x|`` (the same displacement, ``max|x| = 1``); refuses a point whose translation
    ``|y| / |x|`` overflows."""
    with np.errstate(over="ignore"):
        out = z / _max_abs(z[..., :4])
    if not np.all(np.isfinite(out)):
        raise _not_finite(name, "its translation (|y| / |x|)")
    return out


def _conj(q):
    return q * np.array([1, -1, -1, -1], dtype=q.dtype if q.dtype != object else object)


@overload
def quaternion_multiply(p: NumericInput, q: NumericInput) -> FloatArray: ...
@overload
def quaternion_multiply(p: Any, q: Any) -> Any: ...
def quaternion_multiply(p, q):
    """The Hamilton product ``p q`` of quaternions ``(w, x, y, z)``.

    Parameters
    ----------
    p, q : (4,) or (n, 4) float, or 4 sympy expressions
        Quaternions, scalar part first; batches broadcast.

    Returns
    -------
    (4,) or (n, 4) float, or sympy.Matrix

    Raises
    ------
    InputError
        If an argument does not have 4 entries on its last axis, is not finite, or the batch
        sizes of ``p`` and ``q`` do not match.

    Examples
    --------
    >>> quaternion_multiply([0, 1, 0, 0], [0, 0, 1, 0])     # i j = k
    array([0., 0., 0., 1.])
    """
    if is_symbolic(p) or is_symbolic(q):
        return sp.Matrix(list(_qmul(_sym(p, 4, "p"), _sym(q, 4, "q"))))
    p, q = as_float_array(p, "p", last=4), as_float_array(q, "q", last=4)
    _batch_shape(p, q, ("p", "q"))
    if _safe(_sq(p)) and _safe(_sq(q)):
        return _qmul(p, q)
    mp, mq = _max_abs(p), _max_abs(q)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        unit = _qmul(p / mp, q / mq)
        out = unit * mp * mq                 # |p q| = |p| |q|: out of range only when it must be
    if not np.all(np.isfinite(out)):
        raise _not_finite("p or q", "the product p q")
    if np.any(np.all(out == 0, axis=-1) & np.any(unit != 0, axis=-1)):
        raise InputError("p or q is too small: the product p q of non-zero quaternions underflows to zero "
                         "(below about 1e-308); expected magnitudes whose product a float can hold")
    return out


@overload
def quaternion_conjugate(q: NumericInput) -> FloatArray: ...
@overload
def quaternion_conjugate(q: Any) -> Any: ...
def quaternion_conjugate(q):
    """The conjugate ``(w, -x, -y, -z)`` of a quaternion.

    Parameters
    ----------
    q : (4,) or (n, 4) float, or 4 sympy expressions

    Returns
    -------
    (4,) or (n, 4) float, or sympy.Matrix

    Raises
    ------
    InputError
        If ``q`` does not have 4 entries on its last axis or is not finite.

    Examples
    --------
    >>> quaternion_conjugate([1.0, 2.0, 3.0, 4.0])
    array([ 1., -2., -3., -4.])
    """
    if is_symbolic(q):
        return sp.Matrix(list(_conj(_sym(q, 4, "q"))))
    return _conj(as_float_array(q, "q", last=4))


def rotation_entries(x0: Any, x1: Any, x2: Any, x3: Any) -> list[list[Any]]:
    """The rotation of the quaternion ``x`` times its squared norm ``x x~``: the nine entries
    ``N R`` (rows of a nested list) with ``R p = x p x~ / (x x~)``, in whatever arithmetic the
    components are (floats, numpy arrays, Fractions, sympy): the one home of this formula.

    Examples
    --------
    >>> from fractions import Fraction
    >>> from imagespace.spatial.study import rotation_entries
    >>> rotation_entries(1, 0, 0, 1)          # a quarter turn about z, times N = 2
    [[0, -2, 0], [2, 0, 0], [0, 0, 2]]
    """
    return [[x0 * x0 + x1 * x1 - x2 * x2 - x3 * x3, 2 * (x1 * x2 - x0 * x3), 2 * (x1 * x3 + x0 * x2)],
            [2 * (x1 * x2 + x0 * x3), x0 * x0 - x1 * x1 + x2 * x2 - x3 * x3, 2 * (x2 * x3 - x0 * x1)],
            [2 * (x1 * x3 - x0 * x2), 2 * (x2 * x3 + x0 * x1), x0 * x0 - x1 * x1 - x2 * x2 + x3 * x3]]


def _rotation_of(x):
    """``R`` with ``R p = x p x~ / (x x~)`` from quaternions ``(..., 4)`` (numpy or object)."""
    x0, x1, x2, x3 = x[..., 0], x[..., 1], x[..., 2], x[..., 3]
    n = x0 * x0 + x1 * x1 + x2 * x2 + x3 * x3
    if x.dtype == object:
        n = np.asarray(n, dtype=object)      # one sympy quaternion: a 0-d array so n[..., None] works
    rows = rotation_entries(x0, x1, x2, x3)
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2) / n[..., None, None]


@overload
def matrix_from_quaternion(q: NumericInput) -> FloatArray: ...
@overload
def matrix_from_quaternion(q: Any) -> Any: ...
def matrix_from_quaternion(q):
    """The rotation matrix of a (not necessarily unit) quaternion: ``R p = q p q~ / (q q~)``.

    Parameters
    ----------
    q : (4,) or (n, 4) float, or 4 sympy expressions
        Non-zero quaternions.

    Returns
    -------
    (3, 3) or (n, 3, 3) float, or sympy.Matrix

    Raises
    ------
    InputError
        If ``q`` is zero, not finite, or not of length 4 on its last axis.

    Examples
    --------
    >>> R = matrix_from_quaternion([0.0, 0.0, 0.0, 1.0])     # a half-turn about z
    >>> R.round(12) + 0.0
    array([[-1.,  0.,  0.],
           [ 0., -1.,  0.],
           [ 0.,  0.,  1.]])
    """
    if is_symbolic(q):
        x = _sym(q, 4, "q")
        if all(v.is_number and v == 0 for v in x):
            raise InputError("q must be a non-zero quaternion, got zero")
        return sp.Matrix(3, 3, [sp.simplify(v) for v in _rotation_of(x).ravel()])
    x = as_float_array(q, "q", last=4)
    if np.any(np.all(x == 0.0, axis=-1)):
        raise InputError("q must be a non-zero quaternion, got zero")
    if _safe(_sq(x)):
        return _rotation_of(x)
    return _rotation_of(x / _max_abs(x))          # homogeneous of degree 0: scaled, never overflows


def quaternion_from_matrix(R: npt.ArrayLike, tolerances: Optional[Tolerances] = None) -> FloatArray:
    """The unit quaternion of a rotation matrix (scalar part first, first non-zero entry positive).

    Parameters
    ----------
    R : (3, 3) or (n, 3, 3) float
        Rotation matrices: orthogonal with determinant +1 to within
        ``Tolerances.rotation_matrix`` (on ``|R^T R - I|`` and ``|det R - 1|``).
    tolerances : Tolerances, optional

    Returns
    -------
    (4,) or (n, 4) float

    Raises
    ------
    InputError
        If ``R`` is not a rotation matrix, not finite or not of shape ``(3, 3)`` / ``(n, 3, 3)``.
    TypeError
        If ``R`` is not numeric, or ``tolerances`` is not a Tolerances.

    Examples
    --------
    >>> quaternion_from_matrix(np.diag([1.0, -1.0, -1.0]))     # a half-turn about x
    array([0., 1., 0., 0.])
    """
    return _quaternion_from_matrix(R, tolerances, "R")


def _quaternion_from_matrix(R, tolerances, name):
    """:func:`quaternion_from_matrix` with the parameter's name for the error messages."""
    tol = as_tolerances(tolerances).rotation_matrix
    R = as_float_array(R, name, finite=False)
    if R.ndim not in (2, 3) or R.shape[-2:] != (3, 3):
        raise InputError(f"{name} must have shape (3, 3) or (n, 3, 3), got shape {R.shape}")
    if not np.all(np.isfinite(R)):
        raise InputError(f"{name} must be finite, got NaN or inf entries")
    if np.any(np.abs(R) > 1.0 + tol):                   # before R^T R, which could overflow
        raise InputError(f"{name} must be a rotation matrix (orthogonal, det +1, to {tol:g}), got an "
                         f"entry {float(np.max(np.abs(R)))!r} (a rotation's entries lie in [-1, 1])")
    err = np.abs(np.einsum("...ji,...jk->...ik", R, R) - np.eye(3)).max(axis=(-2, -1))
    det_err = np.abs(np.linalg.det(R) - 1.0)
    if np.any(err > tol) or np.any(det_err > tol):
        raise InputError(f"{name} must be a rotation matrix (orthogonal, det +1, to {tol:g}), "
                         f"got |R^T R - I| up to {float(np.max(err))!r} and |det - 1| up to "
                         f"{float(np.max(det_err))!r}")
    # the four candidate squared components; take the largest for a stable root
    tr = np.trace(R, axis1=-2, axis2=-1)
    sq = np.stack([1 + tr, 1 + 2 * R[..., 0, 0] - tr, 1 + 2 * R[..., 1, 1] - tr,
                   1 + 2 * R[..., 2, 2] - tr], axis=-1) / 4
    k = np.argmax(sq, axis=-1)
    off = np.stack([R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1],
                    R[..., 0, 1] + R[..., 1, 0], R[..., 0, 2] + R[..., 2, 0], R[..., 1, 2] + R[..., 2, 1]],
                   axis=-1) / 4
    # products q_i q_j: (0,1)(0,2)(0,3)(1,2)(1,3)(2,3) in the order of `off`
    pair = {(0, 1): 0, (0, 2): 1, (0, 3): 2, (1, 2): 3, (1, 3): 4, (2, 3): 5}
    q = np.zeros(R.shape[:-2] + (4,))
    flat_q, flat_k = q.reshape(-1, 4), np.reshape(k, -1)
    flat_sq, flat_off = sq.reshape(-1, 4), off.reshape(-1, 6)
    for r in range(flat_q.shape[0]):
        i = int(flat_k[r])
        qi = np.sqrt(flat_sq[r, i])
        flat_q[r, i] = qi
        for j in range(4):
            if j != i:
                flat_q[r, j] = flat_off[r, pair[(min(i, j), max(i, j))]] / qi
    return _normalise_sign(q)


def _normalise_sign(x):
    """Flip each quaternion (or Study point, on its first 4 entries) so its first non-zero is > 0."""
    lead = np.take_along_axis(x[..., :4], np.argmax(x[..., :4] != 0, axis=-1)[..., None], axis=-1)
    return np.where(lead < 0, -x, x)


# --------------------------------------------------------------------------- the map

@overload
def study_point(rotation: NumericInput, translation: NumericInput) -> FloatArray: ...
@overload
def study_point(rotation: Any, translation: Any) -> Any: ...
def study_point(rotation, translation):
    """The Study parameters ``(x0:x1:x2:x3:y0:y1:y2:y3)`` of a displacement.

    Parameters
    ----------
    rotation : (4,) / (n, 4) quaternion, or (3, 3) / (n, 3, 3) rotation matrix, or sympy
        The orientation. A quaternion need not be a unit quaternion (its rotation is
        ``q p q~ / (q q~)``); it is used as it is, so exact sympy input stays exact.
    translation : (3,) or (n, 3) float, or 3 sympy expressions
        The position of the moving frame's origin.

    Returns
    -------
    (8,) or (n, 8) float, or sympy.Matrix
        ``(x, y)`` with ``x`` the quaternion and ``y = t x / 2``; numeric output is normalised
        (see :func:`normalize_study`).

    Raises
    ------
    InputError
        On wrong shapes, non-finite entries, a zero quaternion, a non-rotation matrix, or batch
        sizes of ``rotation`` and ``translation`` that do not match.
    TypeError
        If an input is not numeric.

    Examples
    --------
    >>> study_point([1.0, 0.0, 0.0, 0.0], [2.0, 0.0, 0.0])      # a pure translation
    array([1., 0., 0., 0., 0., 1., 0., 0.])
    """
    if is_symbolic(rotation) or is_symbolic(translation):
        if isinstance(rotation, (list, tuple, np.ndarray, sp.MatrixBase)):
            count = rotation.size if isinstance(rotation, np.ndarray) else len(rotation)
            if count != 4:
                raise InputError("rotation must be a quaternion of 4 sympy entries on the symbolic face, "
                                 f"got {count} entries")
        x = _sym(rotation, 4, "rotation")
        t = _sym(translation, 3, "translation")
        y = _qmul(np.concatenate([[sp.Integer(0)], t]), x) / 2
        return sp.Matrix([sp.expand(v) for v in np.concatenate([x, y])])
    rot = as_float_array(rotation, "rotation", finite=False)
    if rot.ndim >= 2 and rot.shape[-2:] == (3, 3):
        x = _quaternion_from_matrix(rot, None, "rotation")
    else:
        if rot.shape[-1:] != (4,):
            raise InputError(f"rotation must be a quaternion (4,) or a rotation matrix (3, 3), got shape "
                             f"{rot.shape}; spatial poses are also built by pose_from_rotation(R, t), "
                             "pose_from_quaternion(q, t), pose_from_rpy(rpy, t, degrees=False) and "
                             "pose_from_matrix(T) (imagespace.spatial)")
        if rot.shape == (4, 4) and np.array_equal(rot[3], [0.0, 0.0, 0.0, 1.0]):
            import warnings

            warnings.warn("rotation of shape (4, 4) ending in the row (0, 0, 0, 1) is read as four quaternions; "
                          "for a 4x4 homogeneous matrix use imagespace.spatial.pose_from_matrix(T)", UserWarning,
                          stacklevel=2)
        x = as_float_array(rotation, "rotation", last=4)
        if np.any(np.all(x == 0.0, axis=-1)):
            raise InputError("rotation must be a non-zero quaternion, got zero")
    t = as_float_array(translation, "translation", last=3)
    shape = _batch_shape(x, t, ("rotation", "translation"))
    x, t = np.broadcast_to(x, shape + (4,)), np.broadcast_to(t, shape + (3,))
    tq = np.concatenate([np.zeros(t.shape[:-1] + (1,)), t], axis=-1)
    if _safe(_sq(x)) and _safe(_sq(t), zero_ok=True):
        return normalize_study(np.concatenate([x, _qmul(tq, x) / 2], axis=-1))
    x = x / _max_abs(x)                         # projective: the same rotation, max |x_i| = 1
    mt = _max_abs(t)
    tq = np.concatenate([np.zeros(t.shape[:-1] + (1,)), t / mt], axis=-1)
    with np.errstate(over="ignore"):
        y = _qmul(tq, x) * (mt / 2)
    if not np.all(np.isfinite(y)):
        raise _not_finite("translation", "the dual part y = t x / 2")
    return normalize_study(np.concatenate([np.broadcast_to(x, y.shape), y], axis=-1))


def _check_study(s, name="s", on_quadric=False):
    """``s`` as checked floats ``(8,)`` or ``(n, 8)`` with ``x != 0``, and (``on_quadric``) on
    Study's quadric within ``Tolerances.study_quadric``; ``(s, x . x)``. The quadric is asked
    for where the answer is Euclidean (the translation, and so the transforms); the rotation of
    ``x``, normalising, inverting and composing are defined for any point with ``x != 0``."""
    s = as_float_array(s, name, last=8)
    n = np.einsum("...i,...i->...", s[..., :4], s[..., :4])
    if np.any(n == 0.0) and np.any(np.all(s[..., :4] == 0.0, axis=-1)):      # n == 0 also by underflow
        raise InputError(f"{name} must have x = (x0, x1, x2, x3) != 0 (points with x = 0 are not "
                         "displacements), got x = 0")
    if on_quadric:
        _check_on_quadric(s, name)
    return s, n


def _check_on_quadric(s, name):
    zs = s / _max_abs(s)                            # scaled: the ratio is homogeneous of degree 0
    off = np.abs(np.einsum("...i,...i->...", zs[..., :4], zs[..., 4:])) / np.einsum("...i,...i->...", zs, zs)
    if np.any(off > TOLERANCES.study_quadric):
        worst = float(np.max(off))
        raise InputError(f"{name} must lie on Study's quadric x0 y0 + x1 y1 + x2 y2 + x3 y3 = 0 (a "
                         f"displacement), got |x . y| / (|x|^2 + |y|^2) = {worst:.3g} (at most "
                         f"Tolerances.study_quadric = {TOLERANCES.study_quadric:g}); build points with "
                         "study_point(rotation, translation)")


@overload
def rotation_matrix(s: NumericInput) -> FloatArray: ...
@overload
def rotation_matrix(s: Any) -> Any: ...
def rotation_matrix(s):
    """The rotation matrix ``R`` of a Study point: ``R p = x p x~ / (x x~)``.

    Parameters
    ----------
    s : (8,) or (n, 8) float, or 8 sympy expressions

    Returns
    -------
    (3, 3) or (n, 3, 3) float, or sympy.Matrix

    Raises
    ------
    InputError
        If ``x = 0``, on wrong shapes or non-finite entries.

    Examples
    --------
    >>> rotation_matrix([0, 0, 0, 1, 0, 0, 0, 0]).round(12) + 0.0
    array([[-1.,  0.,  0.],
           [ 0., -1.,  0.],
           [ 0.,  0.,  1.]])
    """
    if is_symbolic(s):
        z = _sym(s, 8, "s")
        return sp.Matrix(3, 3, [sp.cancel(v) for v in _rotation_of(z[:4]).ravel()])
    z, n = _check_study(s)
    x = z[..., :4]
    if _safe(n):
        return _rotation_of(x)
    return _rotation_of(x / _max_abs(x))          # homogeneous of degree 0: scaled, never overflows


@overload
def translation(s: NumericInput) -> FloatArray: ...
@overload
def translation(s: Any) -> Any: ...
def translation(s):
    """The translation ``t = 2 y x~ / (x x~)`` of a Study point.

    Parameters
    ----------
    s : (8,) or (n, 8) float, or 8 sympy expressions
        Should lie on Study's quadric; the scalar part of ``2 y x~`` is dropped.

    Returns
    -------
    (3,) or (n, 3) float, or sympy.Matrix

    Raises
    ------
    InputError
        If ``x = 0``, on wrong shapes or non-finite entries.

    Examples
    --------
    >>> translation([1, 0, 0, 0, 0, 1, 0, 0])
    array([2., 0., 0.])
    """
    if is_symbolic(s):
        z = _sym(s, 8, "s")
        n = sum(v * v for v in z[:4])
        t = 2 * _qmul(z[4:], _conj(z[:4]))
        return sp.Matrix([sp.cancel(v / n) for v in t[1:]])
    z, n = _check_study(s, on_quadric=True)
    if _safe(n) and _safe(_sq(z[..., 4:]), zero_ok=True):
        return 2 * _qmul(z[..., 4:], _conj(z[..., :4]))[..., 1:] / n[..., None]
    z = _scaled_study(z, "s")                       # max |x_i| = 1, so 1 <= x . x <= 4
    x, y = z[..., :4], z[..., 4:]
    my = _max_abs(y)
    with np.errstate(over="ignore"):
        t = 2 * _qmul(y / my, _conj(x))[..., 1:] * (my / np.einsum("...i,...i->...", x, x)[..., None])
    if not np.all(np.isfinite(t)):
        raise _not_finite("s", "its translation")
    return t


def transform_matrix(s: npt.ArrayLike) -> FloatArray:
    """The homogeneous ``4 x 4`` matrix ``[[R, t], [0, 1]]`` of a Study point.

    Parameters
    ----------
    s : (8,) or (n, 8) float

    Returns
    -------
    (4, 4) or (n, 4, 4) float

    Raises
    ------
    InputError
        If ``x = 0``, on wrong shapes or non-finite entries.

    Examples
    --------
    >>> transform_matrix([1, 0, 0, 0, 0, 1, 0, 0])[:3, 3]
    array([2., 0., 0.])
    """
    R, t = rotation_matrix(s), translation(s)
    out = np.zeros(R.shape[:-2] + (4, 4))
    out[..., :3, :3] = R
    out[..., :3, 3] = t
    out[..., 3, 3] = 1.0
    return out


def transform_points(s: npt.ArrayLike, points: npt.ArrayLike) -> FloatArray:
    """Platform points ``p`` (moving frame) in the base frame: ``X = R p + t``.

    Parameters
    ----------
    s : (8,) float
        One Study point.
    points : (3,) or (m, 3) float

    Returns
    -------
    (3,) or (m, 3) float

    Raises
    ------
    InputError
        If ``x = 0``, on wrong shapes or non-finite entries.

    Examples
    --------
    >>> transform_points([0, 0, 0, 1, 0, 0, 0, 0], [1.0, 0.0, 0.0]).round(12) + 0.0
    array([-1.,  0.,  0.])
    """
    R, t = rotation_matrix(as_float_array(s, "s", last=8, allow_batch=False)), translation(s)
    p = as_float_array(points, "points", last=3)
    with np.errstate(over="ignore", invalid="ignore"):
        out = p @ R.T + t
    if not np.all(np.isfinite(out)):
        raise _not_finite("points", "R p + t")
    return out


@overload
def study_condition(s: NumericInput) -> Union[float, FloatArray]: ...
@overload
def study_condition(s: Any) -> Any: ...
def study_condition(s):
    """The value of Study's quadric ``x0 y0 + x1 y1 + x2 y2 + x3 y3`` (zero for displacements).

    Parameters
    ----------
    s : (8,) or (n, 8) float, or 8 sympy expressions

    Returns
    -------
    float or (n,) float, or sympy expression

    Raises
    ------
    InputError
        On wrong shapes or non-finite entries.

    Examples
    --------
    >>> float(study_condition(study_point([1.0, 2.0, 3.0, 4.0], [1.0, -2.0, 0.5])))
    0.0
    """
    if is_symbolic(s):
        z = _sym(s, 8, "s")
        return sp.expand(sum(z[i] * z[i + 4] for i in range(4)))
    z = as_float_array(s, "s", last=8)
    m = _max_abs(z)[..., 0]
    zs = z / m[..., None]
    with np.errstate(over="ignore", under="ignore"):
        unit = np.einsum("...i,...i->...", zs[..., :4], zs[..., 4:])
        out = unit * m * m
    if not np.all(np.isfinite(out)):
        raise _not_finite("s", "the value x . y of Study's quadric")
    if np.any((out == 0) & (unit != 0)):
        raise InputError("s is too small: the value x . y of Study's quadric underflows to zero (below "
                         "about 1e-308) where it is not zero; pass normalised Study points (normalize_study)")
    return out


def normalize_study(s: npt.ArrayLike) -> FloatArray:
    """The normalised representative: ``|x| = 1``, first non-zero of ``x`` positive.

    Parameters
    ----------
    s : (8,) or (n, 8) float

    Returns
    -------
    (8,) or (n, 8) float

    Raises
    ------
    InputError
        If ``x = 0``, on wrong shapes or non-finite entries.

    Examples
    --------
    >>> normalize_study([0, 0, 0, -2, 0, 0, 1, 0])
    array([ 0. ,  0. ,  0. ,  1. ,  0. ,  0. , -0.5,  0. ])
    """
    z, n = _check_study(s)
    return _normalised(z, "s", n)


def _normalised(z, name, n=None):
    """The normalised representative of checked Study points ``z`` (no ``x = 0``); ``n`` is
    ``x . x`` if known."""
    n = _sq(z[..., :4]) if n is None else n
    if _safe(n) and _safe(_sq(z[..., 4:]), zero_ok=True):
        return _normalise_sign(z / np.sqrt(n)[..., None]) + 0.0
    z = _scaled_study(z, name)                      # max |x_i| = 1: |x| in [1, 2], no overflow
    n = np.sqrt(np.einsum("...i,...i->...", z[..., :4], z[..., :4]))
    return _normalise_sign(z / n[..., None]) + 0.0


def _dual_mul(a, b):
    """Dual-quaternion product ``(xa + eps ya)(xb + eps yb)`` on the last axis."""
    return np.concatenate([_qmul(a[..., :4], b[..., :4]),
                           _qmul(a[..., :4], b[..., 4:]) + _qmul(a[..., 4:], b[..., :4])], axis=-1)


@overload
def compose_study(a: NumericInput, b: NumericInput) -> FloatArray: ...
@overload
def compose_study(a: Any, b: Any) -> Any: ...
def compose_study(a, b):
    """The displacement "first ``b``, then ``a``": ``X = R_a (R_b p + t_b) + t_a``.

    It is the dual-quaternion product ``(x_a + eps y_a)(x_b + eps y_b)``.

    Parameters
    ----------
    a, b : (8,) or (n, 8) float, or 8 sympy expressions

    Returns
    -------
    (8,) or (n, 8) float (normalised), or sympy.Matrix

    Raises
    ------
    InputError
        If ``x = 0`` in either, on wrong shapes, mismatched batch sizes or non-finite entries.

    Examples
    --------
    >>> a = study_point([1.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    >>> translation(compose_study(a, a))
    array([2., 0., 0.])
    """
    if is_symbolic(a) or is_symbolic(b):
        return sp.Matrix([sp.expand(v) for v in _dual_mul(_sym(a, 8, "a"), _sym(b, 8, "b"))])
    za, _ = _check_study(a, "a")      # the dual-quaternion product: any points with x != 0
    zb, _ = _check_study(b, "b")
    _batch_shape(za, zb, ("a", "b"))
    if _safe(_sq(za)) and _safe(_sq(zb)):
        return _normalised(_dual_mul(za, zb), "a or b")
    za, zb = _scaled_study(za, "a"), _scaled_study(zb, "b")     # projective: the same displacements
    with np.errstate(over="ignore", invalid="ignore"):
        z = _dual_mul(za, zb)
    if not np.all(np.isfinite(z)):
        raise _not_finite("a or b", "the translation of the composition")
    return _normalised(z, "a or b")


@overload
def inverse_study(s: NumericInput) -> FloatArray: ...
@overload
def inverse_study(s: Any) -> Any: ...
def inverse_study(s):
    """The inverse displacement: the conjugate dual quaternion ``(x~, y~)``.

    Parameters
    ----------
    s : (8,) or (n, 8) float, or 8 sympy expressions

    Returns
    -------
    (8,) or (n, 8) float (normalised), or sympy.Matrix

    Raises
    ------
    InputError
        If ``x = 0``, on wrong shapes or non-finite entries.

    Examples
    --------
    >>> s = study_point([1.0, 2.0, 3.0, 4.0], [1.0, -2.0, 0.5])
    >>> np.allclose(compose_study(s, inverse_study(s)), [1, 0, 0, 0, 0, 0, 0, 0])
    True
    """
    sign = np.array([1, -1, -1, -1, 1, -1, -1, -1])
    if is_symbolic(s):
        return sp.Matrix(list(_sym(s, 8, "s") * sign))
    z, _ = _check_study(s)
    return _normalised(z * sign, "s")


@overload
def planar_to_study(image_point: NumericInput) -> FloatArray: ...
@overload
def planar_to_study(image_point: Any) -> Any: ...
def planar_to_study(image_point):
    """Embed planar image points ``(p0, p1, p2, p3)`` as Study points ``(p0, 0, 0, p1, 0, p3, -p2, 0)``.

    Parameters
    ----------
    image_point : (4,) or (n, 4) float, or 4 sympy expressions

    Returns
    -------
    (8,) or (n, 8) float, or sympy.Matrix

    Raises
    ------
    InputError
        On wrong shapes or non-finite entries.

    Examples
    --------
    >>> planar_to_study([1.0, 0.0, 0.0, 0.5])       # the planar translation (1, 0)
    array([1. , 0. , 0. , 0. , 0. , 0.5, 0. , 0. ])
    """
    if is_symbolic(image_point):
        p = _sym(image_point, 4, "image_point")
        z = sp.Integer(0)
        return sp.Matrix([p[0], z, z, p[1], z, p[3], -p[2], z])
    p = as_float_array(image_point, "image_point", last=4)
    out = np.zeros(p.shape[:-1] + (8,))
    out[..., 0], out[..., 3], out[..., 5], out[..., 6] = p[..., 0], p[..., 1], p[..., 3], -p[..., 2]
    return out + 0.0


def study_to_planar(s: npt.ArrayLike, tolerances: Optional[Tolerances] = None) -> FloatArray:
    """The planar image point ``(x0, x3, -y2, y1)`` of a Study point of a planar displacement.

    Parameters
    ----------
    s : (8,) or (n, 8) float
        Study points with ``x1 = x2 = y0 = y3 = 0`` to within ``Tolerances.planar_subspace``
        relative to ``|s|``.
    tolerances : Tolerances, optional

    Returns
    -------
    (4,) or (n, 4) float

    Raises
    ------
    InputError
        If a point is not planar (rotation about ``z``, translation in ``z = 0``), has ``x = 0``,
        or on wrong shapes or non-finite entries.

    Examples
    --------
    >>> study_to_planar([1.0, 0, 0, 0, 0, 0.5, 0, 0])
    array([1. , 0. , 0. , 0.5])
    """
    tol = as_tolerances(tolerances).planar_subspace
    z, _ = _check_study(s)            # a planar point (x1 = x2 = y0 = y3 = 0) is on Study's quadric
    off = np.abs(z[..., [1, 2, 4, 7]]).max(axis=-1)
    if np.any(off > tol * np.abs(z).max(axis=-1)):
        raise InputError(f"s must be a planar displacement (x1 = x2 = y0 = y3 = 0), got components "
                         f"up to {float(np.max(off)):.3g} there")
    return np.stack([z[..., 0], z[..., 3], -z[..., 6], z[..., 5]], axis=-1) + 0.0
