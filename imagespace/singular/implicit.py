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
from ..core.certify import flint_precision
from ..core.codegen import compile_exprs
from ..exceptions import InputError
from .charts import ARB_PRECISION, UnsupportedShape, arb_constant, chart_terms, grid_coefficients, joint_table

__all__ = ["Implicit", "PolynomialImplicit", "FunctionImplicit", "surface_implicit", "TRIG_ULPS"]

TRIG_ULPS = 2
"""Assumed accuracy of numpy's float64 ``sin``/``cos``, in units in the last place (measured: at most
0.52 ulp against arb on 140,000 arguments); the rounding-error bound of the pose chart relies on
it, and a sample is checked against arb at first use (else that chart falls back to float signs)."""
_FILTER_SAFETY = 2.0              # the rounding-error bound is doubled (second-order terms, rounding of the bound)
_ARB_PRECISIONS = (ARB_PRECISION, 512)   # bits; arb decides a sign the float filter left open
_ARB_MAX_POINTS = 20000           # arb evaluations per mesh at most; points beyond stay undecided
UNIT_ROUNDOFF = np.finfo(float).eps / 2
"""The unit roundoff ``u = 2**-53`` of float64 (shared with :mod:`imagespace.singular.meshing`)."""
_TINY = 2.0**-1074                # smallest subnormal: absolute error of an underflowing product


def _gamma(k):
    """Higham's ``gamma_k = k u / (1 - k u)``."""
    return k * UNIT_ROUNDOFF / (1 - k * UNIT_ROUNDOFF)



# python-flint's working precision for a block, under imagespace's lock, restored after.
# Correctness never depends on it (arb balls enclose the exact value at any precision); it only
# decides how often a sign can be settled.
_flint_precision = flint_precision


# -- proven signs ---------------------------------------------------------------------------------
_Unsupported = UnsupportedShape          # a shape the rounding-error bound does not cover
_arb_constant = arb_constant

_TRIG_CHECK = {}


def _trig_accuracy_ok():
    """True when numpy's float64 sin and cos are within :data:`TRIG_ULPS` ulp of arb on a fixed sample
    (uniform in [-8, 8], near multiples of pi/2, tiny arguments) and exact at +-0. Cached."""
    if "ok" in _TRIG_CHECK:
        return _TRIG_CHECK["ok"]
    import flint

    rng = np.random.default_rng(20240613)
    x = np.concatenate([rng.uniform(-8, 8, 192), np.pi / 2 * np.arange(-5, 6) + rng.uniform(-1e-9, 1e-9, 11),
                        np.pi / 2 * np.arange(-5, 6), [1e-300, -2e-12, 5e-324, np.pi, -np.pi]])
    zeros = np.array([0.0, -0.0])
    ok = bool(np.all(np.sin(zeros) == 0) and np.all(np.cos(zeros) == 1))
    with _flint_precision(128):
        for fn, name in ((np.sin, "sin"), (np.cos, "cos")):
            y = fn(x)
            for xi, yi in zip(x.tolist(), y.tolist()):
                exact = getattr(flint.arb(xi), name)()
                err = abs(flint.arb(yi) - exact)
                if not err.upper() <= TRIG_ULPS * float(np.spacing(abs(yi))):
                    ok = False
    _TRIG_CHECK["ok"] = ok
    return ok


