"""Paths in image space and their certified singularity checks.

A path is a chain of pieces ``t -> X(t)``, ``t in [0, 1]``, each polynomial in ``t`` in the
homogeneous coordinates (straight segments, polylines, polynomial and rational curves - a rational
curve is the polynomial curve of its numerators, since ``X`` and ``X / d(t)`` are the same point),
or a straight segment in pose space ``(x, y, phi)`` (trigonometric in ``t``).

:func:`check_path` substitutes every polynomial piece into the singularity quartic ``S`` and
decides **exactly** whether the univariate polynomial ``p(t) = S(X(t))`` has a root in ``[0, 1]``:
``S`` is scaled to rational coefficients when it is a constant multiple of a rational form (the
seed-002 quartic is ``sqrt(181)/362`` times one), the endpoints are taken as the exact binary
rationals they are, ``p`` is built in python-flint ``fmpq_poly`` arithmetic, factored over Q, and
the real roots of each factor in ``[0, 1]`` are isolated by Sturm sequences and refined by sign
bisection, all in exact rational arithmetic (no arb ball, no float, nothing that depends on
``flint.ctx.prec``); each root in ``[0, 1]`` is reported with an isolating interval narrower
than ``1e-12`` (float end points rounded outwards) and its multiplicity (odd: the path crosses
the surface; even: it touches it tangentially without crossing). Designs whose quartic is not a
multiple of a rational one are decided by sympy's exact root counting over the algebraic field.
Pose-space segments are decided by interval arithmetic (python-flint ``arb``) with subdivision,
at a working precision of their own set under a module lock; where that cannot decide (a
tangency), the result says so.

Certificates therefore do not depend on python-flint's process-global precision (a user's
``flint.ctx.dps = 30`` or ``ctx.prec = 212``), and calls from several threads at once give the
single-thread answers; the only change this module makes to ``flint.ctx.prec`` is the pose
check's, made under a lock and undone afterwards.

:func:`segments_free` is the batched fast path for straight segments: the Bernstein coefficients
of ``p`` on ``[0, 1]`` are computed in floating point with a rigorous bound on their rounding
error; if all of them are certainly of one sign the segment is free (convex-hull property), if the
two end values are certainly of opposite signs it crosses; the rest (and ``exact=True``) go to the
exact path above.
"""

from __future__ import annotations

import threading
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from fractions import Fraction

import numpy as np
import sympy as sp

from .._validate import as_float_array
from .curves import ImagePath, pose_segment, polyline, polynomial_curve, rational_curve, segment  # noqa: F401
from ..core.exact_roots import ISOLATION_WIDTH, float_down, float_up, fmpq_of, roots_in_unit_interval
from ..core.quadrics import image_symbols
from ..exceptions import InputError, InputTypeError
from .._html import counts_text, dataclass_html, dataclass_items, html_table, summary

__all__ = ["ImagePath", "PathCheck", "Crossing", "check_path", "segments_free", "segment", "polyline",
           "polynomial_curve", "rational_curve", "pose_segment"]

# Every root is reported in an interval of the path parameter narrower than this (a promise
# about the output, not a decision threshold: isolation is exact whatever the width).
# Working precision (bits) of the arb interval arithmetic for pose-space segments. arb enclosures
# are valid at every precision; this only sets their width, hence how soon a sign is decided.
# If a pose piece is left undecided at _POSE_PREC it is recomputed once at _POSE_PREC_RETRY
# (a genuine tangency stays undecided at any precision and is reported uncertified).
_POSE_PREC = 128
_POSE_PREC_RETRY = 512
# python-flint's working precision (flint.ctx.prec) is one process-global setting, not local to
# a thread; every change of it made here happens under this lock (see _arb_precision).
_FLINT_PREC_LOCK = threading.Lock()
# Prepared quartics by polynomial: a PlanarParallel builds a new SingularitySurface per call.
_PREPARED: dict[sp.Poly, _Quartic] = {}
_PREPARED_MAX = 64


# -- the exact decision ----------------------------------------------------------------------------
@dataclass(frozen=True)
class _Quartic:
    """The singularity quartic prepared for paths: rational coefficients when possible."""

    poly: sp.Poly                     # in x0..x3, rational when `rational`
    rational: bool
    monomials: tuple                  # exponent tuples
    coeffs_q: tuple                   # Fractions (rational case)
    coeffs_f: np.ndarray              # floats
    surface: object


