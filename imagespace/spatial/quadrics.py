r"""Constraint quadrics in Study coordinates: each geometric condition as ``z^T Q z = 0`` in ``P^7``.

``z = (x0, x1, x2, x3, y0, y1, y2, y3)`` is a Study point (:mod:`imagespace.spatial.study`); a
quadric is stored as its symmetric ``8 x 8`` matrix ``Q``. With ``N = x . x``, the platform point
``p`` lands at ``X = (x p x~ + 2 y x~) / N``, so any condition polynomial in ``X`` becomes a form in
``z`` after multiplying by a power of ``N``.

The sphere condition (an S-S or S-P-S leg of length ``L``: the platform point ``b`` at distance
``L`` from the base point ``a``). Expanding ``|R b + t - a|^2 = L^2`` with ``R b = x b x~ / N``,
``t = 2 y x~ / N`` and the identity ``(p x~) . (q x~) = N (p . q)`` (right multiplication by ``x~``
is ``sqrt(N)`` times an isometry of the quaternions) gives, after multiplying by ``N``,

.. math::

    (|a|^2 + |b|^2 - L^2)\,N + 4\,y \cdot y + 4\,(x b) \cdot y - 4\,a \cdot (y \tilde x)
    - 2\,a \cdot (x b \tilde x) = 0,

where ``.`` is the Euclidean inner product of quaternions as 4-vectors and ``a``, ``b`` are pure
quaternions. The one step that uses Study's quadric is ``|t|^2 = 4 y . y / N``: the scalar part of
``2 y x~`` is ``2 x . y``, so the form equals ``N (|X - a|^2 - L^2) + 4 (x . y)^2 / N``; on Study's
quadric the two agree. This is Husty's sphere condition (1996), derived here in our convention.
The form is ``(..) N + 4 y.y + (bilinear in x, y) + (quadratic in x)``: the difference of two
sphere conditions is linear in ``y``.

A point on a plane ``n . (X - c) = 0`` and a point on a line ``(X - c) x d = 0`` are linear in
``X``: multiplying by ``N`` gives quadrics with no reduction at all.

Each matrix is derived once with sympy (:func:`sphere_quadric_symbolic` ...) and compiled from
that derivation (:func:`imagespace.core.codegen.compile_exprs`) for the numeric face.

References
----------
M. L. Husty, An algorithm for solving the direct kinematics of general Stewart-Gough platforms,
Mechanism and Machine Theory 31(4), 365-379, 1996, doi:10.1016/0094-114X(95)00091-C.
"""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING, Any, Sequence, Union, overload

import numpy as np
import numpy.typing as npt
import sympy as sp

from .._validate import (as_float_array, as_fraction, as_sympy_entry, as_sympy_vector, check_squares,
                         is_symbolic)
from ..exceptions import InputError, InputTypeError
from .study import quaternion_multiply, quaternion_conjugate, study_symbols

if TYPE_CHECKING:
    from ..core.kinematic_map import FloatArray, NumericInput

__all__ = [
    "study_quadric_matrix",
    "form_matrix",
    "quadric_value",
    "sphere_quadric_symbolic",
    "sphere_quadric",
    "sphere_quadric_exact",
    "sphere_quadric_linear",
    "point_on_plane_quadric_linear",
    "point_on_plane_quadric",
    "point_on_line_quadrics",
    "landed_point_times_n",
]


