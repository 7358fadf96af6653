r"""Certified counts of the real roots of a binary form on the projective line (python-flint).

The answer to "how many real assembly modes" is a yes/no question per root, so it is decided here
with exact or rigorous interval arithmetic, never with floating point:

* **Rational coefficients** (integers, rationals, and floats taken as the exact binary rationals
  they are): the dehomogenised polynomial goes to python-flint as an ``fmpq_poly``;
  ``complex_roots()`` (FLINT's ``arb_fmpz_poly_complex_roots`` on the square-free factors) returns
  disjoint isolating balls with multiplicities, real roots with an imaginary part exactly zero.
  Exact, multiple roots included.
* **Other exact coefficients** (algebraic numbers such as the seed-002 offset in
  :math:`\mathbb{Q}(\sqrt{181})`, or ``cos(7*pi/18)``): every coefficient is enclosed in an
  ``arb`` ball (sympy evaluates it to the working precision plus guard digits; the ball radius covers
  that error), ``acb_poly.roots()`` isolates the roots in disjoint discs, and a root is **real**
  when the hull of its disc and the conjugate disc (a disc centred on the real axis) meets no
  other disc (then the conjugate root must be itself), **non-real** when its disc misses the
  real axis. The precision doubles (64 -> 1024 bits) until every disc is decided; a multiple root
  with irrational coefficients cannot be isolated this way and is reported as not certified.

The point at infinity ``x0 = 0`` (the half-turn) is a root exactly when the coefficient of
``x1**d`` is zero, which is decided exactly (sympy ``equals``/rational zero test).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from .exceptions import InputError

__all__ = ["RealRootCertificate", "certify_real_roots", "certify_real_roots_batch"]


@dataclass(frozen=True)
class RealRootCertificate:
    """Proven number of distinct real roots of a binary form ``sum f_k x0^(d-k) x1^k``.

    Attributes
    ----------
    certified : bool
        True when every root was decided (the count is proven).
    count : int or None
        Number of distinct real roots on the projective line (``x0 = 0`` included); ``None``
        when not certified.
    intervals : tuple of (float, float)
        For each finite real root, an interval of ``t = x1/x0`` (i.e. ``tan(phi/2)``) that
        contains it and no other root, rounded outwards to floats.
    multiplicities : tuple of int
        Multiplicity of each finite real root (1 where only isolation, not the exact
        multiplicity, was computed: the arb path certifies simple roots only).
    at_infinity : int
        Multiplicity of the root ``x0 = 0`` (0 if none).
    method : str
        How the answer was obtained.
    """

    certified: bool
    count: int | None
    intervals: tuple
    multiplicities: tuple
    at_infinity: int
    method: str

    def contains(self, t):
        """True if the finite real root intervals contain ``t = x1/x0`` (a float).

        Examples
        --------
        >>> from imagespace.certify import certify_real_roots
        >>> certify_real_roots([-1, 0, 1]).contains(1.0)      # x1^2 - x0^2
        True
        """
        return any(lo <= t <= hi for lo, hi in self.intervals)


def _is_zero(c):
    c = sp.sympify(c)
    if c.is_Rational:
        return c == 0
    z = c.equals(0)
    if z is None:
        raise InputError(f"cannot decide whether the coefficient {c} is zero")
    return bool(z)


def _exact_path(coeffs):
    import flint

    poly = flint.fmpq_poly([flint.fmpq(int(c.p), int(c.q)) for c in coeffs])
    intervals, mults = [], []
    for root, mult in poly.complex_roots():
        if root.imag.is_zero():
            lo, hi = root.real.lower(), root.real.upper()
            intervals.append((float(lo) - abs(float(lo)) * 2.3e-16 - 5e-324,
                              float(hi) + abs(float(hi)) * 2.3e-16 + 5e-324))
            mults.append(int(mult))
    return intervals, mults


def _ball(c, prec):
    import flint

    digits = int(prec * 0.30103) + 20
    v = sp.N(c, digits)
    if not v.is_real:
        raise InputError(f"coefficient {c} is not real")
    s = sp.Float(v, digits)
    # the decimal string has |error| < 10^(exponent - digits + 2); enclose it generously
    mag = abs(s)
    rad = sp.Float(10) ** (int(sp.floor(sp.log(mag, 10))) - digits + 5) if mag != 0 else sp.Float(10) ** (-digits)
    return flint.arb(str(s)) + flint.arb(0, str(sp.Float(rad, 5)))


def _arb_path(coeffs):
    import flint

    old = flint.ctx.prec
    try:
        for prec in (64, 128, 256, 512, 1024):
            flint.ctx.prec = prec
            poly = flint.acb_poly([flint.acb(_ball(c, prec)) for c in coeffs])
            try:
                roots = poly.roots()
            except ValueError:
                continue
            discs = [(complex(float(r.real.mid()), float(r.imag.mid())),
                      float(r.real.rad()) + float(r.imag.rad())) for r in roots]
            decided, intervals = True, []
            for i, (c, rad) in enumerate(discs):
                if abs(c.imag) > rad:
                    continue                                   # non-real
                hull = (complex(c.real, 0.0), abs(c.imag) + rad)
                clash = any(abs(hull[0] - c2) <= hull[1] + r2 for j, (c2, r2) in enumerate(discs) if j != i)
                if clash:
                    decided = False
                    break
                intervals.append((c.real - hull[1], c.real + hull[1]))
            if decided:
                return intervals, [1] * len(intervals), prec
        return None, None, prec
    finally:
        flint.ctx.prec = old


def certify_real_roots(form):
    """Certified count of the distinct real roots of a binary form on the projective line.

    Parameters
    ----------
    form : sympy.Poly in (x0, x1), or sequence of exact numbers ``[f_0, ..., f_d]``
        ``f_k`` multiplies ``x0**(d-k) x1**k``. Floats are taken as exact binary rationals.

    Returns
    -------
    RealRootCertificate

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.certify import certify_real_roots
    >>> c = certify_real_roots([0, -2, 0, 1, 0])   # x0 x1 (x1^2 - 2 x0^2): roots 0, +-sqrt 2, infinity
    >>> c.count, c.at_infinity, c.certified
    (4, 1, True)
    >>> certify_real_roots([1, 0, -sp.sqrt(2)]).count   # x0^2 - sqrt(2) x1^2
    2
    """
    if isinstance(form, sp.Poly):
        gens = form.gens
        d = form.total_degree()
        coeffs = [form.coeff_monomial(gens[0] ** (d - k) * gens[1] ** k) for k in range(d + 1)]
    else:
        coeffs = [sp.Rational(c) if isinstance(c, (float, np.floating)) else sp.sympify(c) for c in form]
    if len(coeffs) == 0 or all(_is_zero(c) for c in coeffs):
        raise InputError("form must not vanish identically (every coefficient is zero)")
    at_inf = 0
    while _is_zero(coeffs[-1]):
        coeffs = coeffs[:-1]
        at_inf += 1
    if len(coeffs) == 1:
        return RealRootCertificate(True, int(at_inf > 0), (), (), at_inf,
                                   "exact: the form is a constant times a power of x0")
    if all(sp.sympify(c).is_Rational for c in coeffs):
        intervals, mults = _exact_path(coeffs)
        return RealRootCertificate(True, len(intervals) + int(at_inf > 0), tuple(intervals), tuple(mults),
                                   at_inf, "exact: python-flint fmpq_poly.complex_roots "
                                   "(arb_fmpz_poly_complex_roots on square-free factors)")
    intervals, mults, prec = _arb_path(coeffs)
    if intervals is None:
        return RealRootCertificate(False, None, (), (), at_inf,
                                   f"not certified: acb_poly.roots could not isolate every root up to "
                                   f"{prec} bits (a multiple root with irrational coefficients?)")
    return RealRootCertificate(True, len(intervals) + int(at_inf > 0), tuple(intervals), tuple(mults), at_inf,
                               f"arb balls: python-flint acb_poly.roots isolation at {prec} bits, real "
                               "roots by conjugate-symmetric discs")


_U = 2.0**-53


def certify_real_roots_batch(F):
    """Certified real-root counts for a batch of float binary forms, vectorised, with a fallback.

    The coefficients are taken as the exact binary rationals they are. For every row the roots
    are approximated (companion eigenvalues) and enclosed in the discs of the Gerschgorin-type
    theorem for polynomials (Braess-Hadeler, Carstensen): with ``z_1..z_d`` distinct
    approximations of the roots of ``p`` (degree ``d``, leading coefficient ``a_d``), the discs
    ``D(z_i, d |p(z_i)| / |a_d prod_{j != i} (z_i - z_j)|)`` cover all roots and a union of ``m``
    discs disjoint from the others holds exactly ``m`` roots. Rounding is bounded rigorously:
    ``|p(z_i)|`` is enlarged by the Horner error bound ``gamma_{2d+1} sum |a_k| |z_i|^k`` and the
    denominator decreased by a relative ``(4d + 4) u``. A row is decided by the discs when they are
    pairwise disjoint and each is either off the real axis (non-real root) or such that the disc
    centred on the real axis that covers it and its mirror image meets no other disc (the root is
    its own conjugate: real). Every other row (multiple or nearly multiple roots, a root at
    ``x0 = 0``, non-finite entries) is decided exactly by :func:`certify_real_roots`.

    Parameters
    ----------
    F : (n, d+1) float
        ``F[:, k]`` multiplies ``x0**(d-k) x1**k``.

    Returns
    -------
    counts : (n,) int
        Distinct real roots on the projective line; ``-1`` for rows that vanish identically or
        are not finite.
    path : (n,) str array
        ``"discs"`` (vectorised inclusion discs), ``"flint"`` (exact fallback) or ``"invalid"``.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.certify import certify_real_roots_batch
    >>> counts, path = certify_real_roots_batch(np.array([[-2.0, 0.0, 1.0], [1.0, -2.0, 1.0]]))
    >>> counts.tolist(), path.tolist()     # x1^2 - 2 x0^2 (two roots); (x1 - x0)^2 (one double)
    ([2, 1], ['discs', 'flint'])
    """
    F = np.asarray(F, dtype=float)
    if F.ndim != 2 or F.shape[1] < 2:
        raise InputError(f"F must have shape (n, d+1) with d >= 1, got {F.shape}")
    n, d1 = F.shape
    d = d1 - 1
    counts = np.full(n, -1, dtype=int)
    path = np.full(n, "invalid", dtype=object)
    finite = np.all(np.isfinite(F), axis=1) & np.any(F != 0, axis=1)
    regular = finite & (F[:, d] != 0)
    idx = np.flatnonzero(regular)
    decided = np.zeros(n, dtype=bool)
    if idx.size:
        comp = np.zeros((idx.size, d, d))
        if d > 1:
            comp[:, np.arange(1, d), np.arange(d - 1)] = 1.0
        comp[:, :, d - 1] = -F[idx, :d] / F[idx, d][:, None]
        with np.errstate(all="ignore"):
            z = np.linalg.eigvals(comp) if d > 1 else -(F[idx, 0] / F[idx, 1])[:, None].astype(complex)
            # Horner on the original (exact) coefficients, with its rounding bound
            val = np.zeros_like(z)
            absum = np.zeros(z.shape)
            az = np.abs(z)
            for k in range(d, -1, -1):
                val = val * z + F[idx, k][:, None]
                absum = absum * az + np.abs(F[idx, k])[:, None]
            gamma = (4 * d + 4) * _U / (1 - (4 * d + 4) * _U)   # complex Horner, generous
            pbound = np.abs(val) * (1 + 4 * _U) + 2 * gamma * absum
            diff = z[:, :, None] - z[:, None, :]
            diff[:, np.arange(d), np.arange(d)] = 1.0
            denom = np.abs(F[idx, d])[:, None] * np.prod(np.abs(diff), axis=2)
            denom = denom * (1 - (4 * d + 4) * _U)
            r = d * pbound / denom * (1 + (4 * d + 4) * _U)
            ok = np.all(np.isfinite(r) & np.isfinite(z.real) & (denom > 0), axis=1)
            dist = np.abs(diff)
            dist[:, np.arange(d), np.arange(d)] = np.inf
            disjoint = np.all(dist > r[:, :, None] + r[:, None, :], axis=(1, 2))
            nonreal = np.abs(z.imag) > r
            hull_r = np.abs(z.imag) + r
            hull_dist = np.abs(z.real[:, :, None] - z[:, None, :])
            hull_dist[:, np.arange(d), np.arange(d)] = np.inf
            real = ~nonreal & np.all(hull_dist > hull_r[:, :, None] + r[:, None, :], axis=2)
            good = ok & disjoint & np.all(nonreal | real, axis=1)
        counts[idx[good]] = np.sum(real[good], axis=1)
        path[idx[good]] = "discs"
        decided[idx[good]] = True
    for i in np.flatnonzero(finite & ~decided):
        cert = certify_real_roots([sp.Rational(float(v)) for v in F[i]])
        counts[i] = cert.count
        path[i] = "flint"
    return counts, path.astype(str)