def _prepare(target):
    from ..core.mechanism import Mechanism
    from ..singular.surface import SingularitySurface, singularity_surface

    if isinstance(target, Mechanism):
        return target.cached("paths: prepared quartic", lambda: _prepare(singularity_surface(target)))
    if isinstance(target, SingularitySurface):
        S = target
    else:
        raise InputTypeError(f"target must be a PlanarParallel or a SingularitySurface, got {type(target).__name__}")
    if not S.is_polynomial:
        raise InputError("path checks need a polynomial surface; use singularity_surface(q=...) "
                         "for a design whose surface depends on the joint values")
    return S.cached("paths", lambda: _prepare_surface(S))


def _prepare_surface(S):
    P = S.polynomial
    if P.is_zero:
        raise InputError("the singularity quartic vanishes identically: every pose is singular")
    key = P
    prep = _PREPARED.get(key)
    if prep is None:
        prep = _prepare_polynomial(P)
        if len(_PREPARED) >= _PREPARED_MAX:
            _PREPARED.clear()
        _PREPARED[key] = prep
    return replace(prep, surface=S)


def _exact_ratio(c, lead):
    """``c / lead`` as a sympy Rational when it is one exactly, else None (proved, not guessed:
    a candidate from nsimplify is accepted only if the difference has minimal polynomial ``z``)."""
    r = sp.radsimp(c / lead)
    if r.is_Rational:
        return r
    cand = sp.nsimplify(r)
    if not cand.is_Rational:
        return None
    z = sp.Dummy("z")
    try:
        return cand if sp.minimal_polynomial(r - cand, z) == z else None
    except (NotImplementedError, sp.polys.polyerrors.NotAlgebraic):
        return None


def _prepare_polynomial(P):
    terms = P.terms()
    lead = terms[0][1]
    ratios = [_exact_ratio(c, lead) for _, c in terms]
    rational = all(r is not None for r in ratios)
    if rational:
        den = sp.ilcm(*[r.q for r in ratios])
        scaled = [r * den for r in ratios]
        coeffs = tuple(Fraction(int(c.p), int(c.q)) for c in scaled)
        poly = sp.Poly(dict(zip([m for m, _ in terms], scaled)), *image_symbols())
    else:
        coeffs = ()
        poly = P
        scaled = [c for _, c in terms]
    return _Quartic(poly, rational, tuple(m for m, _ in terms), coeffs,
                    np.array([float(sp.N(c, 20)) for c in scaled]), None)


def _value_and_gradient(quartic, X):
    """The prepared quartic and its gradient at points ``X`` ``(n, 4)`` (floats: diagnostics only)."""
    X = np.asarray(X, dtype=float)
    v = np.zeros(len(X))
    G = np.zeros((len(X), 4))
    for mono, c in zip(quartic.monomials, quartic.coeffs_f):
        v += c * np.prod([X[:, j] ** e for j, e in enumerate(mono)], axis=0)
        for j, e in enumerate(mono):
            if e:
                G[:, j] += c * e * np.prod([X[:, k] ** (f - (k == j)) for k, f in enumerate(mono)], axis=0)
    return v, G


def _piece_polynomial(quartic, C):
    """``S(X(t))`` as an fmpq_poly (rational case) for a piece with coefficient rows ``C``."""
    from flint import fmpq_poly

    coords = [fmpq_poly([fmpq_of(C[k, j]) for k in range(C.shape[0])]) for j in range(4)]
    powers = [[fmpq_poly([1])] for _ in range(4)]
    total = fmpq_poly([0])
    for mono, c in zip(quartic.monomials, quartic.coeffs_q):
        term = fmpq_poly([fmpq_of(c)])
        for j, e in enumerate(mono):
            while len(powers[j]) <= e:
                powers[j].append(powers[j][-1] * coords[j])
            if e:
                term = term * powers[j][e]
        total = total + term
    return total