def form_matrix(expr: Any) -> sp.Matrix:
    """The symmetric ``8 x 8`` matrix ``Q`` of a quadratic form in the Study symbols.

    Parameters
    ----------
    expr : sympy expression
        Homogeneous of degree 2 in ``x0..x3, y0..y3``.

    Returns
    -------
    sympy.Matrix (8, 8)
        ``z^T Q z == expr``.

    Raises
    ------
    InputError
        If ``expr`` is not a quadratic form in the Study symbols.

    Examples
    --------
    >>> x0, x1 = study_symbols()[:2]
    >>> form_matrix(x0 * x1)[0, 1]
    1/2
    """
    z = study_symbols()
    if isinstance(expr, sp.Poly):
        expr = expr.as_expr()
    expr = as_sympy_entry(expr, "expr")        # a string is refused, never sympified
    try:
        P = sp.Poly(sp.expand(expr), *z)
    except sp.PolynomialError:
        raise InputError(f"expr must be a quadratic form in {z}, got {expr}") from None
    if not P.is_homogeneous or P.total_degree() != 2 and not P.is_zero:
        raise InputError(f"expr must be a quadratic form in {z}, got degree {P.total_degree()}")
    Q = sp.zeros(8, 8)
    if P.is_zero:
        return Q
    for mon, c in P.terms():
        idx = [i for i, e in enumerate(mon) for _ in range(e)]
        if len(idx) != 2:
            raise InputError(f"expr must be a quadratic form in {z}, got the monomial {mon}")
        i, j = idx
        if i == j:
            Q[i, i] += c
        else:
            Q[i, j] += c / 2
            Q[j, i] += c / 2
    return Q


def study_quadric_matrix() -> FloatArray:
    """The matrix of Study's quadric ``x0 y0 + x1 y1 + x2 y2 + x3 y3``.

    Returns
    -------
    (8, 8) float
        ``[[0, I/2], [I/2, 0]]``.

    Examples
    --------
    >>> float(study_quadric_matrix()[0, 4])
    0.5
    """
    out = np.zeros((8, 8))
    out[:4, 4:] = out[4:, :4] = 0.5 * np.eye(4)
    return out


def quadric_value(Q: npt.ArrayLike, s: npt.ArrayLike) -> Union[float, FloatArray]:
    """``z^T Q z`` for Study points ``z``.

    Parameters
    ----------
    Q : (8, 8) or (k, 8, 8) float
        One quadric or a stack of them.
    s : (8,) or (n, 8) float

    Returns
    -------
    float, (n,), (k,) or (n, k) float
        Points first, quadrics last.

    Raises
    ------
    InputError
        On wrong shapes or non-finite entries.

    Examples
    --------
    >>> quadric_value(study_quadric_matrix(), [1, 0, 0, 0, 0, 1, 0, 0])
    0.0
    """
    Q = as_float_array(Q, "Q", allow_batch=True)
    if Q.ndim not in (2, 3) or Q.shape[-2:] != (8, 8):
        raise InputError(f"Q must have shape (8, 8) or (k, 8, 8), got {Q.shape}")
    z = as_float_array(s, "s", last=8)
    # a form of degree 2 in z and 1 in Q: evaluated on scaled copies, the scales multiplied back
    mz = np.abs(z).max(axis=-1, keepdims=True)
    mz = np.where(mz > 0, mz, 1.0)
    mq = float(np.abs(Q).max()) or 1.0
    zs = z / mz
    with np.errstate(over="ignore", under="ignore"):
        unit = np.einsum("...i,kij,...j->...k", zs, Q.reshape(-1, 8, 8) / mq, zs)
        out = unit * mz * mz * mq
    out, unit = out.reshape(z.shape[:-1] + Q.shape[:-2]), unit.reshape(z.shape[:-1] + Q.shape[:-2])
    if not np.all(np.isfinite(out)):
        raise InputError("s or Q is too large: z^T Q z is outside the float range (about 1.8e308); "
                         "pass normalised Study points (normalize_study)")
    if np.any((out == 0) & (unit != 0)):
        raise InputError("s or Q is too small: z^T Q z underflows to zero (below about 1e-308) where it "
                         "is not zero; pass normalised Study points (normalize_study)")
    return float(out) if out.ndim == 0 else out


def _pure(v, name="point"):
    """A 3-vector as the pure quaternion ``(0, v)`` of sympy entries (strings refused, never parsed)."""
    return np.array([sp.Integer(0)] + as_sympy_vector(v, name, 3), dtype=object)


def _dot(p, q):
    return sum(pi * qi for pi, qi in zip(p, q))


