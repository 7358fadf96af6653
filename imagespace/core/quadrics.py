r"""The four dyad constraints as quadrics of the kinematic image space.

Every dyad constraint has the form

.. math::

    Q = c\,(x_2^2 + x_3^2) + x_2\,(a_0 x_0 + a_1 x_1) + x_3\,(b_0 x_0 + b_1 x_1)
        + k_0 x_0^2 + k_1 x_0 x_1 + k_2 x_1^2 ,

so a :class:`Quadric` stores the eight coefficients ``(c, a0, a1, b0, b1, k0, k1, k2)``: ``c``,
the two linear forms and the binary quadratic form. The coefficients may be
sympy expressions (exact or in symbols) or numpy arrays (one quadric per row of a batch); the
formulas below are written once, in plain arithmetic, and serve both.

Derivation (complex notation of :mod:`imagespace.core.kinematic_map`: ``z = x0 + i x1``,
``u = x3 - i x2``, platform point ``p`` lands at ``(z**2 p + 2 u z)/|z|**2``):

* RR, platform point ``p`` on the circle (centre ``M``, radius ``rho``):
  ``|z p + 2u - conj(z) M|**2 - rho**2 |z|**2 = 0`` (the common factor ``|z|**2`` of
  ``|z(zp + 2u) - |z|**2 M|**2`` removed). A hyperboloid; ``c = 4``.
* PR, platform point ``p`` on the base line ``n . X = d``:
  ``Re(conj(n) z (z p + 2u)) - d |z|**2 = 0``. A hyperbolic paraboloid; ``c = 0``.
* RP, platform line ``m . p = e`` through the base point ``B``: the base point seen from the
  platform is ``conj(z)(conj(z) B - 2u)/|z|**2``, so ``Re(conj(m) conj(z)(conj(z) B - 2u)) - e |z|**2 = 0``.
* PP, platform orientation fixed at ``phi_c``: ``Im(z**2 exp(-i phi_c)) = 0``, i.e.
  ``2 x0 x1 cos(phi_c) - (x0**2 - x1**2) sin(phi_c) = 0``: the pair of planes ``phi = phi_c`` and
  ``phi = phi_c + pi``. Only the first is the dyad; callers that need the distinction check the
  leg's inverse kinematics (as :meth:`PlanarParallel.direct_kinematics` does).

Checked against eqs. (5)-(7) of Stigger & Husty in ``tests/core/test_constraints.py``.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import Any, Optional, Sequence

import numpy as np
import numpy.typing as npt
import sympy as sp

from .._validate import _short, as_sympy_entry
from ..exceptions import DegenerateDesignError, InputError, InputTypeError

__all__ = [
    "Quadric",
    "rr_quadric",
    "pr_quadric",
    "rp_quadric",
    "pp_quadric",
    "image_symbols",
    "dyad_value_and_gradient",
    "dk_system",
    "dk_system_row",
]

_X = sp.symbols("x0:4", real=True)
_KINDS = ("RR", "PR", "RP", "PP")
_NAMES = ("c", "a0", "a1", "b0", "b1", "k0", "k1", "k2")
_INT_LIMIT = 2**1023


def _entry(value, name):
    """One coefficient or geometric input: a sympy expression, a finite real number, or a real
    float array (a batch; NaN or inf there marks rows a batch caller already knows are invalid).
    Strings are refused, never parsed. Returns the value unchanged (numbers stay numbers)."""
    if type(value) is float or isinstance(value, np.float64):   # the hot path
        if not math.isfinite(value):
            raise InputError(f"{name} must be finite, got {value}")
        return value
    if type(value) is int:
        if abs(value) > _INT_LIMIT:
            raise InputError(f"{name} must be within the float range, got {_short(value)}; "
                             "give exact large values as sympy.Integer")
        return value
    if isinstance(value, np.ndarray) and value.ndim > 0:
        kind = value.dtype.kind
        if kind in "iuf":
            return value
        if kind == "b":
            raise InputTypeError(f"{name} must be numeric, got booleans {_short(value)}")
        if kind == "c":
            raise InputTypeError(f"{name} must be real, got the complex array {_short(value)}")
        if kind in "USV":
            raise InputTypeError(f"{name} must be numeric, got strings {_short(value)}; strings are never parsed")
        raise InputTypeError(f"{name} must be a number, a sympy expression or a float array, got an array of "
                             f"dtype {value.dtype}: {_short(value)}")
    if isinstance(value, sp.Basic):
        value = as_sympy_entry(value, name)
        if value.has(sp.I):
            raise InputTypeError(f"{name} must be real, got {_short(value)}")
        return value
    if isinstance(value, np.ndarray):             # 0-d
        value = value[()]
    if isinstance(value, (numbers.Real, np.floating, np.integer)) and not isinstance(value, (bool, np.bool_)):
        if isinstance(value, (numbers.Integral, np.integer)):
            return _entry(int(value), name) if not isinstance(value, np.integer) else value
        try:
            finite = math.isfinite(float(value))
        except OverflowError:
            finite = False
        if not finite:
            raise InputError(f"{name} must be finite and within the float range, got {_short(value)}")
        return value
    as_sympy_entry(value, name)                   # raises the right TypeError (str, None, bool, complex ...)
    raise InputTypeError(f"{name} must be a number, a sympy expression or a float array, got "
                         f"{type(value).__name__} {_short(value)}")


def _pair(value, name):
    """A 2-vector (x, y) of entries (numbers, sympy expressions or float arrays, per coordinate)."""
    if isinstance(value, (str, bytes)) or value is None or isinstance(value, (bool, np.bool_)):
        raise InputTypeError(f"{name} must be a 2-vector (x, y), got {type(value).__name__} {_short(value)}")
    if isinstance(value, np.ndarray) and value.ndim == 1 and value.dtype.kind != "O":
        items = list(value)
    else:
        try:
            items = list(value)
        except TypeError:
            raise InputTypeError(f"{name} must be a 2-vector (x, y), got {type(value).__name__} "
                                 f"{_short(value)}") from None
    if len(items) != 2:
        raise InputError(f"{name} must have two entries (x, y), got {len(items)}: {_short(value)}")
    return tuple(_entry(v, f"{name}[{i}]") for i, v in enumerate(items))


def _exact_zero(v):
    if isinstance(v, sp.Basic):
        return v == 0 or (v.is_Number and v.is_zero)
    return v == 0


def _check_nonzero_pair(x, y, name):
    """Refuse a pair that is (0, 0): exactly for sympy, in every row for arrays."""
    if isinstance(x, sp.Basic) or isinstance(y, sp.Basic):
        if _exact_zero(x) and _exact_zero(y):
            raise InputError(f"{name} must be non-zero, got ({x}, {y})")
        return
    zero = (np.asarray(x) == 0) & (np.asarray(y) == 0)
    if np.any(zero):
        where = "" if zero.ndim == 0 else f" in row(s) {np.flatnonzero(zero)[:5].tolist()}"
        raise InputError(f"{name} must be non-zero, got (0, 0){where}")


def image_symbols() -> tuple[sp.Symbol, sp.Symbol, sp.Symbol, sp.Symbol]:
    """The sympy symbols ``(x0, x1, x2, x3)`` used by every symbolic expression of imagespace.

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.image_symbols()
    (x0, x1, x2, x3)
    """
    return _X


def _is_exact_zero(v) -> bool:
    """A scalar coefficient that is exactly zero (a number, not an expression that may vanish)."""
    if isinstance(v, sp.Basic):
        return bool(v.is_number and v == 0)
    return isinstance(v, numbers.Number) and v == 0


@dataclass(frozen=True)
class Quadric:
    """A dyad constraint ``c (x2^2+x3^2) + x2 (a0 x0 + a1 x1) + x3 (b0 x0 + b1 x1) + k0 x0^2 + k1 x0 x1 + k2 x1^2``.

    Attributes
    ----------
    kind : str
        ``"RR"``, ``"PR"``, ``"RP"`` or ``"PP"``.
    c, a0, a1, b0, b1, k0, k1, k2 : sympy expression, float or (n,) float array
        The coefficients (arrays for a batch of quadrics, one per row; all arrays of one shape).

    Raises
    ------
    TypeError
        ``kind`` is not a string; a coefficient is a string (never parsed), ``None``, a bool, a
        complex number, a sympy boolean or an array of such.
    InputError
        ``kind`` is not one of the four; a number or sympy coefficient is NaN or infinite; the
        arrays differ in shape. In an array (a batch) NaN and inf are left alone: batch callers
        mark the rows they know to be invalid that way.
    """

    kind: str
    c: Any
    a0: Any
    a1: Any
    b0: Any
    b1: Any
    k0: Any
    k1: Any
    k2: Any

    def __post_init__(self):
        if not isinstance(self.kind, str):
            raise InputTypeError(f"kind must be one of {', '.join(_KINDS)}, got {type(self.kind).__name__} "
                                 f"{_short(self.kind)}")
        if self.kind not in _KINDS:
            raise InputError(f"kind must be one of {', '.join(_KINDS)}, got {self.kind!r}")
        shape = None
        for name, v in zip(_NAMES, self.coefficients()):
            try:
                _entry(v, f"Quadric coefficient {name}")
            except InputError as exc:
                raise type(exc)(f"{exc} (an overflow of the inputs beyond the float range?)"
                                if "finite" in str(exc) else str(exc)) from None
            if isinstance(v, np.ndarray) and v.ndim > 0:
                if shape is None:
                    shape = (name, v.shape)
                elif v.shape != shape[1]:
                    raise InputError(f"the Quadric coefficients must be numbers or arrays of one common "
                                     f"shape, got {shape[0]} of shape {shape[1]} and {name} of shape {v.shape}")
        if shape is None and all(_is_exact_zero(v) for v in self.coefficients()):
            raise DegenerateDesignError(f"a {self.kind} Quadric with every coefficient zero is all of image "
                                        "space (it constrains nothing); got c = a0 = ... = k2 = 0")

    def coefficients(self) -> tuple[Any, Any, Any, Any, Any, Any, Any, Any]:
        """The eight coefficients ``(c, a0, a1, b0, b1, k0, k1, k2)`` as a tuple.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.pp_quadric(1, 0).coefficients()
        (0, 0, 0, 0, 0, 0, 2, 0)
        """
        return (self.c, self.a0, self.a1, self.b0, self.b1, self.k0, self.k1, self.k2)

    def expr(self, x: Optional[Sequence[Any]] = None) -> sp.Expr:
        """The quadric as a sympy expression in ``x`` (default :func:`image_symbols`).

        Raises
        ------
        TypeError
            ``x`` is not four sympy symbols or expressions, or a coefficient is not a sympy-
            convertible number.
        InputError
            the Quadric is a batch (a coefficient is an array).

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.rr_quadric((0, 0), 100, (0, 0)).expr()
        -100*x0**2 - 100*x1**2 + 4*x2**2 + 4*x3**2
        """
        if x is None:
            x0, x1, x2, x3 = _X
        else:
            if isinstance(x, (str, bytes)) or not hasattr(x, "__len__") or len(x) != 4:
                raise InputTypeError(f"x must be four sympy symbols or expressions, got {_short(x)}")
            x0, x1, x2, x3 = (as_sympy_entry(v, f"x[{i}]") for i, v in enumerate(x))
        batch = [n for n, v in zip(_NAMES, self.coefficients()) if isinstance(v, np.ndarray) and v.ndim > 0]
        if batch:
            raise InputError(f"expr needs one quadric, but this Quadric is a batch (coefficient {batch[0]} "
                             f"is an array); take one row first")
        coeffs = [as_sympy_entry(v, n) for n, v in zip(_NAMES, self.coefficients())]
        return sp.expand(_dyad_value(coeffs, x0, x1, x2, x3))

    def evaluate(self, points: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """Value at image points ``(..., 4)`` (numeric coefficients only).

        Raises
        ------
        InputError
            ``points`` is not of shape ``(..., 4)`` or does not match the batch of quadrics.
        TypeError
            a coefficient holds sympy symbols.

        Examples
        --------
        >>> import imagespace as isp
        >>> float(isp.rr_quadric((0, 0), 4.0, (0, 0)).evaluate([1.0, 0.0, 0.0, 1.0]))
        0.0
        """
        p = self._points(points)
        try:
            return dyad_value_and_gradient(self._float_coefficients("evaluate"), p)[0]
        except ValueError:
            raise InputError(f"points of shape {p.shape} do not match this batch of quadrics "
                             f"(coefficients of shape {np.shape(self._batch_size())})") from None

    @staticmethod
    def _points(points):
        from .._validate import as_float_array

        p = as_float_array(points, "points", finite=False)
        if p.ndim == 0 or p.shape[-1] != 4:
            raise InputError(f"points must have shape (..., 4) (image points), got shape {p.shape}")
        return p

    def _float_coefficients(self, what):
        out = []
        for name, v in zip(_NAMES, self.coefficients()):
            if isinstance(v, sp.Basic):
                if v.free_symbols:
                    raise InputTypeError(f"{what} needs numeric coefficients, but {name} = {_short(v)} has the "
                                         f"symbols {sorted(map(str, v.free_symbols))}; substitute numbers first")
                v = float(v)
            out.append(np.asarray(v, dtype=float))
        return out

    def _batch_size(self):
        for v in self.coefficients():
            if isinstance(v, np.ndarray) and v.ndim > 0:
                return v
        return 0.0

    def gradient(self, points: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """Gradient with respect to ``(x0, x1, x2, x3)`` at image points, shape ``(..., 4)``.

        Raises
        ------
        InputError
            ``points`` is not of shape ``(..., 4)`` or does not match the batch of quadrics.
        TypeError
            a coefficient holds sympy symbols.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.rr_quadric((0, 0), 4.0, (0, 0)).gradient([1.0, 0.0, 0.0, 1.0])
        array([-8.,  0.,  0.,  8.])
        """
        p = self._points(points)
        try:
            return dyad_value_and_gradient(self._float_coefficients("gradient"), p)[1]
        except ValueError:
            raise InputError(f"points of shape {p.shape} do not match this batch of quadrics "
                             f"(coefficients of shape {np.shape(self._batch_size())})") from None


# -- the one numeric evaluator of the dyad quadrics (coefficient layout _NAMES) -------------------
def dyad_value_and_gradient(coeffs: Sequence[Any], X: npt.NDArray[np.float64]
                            ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Value and gradient of dyad quadrics at image points: the one numeric home of the formula.

    Parameters
    ----------
    coeffs : sequence of eight float arrays
        ``(c, a0, a1, b0, b1, k0, k1, k2)``, each broadcasting against ``X[..., 0]``.
    X : (..., 4) float
        Image points.

    Returns
    -------
    value : (...) float
    gradient : (..., 4) float
        With respect to ``(x0, x1, x2, x3)``.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.quadrics import dyad_value_and_gradient, rr_quadric
    >>> v, g = dyad_value_and_gradient(rr_quadric((0, 0), 4.0, (0, 0)).coefficients(), np.array([1.0, 0, 0, 1]))
    >>> float(v), g.tolist()
    (0.0, [-8.0, 0.0, 0.0, 8.0])
    """
    coeffs = [np.asarray(v, dtype=float) for v in coeffs]
    x = [X[..., j] for j in range(4)]
    return _dyad_value(coeffs, *x), np.stack(np.broadcast_arrays(*_dyad_gradient(coeffs, *x)), axis=-1)