def _sympy_roots(quartic, C):
    """Algebraic (non-rational) quartics: exact root counting with sympy over the extension field."""
    t = sp.Symbol("t")
    X = [sum(sp.Rational(C[k, j].numerator, C[k, j].denominator) * t**k for k in range(C.shape[0]))
         for j in range(4)]
    e = sp.expand(quartic.poly.as_expr().xreplace(dict(zip(image_symbols(), X))))
    if e == 0:
        return None
    p = sp.Poly(e, t, extension=True)
    width = sp.Rational(Fraction(ISOLATION_WIDTH))
    out = []
    for f, mult in p.sqf_list()[1]:
        n = f.count_roots(0, 1)
        if n == 0:
            continue
        lo, hi = sp.Rational(0), sp.Rational(1)
        # isolate by bisection with exact counts
        stack = [(lo, hi, n)]
        while stack:
            a, b, k = stack.pop()
            if k == 0:
                continue
            if k == 1 and b - a < width:
                out.append((float_down(a), float_up(b), mult))
                continue
            m = (a + b) / 2
            while f.eval(m) == 0:               # split at a non-root, so every count is unambiguous
                m = (m + b) / 2
            k1 = f.count_roots(a, m)
            stack += [(a, m, k1), (m, b, k - k1)]
    out.sort()
    return out


# -- results -------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Crossing:
    """Where a path meets the singularity surface: one root of ``p(t) = S(X(t))`` on one piece.

    Attributes
    ----------
    piece : int
    t : (float, float)
        An interval of the piece's parameter containing the root and no other root of ``p``
        (width < 1e-12; the end points are floats rounded outwards from the exact bracket, a
        point interval for a root that is an exact rational).
    multiplicity : int
        The root's multiplicity in ``p``. Odd (1, 3, ...): ``det J`` changes sign there, the path
        crosses the surface (1 transversally, 3, 5, ... tangentially, still crossing). Even (2,
        4, ...): ``det J`` keeps its sign, the path touches the surface tangentially without
        crossing. ``0``: ``p`` vanishes identically, the whole piece lies in the surface
        (``t = (0, 1)``). A vertex of a polyline on the surface is a root of both pieces and is
        reported for each, with that piece's multiplicity.

    Examples
    --------
    >>> from imagespace.paths.check import Crossing
    >>> Crossing(0, (0.25, 0.25), 1).crosses, Crossing(0, (0.5, 0.5), 2).touches
    (True, True)
    """

    piece: int
    t: tuple
    multiplicity: int

    @property
    def crosses(self):
        """True for a root of odd multiplicity (``det J`` changes sign)."""
        return self.multiplicity % 2 == 1

    @property
    def touches(self):
        """True for a tangential contact without crossing: a root of even multiplicity, or a
        piece lying in the surface (multiplicity 0)."""
        return self.multiplicity % 2 == 0

    def _repr_html_(self):
        """A one-row table for Jupyter.

        Examples
        --------
        >>> from imagespace.paths.check import Crossing
        >>> "multiplicity" in Crossing(0, (0.25, 0.25), 1)._repr_html_()
        True
        """
        return dataclass_html(self)


