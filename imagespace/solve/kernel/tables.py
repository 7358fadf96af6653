"""The per-design input of the generic kernel (:class:`DesignTables`, derived once per design by
:func:`design_tables`) and the quadric coefficients of one joint vector from them
(:func:`design_row`, with rigorous error bounds)."""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ..._validate import as_sympy
from ...core._numba import njit
from ...core.bounded_trig import cos_sin_bounded

#: Monomials in ``(q, cos q, sin q)`` a leg's quadric coefficients may use (a leg needing more goes
#: to the numpy path).
MAX_MONOMIALS = 12
_U = 2.0**-53                    # unit roundoff
_GAMMA_SUM = (MAX_MONOMIALS + 4) * _U / (1 - (MAX_MONOMIALS + 4) * _U)  # a sum of rounded products
_INFLATE = 1.0 + 2.0**-40        # covers the rounding of the bound arithmetic itself
_TINY = 2.0**-500                # covers every underflow (each below 2**-1074 per operation); not
                                 # smaller: a product of two such floors must not underflow (slow)


class DesignTables:
    """The per-design input of the generic kernel: each leg's quadric coefficients (and their
    derivatives in the joint value) as polynomials in the features ``q, cos q, sin q``.

    Attributes
    ----------
    expo : (3, MAX_MONOMIALS, 3) int64
        Exponents of ``(q, cos q, sin q)`` of each leg's monomials.
    coef : (3, MAX_MONOMIALS, 16) float
        Constant factor of each monomial in the 8 quadric coefficients ``c, a0, a1, b0, b1, k0,
        k1, k2`` and their 8 derivatives in ``q``, each rounded once from its exact value.
    cerr : (3, MAX_MONOMIALS, 16) float
        Rigorous bounds on that rounding.
    nmono : (3,) int64
        Monomials per leg.
    trig : (3,) int64
        1 where the leg's coefficients use ``cos q``, ``sin q`` (an actuated revolute joint).
    plan : (7,) int64
        :func:`imagespace.core.elimination.plan_array` of the design's elimination plan.
    """

    def __init__(self, expo, coef, cerr, nmono, trig, plan):
        self.expo, self.coef, self.cerr, self.nmono, self.trig, self.plan = (
            expo, coef, cerr, nmono, trig, plan)

    @property
    def degree(self):
        """Degree of the eliminated form ``F`` (6, or 4 when no leg has an RR dyad).

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.solve.kernel import design_tables
        >>> design_tables(isp.examples.choi_3ppr()).degree
        4
        """
        return 4 if self.plan[6] == 1 else 6

    def arrays(self):
        """The arrays in the order the kernel takes them.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.solve.kernel import design_tables
        >>> len(design_tables(isp.examples.general_3rpr()).arrays())
        6
        """
        return self.expo, self.coef, self.cerr, self.nmono, self.trig, self.plan


def _rounded(v):
    """A float of the exact sympy number ``v`` and a rigorous bound on the rounding."""
    if v == 0:
        return 0.0, 0.0
    if v.is_Rational:
        f = float(v)                                   # correctly rounded
        return f, abs(f) * _U + 2.0**-1074
    f = float(sp.N(v, 40))                             # 40 digits, then rounded
    return f, abs(f) * 2 * _U + 2.0**-1000


