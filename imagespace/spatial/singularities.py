r"""Singularities of the Gough-Stewart platform: the line-coordinate Jacobian in Euclidean and in
Study coordinates, the aspect (sign of its determinant) and the constant-orientation singularity
locus in the position ``(x, y, z)``.

**The Jacobian.** Leg ``i`` joins the base point ``a_i`` to the landed platform point
``R b_i + t``; its leg vector is ``s_i = R b_i + t - a_i`` and its line has the Pluecker
coordinates ``(s_i, a_i x s_i)`` (direction, moment about the base origin). Differentiating
``L_i^2 = s_i . s_i`` along a motion of the platform with angular velocity ``omega`` and
``v_O`` the velocity of the platform point that is at the base origin at this instant
(``v_O = t' + t x omega``; every platform point ``X`` moves with ``X' = v_O + omega x X``) gives

.. math::

    L_i \dot L_i = s_i \cdot v_O + (a_i \times s_i) \cdot \omega ,

so the ``6 x 6`` matrix ``J`` with rows ``(s_i, a_i x s_i)`` maps the twist ``(v_O, omega)`` to
``(L_i L_i')``. Rows are the leg lines: ``det J = 0`` exactly where the six lines are linearly
dependent (a singularity of the platform, where it gains an uncontrolled motion).

**In Study coordinates.** With ``N = x . x``, ``N (R b + t)`` is the vector part of
``x b x~ + 2 y x~`` (:func:`imagespace.spatial.quadrics.landed_point_times_n`), a quadratic form
in the Study point ``z``; so is every entry of ``N J``. :func:`leg_line_forms` returns these 36
forms as ``8 x 8`` matrices; their determinant is a form of degree 12 in ``z`` with
``det(N J) = N^6 det J`` everywhere off ``x = 0`` (no reduction on Study's quadric is needed: the
vector part of ``2 y x~ / N`` is the translation whatever ``x . y``). For a normalised Study point
(``N = 1``) it is ``det J`` itself.

**Constant orientation.** For a fixed rotation ``R`` the rows ``(s_i, a_i x s_i)`` with
``s_i = t + R b_i - a_i`` are linear in ``t = (x, y, z)``; their determinant is a polynomial of
nominal degree 6 that cancels to degree 3 for the general 6-6 platform (Mayer St-Onge & Gosselin
2000): the singularity locus at constant orientation is a cubic surface. It is computed exactly
(floats enter as their binary rationals) by :func:`constant_orientation_singularity`; meshing it
(the certified mesher of :mod:`imagespace.singular.meshing`) is
:func:`imagespace.spatial_surfaces.mesh_constant_orientation_singularity`.

References
----------
B. Mayer St-Onge, C. M. Gosselin, Singularity analysis and representation of the general
Gough-Stewart platform, Int. J. Robotics Research 19(3), 271-288, 2000,
doi:10.1177/02783640022066905.
J.-P. Merlet, Singular configurations of parallel manipulators and Grassmann geometry, Int. J.
Robotics Research 8(5), 45-56, 1989, doi:10.1177/027836498900800504.
"""

from __future__ import annotations

from fractions import Fraction
from functools import lru_cache
from typing import TYPE_CHECKING, Any, Optional, Union

import numpy as np
import numpy.typing as npt
import sympy as sp

from .._validate import as_float_array, as_sympy, as_tolerances
from ..exceptions import DegenerateDesignError, InputError, InputTypeError
from .gough_stewart import GoughStewart
from .quadrics import form_matrix, landed_point_times_n
from .study import matrix_from_quaternion, rotation_entries, study_symbols

if TYPE_CHECKING:
    from ..core.kinematic_map import FloatArray
    from ..tolerances import Tolerances

__all__ = ["leg_line_forms", "jacobian_matrix", "jacobian_determinant", "aspect",
           "constant_orientation_singularity", "ConstantOrientationSingularity"]

_FORM_CACHE_SIZE = 32     # designs whose exact line forms are kept (a pure speed knob)


def _check_gs(gs):
    if not isinstance(gs, GoughStewart):
        raise InputTypeError(f"gs must be an imagespace.spatial.GoughStewart, got {type(gs).__name__}")
    return gs


def _check_study_points(s, name="s"):
    z = as_float_array(s, name, last=8)
    if z.ndim > 2:
        raise InputError(f"{name} must have shape (8,) or (n, 8), got {z.shape}")
    if np.any(np.all(z[..., :4] == 0.0, axis=-1)):
        raise InputError(f"{name} must have x = (x0, x1, x2, x3) != 0 (points with x = 0 are not "
                         "displacements), got x = 0")
    return z