@dataclass(frozen=True)
class PathCheck:
    """The certified answer of :func:`check_path`.

    The three flags are decided by the multiplicities of the roots of ``p(t) = S(X(t))`` on
    each piece (:class:`Crossing`); a path can both cross (at one root) and touch (at another).

    Attributes
    ----------
    singularity_free : bool
        True only if no point of the path is on the surface: no root at all in any piece
        (``crossings`` is empty). Whenever it is False, ``crosses`` or ``touches`` is True.
    crosses : bool
        True if some root has odd multiplicity: ``det J`` changes sign there and the path passes
        from one aspect to the other. An ordinary transversal crossing is a root of
        multiplicity 1.
    touches : bool
        True only for a tangential contact without crossing: some root of even multiplicity
        (``det J`` vanishes and keeps its sign), or a piece lying in the surface (multiplicity
        0). False for a path whose only contacts are transversal crossings, however many. For an
        uncertified pose piece, an interval where interval arithmetic could decide nothing is
        reported with multiplicity 2 (a possible tangency, not proven: ``certified`` is False).
    crossings : tuple of Crossing
        Every root, in order of piece and parameter.
    domain_exits : tuple of dict
        ``{"piece", "leg", "t", "what"}`` where a leg's joint reaches zero length or a given limit.
    min_distance : float
        Smallest ``|S| / |grad S|`` over a dense sample of the path (normalised image points):
        a float diagnostic, not part of the certificate.
    certified : bool
        True when every piece was decided exactly or by rigorous intervals.
    method : str
    polynomials : tuple
        ``S(X(t))`` of every polynomial piece (sympy Poly in ``t``, the quartic scaled to
        rational coefficients when possible); ``None`` for pose pieces.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.paths.check import check_path, segment
    >>> m = isp.examples.stigger_husty()
    >>> res = check_path(m, segment([1, -0.1, 0, 1.5], [1, 0.1, 0, 1.5]))   # transversal at t = 1/2
    >>> res.singularity_free, res.crosses, res.touches, res.crossings[0].t
    (False, True, False, (0.5, 0.5))
    >>> on = check_path(m, segment([1, 0, 0, 1], [1, 0, 0, 2]))     # along the line x1 = x2 = 0 of S
    >>> on.singularity_free, on.crosses, on.touches, on.crossings[0].multiplicity
    (False, False, True, 0)
    """

    singularity_free: bool
    crosses: bool
    touches: bool
    crossings: tuple
    domain_exits: tuple
    min_distance: float
    certified: bool
    method: str
    polynomials: tuple = field(repr=False, default=())

    def _summary_items(self, quote=True):
        items = dataclass_items(self, skip=("crossings", "domain_exits"), quote=quote)
        mult = counts_text(c.multiplicity for c in self.crossings)
        items[3:3] = [("crossings", f"{len(self.crossings)}" + (f" (multiplicity {mult})" if mult else "")),
                      ("domain_exits", str(len(self.domain_exits)))]
        return items

    def __repr__(self):
        """The flags, how many crossings (by multiplicity) and domain exits, never the polynomials.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.paths.check import check_path, segment
        >>> m = isp.examples.stigger_husty()
        >>> print(check_path(m, segment([1, -0.1, 0, 1.5], [1, 0.1, 0, 1.5])))  # doctest: +ELLIPSIS
        PathCheck(singularity_free=False, crosses=True, touches=False, crossings=1 (multiplicity 1: 1),
                  domain_exits=0, min_distance=..., certified=True, method=...)
        """
        return summary("PathCheck", self._summary_items())

    def _repr_html_(self):
        """The summary as an HTML table, then one row per crossing (at most 20).

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.paths.check import check_path, segment
        >>> m = isp.examples.stigger_husty()
        >>> check_path(m, segment([1, -0.1, 0, 1.5], [1, 0.1, 0, 1.5]))._repr_html_().count("<table")
        2
        """
        out = html_table(self._summary_items(quote=False), title="PathCheck")
        if self.crossings:
            rows = [(c.piece, f"[{c.t[0]:.12g}, {c.t[1]:.12g}]", c.multiplicity,
                     "crosses" if c.crosses else "touches") for c in self.crossings[:20]]
            more = f" (first 20 of {len(self.crossings)})" if len(self.crossings) > 20 else ""
            out += "\n" + html_table(rows, title="crossings" + more, header=("piece", "t", "multiplicity", ""))
        return out