def design_tables(manipulator):
    """Derive the :class:`DesignTables` of a numeric design, or None where the generic kernel does
    not apply (a PP dyad, a Cramer denominator vanishing identically, coefficients that are not
    polynomial in ``q, cos q, sin q``, too many monomials).

    The derivation is small and done once per design: each leg's dyad quadric with a symbolic
    joint value (eight coefficients and their derivatives), expanded on the monomials of the
    features. Nothing is eliminated symbolically: the kernel eliminates per row.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.kernel import design_tables
    >>> t = design_tables(isp.examples.stigger_husty())
    >>> t.nmono.tolist(), t.trig.tolist(), t.degree
    ([3, 3, 2], [0, 0, 0], 6)
    """
    from ...core.elimination import combine_rows, plan_array

    if "PP" in manipulator.kinds:
        return None
    plan = manipulator.elimination_plan
    # case (a): the Cramer denominator vanishes identically (a property of the design)
    rows = combine_rows(manipulator.quadrics(None), plan)
    E1, E2 = rows[0], rows[1]
    D = [sp.expand(E1.A[0] * E2.B[0] - E2.A[0] * E1.B[0]),
         sp.expand(E1.A[0] * E2.B[1] + E1.A[1] * E2.B[0] - E2.A[0] * E1.B[1] - E2.A[1] * E1.B[0]),
         sp.expand(E1.A[1] * E2.B[1] - E2.A[1] * E1.B[1])]
    if all(v == 0 for v in D):
        return None
    expo = np.zeros((3, MAX_MONOMIALS, 3), dtype=np.int64)
    coef = np.zeros((3, MAX_MONOMIALS, 16))
    cerr = np.zeros((3, MAX_MONOMIALS, 16))
    nmono = np.zeros(3, dtype=np.int64)
    trig = np.zeros(3, dtype=np.int64)
    for i, leg in enumerate(manipulator.legs):
        q = sp.Symbol("q", real=True)
        cs = [sp.expand(as_sympy(c)) for c in leg.dyad(q).coefficients()]
        exprs = cs + [sp.expand(sp.diff(c, q)) for c in cs]
        gens = (q, sp.cos(q), sp.sin(q))
        terms = {}
        for k, e in enumerate(exprs):
            try:
                poly = sp.Poly(e, *gens)
            except sp.PolynomialError:
                return None
            for mono, val in poly.terms():
                if val.free_symbols:
                    return None
                terms.setdefault(mono, {})[k] = val
        if len(terms) > MAX_MONOMIALS:
            return None
        for j, mono in enumerate(sorted(terms)):
            expo[i, j] = mono
            for k, val in terms[mono].items():
                coef[i, j, k], cerr[i, j, k] = _rounded(as_sympy(val))
        nmono[i] = len(terms)
        trig[i] = int(any(mono[1] or mono[2] for mono in terms))
    return DesignTables(expo, coef, cerr, nmono, trig, plan_array(plan))


@njit(cache=True)
def design_row(qr, expo, coef, cerr, nmono, trig, bounded, buf, Ce, acc):
    """The quadric coefficients of one joint vector ``qr`` (3,) from the design tables: ``buf[0:24]``
    the three quadrics, ``buf[24:48]`` their derivatives in the joint values; with ``bounded``
    also rigorous bounds ``Ce`` (24,) on the error of ``buf[0:24]`` (``acc``: 8 floats of scratch).

    The joint values are exact binary rationals; ``cos q``, ``sin q`` come with rigorous bounds
    from :func:`imagespace.core.bounded_trig.cos_sin_bounded` when ``bounded``, else from libm.

    Examples
    --------
    >>> import numpy as np
    >>> import imagespace as isp
    >>> from imagespace.solve.kernel import design_row, design_tables
    >>> m = isp.examples.general_3rpr()
    >>> t = design_tables(m)
    >>> buf, Ce, acc = np.zeros(48), np.zeros(24), np.zeros(8)
    >>> design_row(np.array(m.q_example_float), t.expo, t.coef, t.cerr, t.nmono, t.trig, True, buf, Ce, acc)
    >>> quads = m.quadrics(m.q_example_float)
    >>> bool(np.allclose(buf[:24], [float(v) for qd in quads for v in qd.coefficients()]))
    True
    """
    for i in range(3):
        q = qr[i]
        cq = 0.0
        sq = 0.0
        ec = 0.0
        es = 0.0
        if trig[i] != 0:
            if bounded:
                cq, sq, ec, es = cos_sin_bounded(q)
            else:
                cq = math.cos(q)
                sq = math.sin(q)
        for k in range(8):
            buf[8 * i + k] = 0.0
            buf[24 + 8 * i + k] = 0.0
            Ce[8 * i + k] = 0.0
            acc[k] = 0.0
        for j in range(nmono[i]):
            mv = 1.0
            me = 0.0
            for _ in range(expo[i, j, 0]):
                nv = mv * q
                me = me * abs(q) + _U * abs(nv)
                mv = nv
            for _ in range(expo[i, j, 1]):
                nv = mv * cq
                me = abs(mv) * ec + me * abs(cq) + me * ec + _U * abs(nv)
                mv = nv
            for _ in range(expo[i, j, 2]):
                nv = mv * sq
                me = abs(mv) * es + me * abs(sq) + me * es + _U * abs(nv)
                mv = nv
            for k in range(8):
                v = coef[i, j, k]
                p = mv * v
                buf[8 * i + k] += p
                buf[24 + 8 * i + k] += mv * coef[i, j, 8 + k]
                if bounded:
                    Ce[8 * i + k] += abs(mv) * cerr[i, j, k] + me * abs(v) + me * cerr[i, j, k]
                    acc[k] += abs(p)
        if bounded:
            for k in range(8):
                Ce[8 * i + k] = (Ce[8 * i + k] + _GAMMA_SUM * acc[k]) * _INFLATE + _TINY
