r"""The planar kinematic map: poses <-> points of the kinematic image space.

Convention (``docs/conventions.md``; the matrix is eq. (3) of Stigger & Husty, seed 002): a pose
``(x, y, phi)`` maps to the
homogeneous image point

.. math::

    x_0 = \cos\tfrac{\varphi}{2},\quad x_1 = \sin\tfrac{\varphi}{2},\quad
    x_2 = \tfrac12(x_1 x - x_0 y),\quad x_3 = \tfrac12(x_0 x + x_1 y).

With the complex numbers ``z = x0 + i x1`` and ``u = x3 - i x2`` a platform point ``p`` (as a
complex number) lands at ``X = (z**2 p + 2 u z) / |z|**2``. Composition of displacements is the
planar quaternion product ``z = z_a z_b``, ``u = z_a u_b + conj(z_b) u_a`` and the inverse of
``(x0, x1, x2, x3)`` is ``(x0, -x1, -x2, -x3)``.

Every function has a numeric face (numpy, shapes ``(4,)`` / ``(n, 4)`` and ``(3,)`` /
``(n, 3)``) and a symbolic face (sympy objects in, ``sympy.Matrix`` out) under the same name.

References
----------
M. Husty et al., *Kinematik und Robotik*, Springer 1997, doi:10.1007/978-3-642-59029-0.
"""

from __future__ import annotations

from typing import Any, Sequence, Union, overload

import numpy as np
import numpy.typing as npt
import sympy as sp

from .._validate import as_float_array, as_sympy_vector, is_symbolic
from ..exceptions import InputError

__all__ = [
    "image_point",
    "pose_of",
    "normalize",
    "transform_matrix",
    "transform_points",
    "compose",
    "inverse",
]


#: A numeric array of image points or poses (``(4,)``/``(n, 4)`` or ``(3,)``/``(n, 3)``).
FloatArray = npt.NDArray[np.float64]
#: The symbolic face: a sympy column or a sequence of sympy expressions.
Symbolic = Union[sp.MatrixBase, Sequence[sp.Basic]]
#: Numeric input: float arrays or (nested) sequences of numbers; the numeric face returns arrays.
NumericInput = Union[npt.NDArray[np.floating], npt.NDArray[np.integer], Sequence[float], Sequence[Sequence[float]]]


def _sym_vector(value, n, name):
    """The ``n`` entries of a symbolic input as sympy objects; strings are refused, never parsed."""
    return as_sympy_vector(value, name, n)


def _exact_zero(x):
    return x == 0 or (x.is_Number and x.is_zero)


def _sym_check_not_absolute(x0, x1, name):
    """Refuse a symbolic point with ``x0 = x1 = 0`` where that is decidable (both exact zeros)."""
    if _exact_zero(x0) and _exact_zero(x1):
        raise InputError(f"{name} must have (x0, x1) != (0, 0): points with x0 = x1 = 0 lie on the "
                         f"absolute line and are not displacements; got x0 = {x0}, x1 = {x1}")


@overload
def image_point(pose: NumericInput) -> FloatArray:
    ...


@overload
def image_point(pose: Any) -> Any:
    ...


def image_point(pose: Union[Symbolic, npt.ArrayLike]) -> Union[sp.Matrix, FloatArray]:
    """Image point of a pose, normalised (``x0**2 + x1**2 = 1``).

    Parameters
    ----------
    pose : (3,) or (n, 3) float, or three sympy expressions
        ``(x, y, phi)`` with ``phi`` in radians.

    Returns
    -------
    (4,) or (n, 4) float, or sympy.Matrix (4, 1)
        ``(x0, x1, x2, x3)``. For ``phi`` in ``(-pi, pi)`` the result has ``x0 > 0``; it is the
        normalised representative of :func:`normalize` except at ``phi = pi`` mod ``2 pi``,
        where ``x0 = 0`` and ``x1 = 1``.

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.image_point([2.0, 0.0, 0.0])
    array([1., 0., 0., 1.])
    """
    if is_symbolic(pose):
        x, y, phi = _sym_vector(pose, 3, "pose")
        x0, x1 = sp.cos(phi / 2), sp.sin(phi / 2)
        return sp.Matrix([x0, x1, (x1 * x - x0 * y) / 2, (x0 * x + x1 * y) / 2])
    p = as_float_array(pose, "pose", last=3)
    x, y, phi = p[..., 0], p[..., 1], p[..., 2]
    half = np.pi / 2 - np.remainder(np.pi / 2 - phi / 2, np.pi)  # phi/2 mod pi in (-pi/2, pi/2]
    x0 = np.where(half == np.pi / 2, 0.0, np.cos(half))           # the half-turn exactly at x0 = 0
    x1 = np.sin(half)
    return np.stack([x0, x1, (x1 * x - x0 * y) / 2, (x0 * x + x1 * y) / 2], axis=-1)