def check_path(target, path, joint_limits=None, manipulator=None):
    """Certify whether a path in image space meets the singularity surface.

    Parameters
    ----------
    target : PlanarParallel or SingularitySurface
        A polynomial surface (``"joint-free"`` or ``"given-joints"``).
    path : ImagePath
    joint_limits : (3, 2) float, optional
        ``(min, max)`` per actuated joint; crossings of a limit are reported in
        ``domain_exits`` (exactly, through the leg's quadric at the limit value).
    manipulator : PlanarParallel, optional
        For domain checks when ``target`` is a surface (default: the surface's manipulator).

    Returns
    -------
    PathCheck
        ``singularity_free`` only if no root at all; ``crosses`` for a root of odd
        multiplicity, ``touches`` for a tangential contact (even multiplicity) only.

    Raises
    ------
    TypeError
        ``target`` not a design or a singularity surface; ``path`` not an
        :class:`ImagePath`.
    InputError
        A surface that is not polynomial or vanishes identically; bad ``joint_limits``.

    Notes
    -----
    Polynomial pieces are decided in exact rational arithmetic and pose pieces by arb intervals
    at their own precision (see the module notes): the answer is the same whatever
    ``flint.ctx.prec`` or ``flint.ctx.dps`` the caller has set, and from any thread.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.paths.check import check_path, segment
    >>> m = isp.examples.stigger_husty()
    >>> a, b = [mm.image_point for mm in m.direct_kinematics(m.q_example)[:2]]
    >>> res = check_path(m, segment(a, b))
    >>> res.crosses, res.touches, res.certified     # modes 1 and 2 have opposite aspects
    (True, False, True)
    """
    if not isinstance(path, ImagePath):
        raise InputTypeError(f"path must be an ImagePath (segment, polyline, ...), got {type(path).__name__}")
    quartic = _prepare(target)
    m = manipulator or quartic.surface.manipulator
    crossings, polys, certified, methods = [], [], True, set()
    t_sym = sp.Symbol("t")
    for k, piece in enumerate(path.pieces):
        if path.kind == "pose":
            roots, ok = _pose_roots(quartic, piece)
            certified &= ok
            methods.add("arb interval subdivision (python-flint)")
            polys.append(None)
        elif quartic.rational:
            p = _piece_polynomial(quartic, piece)
            if p.is_zero():
                roots = [(0.0, 1.0, 0)]
            else:
                roots = roots_in_unit_interval(p)
            polys.append(sp.Poly([sp.Rational(int(c.p), int(c.q)) for c in reversed(p.coeffs())] or [0], t_sym))
            methods.add("exact: fmpq_poly factors over Q, Sturm sequences and sign bisection in rational arithmetic")
        else:
            roots = _sympy_roots(quartic, piece)
            roots = [(0.0, 1.0, 0)] if roots is None else roots
            polys.append(None)
            methods.add("exact: sympy root counting over the algebraic coefficient field")
        for lo, hi, mult in roots:
            crossings.append(Crossing(k, (lo, hi), mult))
    exits = _domain_exits(m, path, joint_limits) if m is not None else []
    X, _ = path.sample(128)
    X = X / np.max(np.abs(X), axis=1)[:, None]           # scale first: representatives may be huge
    X = X / np.hypot(X[:, 0], X[:, 1])[:, None]
    v, G = _value_and_gradient(quartic, X)
    with np.errstate(divide="ignore", invalid="ignore"):
        min_dist = float(np.nanmin(np.where(v == 0, 0.0, np.abs(v) / np.linalg.norm(G, axis=1))))
    on_surface = any(c.multiplicity == 0 for c in crossings)
    free = not crossings
    crosses = any(c.crosses for c in crossings)
    touches = any(c.touches for c in crossings)
    return PathCheck(free, crosses, touches, tuple(crossings), tuple(exits), min_dist, certified,
                     "; ".join(sorted(methods)) + ("; a piece lies on the surface" if on_surface else ""),
                     tuple(polys))


def _domain_exits(m, path, joint_limits):
    """Where a leg's joint value reaches a bound: zero length of a prismatic leg that must stay
    positive, or a user limit; decided exactly from ``Q_i(X(t), bound) = 0``."""
    from flint import fmpq_poly

    out = []
    bounds = []
    for i, leg in enumerate(m.legs):
        # a prismatic actuator whose domain is q >= 0 (an RPR leg's length) ends at zero length
        if not leg.actuated_is_angle and not bool(np.all(leg.joint_values_ok(np.array([-1.0])))):
            bounds.append((i, 0, "zero length"))
    if joint_limits is not None:
        L = as_float_array(joint_limits, "joint_limits")
        if L.shape != (3, 2) or np.any(L[:, 0] > L[:, 1]):
            raise InputError(f"joint_limits must be (3, 2) with min <= max per joint, got {L.tolist()}")
        for i in range(3):
            for j, name in ((0, "lower limit"), (1, "upper limit")):
                if np.isfinite(L[i, j]):
                    bounds.append((i, sp.Rational(Fraction(float(L[i, j]))), name))
    if not bounds or path.kind == "pose":
        return out
    for i, value, what in bounds:
        prep = m.cached(("paths: leg quadric at a bound", i, value),
                        lambda i=i, value=value: _leg_quadric(m.legs[i], value))
        if prep is None:
            continue
        for k, piece in enumerate(path.pieces):
            p = _piece_polynomial(prep, piece)
            if isinstance(p, fmpq_poly) and not p.is_zero():
                for lo, hi, _ in roots_in_unit_interval(p):
                    out.append({"piece": k, "leg": i, "t": (lo, hi), "what": what})
    return out


def _leg_quadric(leg, value):
    """A leg's quadric at a joint value, prepared like the quartic (None if not rational)."""
    Q = sp.Poly(sp.expand(leg.dyad(sp.Integer(value) if value == 0 else value).expr()), *image_symbols())
    if any(not c.is_Rational for c in Q.coeffs()):
        return None
    return _Quartic(Q, True, tuple(Q.monoms()), tuple(Fraction(int(c.p), int(c.q)) for c in Q.coeffs()),
                    np.array([float(c) for c in Q.coeffs()]), None)


