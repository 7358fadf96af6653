"""The singularity quartic in a chart as a table of monomials, and that table general in the joint values.

:func:`chart_substitution` writes a quartic in ``x0..x3`` in the image chart ``(x2/x0, x3/x0,
x1/x0)`` or the pose chart ``(x, y, phi)``; :func:`chart_terms` splits a chart expression into its
generators (the chart variables and ``sin``/``cos`` of rational multiples of them), monomial
exponents and coefficients; :class:`JointTable` keeps those coefficients as polynomials in the
joint values' features, derived once per design, so the surface at new joint values is a handful
of arb evaluations (:func:`arb_constant`) and no symbolic work - the mesher
(:mod:`imagespace.singular.implicit`) and the sections (:mod:`imagespace.singular.surface`) read it.
Not public API.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Optional

import numpy as np
import numpy.typing as npt
import sympy as sp

from .._validate import as_sympy, as_sympy_entry
from ..core.certify import flint_precision
from ..core.quadrics import image_symbols

__all__: list[str] = []

ARB_PRECISION = 128
"""Bits of the coefficient balls a table hands out first (the sign filter's precision)."""


class UnsupportedShape(Exception):
    """The expression has a shape the tables (and the rounding-error bound built on them) do not cover."""


def arb_constant(expr):
    """A sympy constant (no free symbols) as a python-flint arb ball at the current precision.

    Raises
    ------
    UnsupportedShape
        A constant arb cannot evaluate (e.g. ``tan(1)``).

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.singular.charts import arb_constant
    >>> arb_constant(sp.Rational(1, 4) + sp.cos(0)).mid().str()
    '1.25000000000000'
    """
    import flint

    if expr.is_Integer:
        return flint.arb(int(expr))
    if expr.is_Rational:
        return flint.arb(flint.fmpq(int(expr.p), int(expr.q)))
    if expr.is_Float:
        r = sp.Rational(expr)          # the exact binary value
        return flint.arb(flint.fmpq(int(r.p), int(r.q)))
    if expr is sp.pi:
        return flint.arb.pi()
    if expr is sp.E:
        return flint.arb(1).exp()
    if expr.is_Add:
        out = flint.arb(0)
        for a in expr.args:
            out = out + arb_constant(a)
        return out
    if expr.is_Mul:
        out = flint.arb(1)
        for a in expr.args:
            out = out * arb_constant(a)
        return out
    if expr.is_Pow:
        b, e = expr.args
        if e.is_Integer:
            base = arb_constant(b)
            return base ** int(e) if int(e) >= 0 else 1 / base ** (-int(e))
        if e.is_Rational:
            base = arb_constant(b)
            root = base.sqrt() if e.q == 2 else base.root(int(e.q))
            return root ** int(e.p) if e.p >= 0 else 1 / root ** (-int(e.p))
        raise UnsupportedShape(f"power {expr}")
    if isinstance(expr, (sp.sin, sp.cos)):
        x = arb_constant(expr.args[0])
        return x.sin() if isinstance(expr, sp.sin) else x.cos()
    raise UnsupportedShape(f"constant {expr}")


def chart_substitution(expr, chart):
    """An expression in ``x0..x3`` written in chart coordinates, expanded: ``(expr, (u, v, w))``.

    ``chart="image"``: ``(x2/x0, x3/x0, x1/x0)`` (``x0 = 1``); ``chart="pose"``: ``(x, y, phi)``
    at ``(x0, x1) = (cos(phi/2), sin(phi/2))``.

    Examples
    --------
    >>> from imagespace.singular.charts import chart_substitution
    >>> from imagespace.core.quadrics import image_symbols
    >>> x0, x1, x2, x3 = image_symbols()
    >>> chart_substitution(x0**2 * x2 + x1 * x3, "image")[0]
    u + v*w
    """
    u, v, w = sp.symbols("u v w", real=True)
    x0, x1, x2, x3 = image_symbols()
    if chart == "image":
        sub = {x0: 1, x1: w, x2: u, x3: v}
    else:
        c, s = sp.cos(w / 2), sp.sin(w / 2)
        sub = {x0: c, x1: s, x2: (s * u - c * v) / 2, x3: (c * u + s * v) / 2}
    return sp.expand(expr.xreplace(sub)), (u, v, w)


def chart_terms(expr, symbols, params=()):
    """A sympy expression as a polynomial in chart generators: the chart variables ``symbols`` and
    ``sin``/``cos`` of a rational multiple of one of them.

    Not public API. Returns ``(plain, trig, monoms, coefficients)``: the indices of the chart
    variables that occur as plain generators, the trigonometric generators ``(is_sin, variable
    index, Rational multiple)``, the exponents ``(T, G)`` (plain generators first) and the ``T``
    coefficients, sympy expressions free of the chart variables (they may hold ``params``, e.g.
    joint symbols, and functions of them).

    Raises
    ------
    UnsupportedShape
        A shape the rounding-error bound does not cover (a trigonometric argument that is not a
        rational multiple of one chart variable, a coefficient depending on a chart variable ...).

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.singular.charts import chart_terms
    >>> u, v, w = sp.symbols("u v w")
    >>> plain, trig, monoms, coeffs = chart_terms(3 * u**2 * sp.sin(w / 2) - v, (u, v, w))
    >>> plain, trig, monoms.tolist(), coeffs
    ([0, 1], [(True, 2, 1/2)], [[2, 0, 1], [0, 1, 0]], [3, -1])
    """
    expr = sp.expand(as_sympy_entry(expr, "expr"))
    symbols = tuple(symbols)
    chart = set(symbols)
    trig_atoms = sorted((a for a in expr.atoms(sp.sin, sp.cos) if a.free_symbols & chart or
                         (a.free_symbols and not params)), key=sp.default_sort_key)
    trig = []
    for a in trig_atoms:
        coeff, rest = a.args[0].as_coeff_Mul()
        if rest not in symbols or not coeff.is_Rational or coeff == 0:
            raise UnsupportedShape(f"{a}: the argument must be a rational multiple of one chart variable")
        trig.append((isinstance(a, sp.sin), symbols.index(rest), sp.Rational(coeff)))
    dummies = {a: sp.Dummy() for a in trig_atoms}
    free = expr.xreplace(dummies).free_symbols
    plain = [s_ for s_ in symbols if s_ in free]
    gens = plain + trig_atoms
    if not gens:
        gens = [symbols[0]]
        plain = [symbols[0]]
    try:
        poly = sp.Poly(expr, *gens)
    except sp.PolynomialError as exc:
        raise UnsupportedShape(str(exc)) from None
    coeffs = poly.coeffs()
    allowed = set(params)
    if any(c.free_symbols - allowed for c in coeffs):
        raise UnsupportedShape("a coefficient depends on the chart variables")
    monoms = np.array(poly.monoms(), dtype=np.int64).reshape(len(coeffs), len(gens))
    return [symbols.index(s_) for s_ in plain], trig, monoms, coeffs


class JointTable:
    """A design's singularity quartic in one chart, general in the joint values: the chart
    monomials (plain and trigonometric generators, as in :func:`chart_terms`) with coefficients
    that are polynomials in the *joint features* (the joint symbols and ``sin``/``cos`` of them)
    with exact constant coefficients. Derived once per design and chart; :meth:`evaluator` then
    gives the surface at any joint values ``q`` with no symbolic work: the coefficients as arb
    balls at the exact ``q`` (python-flint); the mesher's float table and its rounding-error bound
    are made from them (:mod:`imagespace.singular.implicit`). Not public API.

    Raises
    ------
    UnsupportedShape
        The quartic does not have this shape (the caller then derives per ``q``).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.charts import JointTable
    >>> m = isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
    ...                         isp.RPR(base=(6, 0), platform=(1, 0)), isp.RPR(base=(2, 5), platform=(0, 1))])
    >>> table = JointTable(m, "image")
    >>> monoms, balls, _ = table.at((0.5, 5.0, 5.5))
    >>> monoms.shape[1] == len(table.plain) + len(table.trig), len(balls) == len(monoms)
    (True, True)
    """

    def __init__(self, manipulator, chart):
        self.joint_symbols = tuple(manipulator.joint_symbols)
        expr, self.symbols = chart_substitution(manipulator.singularity_polynomial().as_expr(), chart)
        self.plain, self.trig, self.monoms, coeffs = chart_terms(expr, self.symbols, params=self.joint_symbols)
        joints = set(self.joint_symbols)
        feats = set()
        for c in coeffs:
            feats |= c.free_symbols & joints
            feats |= {a for a in c.atoms(sp.Function) if a.free_symbols & joints}
        if any(f.free_symbols - joints for f in feats):
            raise UnsupportedShape("a joint-dependent coefficient holds other symbols")
        self.features = sorted(feats, key=sp.default_sort_key)
        self.coeff_terms = []                   # per chart coefficient: [(exponents, constant expr)]
        for c in coeffs:
            if self.features:
                try:
                    poly = sp.Poly(c, *self.features)
                except sp.PolynomialError as exc:
                    raise UnsupportedShape(str(exc)) from None
                terms = poly.terms()
            else:
                terms = [((), c)]
            if any(k.free_symbols for _, k in terms):
                raise UnsupportedShape("a coefficient is not polynomial in the joint features")
            self.coeff_terms.append(terms)
        self._constants = {}

    def _balls(self, q, prec):
        """The chart coefficients at the exact joint values ``q`` as arb balls at ``prec`` bits."""
        import flint

        with flint_precision(prec):
            if prec not in self._constants:
                self._constants[prec] = [[arb_constant(k) for _, k in terms] for terms in self.coeff_terms]
            sub = dict(zip(self.joint_symbols, q))
            fb = [arb_constant(f.xreplace(sub)) for f in self.features]
            out = []
            for terms, consts in zip(self.coeff_terms, self._constants[prec]):
                total = flint.arb(0)
                for (mono, _), k in zip(terms, consts):
                    t = k
                    for b, a in zip(fb, mono):
                        if a:
                            t = t * b ** int(a)
                    total = total + t
                out.append(total)
        return out

    def at(self, q):
        """The surface at joint values ``q`` (three exact sympy numbers, or floats taken as exact
        binary rationals): ``(monoms, balls, source)`` - the exponents of the monomials whose
        coefficient is not exactly 0 at ``q`` (the derivation at ``q`` drops those), their
        coefficients as arb balls at ``ARB_PRECISION`` bits, and ``source(prec)`` giving them at
        another precision.

        Raises
        ------
        UnsupportedShape
            Every coefficient is exactly 0 at ``q`` (the surface vanishes identically).

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.singular.charts import JointTable
        >>> m = isp.PlanarParallel([isp.PRR(base=(0, 0), axis=(1, 0), platform=(0, 0), length=3),
        ...                         isp.RPR(base=(6, 0), platform=(1, 0)), isp.RPR(base=(2, 5), platform=(0, 1))])
        >>> monoms, balls, source = JointTable(m, "image").at((1.5, 5.0, 5.5))
        >>> len(monoms) == len(balls) == len(source(256))
        True
        """
        q = tuple(sp.Rational(v) if isinstance(v, float) else as_sympy(v) for v in q)
        balls = self._balls(q, ARB_PRECISION)
        keep = [i for i, b in enumerate(balls) if not b.is_zero()]
        if not keep:
            raise UnsupportedShape("the surface vanishes identically at these joint values")
        return (self.monoms[keep], [balls[i] for i in keep],
                lambda prec: [self._balls(q, prec)[i] for i in keep])

    def float_coefficients(self, q):
        """``(monoms, coefficients)`` at ``q`` in float (the balls' midpoints), for sections.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.singular.charts import JointTable
        >>> m = isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
        ...                         isp.RPR(base=(6, 0), platform=(1, 0)), isp.RPR(base=(2, 5), platform=(0, 1))])
        >>> monoms, c = JointTable(m, "pose").float_coefficients((0.5, 5.0, 5.5))
        >>> len(monoms) == len(c)
        True
        """
        monoms, balls, _ = self.at(q)
        return monoms, np.array([float(b.mid()) for b in balls])


def joint_table(manipulator, chart):
    """The design's :class:`JointTable` for ``chart``, cached on it (``None`` where the quartic does
    not have the table's shape, or the design holds symbols).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.charts import joint_table
    >>> m = isp.examples.general_3rpr()
    >>> joint_table(m, "image") is joint_table(m, "image")
    True
    """
    if not manipulator.is_numeric:
        return None

    def build():
        try:
            return JointTable(manipulator, chart)
        except UnsupportedShape:
            return None
    return manipulator.cached(("singularity joint table", chart), build)


def grid_coefficients(plain: Sequence[int], trig: Sequence[tuple[bool, int, Any]], monoms: Any,
                      coeffs: Sequence[Any], w: npt.ArrayLike
                      ) -> Optional[tuple[list[tuple[int, int]], npt.NDArray[np.float64]]]:
    """A chart table on a tensor grid: ``(monomials, C)`` - the monomials ``(a, b)`` of
    ``u**a v**b`` and their coefficients at the values ``w`` of the third chart variable,
    ``(len(w), len(monomials))`` - or ``None`` when a trigonometric generator depends on ``u`` or
    ``v``.

    Examples
    --------
    >>> import numpy as np, sympy as sp
    >>> from imagespace.singular.charts import chart_terms, grid_coefficients
    >>> u, v, w = sp.symbols("u v w")
    >>> plain, trig, monoms, coeffs = chart_terms(u**2 + sp.cos(w) * v - 1, (u, v, w))
    >>> mons, C = grid_coefficients(plain, trig, monoms, [float(c) for c in coeffs], np.array([0.0]))
    >>> sorted(zip(mons, C[0].tolist()))
    [((0, 0), -1.0), ((0, 1), 1.0), ((2, 0), 1.0)]
    """
    var = list(plain) + [k for _, k, _ in trig]
    if any(k != 2 for _, k, _ in trig):
        return None
    ju = var.index(0) if 0 in plain else None
    jv = var.index(1) if 1 in plain else None
    w = np.asarray(w, dtype=float)
    g = []
    for k in plain:
        g.append(w if k == 2 else np.zeros_like(w))
    for is_sin, _, c in trig:
        arg = float(c) * w
        g.append(np.sin(arg) if is_sin else np.cos(arg))
    rest = [j for j in range(len(var)) if j not in (ju, jv)]
    keys: dict = {}
    cols: list = []
    for c, mono in zip(coeffs, np.asarray(monoms).tolist()):
        key = (mono[ju] if ju is not None else 0, mono[jv] if jv is not None else 0)
        part = np.full(len(w), float(c))
        for j in rest:
            if mono[j]:
                part = part * g[j] ** mono[j]
        if key not in keys:
            keys[key] = len(cols)
            cols.append(part)
        else:
            cols[keys[key]] = cols[keys[key]] + part
    return list(keys), np.stack(cols, axis=-1) if cols else np.zeros((len(w), 0))