def _dyad_value(coeffs, x0, x1, x2, x3):
    """The dyad quadric in plain arithmetic: sympy expressions and numpy arrays alike."""
    c, a0, a1, b0, b1, k0, k1, k2 = coeffs
    return (c * (x2**2 + x3**2) + x2 * (a0 * x0 + a1 * x1) + x3 * (b0 * x0 + b1 * x1)
            + k0 * x0**2 + k1 * x0 * x1 + k2 * x1**2)


def _dyad_gradient(coeffs, x0, x1, x2, x3):
    """Its partial derivatives in ``x0, x1, x2, x3`` (plain arithmetic)."""
    c, a0, a1, b0, b1, k0, k1, k2 = coeffs
    return (a0 * x2 + b0 * x3 + 2 * k0 * x0 + k1 * x1,
            a1 * x2 + b1 * x3 + k1 * x0 + 2 * k2 * x1,
            2 * c * x2 + a0 * x0 + a1 * x1,
            2 * c * x3 + b0 * x0 + b1 * x1)


def dk_system(C: npt.NDArray[np.float64], X: npt.NDArray[np.float64]) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The direct-kinematics system ``[Q1, Q2, Q3, x0^2 + x1^2 - 1]`` and its Jacobian.

    Parameters
    ----------
    C : (n, 3, 8) float
        The three quadrics' coefficients per row (layout of :meth:`Quadric.coefficients`).
    X : (n, k, 4) float
        ``k`` image points per row.

    Returns
    -------
    values : (n, k, 4) float
    jacobian : (n, k, 4, 4) float

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.quadrics import dk_system
    >>> C = np.zeros((1, 3, 8)); C[0, :, 0] = 4.0; C[0, :, 5] = -4.0     # x2^2 + x3^2 = x0^2 (x4)
    >>> Fv, J = dk_system(C, np.array([[[1.0, 0.0, 1.0, 0.0]]]))
    >>> Fv.tolist(), J[0, 0, 3].tolist()
    ([[[0.0, 0.0, 0.0, 0.0]]], [2.0, 0.0, 0.0, 0.0])
    """
    val, grad = dyad_value_and_gradient([C[:, None, :, j] for j in range(8)], X[..., None, :])
    J = np.empty(X.shape[:-1] + (4, 4))
    J[..., :3, :] = grad
    J[..., 3, 0], J[..., 3, 1] = 2 * X[..., 0], 2 * X[..., 1]
    J[..., 3, 2] = J[..., 3, 3] = 0.0
    Fv = np.concatenate([val, (X[..., 0]**2 + X[..., 1]**2 - 1)[..., None]], axis=-1)
    return Fv, J


def dk_system_row(C, X, val, J):
    """:func:`dk_system` for one row and one point, written for numba (the compiled kernel of
    :mod:`imagespace.solve.kernel` compiles this very function; ``tests`` hold it equal to
    :func:`dk_system` on random input).

    ``C``: (24,) coefficients, quadric ``i`` at ``8 i .. 8 i + 7``; ``X``: (4,); fills ``val``
    (4,) and ``J`` (4, 4) in place.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.quadrics import dk_system_row
    >>> C = np.tile([4.0, 0, 0, 0, 0, -4.0, 0, 0], 3); val = np.empty(4); J = np.empty((4, 4))
    >>> dk_system_row(C, np.array([1.0, 0.0, 1.0, 0.0]), val, J); val.tolist()
    [0.0, 0.0, 0.0, 0.0]
    """
    x0, x1, x2, x3 = X[0], X[1], X[2], X[3]
    for i in range(3):
        c, a0, a1, b0, b1 = C[8 * i], C[8 * i + 1], C[8 * i + 2], C[8 * i + 3], C[8 * i + 4]
        k0, k1, k2 = C[8 * i + 5], C[8 * i + 6], C[8 * i + 7]
        val[i] = (c * (x2 * x2 + x3 * x3) + x2 * (a0 * x0 + a1 * x1) + x3 * (b0 * x0 + b1 * x1)
                  + k0 * x0 * x0 + k1 * x0 * x1 + k2 * x1 * x1)
        J[i, 0] = a0 * x2 + b0 * x3 + 2 * k0 * x0 + k1 * x1
        J[i, 1] = a1 * x2 + b1 * x3 + k1 * x0 + 2 * k2 * x1
        J[i, 2] = 2 * c * x2 + a0 * x0 + a1 * x1
        J[i, 3] = 2 * c * x3 + b0 * x0 + b1 * x1
    val[3] = x0 * x0 + x1 * x1 - 1.0
    J[3, 0] = 2 * x0
    J[3, 1] = 2 * x1
    J[3, 2] = 0.0
    J[3, 3] = 0.0


def rr_quadric(centre: Any, radius_squared: Any, point: Any) -> Quadric:
    """RR dyad: the platform point ``point`` stays on the base circle (``centre``, radius**2).

    Parameters
    ----------
    centre : (2,) numbers, sympy expressions or (n,) arrays per coordinate
    radius_squared : number, sympy expression or (n,) array
        The squared radius (kept squared so that no square root enters the algebra).
    point : (2,)
        The platform point in the moving frame.

    Returns
    -------
    Quadric

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.rr_quadric((7, 0), 232, (5, 0)).expr()
    -228*x0**2 - 8*x0*x3 - 88*x1**2 - 48*x1*x2 + 4*x2**2 + 4*x3**2
    """
    mx, my = _pair(centre, "centre")
    px, py = _pair(point, "point")
    radius_squared = _entry(radius_squared, "radius_squared")
    r0, r1 = px - mx, -(py + my)
    i0, i1 = py - my, px + mx
    return Quadric("RR", 4 + 0 * px, -4 * i0, -4 * i1, 4 * r0, 4 * r1,
                   r0 * r0 + i0 * i0 - radius_squared, 2 * (r0 * r1 + i0 * i1),
                   r1 * r1 + i1 * i1 - radius_squared)


def pr_quadric(point: Any, line_point: Any, line_direction: Any) -> Quadric:
    """PR dyad: the platform point ``point`` stays on the base line through ``line_point``.

    The line is ``n . X = n . line_point`` with ``n`` the direction turned by +90 degrees (not
    normalised: the quadric scales with ``|line_direction|``).

    Returns
    -------
    Quadric

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.pr_quadric((0, 0), (0, 1), (1, 0)).expr()   # the origin of the platform on y = 1
    -x0**2 - 2*x0*x2 - x1**2 + 2*x1*x3
    """
    px, py = _pair(point, "point")
    lx, ly = _pair(line_point, "line_point")
    wx, wy = _pair(line_direction, "line_direction")
    _check_nonzero_pair(wx, wy, "line_direction")
    nx, ny = -wy, wx
    d = nx * lx + ny * ly
    s = px * nx + py * ny
    return Quadric("PR", 0 * px, -2 * ny, 2 * nx, 2 * nx, 2 * ny,
                   s - d, 2 * (px * ny - py * nx), -s - d)


def rp_quadric(line_point: Any, line_direction: Any, base_point: Any) -> Quadric:
    """RP dyad: the platform line through ``line_point`` along ``line_direction`` passes through ``base_point``.

    Returns
    -------
    Quadric

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.rp_quadric((0, 0), (1, 0), (0, 0)).expr()   # the platform x axis through the base origin
    2*x0*x2 + 2*x1*x3
    """
    lx, ly = _pair(line_point, "line_point")
    vx, vy = _pair(line_direction, "line_direction")
    bx, by = _pair(base_point, "base_point")
    _check_nonzero_pair(vx, vy, "line_direction")
    mx, my = -vy, vx
    e = mx * lx + my * ly
    s = bx * mx + by * my
    return Quadric("RP", 0 * bx, 2 * my, 2 * mx, -2 * mx, 2 * my,
                   s - e, 2 * (by * mx - bx * my), -s - e)


def pp_quadric(cos_phi: Any, sin_phi: Any) -> Quadric:
    """PP dyad: the platform orientation is ``phi_c`` (given by its cosine and sine).

    The quadric ``2 x0 x1 cos(phi_c) - (x0**2 - x1**2) sin(phi_c)`` is the pair of planes
    ``phi = phi_c`` and ``phi = phi_c + pi``.

    Returns
    -------
    Quadric

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.pp_quadric(0, 1).expr()      # phi_c = pi/2
    -x0**2 + x1**2
    """
    cos_phi = _entry(cos_phi, "cos_phi")
    sin_phi = _entry(sin_phi, "sin_phi")
    _check_nonzero_pair(cos_phi, sin_phi, "(cos_phi, sin_phi)")
    z = 0 * cos_phi
    return Quadric("PP", z, z, z, z, z, -sin_phi, 2 * cos_phi, sin_phi)