@contextmanager
def _arb_precision(bits):
    """Run a block with ``flint.ctx.prec = bits``, under the module lock, restoring the previous
    value afterwards.

    python-flint has one working precision per process (``ctx.workprec`` sets the same global),
    so two threads of this module never change it at once. A thread outside this module may
    still change it meanwhile; that cannot make an answer wrong (arb enclosures are valid at
    every precision, only wider), and its newer setting is then left in place on exit.
    """
    from flint import ctx

    with _FLINT_PREC_LOCK:
        old = ctx.prec
        ctx.prec = bits
        try:
            yield
        finally:
            if ctx.prec == bits:
                ctx.prec = old


def _pose_roots(quartic, piece, max_depth=64):
    """Roots of ``S`` along a pose-space segment by arb interval subdivision.

    On each interval ``T`` the value is enclosed by the mean-value form
    ``S(mid) + S'(T) [-r, r]`` (``S'`` by the chain rule through the pose-to-image map); where
    ``0`` is outside ``S'(T)`` the function is monotone on ``T``, so the end signs decide
    (opposite: exactly one root, refined by bisection to 1e-12; equal: none). An interval
    narrower than 1e-12 where neither can be shown is reported as a possible tangency with
    ``certified = False``.

    The arithmetic runs at a precision of its own (:data:`_POSE_PREC` bits, then once
    :data:`_POSE_PREC_RETRY` if something was left undecided), whatever ``flint.ctx.prec`` the
    caller has set; the decisions are signs of rigorous enclosures and the brackets are exact
    rationals, so the answer is correct at any precision.

    Returns ``(roots, certified)``.
    """
    for bits in (_POSE_PREC, _POSE_PREC_RETRY):
        with _arb_precision(bits):
            roots, ok = _pose_roots_at_current_precision(quartic, piece, max_depth)
        if ok:
            break
    return roots, ok


def _pose_roots_at_current_precision(quartic, piece, max_depth):
    from flint import arb

    p0, p1 = (np.asarray(v, float) for v in piece)
    if quartic.rational:
        coeffs = [arb(fmpq_of(c)) for c in quartic.coeffs_q]
    else:
        # float(sp.N(c, 20)) is within 2**-52 |c| of c (20 correct digits, then one rounding)
        coeffs = [arb(fmpq_of(Fraction(float(c)))) + arb(0, fmpq_of(Fraction(abs(float(c))) / 2**50))
                  for c in quartic.coeffs_f]
    P0 = [arb(fmpq_of(Fraction(float(v)))) for v in p0]
    D = [arb(fmpq_of(Fraction(float(v1)) - Fraction(float(v0)))) for v0, v1 in zip(p0, p1)]

    def value_and_slope(t):
        x, y, phi = (P0[j] + t * D[j] for j in range(3))
        c, sn = (phi / 2).cos(), (phi / 2).sin()
        dc, ds = -sn * D[2] / 2, c * D[2] / 2
        X = (c, sn, (sn * x - c * y) / 2, (c * x + sn * y) / 2)
        dX = (dc, ds, (ds * x + sn * D[0] - dc * y - c * D[1]) / 2,
              (dc * x + c * D[0] + ds * y + sn * D[1]) / 2)
        val, slope = arb(0), arb(0)
        for mono, co in zip(quartic.monomials, coeffs):
            term = co
            for j, e in enumerate(mono):
                if e:
                    term = term * X[j] ** e
            val += term
            for j, e in enumerate(mono):
                if e:
                    part = co * e * X[j] ** (e - 1) * dX[j]
                    for k, f in enumerate(mono):
                        if k != j and f:
                            part = part * X[k] ** f
                    slope += part
        return val, slope

    def sign_at(t):
        v, _ = value_and_slope(arb(fmpq_of(t)))
        if v.is_zero():
            return 0
        return 1 if v > 0 else (-1 if v < 0 else None)

    width = Fraction(ISOLATION_WIDTH)
    roots, ok = [], True
    stack = [(Fraction(0), Fraction(1), 0)]
    while stack:
        a, b, depth = stack.pop()
        mid, rad = (a + b) / 2, (b - a) / 2
        vm, _ = value_and_slope(arb(fmpq_of(mid)))
        _, dT = value_and_slope(arb(fmpq_of(mid), fmpq_of(rad)))
        enclosure = vm + dT * arb(0, fmpq_of(rad))
        if not enclosure.contains(0):
            continue
        if not dT.contains(0):                   # monotone on [a, b]
            sa, sb = sign_at(a), sign_at(b)
            if sa is None or sb is None:
                ok = False
                roots.append((a, b, 1))
            elif sa == 0 or sb == 0:
                r = a if sa == 0 else b
                roots.append((r, r, 1))
            elif sa != sb:
                roots.append(_refine_monotone(sign_at, a, b, sa, width))
            continue
        if b - a < width or depth >= max_depth:
            ok = False                           # a tangency or a root of even multiplicity?
            roots.append((a, b, 2))
            continue
        stack += [(mid, b, depth + 1), (a, mid, depth + 1)]
    roots = sorted({(float_down(a), float_up(b), mult) for a, b, mult in roots})
    return roots, ok