def landed_point_times_n(point: Any) -> sp.Matrix:
    """``N X`` as quaternion forms in the Study symbols: ``x p x~ + 2 y x~`` for a platform point ``p``.

    Its scalar part is ``2 x . y`` (zero on Study's quadric); its vector part is ``N (R p + t)``.

    Parameters
    ----------
    point : 3 numbers or sympy expressions

    Returns
    -------
    sympy.Matrix (4,)

    Examples
    --------
    >>> landed_point_times_n([0, 0, 0])[1]
    2*x0*y1 - 2*x1*y0 + 2*x2*y3 - 2*x3*y2
    """
    z = study_symbols()
    x, y = list(z[:4]), list(z[4:])
    xc = list(quaternion_conjugate(x))
    xp = list(quaternion_multiply(x, list(_pure(point))))
    rot = quaternion_multiply(xp, xc)
    tr = quaternion_multiply(y, xc)
    return sp.Matrix([sp.expand(r + 2 * t) for r, t in zip(rot, tr)])


@lru_cache(maxsize=1)
def sphere_quadric_symbolic() -> tuple[sp.Matrix, tuple[sp.Symbol, ...]]:
    """The sphere condition's matrix with symbolic geometry: ``a1..a3``, ``b1..b3``, ``L``.

    Returns
    -------
    Q : sympy.Matrix (8, 8)
        Entries polynomial in the base point ``a``, the platform point ``b`` and ``L``.
    symbols : tuple
        ``(a1, a2, a3, b1, b2, b3, L)``.

    Examples
    --------
    >>> Q, syms = sphere_quadric_symbolic()
    >>> Q[4, 4]
    4
    """
    a = sp.symbols("a1:4")
    b = sp.symbols("b1:4")
    L = sp.Symbol("L")
    z = study_symbols()
    x, y = list(z[:4]), list(z[4:])
    N = _dot(x, x)
    xb = list(quaternion_multiply(x, list(_pure(b))))
    yxc = list(quaternion_multiply(y, list(quaternion_conjugate(x))))
    xbxc = list(quaternion_multiply(xb, list(quaternion_conjugate(x))))
    A, B = _pure(a), _pure(b)
    form = ((_dot(A, A) + _dot(B, B) - L ** 2) * N + 4 * _dot(y, y) + 4 * _dot(xb, y)
            - 4 * _dot(A, yxc) - 2 * _dot(A, xbxc))
    return form_matrix(form), tuple(a) + tuple(b) + (L,)


@lru_cache(maxsize=1)
def _sphere_compiled():
    from ..core.codegen import compile_exprs
    Q, syms = sphere_quadric_symbolic()
    return compile_exprs(list(Q), syms)


@lru_cache(maxsize=1)
def _sphere_exact_compiled():
    Q, syms = sphere_quadric_symbolic()
    # twice the matrix has integer coefficients: the generated code is integer arithmetic, so
    # Fraction arguments give exact Fractions
    return sp.lambdify(syms, list(2 * Q), modules=[{}, "math"])


def sphere_quadric_exact(base_point: Sequence[Any], platform_point: Sequence[Any],
                         length: Any) -> npt.NDArray[np.object_]:
    """The sphere quadric in exact rational arithmetic (floats enter as their binary rationals).

    Compiled from the same derivation as :func:`sphere_quadric`.

    Parameters
    ----------
    base_point, platform_point : 3 numbers (float, int or Fraction)
    length : float, int or Fraction

    Returns
    -------
    (8, 8) object array of Fraction

    Examples
    --------
    >>> sphere_quadric_exact([0, 0, 0], [1, 0, 0], 0.1)[4, 4]
    Fraction(4, 1)
    """
    from fractions import Fraction

    vals = []
    for name, v in (("base_point", base_point), ("platform_point", platform_point)):
        if not isinstance(v, (list, tuple, np.ndarray)) or (isinstance(v, np.ndarray) and v.ndim != 1):
            raise InputTypeError(f"{name} must be a sequence of 3 numbers, got {type(v).__name__} {v!r:.80}")
        if len(v) != 3:
            raise InputError(f"{name} must have 3 entries, got {len(v)}")
        vals += [as_fraction(c, f"{name}[{i}]") for i, c in enumerate(v)]
    vals.append(as_fraction(length, "length"))
    if vals[6] < 0:
        raise InputError(f"length must be >= 0, got {length!r}")
    twice = _sphere_exact_compiled()(*vals)
    return np.array([Fraction(v) / 2 for v in twice], dtype=object).reshape(8, 8)


