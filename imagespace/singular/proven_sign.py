"""Signs of a polynomial expression at float points, proven against rounding (the engine of
:class:`imagespace.singular.implicit.PolynomialImplicit`).

:class:`ProvenSign` evaluates an expression that is a polynomial in the chart variables and in
``sin``/``cos`` of rational multiples of them as a monomial sum, with an a priori bound on the
rounding error of that very evaluation (Higham, *Accuracy and Stability of Numerical Algorithms*,
2nd ed., SIAM 2002, ch. 3-5); a sign the bound cannot decide is decided in arb ball arithmetic
(python-flint), and a point whose ball still contains 0 stays undecided. :class:`ArbBudget` caps
the arb evaluations of one mesh. Split from :mod:`imagespace.singular.implicit` (issue [15]), which
still re-exports :data:`TRIG_ULPS`, :data:`UNIT_ROUNDOFF` and :class:`ArbBudget`. Not public API
beyond those names.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..core.certify import flint_precision
from .charts import ARB_PRECISION, UnsupportedShape, arb_constant, chart_terms, grid_coefficients

__all__ = ["TRIG_ULPS", "UNIT_ROUNDOFF", "ArbBudget"]

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
_arb_constant = arb_constant

_TRIG_CHECK: dict[str, bool] = {}


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


class ProvenSign:
    """Signs of a sympy expression at float points, proven.

    The expression is written as a polynomial ``sum_i c_i prod_j g_j**a_ij`` in generators ``g_j``:
    the chart variables, and ``sin``/``cos`` of a rational multiple of one variable. In float it is
    evaluated as that monomial sum, whose rounding error is bounded a priori: the coefficients are
    rounded from arb balls (relative error known), each monomial takes at most ``d + G`` roundings,
    the sum of ``N`` terms at most ``N - 1`` (any order), and a trigonometric generator is off by
    at most its argument's rounding plus :data:`TRIG_ULPS` ulp; a generator's error ``e_j`` enters
    through ``prod (|g_j| + e_j)**a - prod |g_j|**a``. Where ``|F|`` is not above the bound (or a
    value is not finite), arb decides at 128 then 512 bits.

    Examples
    --------
    >>> import numpy as np, sympy as sp
    >>> from imagespace.singular.proven_sign import ProvenSign
    >>> u, v, w = sp.symbols("u v w")
    >>> ps = ProvenSign.of_expr(u**2 + v**2 - 1 + sp.cos(w), (u, v, w), 1e-6)
    >>> F, bound, zero = ps.filter(np.array([[2.0, 0.0, 0.0], [1.0, 0.0, np.pi / 2]]))
    >>> (abs(F) > bound).tolist()                 # the second sign is not decided by the float bound
    [True, False]
    >>> ps.arb_sign([1.0, 0.0, np.pi / 2])        # float(pi/2) < pi/2, so cos is positive there
    1
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
            raise UnsupportedShape(f"numpy's sin/cos are not within {TRIG_ULPS} ulp on this machine")
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
                    raise UnsupportedShape(f"coefficient {c} is not finite")
                f = float(ball.mid())
                err = float(abs(flint.arb(f) - ball).upper()) * (1 + 4 * UNIT_ROUNDOFF)
                if f == 0 or not np.isfinite(f) or err > coefficient_rel * abs(f):
                    raise UnsupportedShape(f"coefficient {c} is not well represented in float")
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

    Shared by :mod:`imagespace.singular.implicit` and :mod:`imagespace.singular.meshing` (not public API).

    Examples
    --------
    >>> from imagespace.singular.proven_sign import ArbBudget
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