def _refine_monotone(sign_at, a, b, sa, width):
    """Bisect ``[a, b]`` (exact rationals; one simple root of a function monotone there, sign
    ``sa`` at ``a`` and the opposite at ``b``) until narrower than ``width``.

    A split point whose sign the enclosure cannot decide lies within rounding distance of the
    root; then the quarter points are tried (they are decided, being far from the root compared
    with the enclosure's radius), and only if all three fail is the current bracket returned:
    it contains the root in any case."""
    while b - a >= width:
        for c in ((a + b) / 2, (3 * a + b) / 4, (a + 3 * b) / 4):
            sc = sign_at(c)
            if sc is not None:
                break
        else:
            return (a, b, 1)
        if sc == 0:
            return (c, c, 1)
        a, b = (c, b) if sc == sa else (a, c)
    return (a, b, 1)


# -- the batched exclusion test ---------------------------------------------------------------------
_U = 2.0**-53


def segments_free(target, A, B, exact=True):
    """Batched certified check of straight segments ``(1 - t) A + t B``.

    Parameters
    ----------
    target : PlanarParallel or SingularitySurface
    A, B : (n, 4) float
        Endpoint representatives.
    exact : bool
        Send the segments the floating-point test cannot decide to the exact path (default);
        with ``False`` they are reported undecided.

    Returns
    -------
    free : (n,) bool
        Proven free of the surface (``False`` for undecided rows when ``exact=False``).
    decided_by : (n,) str
        ``"bernstein"`` (all Bernstein coefficients of one certain sign, or certain opposite end
        signs), ``"exact"`` or ``"undecided"``.

    Raises
    ------
    TypeError
        ``A`` or ``B`` not numeric.
    InputError
        ``A`` and ``B`` not of one shape ``(4,)`` or ``(n, 4)``, or not finite; a surface
        that is not polynomial.

    Notes
    -----
    Both stages are independent of ``flint.ctx.prec``: the Bernstein stage is numpy floating
    point with rigorous rounding bounds, the exact stage the rational root isolation of
    :func:`check_path`. ``free[i]`` equals ``check_path(target, segment(A[i], B[i]))
    .singularity_free`` for every decided row.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.paths.check import segments_free
    >>> m = isp.examples.stigger_husty()
    >>> modes = m.direct_kinematics(m.q_example)
    >>> A = np.array([modes[0].image_point] * 2)
    >>> B = np.array([modes[1].image_point, isp.image_point(modes[0].pose + [0.1, 0.0, 0.0])])
    >>> free, how = segments_free(m, A, B)
    >>> free.tolist()                      # to another mode (a chord: always singular), to a neighbour
    [False, True]
    """
    quartic = _prepare(target)
    A = as_float_array(A, "A", last=4)
    B = as_float_array(B, "B", last=4)
    A, B = np.atleast_2d(A), np.atleast_2d(B)
    if A.shape != B.shape:
        raise InputError(f"A and B must have the same shape, got {A.shape} and {B.shape}")
    bern, err = _bernstein(quartic, A, B)
    free, decided = _bernstein_decide(bern, err, levels=3)
    how = np.where(decided, "bernstein", "undecided").astype(object)
    if exact and quartic.rational:
        for i in np.flatnonzero(~decided):
            path = segment(A[i], B[i])
            p = _piece_polynomial(quartic, path.pieces[0])
            free[i] = (not p.is_zero()) and not roots_in_unit_interval(p)
            how[i] = "exact"
    elif exact:
        for i in np.flatnonzero(~decided):
            res = _sympy_roots(quartic, segment(A[i], B[i]).pieces[0])
            free[i] = res is not None and not res
            how[i] = "exact"
    return free, how.astype(str)