def representative_sign(x0: npt.ArrayLike, x1: npt.ArrayLike) -> FloatArray:
    """``-1`` where ``(x0, x1)`` must be negated to reach the normalised representative, else ``+1``.

    The representative has ``x0 > 0``, or ``x1 > 0`` when ``x0 = 0``.

    Examples
    --------
    >>> from imagespace.core.kinematic_map import representative_sign
    >>> representative_sign(np.array([-1.0, 0.0, 0.0]), np.array([0.0, -1.0, 1.0]))
    array([-1., -1.,  1.])
    """
    a, b = np.asarray(x0), np.asarray(x1)
    return np.where((a < 0) | ((a == 0) & (b < 0)), -1.0, 1.0)


def _check_not_absolute(x0, x1, name):
    bad = (x0 == 0) & (x1 == 0)
    if np.any(bad):
        idx = np.flatnonzero(np.atleast_1d(bad))
        raise InputError(
            f"{name} must have (x0, x1) != (0, 0): points with x0 = x1 = 0 lie on the absolute line "
            f"and are not displacements; got such a point at row(s) {idx[:5].tolist()}")


def _finite_result(out, name, trailing=1):
    """Refuse points whose displacement is beyond the float range: finite, non-absolute input gives
    a non-finite result only when (x0, x1) is tiny next to (x2, x3) (a translation above 1e308).
    ``trailing``: the number of axes of one point's result."""
    ok = np.isfinite(out)
    if np.all(ok):
        return out
    bad = ~np.all(ok.reshape(ok.shape[:ok.ndim - trailing] + (-1,)), axis=-1)
    where = f" at row(s) {np.flatnonzero(bad)[:5].tolist()}" if bad.ndim else ""
    raise InputError(f"{name} describes a displacement beyond the float range ((x0, x1) too small next to "
                     f"(x2, x3): a translation above 1e308){where}")


def _rescaled(p):
    """The same homogeneous points divided by their largest entry, so that squaring neither
    underflows (1e-300) nor overflows (1e200). Rows of zeros stay zeros."""
    m = np.max(np.abs(p), axis=-1, keepdims=True)
    return p / np.where(m > 0, m, 1.0)


@overload
def pose_of(image_point: NumericInput) -> FloatArray:
    ...


@overload
def pose_of(image_point: Any) -> Any:
    ...


def pose_of(image_point: Union[Symbolic, npt.ArrayLike]) -> Union[sp.Matrix, FloatArray]:
    """Pose ``(x, y, phi)`` of an image point (any non-zero multiple).

    Parameters
    ----------
    image_point : (4,) or (n, 4) float, or four sympy expressions
        ``(x0, x1, x2, x3)`` with ``(x0, x1) != (0, 0)``.

    Returns
    -------
    (3,) or (n, 3) float, or sympy.Matrix (3, 1)
        ``phi`` in ``(-pi, pi]``.

    Raises
    ------
    InputError
        If ``x0 = x1 = 0`` (a point of the absolute line, not a displacement).

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.pose_of([0.0, 1.0, 0.0, 0.0])   # the half-turn about the origin
    array([0.        , 0.        , 3.14159265])
    """
    if is_symbolic(image_point):
        x0, x1, x2, x3 = _sym_vector(image_point, 4, "image_point")
        _sym_check_not_absolute(x0, x1, "image_point")
        n = x0**2 + x1**2
        return sp.Matrix([2 * (x0 * x3 + x1 * x2) / n, 2 * (-x0 * x2 + x1 * x3) / n,
                          2 * sp.atan2(x1, x0)])
    p = _rescaled(as_float_array(image_point, "image_point", last=4))
    x0, x1, x2, x3 = (p[..., i] for i in range(4))
    _check_not_absolute(x0, x1, "image_point")
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        n = x0**2 + x1**2
        # the angle of (x0, x1) mod pi, doubled: phi in (-pi, pi]
        s = representative_sign(x0, x1)
        phi = 2 * np.arctan2(s * x1, s * x0)
        out = np.stack([2 * (x0 * x3 + x1 * x2) / n, 2 * (-x0 * x2 + x1 * x3) / n, phi], axis=-1)
    return _finite_result(out, "image_point")