def _monomial_chain(monos, n_gens, extra=()):
    """``(nodes, parent, gen)``: every monomial of ``monos``, then of ``extra`` (and those on the way)
    as a node that is its parent node times generator ``gen``, node 0 the monomial 1; ``nodes``
    maps exponents to nodes. The nodes of ``monos`` do not depend on ``extra`` (the same products,
    the same rounding)."""
    nodes = {(0,) * n_gens: 0}
    order = [(0,) * n_gens]
    key = lambda m_: (sum(m_), m_)                     # noqa: E731
    for mono in sorted(monos, key=key) + sorted(set(extra) - set(monos), key=key):
        chain = []
        cur = mono
        while cur not in nodes:
            chain.append(cur)
            j = next(i for i, a in enumerate(cur) if a)
            cur = cur[:j] + (cur[j] - 1,) + cur[j + 1:]
        for c in reversed(chain):
            nodes[c] = len(order)
            order.append(c)
    parent = np.zeros(len(order), dtype=np.int64)
    gen = np.zeros(len(order), dtype=np.int64)
    for i, mono in enumerate(order[1:], start=1):
        j = next(k for k, a in enumerate(mono) if a)
        parent[i] = nodes[mono[:j] + (mono[j] - 1,) + mono[j + 1:]]
        gen[i] = j
    return nodes, parent, gen