def _cross(u, v):
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


# --------------------------------------------------------------------------- Study forms

@lru_cache(maxsize=1)
def _line_form_table():
    """The six line-coordinate forms of one leg with symbolic anchors, as a sparse monomial table.

    Returns ``(monomials, entries)``: ``monomials`` the exponent tuples of the anchor coordinates
    ``(a1, a2, a3, b1, b2, b3)``; ``entries`` a list of ``(m, k, i, j, c)`` with ``c`` a Fraction:
    ``N (s, a x s)[k] = z^T Q_k z`` with ``Q_k[i, j] = sum c * anchors^monomials[m]``.
    """
    a = sp.symbols("a1:4")
    b = sp.symbols("b1:4")
    z = study_symbols()
    N = sum(v * v for v in z[:4])
    landed = landed_point_times_n(b)                       # vector part: N (R b + t)
    ns = [sp.expand(landed[1 + k] - a[k] * N) for k in range(3)]
    moment = [sp.expand(e) for e in _cross(a, ns)]
    anchors = tuple(a) + tuple(b)
    raw = []
    for k, e in enumerate(ns + moment):
        Q = form_matrix(e)             # entries polynomial in the anchors
        for i in range(8):
            for j in range(8):
                if Q[i, j] != 0:
                    for mon, c in sp.Poly(Q[i, j], *anchors).terms():
                        raw.append((mon, k, i, j, Fraction(int(c.p), int(c.q))))
    monomials = sorted({r[0] for r in raw})
    index = {m: n for n, m in enumerate(monomials)}
    return monomials, [(index[mon], k, i, j, c) for mon, k, i, j, c in raw]


@lru_cache(maxsize=_FORM_CACHE_SIZE)
def _forms_of(anchor_bytes):
    anchors = np.frombuffer(anchor_bytes, dtype=np.float64).reshape(6, 6)
    monomials, entries = _line_form_table()
    out = np.zeros((6, 6, 8, 8))
    for leg in range(6):
        vals = [Fraction(float(v)) for v in anchors[leg]]            # exact binary rationals
        weights = []
        for mon in monomials:
            w = Fraction(1)
            for v, e in zip(vals, mon):
                if e:
                    w *= v ** e
            weights.append(w)
        exact = {}
        for m, k, i, j, c in entries:
            exact[k, i, j] = exact.get((k, i, j), 0) + c * weights[m]
        for (k, i, j), v in exact.items():
            out[leg, k, i, j] = float(v)                              # rounded once
    out.setflags(write=False)
    return out


def leg_line_forms(gs: GoughStewart) -> FloatArray:
    """The line-coordinate Jacobian in Study coordinates: 36 quadratic forms in the Study point.

    Row ``i`` is ``N (s_i, a_i x s_i)`` with ``s_i = R b_i + t - a_i`` the leg vector, ``a_i x s_i``
    its moment about the base origin and ``N = x . x``; every entry is a quadratic form
    ``z^T Q z`` in the Study point ``z`` (derived with sympy from
    :func:`imagespace.spatial.quadrics.landed_point_times_n`; the anchors enter as exact binary
    rationals and each matrix entry is rounded to float once).

    Parameters
    ----------
    gs : GoughStewart

    Returns
    -------
    (6, 6, 8, 8) float
        ``Q[i, k]`` is the symmetric matrix of entry ``(i, k)``: ``z^T Q[i, k] z = N J[i, k]``
        (:func:`jacobian_matrix`), for every ``z`` with ``x != 0``.

    Raises
    ------
    TypeError
        If ``gs`` is not a :class:`~imagespace.spatial.gough_stewart.GoughStewart`.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.gough_stewart import GoughStewart
    >>> rng = np.random.default_rng(0)
    >>> gs = GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
    >>> Q = leg_line_forms(gs)
    >>> Q.shape
    (6, 6, 8, 8)
    >>> z = np.array([1.0, 0, 0, 0, 0, 0, 0, 0])                      # the identity, N = 1
    >>> bool(np.allclose(np.einsum("a,ikab,b->ik", z, Q, z), jacobian_matrix(gs, z)))
    True
    """
    gs = _check_gs(gs)
    anchors = np.ascontiguousarray(np.concatenate([gs.base_points, gs.platform_points], axis=1),
                                   dtype=np.float64)
    return _forms_of(anchors.tobytes()).copy()


