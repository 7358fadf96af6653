"""The singularity surface ``det J = 0``, the Jacobians ``Jx``/``Jq`` and fixed-orientation sections.

Three objects, one derivation (:meth:`PlanarParallel.singularity_polynomial`, the determinant of
the Jacobian of the three constraint quadrics and ``x0**2 + x1**2 - 1`` with respect to
``x0..x3``):

* :class:`SingularitySurface` - the quartic as a function on image space, compiled (value and
  gradient, batched), with a label saying what it is: ``"joint-free"`` (every actuated joint only
  changes a radius or an offset, the joint values dropped out), ``"given-joints"`` (the surface
  for fixed joint values) or ``"working-mode"`` (the joint values of the legs whose actuator moves
  a circle's centre or a line were eliminated through that leg's inverse kinematics, one surface
  per choice of branches).
* :class:`PoseJacobians` - seed 003's ``Jx = dF/dx``, ``Jq = -dF/dq``, ``J = Jq^-1 Jx`` in the
  pose coordinates ``(x, y, phi)`` and the classification inverse-kinematic / direct-kinematic /
  both. ``F_i`` is leg ``i``'s quadric at the normalised image point of the pose, which for an RR
  dyad is exactly ``|P_i - A_i|**2 - r_i**2``.
* :class:`ConicSection` - the surface at a fixed orientation ``phi``: a conic in the workspace
  ``(x, y)`` (Sefrioui & Gosselin's quadratic nature), with its type.

Beside it: the chart points and the compiled constraint quadrics in
:mod:`imagespace.singular.pointwise` (:func:`pose_chart_point` and :func:`image_chart_point` are
importable here too), the conic classification in :mod:`imagespace.singular.conics`, the
Jacobians in :mod:`imagespace.singular.jacobians`.

Identity used by the tests: at a pose and joint values that satisfy the constraints,
``S(image_point(pose)) = -16 det Jx(pose)``, because the map
``(x, y, phi) -> (cos(phi/2), sin(phi/2), ...)`` completed by the image point itself has
determinant ``-1/8`` and ``grad(x0**2 + x1**2 - 1) . X = 2``. So the image-space surface is the
direct-kinematic singularity locus, and ``sign S = -sign det Jx``.

References
----------
M. J. D. Hayes, M. L. Husty, P. J. Zsombor-Murray, *Singular configurations of wrist-partitioned
6R serial robots: a geometric perspective for users*, and T. Stigger, M. L. Husty (seed 002), for the
quartic; C. Gosselin, J. Angeles, *Singularity analysis of closed-loop kinematic chains*, IEEE
Trans. Robot. Autom. 6 (1990) 281-290, doi:10.1109/70.56660, for the singularity types;
J. Sefrioui, C. Gosselin, *On the quadratic nature of the singularity curves of planar
three-degree-of-freedom parallel manipulators*, Mech. Mach. Theory 30 (1995) 533-551,
doi:10.1016/0094-114X(94)00054-M.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from .._validate import _short, as_flag, as_float_array, as_scalar, as_sympy_entry, is_symbolic
from ..core.codegen import compile_exprs
from ..core.quadrics import image_symbols
from ..exceptions import InputError, InputTypeError
from ..core.kinematic_map import pose_of
from ..core.mechanism import check_mechanism
from .._html import latex_collected
from .charts import UnsupportedShape, chart_substitution, grid_coefficients, joint_table
from .conics import conic_type, exact_sign, float_sign_fn
from .pointwise import (check_joint_values, constraint_values, image_chart_point, pose_chart_point,
                        require_numeric)

__all__ = ["SingularitySurface", "ConicSection", "singularity_surface", "singularity_surfaces",
           "pose_chart_point", "image_chart_point"]

_KINDS = ("joint-free", "given-joints", "working-mode")


# -- the surface --------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class SingularitySurface:
    """The direct-kinematic singularity surface ``det J = 0`` of one manipulator, ready to evaluate.

    Build it with :meth:`PlanarParallel.singularity_surface` (or :func:`singularity_surface`).

    Attributes
    ----------
    manipulator : PlanarParallel
    polynomial : sympy.Poly
        The quartic in ``(x0, x1, x2, x3)``. For ``kind == "working-mode"`` it still contains the
        joint symbols of the legs in :attr:`eliminated`.
    kind : str
        ``"joint-free"``: the joint values dropped out, one surface for all joint values;
        ``"given-joints"``: the surface at the joint values :attr:`q`;
        ``"working-mode"``: the joint values of the legs :attr:`eliminated` are replaced by those
        legs' inverse kinematics on the branches :attr:`working_modes` (not a polynomial
        surface; its points are where the manipulator *assembled in that working mode* is
        direct-kinematically singular).
    q : tuple or None
        The joint values (``"given-joints"`` only).
    working_modes : tuple or None
        Per leg, the inverse-kinematics branch used, or ``None`` for legs not eliminated.
    eliminated : tuple of int
        The legs whose joint values were eliminated.

    Notes
    -----
    Sign convention: ``S(X)`` is a form of even degree (4), so ``S(-X) = S(X)`` and its sign at a
    pose does not depend on the representative; :attr:`AssemblyMode.aspect` is this sign.
    At poses satisfying the constraints ``S(image_point(pose)) = -16 det Jx(pose)``.

    Examples
    --------
    >>> import imagespace as isp
    >>> S = isp.examples.stigger_husty().singularity_surface()
    >>> S.kind, S.polynomial.total_degree()
    ('joint-free', 4)
    """

    manipulator: object
    polynomial: sp.Poly
    kind: str
    q: tuple | None = None
    working_modes: tuple | None = None
    eliminated: tuple = ()
    _cache: dict = field(default_factory=dict, repr=False)


    def cached(self, key, factory):
        """The artefact stored on this surface under ``key``, built by ``factory()`` on first use
        (compiled functions, the mesher's implicit function, the path checker's prepared quartic).

        Examples
        --------
        >>> import imagespace as isp
        >>> S = isp.singularity_surface(isp.examples.general_3rpr())
        >>> S.cached("answer", lambda: 42), S.cached("answer", lambda: 0)
        (42, 42)
        """
        if key not in self._cache:
            self._cache[key] = factory()
        return self._cache[key]

    def __repr__(self):
        qtext = None if self.q is None else "(" + ", ".join(f"{float(v):.10g}" for v in self.q) + ")"
        extra = {"joint-free": "", "given-joints": f", q={qtext}",
                 "working-mode": f", working_modes={self.working_modes}"}[self.kind]
        return f"SingularitySurface({self.manipulator.name!r}, kind={self.kind!r}{extra})"

    @property
    def is_polynomial(self):
        """True unless joint values were eliminated through the leg inverse kinematics."""
        return self.kind != "working-mode"

    def expr(self):
        """The quartic as a sympy expression in ``x0..x3`` (joint symbols for ``"working-mode"``).

        Examples
        --------
        >>> import imagespace as isp
        >>> S = isp.examples.general_3rpr().singularity_surface()
        >>> sorted(map(str, S.expr().free_symbols))
        ['x0', 'x1', 'x2', 'x3']
        """
        return self.polynomial.as_expr()

    def _args(self):
        x = image_symbols()
        if self.kind == "working-mode":
            return list(x) + [self.manipulator.joint_symbols[i] for i in self.eliminated]
        return list(x)

    def _compiled(self, what):
        if what not in self._cache:
            require_numeric(self.manipulator)
            e = self.expr()
            args = self._args()
            if what == "value":
                self._cache[what] = compile_exprs([e], args)
            else:
                self._cache[what] = compile_exprs([sp.diff(e, a) for a in args], args)
        return self._cache[what]

    def _joints(self, X):
        """Joint values of the eliminated legs at image points ``X``: ``(n, k)``, NaN out of reach."""
        m = self.manipulator
        ok = np.hypot(X[:, 0], X[:, 1]) > 0
        P = np.full((len(X), 3), np.nan)
        if ok.any():
            P[ok] = pose_of(X[ok])
        cols = []
        for i in self.eliminated:
            vals = m.legs[i].actuated_values(np.where(np.isfinite(P), P, 0.0))[:, self.working_modes[i]]
            cols.append(np.where(ok, vals, np.nan))
        return np.stack(cols, axis=-1)

    def _check_X(self, X, name="X"):
        X = as_float_array(X, name, last=4, finite=False)
        return X, X.ndim == 1

    def __call__(self, X):
        """``S`` at image points (any representatives).

        Parameters
        ----------
        X : (4,) or (n, 4) float

        Returns
        -------
        float or (n,) float
            NaN where a working-mode surface is undefined (a leg cannot reach the pose).

        Raises
        ------
        TypeError
            ``X`` not numeric.
        InputError
            ``X`` not ``(4,)`` or ``(n, 4)`` (NaN passes through); a design with free
            symbols.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.stigger_husty()
        >>> S = m.singularity_surface()
        >>> modes = m.direct_kinematics(m.q_example)
        >>> np.sign(S([mm.image_point for mm in modes])).astype(int).tolist() == [mm.aspect for mm in modes]
        True
        """
        X, single = self._check_X(X)
        X2 = np.atleast_2d(X)
        args = list(X2.T)
        if self.kind == "working-mode":
            args += list(self._joints(X2).T)
        v = self._compiled("value")(*args)[:, 0]
        return v[0] if single else v

    def value_and_gradient(self, X):
        """``S`` and its gradient with respect to ``x0..x3`` at image points, batched.

        For a ``"working-mode"`` surface the gradient includes the joint values' dependence on
        the pose (implicit function theorem on the leg's quadric ``Q_i(X, q_i) = 0``:
        ``dq_i/dX = -grad_X Q_i / (dQ_i/dq_i)``).

        Parameters
        ----------
        X : (4,) or (n, 4) float

        Returns
        -------
        value : float or (n,) float
        gradient : (4,) or (n, 4) float

        Raises
        ------
        TypeError
            ``X`` not numeric.
        InputError
            ``X`` not ``(4,)`` or ``(n, 4)`` (NaN passes through); a design with free
            symbols.

        Examples
        --------
        >>> import imagespace as isp
        >>> S = isp.examples.general_3rpr().singularity_surface()
        >>> v, g = S.value_and_gradient([[1.0, 0.2, 0.3, -0.4]])
        >>> bool(abs(g[0] @ [1.0, 0.2, 0.3, -0.4] - 4 * v[0]) < 1e-9 * abs(v[0]))   # Euler: degree 4
        True
        """
        X, single = self._check_X(X)
        X2 = np.atleast_2d(X)
        args = list(X2.T)
        if self.kind == "working-mode":
            qe = self._joints(X2)
            args += list(qe.T)
        v = self._compiled("value")(*args)[:, 0]
        g = self._compiled("gradient")(*args)
        G = g[:, :4].copy()
        if self.kind == "working-mode":
            Q = np.zeros((len(X2), 3))
            for k, i in enumerate(self.eliminated):
                Q[:, i] = qe[:, k]
            _, dQdx, dQdq = constraint_values(self.manipulator, X2, np.nan_to_num(Q))
            with np.errstate(divide="ignore", invalid="ignore"):
                for k, i in enumerate(self.eliminated):
                    G -= (g[:, 4 + k] / dQdq[:, i])[:, None] * dQdx[:, i, :]
            G[~np.isfinite(v)] = np.nan
        return (v[0], G[0]) if single else (v, G)

    def at_poses(self, P, gradient=False):
        """``S`` at the normalised image points of poses (and the gradient in ``(x, y, phi)``).

        Parameters
        ----------
        P : (3,) or (n, 3) float
        gradient : bool

        Returns
        -------
        value : float or (n,) float
        gradient : (3,) or (n, 3) float, only with ``gradient=True``

        Raises
        ------
        TypeError
            ``P`` not numeric, ``gradient`` not a bool.
        InputError
            ``P`` not ``(3,)`` or ``(n, 3)`` (NaN and infinity pass through).

        Examples
        --------
        >>> import imagespace as isp
        >>> S = isp.examples.stigger_husty().singularity_surface()
        >>> float(S.at_poses([0.0, 0.0, 0.3])) == float(S(isp.image_point([0.0, 0.0, 0.3])))
        True
        """
        P = as_float_array(P, "P", last=3, finite=False)
        gradient = as_flag(gradient, "gradient")
        single = P.ndim == 1
        X, dX = pose_chart_point(np.atleast_2d(P))
        if not gradient:
            v = self(X)
            return v[0] if single else v
        v, G = self.value_and_gradient(X)
        Gp = np.einsum("ni,nik->nk", G, dX)
        return (v[0], Gp[0]) if single else (v, Gp)

    def section(self, phi):
        """The surface at a fixed orientation: a conic in the workspace ``(x, y)``.

        Parameters
        ----------
        phi : float or sympy expression
            The orientation (radians). A sympy value (``sp.pi/3``, ``2*sp.atan(sp.Rational(1, 3))``
            ...) gives exact coefficients and an exactly decided type.

        Returns
        -------
        ConicSection

        Raises
        ------
        TypeError
            ``phi`` not one real number or sympy expression (strings, sequences, bools and
            complex numbers are refused; a string is never parsed).
        InputError
            For a ``"working-mode"`` surface (not polynomial in ``x, y``; take the surface for
            given joint values instead); a non-finite ``phi`` or one with free symbols.

        Examples
        --------
        >>> import imagespace as isp, sympy as sp
        >>> S = isp.examples.stigger_husty().singularity_surface()
        >>> S.section(2 * sp.atan(sp.Rational(1, 2))).type
        'hyperbola'
        """
        if self.kind == "working-mode":
            raise InputError("section() needs a polynomial surface; a working-mode surface is not "
                             "a conic at fixed phi - use singularity_surface(q=...) for given joint values")
        return ConicSection.of(self, phi)

    def section_coefficients(self, phi):
        """Conic coefficients ``(A, B, C, D, E, F)`` for many orientations at once (float, batched).

        The fast face of :meth:`section`: the pose-chart expression is compiled once as
        coefficients of ``x**a y**b`` that are functions of ``phi``.

        Parameters
        ----------
        phi : (n,) float

        Returns
        -------
        (n, 6) float

        Raises
        ------
        TypeError
            ``phi`` not numeric.
        InputError
            A surface that is not polynomial; ``phi`` not a number or a 1-d array; a
            section that is not a conic.

        Examples
        --------
        >>> import imagespace as isp
        >>> S = isp.examples.stigger_husty().singularity_surface()
        >>> bool(np.allclose(S.section_coefficients([0.7])[0], S.section(0.7).coefficients))
        True
        """
        if self.kind == "working-mode":
            raise InputError("section_coefficients() needs a polynomial surface; use "
                             "singularity_surface(q=...) for given joint values")
        phi = np.atleast_1d(as_float_array(phi, "phi"))
        if phi.ndim != 1:
            raise InputError(f"phi must be a number or a (n,) array of orientations, got shape {phi.shape}")
        monomials, coefficients = self.cached("section coefficients", self._section_functions)
        C = coefficients(phi)
        order = {(2, 0): 0, (1, 1): 1, (0, 2): 2, (1, 0): 3, (0, 1): 4, (0, 0): 5}
        out = np.zeros((len(phi), 6))
        for k, mono in enumerate(monomials):
            if mono not in order:
                raise InputError(f"the section has the monomial x**{mono[0]} y**{mono[1]}; expected a conic")
            out[:, order[mono]] = C[:, k]
        return out

    def _section_functions(self):
        """The monomials in ``(x, y)`` of the pose-chart quartic and their coefficients as a
        function of ``phi``: for a given-joints surface from the design's table general in the
        joint values (:class:`~imagespace.singular.charts.JointTable`, no derivation per ``q``),
        else compiled from the expression."""
        if self.kind == "given-joints":
            table = joint_table(self.manipulator, "pose")
            try:
                monoms, coeffs = table.float_coefficients(self.q) if table is not None else (None, None)
            except UnsupportedShape:
                monoms = None
            if monoms is not None:
                probe = grid_coefficients(table.plain, table.trig, monoms, coeffs, np.zeros(1))
                if probe is not None:
                    return probe[0], lambda phi: grid_coefficients(table.plain, table.trig, monoms, coeffs, phi)[1]
        expr, (x, y, w) = self.chart_expression("pose")
        poly = sp.Poly(sp.expand(expr), x, y)
        return poly.monoms(), compile_exprs(poly.coeffs(), [w])

    def chart_expression(self, chart):
        """The quartic in chart coordinates as a sympy expression (polynomial kinds).

        Returns ``(expr, (u, v, w))``.

        ``chart="image"``: ``(u, v, w) = (x2/x0, x3/x0, x1/x0)``; ``chart="pose"``:
        ``(u, v, w) = (x, y, phi)`` (polynomial in ``x, y``, trigonometric in ``phi/2``).

        Raises
        ------
        TypeError
            ``chart`` not a string.
        InputError
            A surface that is not polynomial; ``chart`` not ``'image'`` or ``'pose'``.

        Examples
        --------
        >>> import imagespace as isp
        >>> S = isp.examples.general_3rpr().singularity_surface()
        >>> expr, (u, v, w) = S.chart_expression("image")
        >>> sp.Poly(expr, u, v, w).total_degree()
        4
        """
        if not self.is_polynomial:
            raise InputError("chart_expression() needs a polynomial surface (kind 'joint-free' or "
                             f"'given-joints'), got kind {self.kind!r}")
        if not isinstance(chart, str):
            raise InputTypeError(f"chart must be 'image' or 'pose', got {type(chart).__name__} {_short(chart)}")
        if chart not in ("image", "pose"):
            raise InputError(f"chart must be 'image' or 'pose', got {chart!r}")
        return chart_substitution(self.expr(), chart)

    def _repr_latex_(self):
        """The quartic ``S = 0`` collected by powers of ``x0, x1``, for Jupyter.

        Coefficients are rounded to 6 significant digits when the LaTeX would be longer than
        2,000 characters; :func:`imagespace.display.latex_form` gives the same form of any
        polynomial (e.g. :meth:`PlanarParallel.kinematic_polynomial`).

        Examples
        --------
        >>> import imagespace as isp
        >>> text = isp.examples.stigger_husty().singularity_surface()._repr_latex_()
        >>> text.startswith("$") and text.endswith(" = 0$"), "x_{0}^{3}" in text
        (True, True)
        """
        return rf"$\displaystyle {latex_collected(self.polynomial, by=('x0', 'x1'))} = 0$"


class _Deferred:
    """A value built on first read (the polynomial of a given-joints surface: meshing and sections
    of such a surface come from the design's table general in the joint values and never need it)."""

    def __init__(self, factory):
        self.factory = factory


class _PolynomialAttribute:
    """``SingularitySurface.polynomial``: stored as given, or built on first read from a
    :class:`_Deferred`."""

    def __get__(self, obj, owner=None):
        if obj is None:
            return self
        value = obj.__dict__["_polynomial"]
        if isinstance(value, _Deferred):
            value = value.factory()
            obj.__dict__["_polynomial"] = value
        return value

    def __set__(self, obj, value):
        obj.__dict__["_polynomial"] = value


SingularitySurface.polynomial = _PolynomialAttribute()  # type: ignore[assignment]


def _dependent_legs(manipulator):
    """Indices of the legs whose joint value stays in the singularity quartic."""
    free = manipulator.singularity_polynomial().free_symbols
    return tuple(i for i, s in enumerate(manipulator.joint_symbols) if s in free)


def singularity_surface(manipulator, q=None, working_modes=None):
    """The singularity surface of a manipulator, labelled by what it is.

    Parameters
    ----------
    manipulator : PlanarParallel
    q : None or (3,) numbers
        Joint values. Needed (or ``working_modes``) when an actuated joint moves a circle's
        centre or a line; ignored (with the label ``"joint-free"``) when the joint values drop out.
    working_modes : sequence of three ints, optional
        Branches of the leg inverse kinematics through which the joint values are eliminated
        (``"working-mode"`` surface); only the legs whose joint value stays in the quartic use it.

    Returns
    -------
    SingularitySurface

    Raises
    ------
    InputError
        If the surface depends on the joint values and neither ``q`` nor ``working_modes`` is
        given, or both are; if ``q`` (not of shape ``(3,)``, not finite, outside a leg's domain)
        or ``working_modes`` (not three branch indices) is wrong, even where the surface does
        not depend on them.
    TypeError
        ``manipulator`` is not a :class:`PlanarParallel`; ``q`` holds strings, booleans or
        complex numbers; a working mode is not a whole number.

    Examples
    --------
    >>> import imagespace as isp
    >>> m = isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
    ...                         isp.RPR(base=(6, 0), platform=(1, 0)), isp.RPR(base=(2, 5), platform=(0, 1))])
    >>> isp.singularity_surface(m, working_modes=(1, 0, 0))
    SingularitySurface('RRR-RPR-RPR', kind='working-mode', working_modes=(1, None, None))
    """
    check_mechanism(manipulator)
    if q is not None and working_modes is not None:
        raise InputError("give either q (the surface at given joint values) or working_modes (the "
                         "joint values eliminated through the leg inverse kinematics), not both")
    qs = None if q is None else check_joint_values(manipulator, q)
    wm = None if working_modes is None else manipulator.check_working_modes(working_modes)
    P = manipulator.singularity_polynomial()
    joint_syms = manipulator.joint_symbols
    depends = _dependent_legs(manipulator)
    if not depends:
        return SingularitySurface(manipulator, P, "joint-free")
    if qs is not None:
        Pq = _Deferred(lambda: sp.Poly(P.as_expr().xreplace(dict(zip(joint_syms, qs))), *image_symbols()))
        return SingularitySurface(manipulator, Pq, "given-joints", q=tuple(qs))
    if working_modes is None:
        legs = ", ".join(f"legs[{i}] ({manipulator.legs[i].joints}, {manipulator.legs[i].n_branches} branches)"
                         for i in depends)
        raise InputError(f"the singularity surface of {manipulator.name} depends on the joint values of "
                         f"{legs}: pass q=... for the surface at given joint values, or "
                         "working_modes=(b0, b1, b2) to eliminate them through the leg inverse "
                         "kinematics (singularity_surfaces() lists every working mode)")
    used = tuple(int(wm[i]) if i in depends else None for i in range(3))
    return SingularitySurface(manipulator, P, "working-mode", working_modes=used, eliminated=depends)


def singularity_surfaces(manipulator):
    """Every singularity surface in image space alone: one per combination of working modes.

    A single ``"joint-free"`` surface when the joint values drop out.

    Parameters
    ----------
    manipulator : PlanarParallel

    Returns
    -------
    list of SingularitySurface

    Raises
    ------
    TypeError
        ``manipulator`` not a design.

    Examples
    --------
    >>> import imagespace as isp
    >>> len(isp.singularity_surfaces(isp.examples.stigger_husty()))
    1
    """
    check_mechanism(manipulator)
    depends = _dependent_legs(manipulator)
    if not depends:
        return [singularity_surface(manipulator)]
    ranges = [range(manipulator.legs[i].n_branches) if i in depends else [0] for i in range(3)]
    return [singularity_surface(manipulator, working_modes=wm) for wm in itertools.product(*ranges)]


# -- fixed-orientation sections -----------------------------------------------------------------
@dataclass(frozen=True)
class ConicSection:
    """The singularity surface at a fixed orientation: ``A x² + B xy + C y² + D x + E y + F = 0``.

    Attributes
    ----------
    phi : float
    coefficients : tuple of six
        ``(A, B, C, D, E, F)``: sympy numbers when exact, floats otherwise. Computed from the
        representative ``(x0, x1) = (cos(phi/2), sin(phi/2))`` (exact: ``(1, tan(phi/2))``, a
        positive multiple), so the sign of the conic's value is the aspect.
    type : str
        One of ``ellipse, imaginary ellipse, parabola, hyperbola, intersecting lines, parallel
        lines, coincident lines, imaginary parallel lines, point, line, empty, plane``.
    exact : bool
        True when the coefficients are exact and the type was decided by exact sign tests;
        otherwise decided in floating point with the relative tolerance ``Tolerances.singular``.

    Examples
    --------
    >>> import imagespace as isp
    >>> c = isp.examples.general_3rpr().singularity_surface().section(0.4)
    >>> c.type in ("ellipse", "hyperbola", "parabola", "intersecting lines")
    True
    """

    phi: float
    coefficients: tuple
    type: str
    exact: bool

    @classmethod
    def of(cls, surface, phi):
        """The section of ``surface`` (a polynomial :class:`SingularitySurface`) at ``phi``.

        Raises
        ------
        TypeError
            ``surface`` not a :class:`SingularitySurface`; ``phi`` not a number.
        InputError
            A surface that is not polynomial; a section of degree above 2; a non-finite
            ``phi``.

        Examples
        --------
        >>> import imagespace as isp
        >>> S = isp.examples.general_3rpr().singularity_surface()
        >>> isp.ConicSection.of(S, 0.4).type == S.section(0.4).type
        True
        """
        if not isinstance(surface, SingularitySurface):
            raise InputTypeError(f"surface must be a SingularitySurface, got {type(surface).__name__} {_short(surface)}")
        if not surface.is_polynomial:
            raise InputError("surface must be polynomial (kind 'joint-free' or 'given-joints') for a conic "
                             "section, got a working-mode surface; use singularity_surface(q=...)")
        (u, v, w) = sp.symbols("u v w", real=True)
        x0, x1, x2, x3 = image_symbols()
        e = surface.expr()
        exact = is_symbolic(phi)
        if exact:
            phi_s = as_sympy_entry(phi, "phi")        # one sympy number; a string is refused, never parsed
            if phi_s.free_symbols:
                raise InputError(f"phi must be a number or an exact sympy number, got {phi!r}")
            half = sp.simplify(sp.tan(phi_s / 2))
            c0, s0 = (sp.Integer(0), sp.Integer(1)) if half in (sp.zoo, sp.oo, -sp.oo) else (sp.Integer(1), half)
        else:
            phi_f = as_scalar(phi, "phi")
            c0, s0 = sp.Float(np.cos(phi_f / 2), 17), sp.Float(np.sin(phi_f / 2), 17)
        sub = {x0: c0, x1: s0, x2: (s0 * u - c0 * v) / 2, x3: (c0 * u + s0 * v) / 2}
        poly = sp.Poly(sp.expand(e.xreplace(sub)), u, v)
        if poly.total_degree() > 2:
            raise InputError(f"the section at phi={phi} has degree {poly.total_degree()} in (x, y); "
                             "expected a conic")
        mons = [(2, 0), (1, 1), (0, 2), (1, 0), (0, 1), (0, 0)]
        co = [poly.coeff_monomial(mm) for mm in mons]
        if exact:
            co = [sp.radsimp(c) for c in co]
            kind = conic_type(co, exact_sign)
            return cls(float(sp.N(phi_s)), tuple(co), kind, True)
        cf = np.array([float(c) for c in co])
        tol = surface.manipulator.tolerances.singular
        kind = conic_type(list(cf), float_sign_fn(cf, tol))
        return cls(phi_f, tuple(float(c) for c in cf), kind, False)

    @property
    def matrix(self):
        """The symmetric 3x3 matrix ``M`` with ``[x, y, 1] M [x, y, 1]^T`` the conic (float)."""
        A, B, C, D, E, F = (float(c) for c in self.coefficients)
        return np.array([[A, B / 2, D / 2], [B / 2, C, E / 2], [D / 2, E / 2, F]])

    def __call__(self, x, y):
        """The conic's value at workspace points (broadcasting); its sign is the aspect.

        Raises
        ------
        TypeError
            ``x`` or ``y`` not numeric.
        InputError
            ``x`` and ``y`` do not broadcast, or are not finite.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.stigger_husty()
        >>> mode = m.direct_kinematics(m.q_example)[0]
        >>> c = m.singularity_surface().section(mode.pose[2])
        >>> int(np.sign(c(mode.pose[0], mode.pose[1]))) == mode.aspect
        True
        """
        A, B, C, D, E, F = (float(c) for c in self.coefficients)
        x, y = as_float_array(x, "x", finite=False), as_float_array(y, "y", finite=False)
        try:
            np.broadcast(x, y)
        except ValueError:
            raise InputError(f"x and y must broadcast to one shape, got shapes {x.shape} and {y.shape}") from None
        return A * x * x + B * x * y + C * y * y + D * x + E * y + F