class _ProvenSign:
    """Signs of a sympy expression at float points, proven.

    The expression is written as a polynomial ``sum_i c_i prod_j g_j**a_ij`` in generators ``g_j``:
    the chart variables, and ``sin``/``cos`` of a rational multiple of one variable. In float it is
    evaluated as that monomial sum, whose rounding error is bounded a priori: the coefficients are
    rounded from arb balls (relative error known), each monomial takes at most ``d + G`` roundings,
    the sum of ``N`` terms at most ``N - 1`` (any order), and a trigonometric generator is off by
    at most its argument's rounding plus :data:`TRIG_ULPS` ulp; a generator's error ``e_j`` enters
    through ``prod (|g_j| + e_j)**a - prod |g_j|**a``. Where ``|F|`` is not above the bound (or a
    value is not finite), arb decides at 128 then 512 bits.
    """

    @classmethod
    def of_expr(cls, expr, symbols, coefficient_rel):
        """The evaluator of a sympy expression in the chart ``symbols`` with constant coefficients."""
        plain, trig, monoms, coeffs = chart_terms(expr, symbols)
        with _flint_precision(_ARB_PRECISIONS[0]):
            balls = [_arb_constant(c) for c in coeffs]
        return cls(plain, trig, monoms, balls, lambda prec: [_arb_constant(c) for c in coeffs], coefficient_rel,
                   names=coeffs)

    def __init__(self, plain, trig, monoms, coefficients, arb_coefficients, coefficient_rel, names=None):
        """From a parsed polynomial (:func:`chart_terms`): ``plain`` the chart-variable indices of the
        plain generators, ``trig`` the trigonometric ones ``(is_sin, variable index, Rational)``,
        ``monoms`` ``(T, G)`` exponents, ``coefficients`` ``(T,)`` arb balls at
        ``_ARB_PRECISIONS[0]`` bits, ``arb_coefficients(prec)`` the balls at another precision;
        ``names`` (for messages) the coefficients as text."""
        if trig and not _trig_accuracy_ok():
            raise _Unsupported(f"numpy's sin/cos are not within {TRIG_ULPS} ulp on this machine")
        self.trig = list(trig)
        self.plain = list(plain)
        self.monoms = np.asarray(monoms, dtype=np.int64).reshape(len(coefficients), len(plain) + len(trig))
        self._arb_source = arb_coefficients
        self._arb_coeffs = {_ARB_PRECISIONS[0]: list(coefficients)}
        names = names if names is not None else [str(c) for c in coefficients]
        cf, rel = [], []
        import flint

        with _flint_precision(_ARB_PRECISIONS[0]):
            for ball, c in zip(coefficients, names):
                if not ball.is_finite():
                    raise _Unsupported(f"coefficient {c} is not finite")
                f = float(ball.mid())
                err = float(abs(flint.arb(f) - ball).upper()) * (1 + 4 * UNIT_ROUNDOFF)
                if f == 0 or not np.isfinite(f) or err > coefficient_rel * abs(f):
                    raise _Unsupported(f"coefficient {c} is not well represented in float")
                cf.append(f)
                rel.append(err / abs(f))
        coeffs = cf
        gens = self.plain + self.trig
        self.coeffs = np.array(cf)
        self.coeff_rel = max(rel, default=0.0)
        d = int(self.monoms.sum(axis=1).max()) if len(coeffs) else 0
        # roundings per monomial: powers and products (<= d + G), the coefficient, the sum of N terms
        self.gamma = _gamma(len(coeffs) + d + len(gens) + 2)
        # every monomial as its parent times one generator (a chain from 1): one product per node
        # every monomial as its parent times one generator (a chain from 1): one product per node;
        # the value's chain (the filter's), and a second one that also holds the monomials of the
        # derivatives along each generator
        nodes, self.parent, self.gen = _monomial_chain(list(map(tuple, self.monoms.tolist())), len(gens))
        self.c_full = np.zeros(len(self.parent))
        for c, mono in zip(self.coeffs, self.monoms.tolist()):
            self.c_full[nodes[tuple(mono)]] = c
        self.terms = np.array([nodes[tuple(m)] for m in self.monoms.tolist()], dtype=np.int64)
        term_monos = list(map(tuple, self.monoms.tolist()))
        wanted = {mono[:j] + (a - 1,) + mono[j + 1:] for mono in term_monos for j, a in enumerate(mono) if a}
        g_nodes, self.g_parent, self.g_gen = _monomial_chain(term_monos, len(gens), extra=wanted)
        self.g_terms = np.array([g_nodes[tuple(m)] for m in self.monoms.tolist()], dtype=np.int64)
        # d/dg_j of the value: sum of c * a_j * (monomial / g_j) over the terms with a_j > 0
        self.dterms = []
        for j in range(len(gens)):
            idx, cj = [], []
            for c, mono in zip(self.coeffs, self.monoms.tolist()):
                if mono[j]:
                    idx.append(g_nodes[tuple(mono[:j] + [mono[j] - 1] + mono[j + 1:])])
                    cj.append(c * mono[j])
            self.dterms.append((np.array(idx, dtype=np.int64), np.array(cj)))
        self.tiny = float(np.abs(self.coeffs).sum()) * (d + len(gens) + 2) * _TINY + _TINY
        n_plain = len(self.plain)
        self.plain_deg = int(self.monoms[:, :n_plain].sum(axis=1).max()) if len(coeffs) else 0
        trig_deg = int(self.monoms[:, n_plain:].sum(axis=1).max()) if len(coeffs) and self.trig else 0
        self.cheap_trig = all(_is_power_of_two(c) for _, _, c in self.trig)
        self.trig_rel = _gamma(2 * TRIG_ULPS * trig_deg)
        self.trig_abs = max(2.0 * trig_deg * (TRIG_ULPS + 1) * float(np.abs(self.coeffs).sum()), 1.0) * _TINY
        self.trig_c = [(float(c), 0.0 if _is_power_of_two(c)
                        else float(abs(sp.Rational(float(c)) - c)) * (1 + 4 * UNIT_ROUNDOFF)) for _, _, c in self.trig]

    # values and gradients ----------------------------------------------------------------------
    def _generator_values(self, P):
        """``(g (n, G), dg (n, G))``: the generators at chart points ``P`` and each one's derivative
        along its own chart variable."""
        vals, ders = [], []
        for k in self.plain:
            vals.append(P[:, k])
            ders.append(np.ones(len(P)))
        for (is_sin, k, _), (cf, _) in zip(self.trig, self.trig_c):
            arg = cf * P[:, k]
            sn, cs = np.sin(arg), np.cos(arg)
            vals.append(sn if is_sin else cs)
            ders.append(cf * cs if is_sin else -cf * sn)
        return np.stack(vals, axis=-1), np.stack(ders, axis=-1)

    @staticmethod
    def _chain(parent, gen, gT, m):
        """The monomial chain ``(K, m)`` at generator values ``gT`` ``(G, m)``."""
        K = len(parent)
        M = np.empty((K, m))
        M[0] = 1.0
        for i in range(1, K):
            np.multiply(M[parent[i]], gT[gen[i]], out=M[i])
        return M

    def value_and_gradient(self, P, gradient=True):
        """``F`` (and its gradient in the chart variables, ``(n, 3)``) at chart points ``P`` ``(n, 3)``,
        evaluated as the monomial sum (the same one the filter bounds)."""
        n = len(P)
        F = np.empty(n)
        G = np.zeros((n, 3)) if gradient else None
        K = len(self.g_parent)
        step = max(1, 2**21 // K)
        var = self.plain + [k for _, k, _ in self.trig]
        for s in range(0, n, step):
            Ps = P[s:s + step]
            m = len(Ps)
            g, dg = self._generator_values(Ps)
            with np.errstate(over="ignore", invalid="ignore"):
                gT = np.ascontiguousarray(g.T)
                f = np.zeros(m)
                tmp = np.empty(m)
                if gradient:
                    M = self._chain(self.g_parent, self.g_gen, gT, m)
                    for c, i in zip(self.coeffs.tolist(), self.g_terms.tolist()):
                        f += np.multiply(M[i], c, out=tmp)
                else:
                    M = self._chain(self.parent, self.gen, gT, m)
                    for i in self.terms:
                        f += np.multiply(M[i], self.c_full[i], out=tmp)
                F[s:s + step] = f
                if gradient:
                    for j, (idx, cj) in enumerate(self.dterms):
                        if len(idx) == 0:
                            continue
                        d = np.zeros(m)
                        for i, c in zip(idx.tolist(), cj.tolist()):
                            d += np.multiply(M[i], c, out=tmp)
                        G[s:s + step, var[j]] += d * dg[:, j]
        return F, G

    def degree_in(self, k):
        """Degree in chart variable ``k`` (``None`` if it enters a trigonometric generator)."""
        if any(kk == k for _, kk, _ in self.trig):
            return None
        if k not in self.plain:
            return 0
        return int(self.monoms[:, self.plain.index(k)].max()) if len(self.monoms) else 0

    def grid_coefficients(self, w):
        """``(monomials, C)`` for a tensor grid (:func:`imagespace.singular.charts.grid_coefficients`)."""
        return grid_coefficients(self.plain, self.trig, self.monoms, self.coeffs, w)

    # float filter ----------------------------------------------------------------------------
    def _generators(self, P):
        """Generator values, their absolute error bounds, and which are exact zeros."""
        vals, errs = [], []
        for k in self.plain:
            vals.append(P[:, k])
            errs.append(np.zeros(len(P)))
        for (is_sin, k, _), (cf, cerr) in zip(self.trig, self.trig_c):
            x = P[:, k]
            arg = cf * x
            # the argument: exact for a power-of-two multiple unless it underflows
            arg_err = cerr * np.abs(x) + np.where(np.abs(arg) < 2.0**-1000, _TINY, 0.0)
            if cerr:
                arg_err = arg_err + UNIT_ROUNDOFF * np.abs(arg)
            g = np.sin(arg) if is_sin else np.cos(arg)
            err = arg_err + TRIG_ULPS * np.spacing(np.abs(g))
            # sin(+-0) = +-0 and cos(+-0) = 1 exactly (C99 Annex F)
            exact0 = (arg == 0) & (arg_err == 0)
            err = np.where(exact0, 0.0, err)
            vals.append(g)
            errs.append(err)
        return np.stack(vals, axis=-1), np.stack(errs, axis=-1)

    def filter(self, P):
        """``(F, bound, zero)``: the float value, a bound on its error, and where it is proven 0."""
        P = np.atleast_2d(np.asarray(P, dtype=float))
        n = len(P)
        F, B = np.empty(n), np.full(n, np.inf)
        zero = np.zeros(n, dtype=bool)
        K = len(self.parent)
        c_abs = np.abs(self.c_full)
        inexact = bool(self.trig)
        step = max(1, 2**21 // K)
        for s in range(0, n, step):
            g, e = self._generators(P[s:s + step])
            gT = np.ascontiguousarray(g.T)
            m = len(g)
            with np.errstate(over="ignore", invalid="ignore"):
                M = np.empty((K, m))
                M[0] = 1.0
                for i in range(1, K):
                    np.multiply(M[self.parent[i]], gT[self.gen[i]], out=M[i])
                # the sums by hand, not as a BLAS product: its threads would keep spinning and slow
                # down the single-threaded numpy work that follows on a busy machine
                f = np.zeros(m)
                A = np.zeros(m)
                tmp = np.empty(m)
                for i in self.terms:
                    f += np.multiply(M[i], self.c_full[i], out=tmp)
                    A += np.abs(tmp, out=tmp)
                rel = self.gamma + self.coeff_rel + 4 * UNIT_ROUNDOFF
                if inexact and self.cheap_trig:
                    # sin/cos of an exact argument: e <= rho |g| + tau with rho = 2 u TRIG_ULPS, so
                    # prod (|g| + e)**a - prod |g|**a <= ((1 + rho)**Dt - 1) prod |g|**a + 2 Dt tau
                    # (|g| <= 1), times |c| and the plain variables' monomial
                    Pm = np.abs(P[s:s + step][:, self.plain]).max(axis=1) if self.plain else np.zeros(m)
                    extra = self.trig_abs * np.maximum(1.0, Pm) ** self.plain_deg
                    bound = ((rel + self.trig_rel) * A + extra) * _FILTER_SAFETY + self.tiny
                else:
                    if inexact:                   # prod (|g| + e)**a: the generators' own errors
                        gi = np.ascontiguousarray((np.abs(g) + e).T)
                        for i in range(1, K):
                            np.multiply(M[self.parent[i]], gi[self.gen[i]], out=M[i])
                        A_inf = np.zeros(m)
                        for i in self.terms:
                            A_inf += np.multiply(M[i], c_abs[i], out=tmp)
                    else:
                        A_inf = A
                    bound = ((A_inf - A) + rel * A_inf) * _FILTER_SAFETY + self.tiny
            F[s:s + step] = f
            B[s:s + step] = np.where(np.isfinite(bound) & np.isfinite(f), bound, np.inf)
            # f == 0 exactly: is every term provably 0 (a factor is an exact zero)?
            z = np.flatnonzero(f == 0)
            if z.size:
                gz = np.ascontiguousarray(((g[z] == 0) & (e[z] == 0)).T)
                Z = np.zeros((K, z.size), dtype=bool)
                for i in range(1, K):
                    np.logical_or(Z[self.parent[i]], gz[self.gen[i]], out=Z[i])
                zero[s + z] = Z[self.terms].all(axis=0)
        return F, B, zero

    # arb -------------------------------------------------------------------------------------
    def arb_sign(self, p):
        """The sign at one point in arb: +1, -1, 0 (the ball is exactly 0) or None (undecided)."""
        import flint

        p = [float(v) for v in p]
        if not all(np.isfinite(p)):
            return None
        for prec in _ARB_PRECISIONS:
            with _flint_precision(prec):
                if prec not in self._arb_coeffs:
                    self._arb_coeffs[prec] = self._arb_source(prec)
                coeffs = self._arb_coeffs[prec]
                gens = [flint.arb(p[k]) for k in self.plain]
                for is_sin, k, c in self.trig:
                    x = flint.arb(flint.fmpq(int(c.p), int(c.q))) * flint.arb(p[k])
                    gens.append(x.sin() if is_sin else x.cos())
                total = flint.arb(0)
                for c, a in zip(coeffs, self.monoms):
                    t = c
                    for g, k in zip(gens, a):
                        if k:
                            t = t * g ** int(k)
                    total = total + t
                if total > 0:
                    return 1
                if total < 0:
                    return -1
                if total.is_zero():
                    return 0
        return None


def _is_power_of_two(c):
    c = abs(sp.Rational(c))
    return c != 0 and (c.p & (c.p - 1)) == 0 and (c.q & (c.q - 1)) == 0


class ArbBudget:
    """Counts the arb evaluations of one mesh (~0.1 ms each) and refuses those beyond ``limit``.

    Shared with :mod:`imagespace.singular.meshing` (not public API).

    Examples
    --------
    >>> from imagespace.singular.implicit import ArbBudget
    >>> b = ArbBudget(1)
    >>> b.take(), b.take(), b.used, b.refused
    (True, False, 1, True)
    """

    def __init__(self, limit=_ARB_MAX_POINTS):
        self.left = limit
        self.used = 0
        self.refused = False

    def take(self):
        if self.left <= 0:
            self.refused = True
            return False
        self.left -= 1
        self.used += 1
        return True





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
        raise TypeError(f"axes must be three 1-d float arrays (u, v, w), got {_short(axes)}")
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
            raise TypeError(f"symbols must be three sympy symbols, got {type(symbols).__name__} "
                            f"{_short(symbols)}; strings are never parsed")
        symbols = tuple(symbols)
        if len(symbols) != 3:
            raise InputError(f"symbols must be three sympy symbols, got {len(symbols)}: {_short(symbols)}")
        for i, s_ in enumerate(symbols):
            if not isinstance(s_, sp.Symbol):
                raise TypeError(f"symbols[{i}] must be a sympy Symbol, got {type(s_).__name__} {_short(s_)}")
        if len(set(symbols)) != 3:
            raise InputError(f"symbols must be three distinct sympy symbols, got {symbols}")
        expr = as_sympy_entry(expr, "expr")          # a string is refused, never sympified
        if expr.has(sp.I):
            raise TypeError(f"expr must be real, got {_short(expr)}")
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
                self._signs = _ProvenSign.of_expr(self.expr, self.symbols, self.tolerances.implicit_coefficient)
                self._sign_note = "rounding-error bound, arb below it"
            except _Unsupported as exc:
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
            raise TypeError(f"value_and_gradient must be callable, P (n, 3) -> (F (n,), grad (n, 3)); "
                            f"got {type(value_and_gradient).__name__} {_short(value_and_gradient)}")
        if value is not None and not callable(value):
            raise TypeError(f"value must be callable or None, got {type(value).__name__} {_short(value)}")
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
            raise TypeError(f"the function's {what} must be numeric, got {_short(values)}") from None
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
        raise TypeError(f"surface must be a SingularitySurface (from PlanarParallel.singularity_surface), "
                        f"got {type(surface).__name__} {_short(surface)}")
    if not isinstance(chart, str):
        raise TypeError(f"chart must be 'image' or 'pose', got {type(chart).__name__} {_short(chart)}")
    if chart not in ("image", "pose"):
        raise InputError(f"chart must be 'image' or 'pose', got {chart!r}")
    return surface.cached(("implicit", chart), lambda: _build_implicit(surface, chart))


def _joint_evaluator(table, q, coefficient_rel):
    """The :class:`_ProvenSign` table of a design's surface at joint values ``q`` from its
    :class:`~imagespace.singular.charts.JointTable` (no symbolic work), or ``None`` where a
    coefficient at ``q`` is not separated from 0 by arb (the caller derives at ``q`` instead)."""
    try:
        monoms, balls, source = table.at(q)
        names = [f"{mm} at q = {[float(v) for v in q]}" for mm in monoms.tolist()]
        return _ProvenSign(table.plain, table.trig, monoms, balls, source, coefficient_rel, names=names)
    except _Unsupported:
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