# --------------------------------------------------------------------------- Euclidean Jacobian

def jacobian_matrix(gs: GoughStewart, s: npt.ArrayLike) -> FloatArray:
    """The Euclidean line-coordinate Jacobian: rows ``(s_i, a_i x s_i)``.

    ``s_i = R b_i + t - a_i`` is leg ``i``'s vector and ``a_i x s_i`` its moment about the base
    origin. The matrix maps the twist ``(v_O, omega)`` of the platform to the leg rates:
    ``L_i dL_i/dt = s_i . v_O + (a_i x s_i) . omega``, with ``omega`` the angular velocity and
    ``v_O`` the velocity of the platform point that is at the base origin at this instant (every
    platform point ``X`` moves with ``v_O + omega x X``).

    Parameters
    ----------
    gs : GoughStewart
    s : (8,) or (n, 8) float
        Study points (any scale; they should lie on Study's quadric).

    Returns
    -------
    (6, 6) or (n, 6, 6) float

    Raises
    ------
    TypeError
        If ``gs`` is not a GoughStewart.
    InputError
        On wrong shapes, non-finite entries or ``x = 0``.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.gough_stewart import GoughStewart
    >>> gs = GoughStewart(np.eye(6, 3), np.eye(6, 3)[::-1] + 1)
    >>> J = jacobian_matrix(gs, [1, 0, 0, 0, 0, 0, 0, 0])
    >>> J.shape, J[0].tolist()
    ((6, 6), [0.0, 1.0, 1.0, 0.0, -1.0, 1.0])
    """
    gs = _check_gs(gs)
    return gs.jacobian(_check_study_points(s)) + 0.0         # the same rows as GoughStewart.jacobian


def jacobian_determinant(gs: GoughStewart, s: npt.ArrayLike) -> Union[float, FloatArray]:
    """The determinant of the Study forms of :func:`leg_line_forms` at Study points.

    It equals ``N^6 det J`` with ``N = x . x`` and ``J`` the Euclidean Jacobian
    (:func:`jacobian_matrix`): a form of degree 12 in ``s``, whose sign does not depend on the
    scale of ``s``; for a normalised Study point (``N = 1``) it is ``det J``.

    Parameters
    ----------
    gs : GoughStewart
    s : (8,) or (n, 8) float

    Returns
    -------
    float or (n,) float

    Raises
    ------
    TypeError
        If ``gs`` is not a GoughStewart.
    InputError
        On wrong shapes, non-finite entries or ``x = 0``.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.gough_stewart import GoughStewart
    >>> rng = np.random.default_rng(0)
    >>> gs = GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
    >>> s = np.array([1.0, 0, 0, 0, 0, 0.5, 0, 0])
    >>> bool(np.isclose(jacobian_determinant(gs, s), np.linalg.det(jacobian_matrix(gs, s))))
    True
    """
    Q = leg_line_forms(gs)
    z = _check_study_points(s)
    # a form of degree 12: evaluated at z / m (entries in [-1, 1]) and multiplied by m^12 one
    # factor at a time, so it leaves the float range only when its value does
    m = np.abs(z).max(axis=-1)
    zs = z / m[..., None]
    unit = np.linalg.det(np.einsum("...a,ikab,...b->...ik", zs, Q, zs))
    d = unit
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        for _ in range(12):
            d = d * m
    if not np.all(np.isfinite(d)) or np.any((d == 0) & (unit != 0)):
        raise InputError("s is out of range: the degree-12 form N^6 det J at s is outside the float range "
                         "(about 1e-308 .. 1.8e308); pass normalised Study points (normalize_study), "
                         "where it is det J")
    return float(d) if d.ndim == 0 else d


def aspect(gs: GoughStewart, s: npt.ArrayLike, tolerances: Optional[Tolerances] = None) -> Union[int, npt.NDArray[np.int8]]:
    """The aspect of poses: the sign of ``det J`` (+1, -1), or 0 at a singularity.

    The decision is scale-free: the moment columns are divided by the design's length scale
    ``c = max |a_i|`` (so both halves of a row are lengths; this multiplies ``det J`` by
    ``c^-3 > 0`` and keeps its sign), and the pose is singular (aspect 0) when
    ``|det| <= Tolerances.spatial_aspect * prod(row norms)`` for these balanced rows (Hadamard's
    bound). Without the balancing the ratio would change with the unit of length (rows mix
    lengths and squared lengths): the same design in micrometres would look singular everywhere.

    Parameters
    ----------
    gs : GoughStewart
    s : (8,) or (n, 8) float
        Study points.
    tolerances : Tolerances, optional
        Default: the design's own ``gs.tolerances``.

    Returns
    -------
    int or (n,) int8

    Raises
    ------
    TypeError
        If ``gs`` is not a GoughStewart or ``tolerances`` not a Tolerances.
    InputError
        On wrong shapes, non-finite entries or ``x = 0``.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.gough_stewart import GoughStewart
    >>> rng = np.random.default_rng(0)
    >>> gs = GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
    >>> aspect(gs, [1, 0, 0, 0, 0, 0, 0, 0]) in (-1, 1)
    True
    """
    return _check_gs(gs).aspects(s, tolerances)