@overload
def normalize(image_point: NumericInput) -> FloatArray:
    ...


@overload
def normalize(image_point: Any) -> Any:
    ...


def normalize(image_point: Union[Symbolic, npt.ArrayLike]) -> Union[sp.Matrix, FloatArray]:
    """The normalised representative: ``x0**2 + x1**2 = 1`` and ``x0 > 0`` (``x1 > 0`` if ``x0 = 0``).

    Parameters
    ----------
    image_point : (4,) or (n, 4) float, or four sympy expressions

    Returns
    -------
    (4,) or (n, 4) float, or sympy.Matrix (4, 1)

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.normalize([-2.0, 0.0, 1.0, 4.0])
    array([ 1. ,  0. , -0.5, -2. ])
    """
    if is_symbolic(image_point):
        x = sp.Matrix(_sym_vector(image_point, 4, "image_point"))
        _sym_check_not_absolute(x[0], x[1], "image_point")
        n = sp.sqrt(x[0]**2 + x[1]**2)
        sign = 1
        if x[0].is_number and x[1].is_number:
            if x[0] < 0 or (x[0] == 0 and x[1] < 0):
                sign = -1
        return (sign * x / n).applyfunc(sp.radsimp)
    p = _rescaled(as_float_array(image_point, "image_point", last=4))
    x0, x1 = p[..., 0], p[..., 1]
    _check_not_absolute(x0, x1, "image_point")
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        n = np.sqrt(x0**2 + x1**2)
        out = p * (representative_sign(x0, x1) / n)[..., None] + 0.0
    return _finite_result(out, "image_point")


@overload
def transform_matrix(image_point: NumericInput) -> FloatArray:
    ...


@overload
def transform_matrix(image_point: Any) -> Any:
    ...


def transform_matrix(image_point: Union[Symbolic, npt.ArrayLike]) -> Union[sp.Matrix, FloatArray]:
    """The 3x3 homogeneous matrix of eq. (3): base coordinates of ``(1, x, y)`` of the platform.

    Parameters
    ----------
    image_point : (4,) or (n, 4) float, or four sympy expressions

    Returns
    -------
    (3, 3) or (n, 3, 3) float, or sympy.Matrix (3, 3)
        First row ``(1, 0, 0)``; the lower-left column is the translation, the lower-right block
        the rotation.

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.transform_matrix(isp.image_point([1.0, 2.0, 0.0]))
    array([[1., 0., 0.],
           [1., 1., 0.],
           [2., 0., 1.]])
    """
    if is_symbolic(image_point):
        x0, x1, x2, x3 = _sym_vector(image_point, 4, "image_point")
        _sym_check_not_absolute(x0, x1, "image_point")
        n = x0**2 + x1**2
        return sp.Matrix([[1, 0, 0],
                          [(2 * x0 * x3 + 2 * x1 * x2) / n, (x0**2 - x1**2) / n, -2 * x0 * x1 / n],
                          [(-2 * x0 * x2 + 2 * x1 * x3) / n, 2 * x0 * x1 / n, (x0**2 - x1**2) / n]])
    p = _rescaled(as_float_array(image_point, "image_point", last=4))
    x0, x1, x2, x3 = (p[..., i] for i in range(4))
    _check_not_absolute(x0, x1, "image_point")
    out = np.zeros(p.shape[:-1] + (3, 3))
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        n = x0**2 + x1**2
        out[..., 0, 0] = 1.0
        out[..., 1, 0] = (2 * x0 * x3 + 2 * x1 * x2) / n
        out[..., 2, 0] = (-2 * x0 * x2 + 2 * x1 * x3) / n
        out[..., 1, 1] = out[..., 2, 2] = (x0**2 - x1**2) / n
        out[..., 1, 2] = -2 * x0 * x1 / n
        out[..., 2, 1] = 2 * x0 * x1 / n
    return _finite_result(out, "image_point", trailing=2) + 0.0  # no negative zeros