@overload
def sphere_quadric(base_point: NumericInput, platform_point: NumericInput,
                   length: Union[float, NumericInput]) -> FloatArray: ...
@overload
def sphere_quadric(base_point: Any, platform_point: Any, length: Any) -> Any: ...
def sphere_quadric(base_point, platform_point, length):
    """The quadric of "platform point ``b`` at distance ``L`` from base point ``a``".

    Parameters
    ----------
    base_point : (3,) or (n, 3) float, or sympy
        ``a`` in the base frame.
    platform_point : (3,) or (n, 3) float, or sympy
        ``b`` in the moving frame.
    length : float or (n,) float, or sympy
        ``L >= 0``.

    Returns
    -------
    (8, 8) or (n, 8, 8) float, or sympy.Matrix
        ``z^T Q z = N (|R b + t - a|^2 - L^2)`` on Study's quadric, ``N = x . x``.

    Raises
    ------
    InputError
        On wrong shapes or batch sizes, non-finite entries or a negative length.
    TypeError
        If an input is not numeric.

    Examples
    --------
    >>> from imagespace.spatial.study import study_point
    >>> Q = sphere_quadric([0, 0, 0], [1, 0, 0], 3.0)
    >>> s = study_point([1, 0, 0, 0], [2.0, 0, 0])      # b lands at (3, 0, 0)
    >>> round(float(s @ Q @ s), 12)
    0.0
    """
    if is_symbolic(base_point) or is_symbolic(platform_point) or is_symbolic(length):
        Q, syms = sphere_quadric_symbolic()
        vals = (as_sympy_vector(base_point, "base_point", 3) + as_sympy_vector(platform_point, "platform_point", 3)
                + [as_sympy_entry(length, "length")])
        if vals[6].is_number and vals[6].is_negative:
            raise InputError(f"length must be >= 0, got {vals[6]}")
        return Q.subs(dict(zip(syms, vals)))
    a = as_float_array(base_point, "base_point", last=3)
    b = as_float_array(platform_point, "platform_point", last=3)
    L = as_float_array(length, "length")
    if L.ndim > 1:
        raise InputError(f"length must be a number or of shape (n,), got shape {L.shape}")
    if np.any(L < 0):
        raise InputError(f"length must be >= 0, got {float(np.min(L))}")
    check_squares(L, "length")
    try:
        shape = np.broadcast_shapes(a.shape[:-1], b.shape[:-1], L.shape)
    except ValueError:
        raise InputError(f"base_point, platform_point and length must have the same batch size, got "
                         f"{a.shape[:-1]}, {b.shape[:-1]} and {L.shape}") from None
    args = [np.broadcast_to(a[..., i], shape) for i in range(3)] + \
           [np.broadcast_to(b[..., i], shape) for i in range(3)] + [np.broadcast_to(L, shape)]
    with np.errstate(over="ignore", invalid="ignore"):
        out = _sphere_compiled()(*args).reshape(shape + (8, 8))
    if not np.all(np.isfinite(out)):
        raise _too_large("base_point, platform_point or length",
                         "the quadric's entries (squares and products of the coordinates)")
    return out


@lru_cache(maxsize=1)
def _sphere_basis():
    """The sphere quadric's coefficient matrices, read off the compiled derivation (exact: at
    coordinates 0 and 1 every entry is a small integer)."""
    z, e = np.zeros(3), np.eye(3)
    K0 = sphere_quadric(z, z, 0.0)
    N = K0 - sphere_quadric(z, z, 1.0)                     # c = -L^2 = -1
    Ka = np.array([sphere_quadric(e[i], z, 0.0) - K0 - N for i in range(3)])
    Kb = np.array([sphere_quadric(z, e[j], 0.0) - K0 - N for j in range(3)])
    KW = np.array([[sphere_quadric(e[i], e[j], 0.0) - K0 - 2 * N - Ka[i] - Kb[j] for j in range(3)]
                   for i in range(3)])
    for M in (K0, N, Ka, Kb, KW):
        M.setflags(write=False)
    return K0, N, Ka, Kb, KW