def _bernstein_decide(bern, err, levels):
    """Decide rows from Bernstein coefficients with error bounds, subdividing undecided rows at
    t = 1/2 up to ``levels`` times. Returns ``(free, decided)``."""
    n = len(bern)
    free = np.zeros(n, dtype=bool)
    decided = np.zeros(n, dtype=bool)
    # pieces: (row index, coefficients (k, 5), error bound (k, 5))
    rows = np.arange(n)
    B, E = bern, err
    for level in range(levels + 1):
        sure_pos = np.all(B > E, axis=1)
        sure_neg = np.all(B < -E, axis=1)
        opp = ((B[:, 0] > E[:, 0]) & (B[:, -1] < -E[:, -1])) | ((B[:, 0] < -E[:, 0]) & (B[:, -1] > E[:, -1]))
        zero_end = (B[:, 0] == 0) & (E[:, 0] == 0) | (B[:, -1] == 0) & (E[:, -1] == 0)
        hit = opp | zero_end
        # a row crosses if any of its pieces does; it is free if all its pieces are one-signed
        crossing_rows = np.unique(rows[hit])
        decided[crossing_rows] = True
        free[crossing_rows] = False
        open_piece = ~(sure_pos | sure_neg | hit) & ~decided[rows]
        if level == levels:
            undecided_rows = np.unique(rows[open_piece])
            break
        # subdivide the open pieces (de Casteljau at 1/2; every average adds a rounding)
        Bo, Eo, ro = B[open_piece], E[open_piece], rows[open_piece]
        left, right = [Bo[:, 0]], [Bo[:, -1]]
        cur = Bo
        for _ in range(4):
            cur = 0.5 * (cur[:, :-1] + cur[:, 1:])
            left.append(cur[:, 0])
            right.append(cur[:, -1])
        L = np.stack(left, axis=1)
        R = np.stack(right[::-1], axis=1)
        grow = np.max(Eo, axis=1) + 8 * _U * np.max(np.abs(Bo), axis=1)
        B = np.concatenate([L, R])
        E = np.repeat(np.concatenate([grow, grow])[:, None], 5, axis=1)
        rows = np.concatenate([ro, ro])
    still = np.zeros(n, dtype=bool)
    still[undecided_rows] = True
    still &= ~decided
    done = ~decided & ~still
    free[done] = True
    decided[done] = True
    return free, decided


def _bernstein(quartic, A, B):
    """Bernstein coefficients ``(n, 5)`` of ``S((1-t)A + tB)`` on ``[0, 1]`` and rigorous bounds
    on their rounding errors.

    Scaled Bernstein coefficients multiply by convolution, and a linear factor
    ``(1-t) a + t b`` has the scaled coefficients ``(a, b)`` - exact inputs. The same products
    with absolute values bound every rounding error by ``gamma_k * |.|`` (Higham, Accuracy and
    Stability of Numerical Algorithms, sec. 3.1), ``k`` the length of the longest chain of
    operations (products, the convolution sums, the coefficient, the sum over monomials, the
    final division by the binomial).
    """
    n = len(A)
    deg = 4
    total = np.zeros((n, deg + 1))
    total_abs = np.zeros((n, deg + 1))
    absA, absB = np.abs(A), np.abs(B)
    for mono, c in zip(quartic.monomials, quartic.coeffs_f):
        prod = np.ones((n, 1))
        prod_abs = np.ones((n, 1))
        for j, e in enumerate(mono):
            for _ in range(e):
                nxt = np.zeros((n, prod.shape[1] + 1))
                nxt[:, :-1] += prod * A[:, j:j + 1]
                nxt[:, 1:] += prod * B[:, j:j + 1]
                nxt_abs = np.zeros_like(nxt)
                nxt_abs[:, :-1] += prod_abs * absA[:, j:j + 1]
                nxt_abs[:, 1:] += prod_abs * absB[:, j:j + 1]
                prod, prod_abs = nxt, nxt_abs
        total += c * prod
        total_abs += abs(c) * prod_abs
    binom = np.array([1.0, 4.0, 6.0, 4.0, 1.0])
    k = 2 * deg + 3 + len(quartic.monomials) + 2
    gamma = k * _U / (1 - k * _U)
    err = (2 * gamma * total_abs + 4 * np.finfo(float).tiny) / binom
    return total / binom, err
