"""Pointwise evaluation for the singularity analyses: the image points of the two charts (with
their derivatives) and the three constraint quadrics at image points and joint values.

:func:`pose_chart_point` maps poses ``(x, y, phi)`` and :func:`image_chart_point` the affine chart
``(x2/x0, x3/x0, x1/x0)`` to image points; :func:`constraint_values` evaluates the legs' quadrics,
their gradients and joint derivatives from functions compiled once per design. The surface
(:mod:`imagespace.singular.surface`), the Jacobians (:mod:`imagespace.singular.jacobians`) and the
mesher (:mod:`imagespace.singular.implicit`) share them; the chart points are public there under
:mod:`imagespace.singular.surface`, where they have always been importable.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from .._validate import _short, as_exact, as_float_array, as_joint_vector, is_symbolic
from ..core.codegen import compile_exprs
from ..core.quadrics import image_symbols
from ..exceptions import InputError, InputTypeError

__all__ = ["pose_chart_point", "image_chart_point", "constraint_values"]


def pose_chart_point(P):
    """Normalised image points of poses and their derivative with respect to ``(x, y, phi)``.

    Parameters
    ----------
    P : (n, 3) float

    Returns
    -------
    X : (n, 4) float
        ``(cos(phi/2), sin(phi/2), (x1 x - x0 y)/2, (x0 x + x1 y)/2)``.
    dX : (n, 4, 3) float
        ``dX[:, :, k]`` is the derivative along ``x``, ``y``, ``phi``.

    Raises
    ------
    TypeError
        ``P`` not numeric.
    InputError
        ``P`` not ``(3,)`` or ``(n, 3)`` (NaN and infinity pass through).

    Examples
    --------
    >>> from imagespace.singular.pointwise import pose_chart_point
    >>> X, dX = pose_chart_point([[2.0, 0.0, 0.0]])
    >>> X.tolist(), dX[0, :, 0].tolist()
    ([[1.0, 0.0, 0.0, 1.0]], [0.0, 0.0, 0.0, 0.5])
    """
    P = np.atleast_2d(as_float_array(P, "P", last=3, finite=False))
    x, y, phi = P[:, 0], P[:, 1], P[:, 2]
    c, s = np.cos(phi / 2), np.sin(phi / 2)
    X = np.stack([c, s, (s * x - c * y) / 2, (c * x + s * y) / 2], axis=-1)
    z = np.zeros_like(c)
    dX = np.stack([np.stack([z, z, s / 2, c / 2], -1),
                   np.stack([z, z, -c / 2, s / 2], -1),
                   np.stack([-s / 2, c / 2, X[:, 3] / 2, -X[:, 2] / 2], -1)], axis=-1)
    return X, dX


def image_chart_point(U):
    """Image points of the affine chart ``(x2/x0, x3/x0, x1/x0)`` (seed 002, Abb. 2) and its derivative.

    Parameters
    ----------
    U : (n, 3) float
        Chart coordinates ``(u, v, w) = (x2/x0, x3/x0, x1/x0)``.

    Returns
    -------
    X : (n, 4) float
        ``(1, w, u, v)``.
    dX : (n, 4, 3) float

    Raises
    ------
    TypeError
        ``U`` not numeric.
    InputError
        ``U`` not ``(3,)`` or ``(n, 3)`` (NaN and infinity pass through).

    Examples
    --------
    >>> from imagespace.singular.pointwise import image_chart_point
    >>> image_chart_point([[1.0, 2.0, 3.0]])[0].tolist()
    [[1.0, 3.0, 1.0, 2.0]]
    """
    U = np.atleast_2d(as_float_array(U, "U", last=3, finite=False))
    X = np.stack([np.ones(len(U)), U[:, 2], U[:, 0], U[:, 1]], axis=-1)
    dX = np.zeros((len(U), 4, 3))
    dX[:, 2, 0] = dX[:, 3, 1] = dX[:, 1, 2] = 1.0
    return X, dX


def check_joint_values(manipulator, q, name="q"):
    """One set of joint values ``(3,)``: exact sympy numbers/expressions or checked floats.

    Shared by the analysis modules (not public API: not in ``__all__``). Floats become their exact
    binary rationals; strings are refused, never parsed.

    Parameters
    ----------
    manipulator : PlanarParallel
        Checks each value against its leg's domain (``manipulator.check_q``).
    q : (3,) numbers or sympy expressions
    name : str
        The parameter name used in error messages.

    Returns
    -------
    tuple of 3 sympy numbers or expressions

    Raises
    ------
    TypeError
        Strings, booleans, complex numbers, a non-sequence.
    InputError
        A wrong shape, a non-finite value, a value outside a leg's domain.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.pointwise import check_joint_values
    >>> check_joint_values(isp.examples.general_3rpr(), [11, 5, 10.5])
    (11, 5, 21/2)
    """
    if is_symbolic(q):
        if not isinstance(q, (list, tuple, np.ndarray, sp.MatrixBase)):
            raise InputTypeError(f"{name} must be a sequence of three joint values, got {_short(q)}")
        items = list(q)
        if len(items) != 3:
            raise InputError(f"{name} must have shape (3,), got {len(items)} entries: {_short(q)}")
        return tuple(as_exact(v, f"{name}[{i}]") for i, v in enumerate(items))
    qa = manipulator.check_q(as_joint_vector(q, name), name)
    return tuple(as_exact(float(v), f"{name}[{i}]") for i, v in enumerate(qa))


# -- compiled constraint functions ----------------------------------------------------------------
def constraint_functions(m):
    """Compiled ``[Q_i, dQ_i/dx (4), dQ_i/dq_i]`` for the three legs, arguments ``(x0..x3, q1..q3)``.

    Built once per design and cached on it (``m.cached("constraint_functions", ...)``); not public
    API (not in ``__all__``): :func:`constraint_values` is the face the analysis modules call.

    Parameters
    ----------
    m : PlanarParallel
        A numeric design.

    Returns
    -------
    callable
        ``f(x0, x1, x2, x3, q1, q2, q3)`` on float arrays of one length ``n``, returning ``(n, 18)``.

    Raises
    ------
    InputError
        If the design has free symbols.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.pointwise import constraint_functions
    >>> m = isp.examples.general_3rpr()
    >>> f = constraint_functions(m)
    >>> f is constraint_functions(m), f(*np.ones((7, 2))).shape
    (True, (2, 18))
    """
    return m.cached("constraint_functions", lambda: _build_constraint_functions(m))


def _build_constraint_functions(m):
    require_numeric(m)
    x = image_symbols()
    qs = m.joint_symbols
    exprs = []
    for leg, qi in zip(m.legs, qs):
        Q = sp.expand(leg.dyad(qi).expr())
        if any(not c.is_Rational for c in sp.Poly(Q, *x).coeffs() if c.is_number):
            Q = sp.expand(sp.N(Q, 20))          # exact trig/radical constants: evaluate once
        P = sp.Poly(Q, *x)
        exprs += [Q] + [P.diff(v).as_expr() for v in x] + [sp.diff(Q, qi)]
    return compile_exprs(exprs, list(x) + list(qs))


def require_numeric(m):
    """Refuse a design with free symbols where numbers are needed (not public API).

    Raises
    ------
    InputError
        Naming the symbols.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.pointwise import require_numeric
    >>> require_numeric(isp.examples.general_3rpr())
    """
    free = m.design_symbols
    if free:
        raise InputError(f"numeric evaluation needs a numeric design; the design has the symbols "
                         f"{sorted(map(str, free))} (substitute numbers first)")


def constraint_values(m, X, Q):
    """The three constraint quadrics, their gradients and joint derivatives at image points and joints.

    Shared with :mod:`imagespace.singular.jacobians` (not public API: not in ``__all__``); the
    compiled functions are cached on the design (``m.cached("constraint_functions", ...)``).

    Parameters
    ----------
    m : PlanarParallel
        A numeric design.
    X : (n, 4) float
        Image points.
    Q : (n, 3) float
        Joint values, one row per image point.

    Returns
    -------
    vals : (n, 3) float
        ``Q_i(X; q_i)``.
    grad : (n, 3, 4) float
        ``dQ_i/dX``.
    dq : (n, 3) float
        ``dQ_i/dq_i``.

    Raises
    ------
    InputError
        If the design has free symbols (numeric evaluation needs numbers).

    Examples
    --------
    >>> import numpy as np
    >>> import imagespace as isp
    >>> from imagespace.singular.pointwise import constraint_values
    >>> m = isp.examples.stigger_husty()
    >>> X = m.direct_kinematics(m.q_example)[0].image_point[None]
    >>> vals, grad, dq = constraint_values(m, X, m.q_example_float[None])
    >>> vals.shape, grad.shape, dq.shape, bool(np.all(np.abs(vals) < 1e-6 * np.abs(grad).max()))
    ((1, 3), (1, 3, 4), (1, 3), True)
    """
    out = constraint_functions(m)(*X.T, *Q.T)
    out = out.reshape(len(X), 3, 6)
    return out[:, :, 0], out[:, :, 1:5], out[:, :, 5]