# --------------------------------------------------------------------------- constant orientation

def _exact_rotation(rotation, tolerances):
    """A rotation matrix with exact rational entries and its float value."""
    rot = as_float_array(rotation, "rotation", allow_batch=True)
    if rot.shape == (4,):
        if not np.any(rot != 0):
            raise InputError("rotation must be a non-zero quaternion, got (0, 0, 0, 0)")
        q = [sp.Rational(float(v)) for v in rot]
        R = sp.Matrix(3, 3, list(np.ravel(_quaternion_rotation_exact(q))))
        return R, matrix_from_quaternion(rot)
    if rot.shape != (3, 3):
        raise InputError(f"rotation must be a (3, 3) rotation matrix or a (4,) quaternion, got shape {rot.shape}")
    tol = tolerances.rotation_matrix
    if np.any(np.abs(rot) > 1.0 + tol):                 # before R^T R, which could overflow
        raise InputError(f"rotation must be a rotation matrix (orthogonal, det +1, to "
                         f"Tolerances.rotation_matrix = {tol:g}), got an entry {float(np.abs(rot).max()):.3g} "
                         "(a rotation's entries lie in [-1, 1])")
    err = float(np.abs(rot.T @ rot - np.eye(3)).max())
    if err > tol or abs(np.linalg.det(rot) - 1.0) > tol:
        raise InputError(f"rotation must be a rotation matrix (orthogonal, det +1, to "
                         f"Tolerances.rotation_matrix = {tol:g}), got |R^T R - I| = {err:.3g}, "
                         f"det = {np.linalg.det(rot):.6g}")
    return sp.Matrix(3, 3, [sp.Rational(float(v)) for v in rot.ravel()]), rot


def _quaternion_rotation_exact(q):
    n = sum(w * w for w in q)
    return [[v / n for v in r] for r in rotation_entries(*q)]


class ConstantOrientationSingularity:
    """The singularity locus of a Gough-Stewart platform at one fixed orientation.

    Made by :func:`constant_orientation_singularity`.

    Attributes
    ----------
    gs : GoughStewart
    rotation : (3, 3) float
        The fixed orientation.
    polynomial : sympy expression
        ``det`` of the rows ``(s_i, a_i x s_i)``, ``s_i = t + R b_i - a_i``, with exact rational
        coefficients, in the position ``t = (x, y, z)`` of the platform frame's origin.
    variables : tuple of 3 sympy.Symbol
        ``(x, y, z)`` (real symbols).
    degree : int
        Its total degree (3 for a general 6-6 platform).

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.gough_stewart import GoughStewart
    >>> rng = np.random.default_rng(0)
    >>> gs = GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
    >>> locus = constant_orientation_singularity(gs, np.eye(3))
    >>> locus.degree
    3
    """

    def __init__(self, gs: GoughStewart, rotation: npt.ArrayLike, polynomial: Any, variables: Any) -> None:
        self.gs = gs
        self.rotation = rotation
        self.polynomial = as_sympy(polynomial, "polynomial")        # a string is refused, never parsed
        self.variables = variables
        self._poly = sp.Poly(self.polynomial, *variables)
        self.degree = int(self._poly.total_degree())
        terms = self._poly.terms()
        self._exponents = np.array([m for m, _ in terms], dtype=np.int64).reshape(-1, 3)
        self._coefficients = np.array([float(c) for _, c in terms], dtype=float)

    def __repr__(self):
        return (f"ConstantOrientationSingularity(degree={self.degree}, terms={len(self._coefficients)}, "
                f"rotation={np.round(self.rotation, 6).tolist()})")

    def value(self, points: npt.ArrayLike) -> Union[float, FloatArray]:
        """The polynomial at positions (float coefficients, float arithmetic).

        Parameters
        ----------
        points : (3,) or (n, 3) float
            Positions ``t`` of the platform frame's origin.

        Returns
        -------
        float or (n,) float
            Equal to ``det`` of :func:`jacobian_matrix` at the pose ``(rotation, t)`` up to
            rounding.

        Raises
        ------
        InputError
            On wrong shapes or non-finite entries.

        Examples
        --------
        >>> import numpy as np
        >>> from imagespace.spatial.gough_stewart import GoughStewart
        >>> from imagespace.spatial.study import study_point
        >>> rng = np.random.default_rng(0)
        >>> gs = GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
        >>> locus = constant_orientation_singularity(gs, np.eye(3))
        >>> t = np.array([0.1, 0.2, 1.0])
        >>> J = jacobian_matrix(gs, study_point(np.eye(3), t))
        >>> bool(np.isclose(locus.value(t), np.linalg.det(J)))
        True
        """
        P = as_float_array(points, "points", last=3)
        with np.errstate(over="ignore", invalid="ignore"):
            pw = np.prod(P[..., None, :] ** self._exponents, axis=-1)      # (..., terms)
            out = pw @ self._coefficients
        if not np.all(np.isfinite(out)):
            raise InputError(f"points is too large: the polynomial of degree {self.degree} is outside the "
                             "float range (about 1.8e308) there; expected positions of the size of the design")
        return float(out) if np.ndim(out) == 0 else out

    def __call__(self, points):
        return self.value(points)