def transform_points(image_point: Union[Symbolic, npt.ArrayLike], points: npt.ArrayLike) -> Union[sp.Matrix, FloatArray]:
    """Base coordinates of platform points under the displacement ``image_point``.

    Parameters
    ----------
    image_point : (4,) or (n, 4) float, or four sympy expressions
    points : (2,) or (m, 2) float, or two sympy expressions
        Platform points in the moving frame.

    Returns
    -------
    (..., 2) float, or sympy.Matrix (2, 1)
        Shape ``image_point.shape[:-1] + points.shape``; the symbolic face (any sympy entry)
        maps one point.

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.transform_points(isp.image_point([1.0, 0.0, 3.141592653589793]), [1.0, 0.0])
    array([0., 0.])
    """
    if is_symbolic(image_point) or is_symbolic(points):
        m = transform_matrix(_sym_vector(image_point, 4, "image_point"))
        px, py = _sym_vector(points, 2, "points")
        out = m * sp.Matrix([1, px, py])
        return sp.Matrix([out[1], out[2]])
    m = transform_matrix(image_point)
    pts = as_float_array(points, "points", last=2)
    h = np.concatenate([np.ones(pts.shape[:-1] + (1,)), pts], axis=-1)
    if m.ndim == 3:
        out = np.einsum("nij,...j->n...i", m, h)
    else:
        out = np.einsum("ij,...j->...i", m, h)
    return out[..., 1:] + 0.0


def compose(a: Union[Symbolic, npt.ArrayLike], b: Union[Symbolic, npt.ArrayLike]) -> Union[sp.Matrix, FloatArray]:
    """Image point of the displacement ``b`` followed by ``a`` (planar quaternion product).

    ``transform_matrix(compose(a, b)) == transform_matrix(a) @ transform_matrix(b)``.

    Parameters
    ----------
    a, b : (4,) or (n, 4) float (broadcast), or four sympy expressions each

    Returns
    -------
    (4,) or (n, 4) float, or sympy.Matrix (4, 1)
        Not normalised (the product of the norms ``x0**2 + x1**2``).

    Raises
    ------
    InputError
        ``a`` or ``b`` is not an image point (or is on the absolute line ``x0 = x1 = 0``), or
        they are batches of different lengths.

    Examples
    --------
    >>> import imagespace as isp
    >>> quarter = isp.image_point([0.0, 0.0, 1.5707963267948966])
    >>> isp.pose_of(isp.compose(quarter, quarter))
    array([0.        , 0.        , 3.14159265])
    """
    if is_symbolic(a) or is_symbolic(b):
        a0, a1, a2, a3 = _sym_vector(a, 4, "a")
        b0, b1, b2, b3 = _sym_vector(b, 4, "b")
        _sym_check_not_absolute(a0, a1, "a")
        _sym_check_not_absolute(b0, b1, "b")
    else:
        pa = as_float_array(a, "a", last=4)
        pb = as_float_array(b, "b", last=4)
        _check_not_absolute(pa[..., 0], pa[..., 1], "a")
        _check_not_absolute(pb[..., 0], pb[..., 1], "b")
        if pa.ndim == 2 and pb.ndim == 2 and len(pa) != len(pb) and 1 not in (len(pa), len(pb)):
            raise InputError(f"a and b must be single points or batches of the same length, got shapes "
                             f"{pa.shape} and {pb.shape}")
        a0, a1, a2, a3 = (pa[..., i] for i in range(4))
        b0, b1, b2, b3 = (pb[..., i] for i in range(4))
    x0 = a0 * b0 - a1 * b1
    x1 = a0 * b1 + a1 * b0
    x2 = a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1
    x3 = a0 * b3 + a1 * b2 + a3 * b0 - a2 * b1
    if is_symbolic(a) or is_symbolic(b):
        return sp.Matrix([sp.expand(x0), sp.expand(x1), sp.expand(x2), sp.expand(x3)])
    return np.stack(np.broadcast_arrays(x0, x1, x2, x3), axis=-1)


@overload
def inverse(image_point: NumericInput) -> FloatArray:
    ...


@overload
def inverse(image_point: Any) -> Any:
    ...


def inverse(image_point: Union[Symbolic, npt.ArrayLike]) -> Union[sp.Matrix, FloatArray]:
    """Image point of the inverse displacement: ``(x0, -x1, -x2, -x3)``.

    Parameters
    ----------
    image_point : (4,) or (n, 4) float, or four sympy expressions

    Returns
    -------
    (4,) or (n, 4) float, or sympy.Matrix (4, 1)

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.pose_of(isp.inverse(isp.image_point([1.0, 0.0, 0.5])))
    array([-0.87758256,  0.47942554, -0.5       ])
    """
    if is_symbolic(image_point):
        x0, x1, x2, x3 = _sym_vector(image_point, 4, "image_point")
        _sym_check_not_absolute(x0, x1, "image_point")
        return sp.Matrix([x0, -x1, -x2, -x3])
    p = as_float_array(image_point, "image_point", last=4)
    _check_not_absolute(p[..., 0], p[..., 1], "image_point")
    return p * np.array([1.0, -1.0, -1.0, -1.0])
