"""Implicit functions for the mesher, with signs proven against rounding.

:class:`PolynomialImplicit` (a sympy expression polynomial in its first two variables: every
singularity surface of a polynomial kind) proves the sign of its value at a point by an a priori
rounding-error bound and, below it, by arb; :class:`FunctionImplicit` wraps numeric callables
(float signs, said so). :func:`surface_implicit` gives a singularity surface's implicit function in
the image or pose chart. Used by :mod:`imagespace.singular.meshing`.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from .._validate import _short, as_float_array, as_sympy_entry
from .._validate import as_tolerances
from ..core.codegen import compile_exprs
from ..exceptions import InputError, InputTypeError
from .charts import UnsupportedShape, joint_table
# the proven signs live in singular.proven_sign (issue [15]); TRIG_ULPS, UNIT_ROUNDOFF and
# ArbBudget stay importable here
from .proven_sign import TRIG_ULPS, UNIT_ROUNDOFF, ArbBudget, ProvenSign  # noqa: F401

__all__ = ["Implicit", "PolynomialImplicit", "FunctionImplicit", "surface_implicit", "TRIG_ULPS"]


# -- implicit functions ---------------------------------------------------------------------------
def _points3(P, name="P"):
    """Points ``(n, 3)`` (or one ``(3,)``) as a float array; NaN allowed (its value is NaN)."""
    if isinstance(P, np.ndarray) and P.dtype == np.float64 and P.ndim == 2 and P.shape[1] == 3:
        return P                                               # the internal hot path
    arr = as_float_array(P, name, last=3, finite=False)
    return np.atleast_2d(arr)


def _axes3(axes):
    """Three 1-d float grid axes."""
    if isinstance(axes, (str, bytes)) or not hasattr(axes, "__len__") or len(axes) != 3:
        raise InputTypeError(f"axes must be three 1-d float arrays (u, v, w), got {_short(axes)}")
    out = []
    for i, a in enumerate(axes):
        arr = as_float_array(a, f"axes[{i}]")
        if arr.ndim != 1:
            raise InputError(f"axes[{i}] must be a 1-d array of grid values, got shape {arr.shape}")
        out.append(arr)
    return out


class Implicit:
    """A scalar function on 3-space that :func:`mesh_implicit` can mesh (its zero set).

    Subclasses implement :meth:`value_and_gradient` and may override :meth:`grid` with a faster
    evaluation on a tensor grid, and :meth:`proven_sign` with signs proven beyond float rounding.

    Attributes
    ----------
    sign_test : str
        How :meth:`proven_sign` knows a sign; the base class: ``"float signs (not proven against
        rounding)"``, the sign of the float value.
    """

    sign_test = "float signs (not proven against rounding)"

    def value_and_gradient(self, P):
        """``(F (n,), grad F (n, 3))`` at points ``P`` ``(n, 3)``.

        Raises
        ------
        NotImplementedError
            Always, on the base class (subclasses implement it).
        """
        raise NotImplementedError

    def value(self, P):
        """``F`` at points ``P`` ``(n, 3)``."""
        return self.value_and_gradient(P)[0]

    def degree_in(self, k):
        """The degree of ``F`` in its ``k``-th variable when ``F`` is a polynomial in it (the others
        fixed), else ``None`` (the base class: unknown). The mesher then locates vertices on grid
        edges along that variable from ``degree + 1`` values per edge.

        Examples
        --------
        >>> import numpy as np
        >>> from imagespace.singular.implicit import FunctionImplicit
        >>> FunctionImplicit(lambda P: (P[:, 0], np.tile([1.0, 0, 0], (len(P), 1)))).degree_in(0) is None
        True
        """
        return None

    def value_bound(self, P):
        """``(F, bound, zero)`` at points ``P`` ``(n, 3)``: a float value whose sign is proven where
        ``|F| > bound`` (or ``zero``: proven to be 0). The base class is the float standard,
        ``bound = 0``; :class:`PolynomialImplicit` gives an a priori rounding-error bound.

        Examples
        --------
        >>> import numpy as np
        >>> from imagespace.singular.implicit import FunctionImplicit
        >>> f = FunctionImplicit(lambda P: (P[:, 0] - 0.5, np.tile([1.0, 0, 0], (len(P), 1))))
        >>> [a.tolist() for a in f.value_bound(np.array([[1.0, 0, 0]]))]
        [[0.5], [0.0], [False]]
        """
        F = self.value(np.atleast_2d(P))
        return F, np.zeros(len(F)), np.zeros(len(F), dtype=bool)

    def proven_sign(self, P, budget=None):
        """Signs of ``F`` at points ``P`` ``(n, 3)`` and whether each is known.

        Returns ``(sign (n,) int8, known (n,) bool)``: ``sign`` in ``{-1, 0, 1}``, meaningful where
        ``known``. The base class knows the sign of every finite non-zero float value (``sign_test
        == "float signs ..."``); :class:`PolynomialImplicit` proves it (see the module docstring).
        ``budget`` (an :class:`ArbBudget`, used by the mesher) caps the number of arb evaluations of one mesh.

        Raises
        ------
        TypeError
            ``P`` not numeric.
        InputError
            ``P`` not of shape ``(3,)`` or ``(n, 3)`` (NaN passes through).

        Examples
        --------
        >>> import numpy as np
        >>> from imagespace.singular.implicit import FunctionImplicit
        >>> f = FunctionImplicit(lambda P: (P[:, 0] - 0.5, np.tile([1.0, 0, 0], (len(P), 1))))
        >>> s, known = f.proven_sign(np.array([[1.0, 0, 0], [0.5, 0, 0]]))
        >>> s.tolist(), known.tolist()
        ([1, 0], [True, False])
        """
        f = self.value(_points3(P))
        known = np.isfinite(f) & (f != 0)
        return np.where(known, np.sign(f), 0).astype(np.int8), known

    def grid(self, axes, block=None):
        """``F`` on the tensor grid of three 1-d ``axes``: ``(len(u), len(v), len(w))`` float.

        ``block(k, n)`` is called after each of ``n`` slabs (progress reporting).

        Raises
        ------
        TypeError
            ``axes`` not three arrays.
        InputError
            An axis not a 1-d array of finite values.
        """
        u, v, w = _axes3(axes)
        out = np.empty((len(u), len(v), len(w)))
        U, V = np.meshgrid(u, v, indexing="ij")
        for k, wk in enumerate(w):
            P = np.stack([U.ravel(), V.ravel(), np.full(U.size, wk)], axis=-1)
            out[:, :, k] = self.value(P).reshape(U.shape)
            if block:
                block(k, len(w))
        return out


class PolynomialImplicit(Implicit):
    """An implicit function given by a sympy expression, polynomial in its first two variables.

    Signs are proven (:meth:`proven_sign`) when the expression is a polynomial in the three
    variables and in ``sin``/``cos`` of rational multiples of them, with constant coefficients
    arb can evaluate (integers, rationals, floats, radicals, ``pi``, ``sin``/``cos`` of
    constants) - every singularity surface of a polynomial kind; otherwise ``sign_test`` says
    ``"float signs (not proven against rounding: <why>)"``.

    Parameters
    ----------
    expr : sympy expression
        Polynomial in ``symbols[0], symbols[1]``; any expression in ``symbols[2]``.
    symbols : three sympy symbols
    tolerances : Tolerances, optional
        Reads ``implicit_coefficient`` (default :data:`imagespace.tolerances.TOLERANCES`).

    Raises
    ------
    TypeError
        ``symbols`` not three sympy symbols; ``expr`` a string, not real, or not an expression;
        ``tolerances`` not a :class:`~imagespace.tolerances.Tolerances`.
    InputError
        ``symbols`` not three distinct symbols; ``expr`` with poles in the chart variables or
        other free symbols.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.singular.implicit import PolynomialImplicit
    >>> u, v, w = sp.symbols("u v w")
    >>> sphere = PolynomialImplicit(u**2 + v**2 + w**2 - 1, (u, v, w))
    >>> sphere.grid(([0.0, 1.0], [0.0], [0.0, 2.0])).tolist()
    [[[-1.0, 3.0]], [[0.0, 4.0]]]
    >>> sphere.sign_test
    'rounding-error bound, arb below it'

    ``(1, 0, 0)`` is on the sphere; the floats nearest to ``(3/5, 4/5, 0)`` are not (arb decides
    what the float value ``0.0`` cannot):

    >>> sphere.value([[0.6, 0.8, 0.0]]).tolist()
    [0.0]
    >>> s, known = sphere.proven_sign([[1.0, 0.0, 0.0], [0.6, 0.8, 0.0]])
    >>> s.tolist(), known.tolist()
    ([0, 1], [True, True])
    """

    def __init__(self, expr, symbols, tolerances=None):
        self.tolerances = as_tolerances(tolerances)
        if isinstance(symbols, (str, bytes)) or not hasattr(symbols, "__iter__"):
            raise InputTypeError(f"symbols must be three sympy symbols, got {type(symbols).__name__} "
                                 f"{_short(symbols)}; strings are never parsed")
        symbols = tuple(symbols)
        if len(symbols) != 3:
            raise InputError(f"symbols must be three sympy symbols, got {len(symbols)}: {_short(symbols)}")
        for i, s_ in enumerate(symbols):
            if not isinstance(s_, sp.Symbol):
                raise InputTypeError(f"symbols[{i}] must be a sympy Symbol, got {type(s_).__name__} {_short(s_)}")
        if len(set(symbols)) != 3:
            raise InputError(f"symbols must be three distinct sympy symbols, got {symbols}")
        expr = as_sympy_entry(expr, "expr")          # a string is refused, never sympified
        if expr.has(sp.I):
            raise InputTypeError(f"expr must be real, got {_short(expr)}")
        chart = set(symbols)
        poles = [a for a in expr.atoms(sp.Pow) if a.base.free_symbols & chart and a.exp.is_negative]
        poles += [a for a in expr.atoms(sp.tan, sp.cot, sp.sec, sp.csc, sp.log) if a.free_symbols & chart]
        if poles:
            raise InputError(f"expr must be continuous in {symbols} (the mesher brackets sign changes, and "
                             f"a pole changes sign too), got {_short(poles[0])} in it; clear the denominators")
        extra = expr.free_symbols - set(symbols)
        if extra:
            raise InputError(f"expr has symbols {sorted(map(str, extra))} besides {symbols}")
        self._expr, self._expr_factory, self.symbols = expr, None, symbols
        self._signs = None
        self._lambdified = None
        self._sign_evaluator()          # the monomial table: values, gradients and proven signs

    @classmethod
    def from_evaluator(cls, evaluator, symbols, expr_factory, tolerances=None):
        """An implicit function built from a ready monomial table (a given-joints singularity surface
        evaluated from its design's table general in the joint values), with ``expr_factory()``
        giving the sympy expression only if someone asks for it. Not public API.

        Examples
        --------
        >>> import sympy as sp
        >>> from imagespace.singular.implicit import PolynomialImplicit
        >>> u, v, w = sp.symbols("u v w")
        >>> f = PolynomialImplicit(u**2 + v**2 + w**2 - 1, (u, v, w))
        >>> g = PolynomialImplicit.from_evaluator(f._sign_evaluator(), (u, v, w), lambda: f.expr)
        >>> g.value([[1.0, 1.0, 1.0]]).tolist(), g.expr == f.expr
        ([2.0], True)
        """
        self = cls.__new__(cls)
        self.tolerances = as_tolerances(tolerances)
        self._expr, self._expr_factory, self.symbols = None, expr_factory, tuple(symbols)
        self._signs = evaluator
        self._sign_note = "rounding-error bound, arb below it"
        self._lambdified = None
        return self

    @property
    def expr(self):
        """The sympy expression (built on first use for a table-made implicit).

        Examples
        --------
        >>> import sympy as sp
        >>> from imagespace.singular.implicit import PolynomialImplicit
        >>> u, v, w = sp.symbols("u v w")
        >>> PolynomialImplicit(u - v * w, (u, v, w)).expr
        u - v*w
        """
        if self._expr is None:
            self._expr = self._expr_factory()
        return self._expr

    @property
    def sign_test(self):
        self._sign_evaluator()
        return self._sign_note

    def _sign_evaluator(self):
        if self._signs is None:
            try:
                self._signs = ProvenSign.of_expr(self.expr, self.symbols, self.tolerances.implicit_coefficient)
                self._sign_note = "rounding-error bound, arb below it"
            except UnsupportedShape as exc:
                self._signs = False
                self._sign_note = f"float signs (not proven against rounding: {exc})"
        return self._signs or None

    def _compiled(self):
        """The lambdified value and gradient, for expressions without a monomial table."""
        if self._lambdified is None:
            expr, symbols = self.expr, self.symbols
            u, v, w = symbols
            vg = compile_exprs([expr] + [sp.diff(expr, s_) for s_ in symbols], symbols)
            val = compile_exprs([expr], symbols)
            try:
                poly = sp.Poly(sp.expand(expr), u, v)
                grid = (poly.monoms(), compile_exprs(poly.coeffs(), [w]))
            except sp.PolynomialError:
                grid = None
            self._lambdified = (vg, val, grid)
        return self._lambdified

    def value_bound(self, P):
        ev = self._sign_evaluator()
        return super().value_bound(P) if ev is None else ev.filter(P)

    def proven_sign(self, P, budget=None):
        P = _points3(P)
        ev = self._sign_evaluator()
        if ev is None:
            return super().proven_sign(P, budget)
        F, bound, zero = ev.filter(P)
        known = zero | (np.abs(F) > bound)
        sign = np.where(zero, 0, np.sign(F)).astype(np.int8)
        for i in np.flatnonzero(~known):
            if budget is not None and not budget.take():
                break
            s = ev.arb_sign(P[i])
            if s is not None:
                sign[i], known[i] = s, True
        return sign, known

    def value_and_gradient(self, P):
        P = _points3(P)
        ev = self._sign_evaluator()
        if ev is not None:
            return ev.value_and_gradient(P)
        out = self._compiled()[0](P[:, 0], P[:, 1], P[:, 2])
        return out[:, 0], out[:, 1:]

    def value(self, P):
        P = _points3(P)
        ev = self._sign_evaluator()
        if ev is not None:
            return ev.value_and_gradient(P, gradient=False)[0]
        return self._compiled()[1](P[:, 0], P[:, 1], P[:, 2])[:, 0]

    def degree_in(self, k):
        """The degree in the ``k``-th chart variable (``None`` where it enters through sin/cos, or
        without a monomial table).

        Examples
        --------
        >>> import sympy as sp
        >>> from imagespace.singular.implicit import PolynomialImplicit
        >>> u, v, w = sp.symbols("u v w")
        >>> f = PolynomialImplicit(u**3 * v + sp.cos(w), (u, v, w))
        >>> f.degree_in(0), f.degree_in(1), f.degree_in(2)
        (3, 1, None)
        """
        ev = self._sign_evaluator()
        if ev is None:
            return None
        return ev.degree_in(k)

    def grid_coefficients(self, w):
        """``(monomials, C)``: the monomials ``(a, b)`` of ``u**a v**b`` and their coefficients at the
        values ``w`` of the third variable (``(len(w), len(monomials))``), or ``None`` when the
        expression is not polynomial in ``u, v`` with coefficients in ``w`` alone.

        Examples
        --------
        >>> import sympy as sp
        >>> from imagespace.singular.implicit import PolynomialImplicit
        >>> u, v, w = sp.symbols("u v w")
        >>> mons, C = PolynomialImplicit(u**2 + w * v - 1, (u, v, w)).grid_coefficients([2.0])
        >>> sorted(zip(mons, C[0].tolist()))
        [((0, 0), -1.0), ((0, 1), 2.0), ((2, 0), 1.0)]
        """
        w = np.atleast_1d(np.asarray(w, dtype=float))
        ev = self._sign_evaluator()
        if ev is not None:
            out = ev.grid_coefficients(w)
            if out is not None:
                return out
        grid = self._compiled()[2]
        if grid is None:
            return None
        return grid[0], grid[1](w)

    def grid(self, axes, block=None):
        u, v, w = _axes3(axes)
        table = self.grid_coefficients(w)
        if table is None:
            return super().grid(axes, block)
        monomials, C = table                                  # (nw, M)
        # Horner in u over Q_a(v, w) = sum_b v**b C_ab(w), slab by slab of u (cache-sized, and no
        # BLAS product: its threads keep spinning and slow down the single-threaded work after it)
        top = max((a for a, _ in monomials), default=0)
        Q = [None] * (top + 1)
        for (a, b), col in zip(monomials, C.T):
            term = np.multiply.outer(v**b, col)
            Q[a] = term if Q[a] is None else Q[a] + term
        out = np.empty((len(u), len(v), len(w)))
        n_blocks = max(1, min(len(u), 16))
        edges = np.linspace(0, len(u), n_blocks + 1).astype(int)
        for k in range(n_blocks):
            o = out[edges[k]:edges[k + 1]]
            uk = u[edges[k]:edges[k + 1], None, None]
            o[...] = 0.0 if Q[top] is None else Q[top]
            for a in range(top - 1, -1, -1):
                o *= uk
                if Q[a] is not None:
                    o += Q[a]
            if block:
                block(k, n_blocks)
        return out


class FunctionImplicit(Implicit):
    """An implicit function given by a Python callable ``f(P) -> (F (n,), grad (n, 3))``.

    Its signs are float signs (``sign_test`` starts with ``"float signs"``): a mesh of it is
    certified only up to the rounding of ``f``.

    Raises
    ------
    TypeError
        ``value_and_gradient`` not callable, or ``value`` neither callable nor ``None``.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.singular.implicit import FunctionImplicit
    >>> f = FunctionImplicit(lambda P: (P[:, 0] - 0.5, np.tile([1.0, 0, 0], (len(P), 1))))
    >>> f.value(np.array([[1.0, 0, 0]])).tolist()
    [0.5]
    """

    def __init__(self, value_and_gradient, value=None):
        if not callable(value_and_gradient):
            raise InputTypeError(f"value_and_gradient must be callable, P (n, 3) -> (F (n,), grad (n, 3)); "
                                 f"got {type(value_and_gradient).__name__} {_short(value_and_gradient)}")
        if value is not None and not callable(value):
            raise InputTypeError(f"value must be callable or None, got {type(value).__name__} {_short(value)}")
        self._vg = value_and_gradient
        self._value = value

    def value_and_gradient(self, P):
        P = _points3(P)
        out = self._vg(P)
        try:
            F, G = out
        except (TypeError, ValueError):
            raise InputError(f"value_and_gradient must return (F (n,), grad (n, 3)), got "
                             f"{type(out).__name__} {_short(out)}") from None
        return self._check_values(F, len(P), "F"), self._check_values(G, len(P), "grad")

    def value(self, P):
        P = _points3(P)
        if self._value is not None:
            return self._check_values(self._value(P), len(P), "value")
        return self.value_and_gradient(P)[0]

    @staticmethod
    def _check_values(values, n, what):
        try:
            arr = np.asarray(values, dtype=float)
        except (TypeError, ValueError):
            raise InputTypeError(f"the function's {what} must be numeric, got {_short(values)}") from None
        want = (n, 3) if what == "grad" else (n,)
        if arr.shape != want:
            raise InputError(f"the function's {what} at {n} points must have shape {want}, got shape {arr.shape}")
        return arr


def surface_implicit(surface, chart="image"):
    """A singularity surface as an :class:`Implicit` in a chart.

    Parameters
    ----------
    surface : SingularitySurface
    chart : {"image", "pose"}
        ``"image"``: ``(x2/x0, x3/x0, x1/x0)``; ``"pose"``: ``(x, y, phi)``.

    Returns
    -------
    Implicit
        A :class:`PolynomialImplicit` for polynomial surfaces (fast grid), else a
        :class:`FunctionImplicit` through the leg inverse kinematics.

    Raises
    ------
    TypeError
        ``surface`` not a :class:`SingularitySurface`, or ``chart`` not a string.
    InputError
        ``chart`` not ``'image'`` or ``'pose'``.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.implicit import surface_implicit
    >>> type(surface_implicit(isp.examples.stigger_husty().singularity_surface(), "pose")).__name__
    'PolynomialImplicit'
    """
    from .surface import SingularitySurface

    if not isinstance(surface, SingularitySurface):
        raise InputTypeError(f"surface must be a SingularitySurface (from PlanarParallel.singularity_surface), "
                             f"got {type(surface).__name__} {_short(surface)}")
    if not isinstance(chart, str):
        raise InputTypeError(f"chart must be 'image' or 'pose', got {type(chart).__name__} {_short(chart)}")
    if chart not in ("image", "pose"):
        raise InputError(f"chart must be 'image' or 'pose', got {chart!r}")
    return surface.cached(("implicit", chart), lambda: _build_implicit(surface, chart))


def _joint_evaluator(table, q, coefficient_rel):
    """The :class:`ProvenSign` table of a design's surface at joint values ``q`` from its
    :class:`~imagespace.singular.charts.JointTable` (no symbolic work), or ``None`` where a
    coefficient at ``q`` is not separated from 0 by arb (the caller derives at ``q`` instead)."""
    try:
        monoms, balls, source = table.at(q)
        names = [f"{mm} at q = {[float(v) for v in q]}" for mm in monoms.tolist()]
        return ProvenSign(table.plain, table.trig, monoms, balls, source, coefficient_rel, names=names)
    except UnsupportedShape:
        return None


def _build_implicit(surface, chart):
    from .pointwise import image_chart_point, pose_chart_point

    to_X = image_chart_point if chart == "image" else pose_chart_point
    if surface.kind == "given-joints":
        m = surface.manipulator
        table = joint_table(m, chart)
        ev = None if table is None else _joint_evaluator(table, surface.q, m.tolerances.implicit_coefficient)
        if ev is not None:
            return PolynomialImplicit.from_evaluator(ev, table.symbols, lambda: surface.chart_expression(chart)[0],
                                                     tolerances=m.tolerances)
    if surface.is_polynomial:
        expr, syms = surface.chart_expression(chart)
        return PolynomialImplicit(expr, syms, tolerances=surface.manipulator.tolerances)

    def vg(P):
        X, dX = to_X(P)
        v, G = surface.value_and_gradient(X)
        return v, np.einsum("ni,nik->nk", G, dX)

    return FunctionImplicit(vg, lambda P: surface(to_X(P)[0]))