def _linear_coefficients(args):
    """Check ``(name, value, tail shape)`` coefficient arguments of the linear quadric families:
    numeric, finite, shape ``tail`` or ``(n,) + tail``, one batch size. Returns the arrays and the
    broadcast batch shape."""
    vals = []
    for name, v, tail in args:
        arr = np.asarray(v)
        if arr.dtype.kind not in "iufc":
            raise InputError(f"{name} must be numeric (not bool), got dtype {arr.dtype}")
        if arr.shape[arr.ndim - len(tail):] != tail or arr.ndim - len(tail) > 1:
            raise InputError(f"{name} must have shape {tail} or (n,) + {tail}, got {arr.shape}")
        if not np.all(np.isfinite(arr)):
            raise InputError(f"{name} must be finite")
        vals.append(arr)
    try:
        shape = np.broadcast_shapes(*(v.shape[:v.ndim - len(t)] for v, (_, _, t) in zip(vals, args)))
    except ValueError:
        raise InputError(f"{', '.join(a[0] for a in args)} must have the same batch size, got shapes "
                         f"{[v.shape for v in vals]}") from None
    return vals, shape


def _linear_result(out, shape, names):
    """The linear families' matrix ``out`` broadcast to the batch ``shape`` (a copy); refuses
    entries beyond the float range (sums of coefficients too large)."""
    if not np.all(np.isfinite(out)):
        raise InputError(f"{names} are too large: the quadric's entries (sums of these coefficients) are "
                         "outside the float range (about 1.8e308)")
    return np.broadcast_to(out, shape + (8, 8)).copy()


def sphere_quadric_linear(base_point: npt.ArrayLike, platform_point: npt.ArrayLike, products: npt.ArrayLike,
                          constant: npt.ArrayLike) -> npt.NDArray[Any]:
    """The sphere quadric written linearly in its coefficients ``(a, b, W, c)``.

    The form of :func:`sphere_quadric` is ``c N + 4 y.y + 4 (x b).y - 4 a.(y x~) - 2 a.(x b x~)``
    with ``c = |a|^2 + |b|^2 - L^2``; its last term is bilinear in ``a`` and ``b``, so the matrix is
    an affine function of ``a``, ``b``, the products ``W = a b^T`` and ``c``. Taken with any ``W``
    and ``c`` (not only ``a b^T`` and ``|a|^2 + |b|^2 - L^2``) it spans the linear family that the
    start systems of :mod:`imagespace.spatial.families` move in.

    Parameters
    ----------
    base_point, platform_point : (3,) or (n, 3) float or complex
    products : (3, 3) or (n, 3, 3) float or complex
        ``W``; ``np.outer(a, b)`` gives the sphere quadric.
    constant : float or (n,) float or complex
        ``c``, the coefficient of ``N = x . x``.

    Returns
    -------
    (8, 8) or (n, 8, 8) float or complex

    Raises
    ------
    InputError
        On shapes that do not match, non-finite or bool entries, or entries whose sums leave the
        float range.

    Examples
    --------
    >>> a, b, L = np.array([0.5, -1.0, 2.0]), np.array([1.0, 0.25, -0.5]), 1.5
    >>> Q = sphere_quadric_linear(a, b, np.outer(a, b), a @ a + b @ b - L ** 2)
    >>> bool(np.allclose(Q, sphere_quadric(a, b, L), rtol=0, atol=1e-14))
    True
    """
    (a, b, W, c), shape = _linear_coefficients((("base_point", base_point, (3,)),
                                                ("platform_point", platform_point, (3,)),
                                                ("products", products, (3, 3)), ("constant", constant, ())))
    K0, N, Ka, Kb, KW = _sphere_basis()
    out = (K0 + np.einsum("...i,ikl->...kl", a, Ka) + np.einsum("...j,jkl->...kl", b, Kb)
           + np.einsum("...ij,ijkl->...kl", W, KW) + np.asarray(c)[..., None, None] * N)
    return _linear_result(out, shape, "base_point, platform_point, products and constant")


def _too_large(names, what):
    return InputError(f"{names} is too large: {what} are outside the float range (about 1.8e308); "
                      "expected coordinates whose squares a float can hold (below about 1e154)")