def constant_orientation_singularity(gs: GoughStewart, rotation: npt.ArrayLike,
                                     tolerances: Optional[Tolerances] = None
                                     ) -> ConstantOrientationSingularity:
    """The constant-orientation singularity locus: ``det J = 0`` as a polynomial in ``(x, y, z)``.

    For the fixed orientation ``R`` the rows ``(s_i, a_i x s_i)`` of :func:`jacobian_matrix`
    with ``s_i = t + R b_i - a_i`` are linear in the position ``t = (x, y, z)``; their
    determinant is computed exactly over ``QQ[x, y, z]`` (fraction-free elimination) from the
    anchors and the rotation as their exact binary rationals (a quaternion gives an exactly
    orthogonal rational ``R``). For a general 6-6 platform the degree is 3 (Mayer St-Onge &
    Gosselin 2000).

    Parameters
    ----------
    gs : GoughStewart
    rotation : (3, 3) float or (4,) float
        A rotation matrix (orthogonal to ``Tolerances.rotation_matrix``) or a non-zero
        quaternion ``(w, x, y, z)``.
    tolerances : Tolerances, optional
        Default: ``gs.tolerances``.

    Returns
    -------
    ConstantOrientationSingularity

    Raises
    ------
    TypeError
        If ``gs`` is not a GoughStewart.
    InputError
        ``rotation`` of a wrong shape, non-finite, not a rotation, or the zero quaternion.
    DegenerateDesignError
        If the determinant vanishes identically: the platform is singular at every position with
        this orientation (an architecture singularity).

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.gough_stewart import GoughStewart
    >>> rng = np.random.default_rng(0)
    >>> gs = GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
    >>> locus = constant_orientation_singularity(gs, [1.0, 0.0, 0.0, 0.0])
    >>> locus.variables, locus.degree
    ((x, y, z), 3)
    """
    from sympy.polys.matrices import DomainMatrix

    gs = _check_gs(gs)
    tols = gs.tolerances if tolerances is None else as_tolerances(tolerances)
    R, R_float = _exact_rotation(rotation, tols)
    x, y, z = variables = sp.symbols("x y z", real=True)
    t = sp.Matrix([x, y, z])
    rows = []
    for a_f, b_f in zip(gs.base_points, gs.platform_points):
        a = sp.Matrix([sp.Rational(float(v)) for v in a_f])
        b = sp.Matrix([sp.Rational(float(v)) for v in b_f])
        s = t + R * b - a
        rows.append(list(s) + list(a.cross(s)))
    ring = sp.QQ[x, y, z]
    det = DomainMatrix.from_Matrix(sp.Matrix(rows)).convert_to(ring).det()
    poly = ring.to_sympy(det)
    if poly == 0:
        raise DegenerateDesignError(
            "the line-coordinate Jacobian is singular at every position for this orientation "
            f"(rotation {np.round(R_float, 6).tolist()}): the design is architecture-singular there; "
            "expected a design whose determinant is not identically zero")
    return ConstantOrientationSingularity(gs, np.array(R_float, dtype=float), sp.expand(poly), variables)