def _as_float_matrix(Q, names):
    """An exact sympy matrix rounded to float; refuses entries beyond the float range."""
    out = np.array(Q.tolist(), dtype=float)
    if not np.all(np.isfinite(out)):
        raise _too_large(names, "the quadric's entries")
    return out


def _exact_or_float(v):
    """Float entries as their exact binary rationals (the matrix is computed exactly, rounded once)."""
    return [sp.Rational(float(c)) for c in v]


@overload
def point_on_plane_quadric(platform_point: NumericInput, plane_point: NumericInput,
                           plane_normal: NumericInput) -> FloatArray: ...
@overload
def point_on_plane_quadric(platform_point: Any, plane_point: Any, plane_normal: Any) -> Any: ...
def point_on_plane_quadric(platform_point, plane_point, plane_normal):
    """The quadric of "platform point ``b`` on the fixed plane through ``c`` with normal ``n``".

    ``n . (X - c) = 0`` times ``N``: ``n . vec(x b x~ + 2 y x~) - (n . c) N = 0`` (no reduction).

    Parameters
    ----------
    platform_point : (3,) float or sympy
    plane_point : (3,) float or sympy
    plane_normal : (3,) float or sympy
        Non-zero.

    Returns
    -------
    (8, 8) float, or sympy.Matrix when any input is symbolic

    Raises
    ------
    InputError
        On wrong shapes, non-finite entries or a zero normal.

    Examples
    --------
    >>> from imagespace.spatial.study import study_point
    >>> Q = point_on_plane_quadric([1, 0, 0], [0, 0, 0], [1, 0, 0])
    >>> s = study_point([1, 0, 0, 0], [-1.0, 5.0, 2.0])       # b lands at (0, 5, 2)
    >>> float(s @ Q @ s)
    0.0
    """
    symbolic = any(is_symbolic(v) for v in (platform_point, plane_point, plane_normal))
    if not symbolic:
        b = as_float_array(platform_point, "platform_point", last=3, allow_batch=False)
        c = as_float_array(plane_point, "plane_point", last=3, allow_batch=False)
        n = as_float_array(plane_normal, "plane_normal", last=3, allow_batch=False)
        if not np.any(n != 0):
            raise InputError("plane_normal must be non-zero, got (0, 0, 0)")
        b, c, n = (_exact_or_float(v) for v in (b, c, n))
    else:
        b = as_sympy_vector(platform_point, "platform_point", 3)
        c = as_sympy_vector(plane_point, "plane_point", 3)
        n = as_sympy_vector(plane_normal, "plane_normal", 3)
        if all(v == 0 for v in n):
            raise InputError("plane_normal must be non-zero, got (0, 0, 0)")
    z = study_symbols()
    X = landed_point_times_n(b)
    N = _dot(z[:4], z[:4])
    Q = form_matrix(sum(ni * Xi for ni, Xi in zip(n, X[1:])) - _dot(n, c) * N)
    return Q if symbolic else _as_float_matrix(Q, "platform_point, plane_point or plane_normal")


@lru_cache(maxsize=1)
def _plane_basis():
    """The plane quadric's coefficient matrices, from :func:`point_on_plane_quadric` (13 exact
    derivations, once per process; every entry a small integer)."""
    z, e = np.zeros(3), np.eye(3)
    T = np.array([point_on_plane_quadric(z, z, e[i]) for i in range(3)])
    V = np.array([[point_on_plane_quadric(e[j], z, e[i]) - T[i] for j in range(3)] for i in range(3)])
    N = T[0] - point_on_plane_quadric(z, e[0], e[0])           # n . c = 1
    for M in (T, V, N):
        M.setflags(write=False)
    return T, V, N


def point_on_plane_quadric_linear(normal: npt.ArrayLike, products: npt.ArrayLike, offset: npt.ArrayLike
                                  ) -> npt.NDArray[Any]:
    """The plane quadric written linearly in its coefficients ``(n, V, d)``.

    The form of :func:`point_on_plane_quadric` is ``n . vec(x b x~) + 2 n . vec(y x~) - d N`` with
    ``d = n . c``: linear in the normal ``n``, the products ``V = n b^T`` and ``d``. Taken with
    any ``V`` (not only ``n b^T``) it spans the linear family that the 3-RPS start systems move in
    (:mod:`imagespace.spatial.families`).

    Parameters
    ----------
    normal : (3,) or (n, 3) float
    products : (3, 3) or (n, 3, 3) float
        ``V``; ``np.outer(n, b)`` gives the plane quadric of the platform point ``b``.
    offset : float or (n,) float
        ``d``, the coefficient of ``-N``.

    Returns
    -------
    (8, 8) or (n, 8, 8) float

    Raises
    ------
    InputError
        On shapes that do not match, non-finite or bool entries, or entries whose sums leave the
        float range.

    Examples
    --------
    >>> b, c, n = np.array([0.5, -1.0, 2.0]), np.array([1.0, 0.25, -0.5]), np.array([0.0, 1.0, 1.0])
    >>> Q = point_on_plane_quadric_linear(n, np.outer(n, b), n @ c)
    >>> bool(np.allclose(Q, point_on_plane_quadric(b, c, n), rtol=0, atol=1e-14))
    True
    """
    (n, V, d), shape = _linear_coefficients((("normal", normal, (3,)), ("products", products, (3, 3)),
                                             ("offset", offset, ())))
    T, B, N = _plane_basis()
    out = (np.einsum("...i,ikl->...kl", n, T) + np.einsum("...ij,ijkl->...kl", V, B)
           - np.asarray(d)[..., None, None] * N)
    return _linear_result(out, shape, "normal, products and offset")


@overload
def point_on_line_quadrics(platform_point: NumericInput, line_point: NumericInput,
                           line_direction: NumericInput) -> FloatArray: ...
@overload
def point_on_line_quadrics(platform_point: Any, line_point: Any, line_direction: Any) -> Any: ...
def point_on_line_quadrics(platform_point, line_point, line_direction):
    """The three quadrics of "platform point ``b`` on the fixed line through ``c`` along ``d``".

    ``(X - c) x d = 0`` times ``N``; two of the three are independent where ``d`` has a non-zero
    component.

    Parameters
    ----------
    platform_point : (3,) float or sympy
    line_point : (3,) float or sympy
    line_direction : (3,) float or sympy
        Non-zero.

    Returns
    -------
    (3, 8, 8) float, or list of 3 sympy.Matrix when any input is symbolic

    Raises
    ------
    InputError
        On wrong shapes, non-finite entries or a zero direction.

    Examples
    --------
    >>> from imagespace.spatial.study import study_point
    >>> Qs = point_on_line_quadrics([0, 0, 0], [0, 0, 0], [0, 0, 1])
    >>> s = study_point([1, 0, 0, 0], [0.0, 0.0, 7.0])
    >>> [float(s @ Q @ s) + 0.0 for Q in Qs]
    [0.0, 0.0, 0.0]
    """
    symbolic = any(is_symbolic(v) for v in (platform_point, line_point, line_direction))
    if not symbolic:
        b = as_float_array(platform_point, "platform_point", last=3, allow_batch=False)
        c = as_float_array(line_point, "line_point", last=3, allow_batch=False)
        d = as_float_array(line_direction, "line_direction", last=3, allow_batch=False)
        if not np.any(d != 0):
            raise InputError("line_direction must be non-zero, got (0, 0, 0)")
        b, c, d = (_exact_or_float(v) for v in (b, c, d))
    else:
        b = as_sympy_vector(platform_point, "platform_point", 3)
        c = as_sympy_vector(line_point, "line_point", 3)
        d = as_sympy_vector(line_direction, "line_direction", 3)
        if all(v == 0 for v in d):
            raise InputError("line_direction must be non-zero, got (0, 0, 0)")
    z = study_symbols()
    N = _dot(z[:4], z[:4])
    X = landed_point_times_n(b)
    V = [X[1 + i] - c[i] * N for i in range(3)]
    cross = [V[1] * d[2] - V[2] * d[1], V[2] * d[0] - V[0] * d[2], V[0] * d[1] - V[1] * d[0]]
    Qs = [form_matrix(e) for e in cross]
    return Qs if symbolic else np.array([_as_float_matrix(Q, "platform_point, line_point or line_direction")
                                         for Q in Qs])
