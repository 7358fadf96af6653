r"""A compiled Krawczyk certificate for the fast path's endpoints (numba, rigorous error bounds).

What it proves, per row
-----------------------
The row's system is ``G(z) = (z^T Q_0 z, ..., z^T Q_6 z, r . x - 1)`` on ``C^8``: the EXACT
quadrics ``Q_k = A_k - p_k E`` of the family (the design's exact rationals, ``p_k`` the exact
square of the user's float length divided by the power-of-two scale) on a real chart ``r . x = 1``
(``r`` a small integer vector). For each tracked endpoint, moved to the chart and polished by a few
float Newton steps, the kernel takes the box ``X = {z : |Re(z_j - m_j)| <= rho, |Im(z_j - m_j)| <=
rho}`` around the polished float point ``m`` and a float matrix ``Y`` (an approximate inverse of
``J(m)``). With the box norm ``||v|| = max_j max(|Re v_j|, |Im v_j|)``,

* ``beta >= ||Y G(m)||``, ``kappa >= ||I - Y J(m)||`` (the induced norm, ``max_i sum_j |Re| +
  |Im|``) and ``mu >= max_i sum_k (|Re Y_ik| + |Im Y_ik|) sum_{j,l} |Q_k[j, l]|`` are computed
  with rigorous bounds on every rounding (below);
* ``G`` is quadratic, so ``G(z) - G(m) = J((z + m) / 2) (z - m)`` exactly and
  ``||Y J(d)|| <= 4 mu ||d||`` (``J`` is linear in ``z``). The map ``N(z) = z - Y G(z)`` then sends
  ``X`` into ``m +- (beta + kappa rho + 2 mu rho^2)``, and ``||I - Y J(z)|| <= kappa + 4 mu rho``
  on ``X``. The kernel takes ``rho = 2 beta / (1 - kappa)`` and checks

  (i) ``beta + kappa rho + 2 mu rho^2 < rho``: ``N(X)`` lies in ``X``, so (Brouwer) ``N`` has a
      fixed point in ``X``, a zero of ``G`` (``Y`` is non-singular by (ii));
  (ii) ``kappa + 4 mu rho < 1``: ``J`` is non-singular on all of ``X``, so that zero is the only
       one in ``X`` (``0 = G(z_1) - G(z_2) = J((z_1 + z_2) / 2)(z_1 - z_2)``) and it is
       non-singular (Krawczyk 1969, Moore 1977, Rump 1983 in this norm form).

* **Real**: ``m`` and ``Y`` real (exactly: imaginary parts zero) — ``N`` maps the real points of
  ``X`` to real points, so the fixed point can be found among them and, unique, is real.
  **Not real**: some ``|Im m_j| > rho``. **A displacement** (not a null rotation, ``x . x != 0``):
  automatic for a real solution (``r . x = 1`` makes ``x`` a non-zero real vector); for a non-real
  one, ``x . x`` is enclosed on ``X`` and must exclude 0.
* **Complete**: boxes pairwise disjoint (separated in some real coordinate part) hold distinct
  solutions. When their number equals a theorem's bound on the isolated solutions with
  ``x . x != 0`` of every member of the family (40 Gough-Stewart, 16 for the 6-3, 3-6 and 3-3
  platforms and the 3-RPS; :mod:`imagespace.spatial.gough_stewart`, :mod:`imagespace.spatial.three_rps`),
  they are all of them and the number of real boxes is the number of real assembly modes.

Rigorous rounding bounds
------------------------
IEEE binary64, round to nearest, no fast-math (numba's default; LLVM neither reassociates nor
contracts, and a contracted ``a * b + c`` would only be more accurate). ``u = 2^-53``,
``eta = 2^-1074``.

* Every float is the exact rational it is: ``m``, ``Y`` and the chart are data, not approximations.
* The exact quadrics are enclosed once per design (:func:`family_enclosure`): ``Amid`` the double
  nearest each exact rational entry, ``Arad`` an upper bound of the difference (exact Fraction
  arithmetic, rounded up). Per row, ``p = l * l`` (``l = L / scale`` exact) is enclosed by
  ``|l^2 - fl(l^2)| <= u |fl(l^2)| + eta``, and ``A_dd - p`` by one more rounding ``u |result|``.
* A sum of ``n`` products computed in any order: ``|fl(sum) - sum| <= gamma_n sum |a_i b_i| +
  n eta`` with ``gamma_n = n u / (1 - n u)`` (Higham, Accuracy and Stability of Numerical
  Algorithms, 2002, Lemma 3.1 and 3.5, with the underflow term of the standard model
  ``fl(ab) = ab(1 + d) + e``). Errors of inputs propagate as ``sum |a_i| err(b_i)``.
* Every bound is a sum of products of non-negative floats, built from fewer than ``2^12`` rounded
  operations in depth: its computed value is at least ``(1 - u)^(2^12) > 1 - 2^-40`` times the
  exact expression, less underflow losses; the kernel multiplies the final bounds by
  ``1 + 2^-38`` and adds ``2^-700``. Underflow losses stay below ``2^-700``: the kernel refuses
  (leaves to arb) any endpoint whose ``|m|``, ``|Y|`` or quadric entries exceed ``2^60``, so no
  product of four factors exceeds ``2^264`` and ``10^4`` underflows of ``eta`` amplified by it
  stay far below.
* NaN or infinity anywhere fails every strict comparison: the endpoint is then not certified.

What the kernel cannot decide (a path that did not arrive, a cluster, an ill-conditioned endpoint,
a box that meets the real space without a real centre) it reports; the caller then uses arb
(:mod:`imagespace.spatial.certify`) and msolve (:mod:`imagespace.spatial.exact`).

References
----------
R. Krawczyk, Newton-Algorithmen zur Bestimmung von Nullstellen mit Fehlerschranken, Computing 4,
1969, doi:10.1007/BF02234758.
R. E. Moore, A test for existence of solutions to nonlinear systems, SIAM J. Numer. Anal. 14(4),
1977, doi:10.1137/0714040.
S. M. Rump, Solving algebraic problems with high accuracy, in: A New Approach to Scientific
Computation, Academic Press, 1983, doi:10.1016/B978-0-12-428660-3.50010-0.
N. J. Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., SIAM, 2002,
doi:10.1137/1.9780898718027.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Optional

import numpy as np
import numpy.typing as npt

from ..core._numba import njit, prange

if TYPE_CHECKING:
    from ..core.kinematic_map import FloatArray

__all__ = ["FamilyEnclosure", "family_enclosure", "parameter_enclosure", "certify_endpoints",
           "FastCertificate", "CHARTS"]

_N = 8
_U = 2.0 ** -53
_ETA = 2.0 ** -1074
_SLACK = 1.0 + 2.0 ** -38             # covers the rounding of the bound computations
_FLOOR = 2.0 ** -700                  # covers underflow in the bound computations
_BIG = 2.0 ** 60                      # magnitudes beyond this are left to arb


def _gamma(n):
    # n u / (1 - n u), rounded up generously (n u < 1e-12 here)
    return n * _U * (1.0 + 2.0 ** -20)


_G4 = _gamma(4)
_G5 = _gamma(5)
_G8 = _gamma(8)
_G16 = _gamma(16)

# numerical choices that propose (a failed proposal decides nothing; it leaves the row to arb)
_POLISH = 1                 # Newton steps in the chart (the tracker polished the endpoint) ...
_POLISH_RETRY = 3           # ... and more where the first test fails (near a double mode)
_REAL_PROPOSAL = 1e-7       # |Im m| / (1 + |m|) below this proposes a real solution
_CHART_MIN = 0.05           # chart r: |r . x| >= this |r| |x| on every endpoint
_BLOCKS = 256               # parallel blocks of rows
# the float Newton steps and the approximate inverse only propose (the bounds decide): they may
# reassociate and contract; no-NaN/no-inf assumptions are left out so finiteness checks hold
_PROPOSAL_MATH = {"reassoc", "contract", "arcp", "nsz"}

#: the chart vectors tried, in order (the first far from every endpoint's ``x`` is used)
CHARTS = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
                  + [list(v) for v in np.random.default_rng(0).integers(-3, 4, size=(60, 4)) if np.any(v)],
                  dtype=np.int64)


@dataclass(frozen=True, eq=False)
class FamilyEnclosure:
    """The exact quadrics of a family enclosed in doubles, once per design.

    Attributes
    ----------
    Amid : (7, 8, 8) float
        The doubles nearest the exact parameter-free quadrics' entries.
    Arad : (7, 8, 8) float
        Upper bounds of ``|Amid - A_exact|`` (0 where the entry is a double).
    Ed : (8,) float
        The diagonal of ``E`` (entries 0 or 1, checked exactly): ``Q_k = A_k - p_k diag(Ed)``.
    pidx : (7,) int
    ok : bool
        False when the family does not have this structure (the compiled certificate is then not
        used).
    """

    Amid: np.ndarray
    Arad: np.ndarray
    Ed: np.ndarray
    pidx: np.ndarray
    ok: bool


_ENCLOSURES: weakref.WeakKeyDictionary[object, FamilyEnclosure] = weakref.WeakKeyDictionary()


def _up(x):
    """A double ``>= x`` for a non-negative Fraction ``x``."""
    f = float(x)
    return f if Fraction(f) >= x else float(np.nextafter(f, np.inf))


def family_enclosure(family: Any) -> FamilyEnclosure:  # a QuadricFamily (solver imports this module)
    """Enclose a :class:`~imagespace.spatial.solver.QuadricFamily`'s exact quadrics (cached).

    Parameters
    ----------
    family : QuadricFamily

    Returns
    -------
    FamilyEnclosure

    Examples
    --------
    >>> import imagespace as isp
    >>> enc = family_enclosure(isp.examples.dietmaier_1998()[0].family())
    >>> enc.ok, enc.Amid.shape
    (True, (7, 8, 8))
    """
    hit = _ENCLOSURES.get(family)
    if hit is not None:
        return hit
    m = family.A.shape[0]
    pidx = np.asarray(family.pidx, dtype=np.int64)
    Ed = np.ascontiguousarray(np.diag(family.E), dtype=float)
    zero = family.exact([Fraction(0)] * family.nparams)
    one = family.exact([Fraction(1)] * family.nparams)
    Amid = np.zeros((m, _N, _N))
    Arad = np.zeros((m, _N, _N))
    ok = m == 7 and bool(np.all((Ed == 0.0) | (Ed == 1.0))) and not np.any(family.E - np.diag(Ed))
    for k in range(m):
        for i in range(_N):
            for j in range(_N):
                v = Fraction(zero[k, i, j])
                f = float(v)
                Amid[k, i, j] = f
                Arad[k, i, j] = _up(abs(Fraction(f) - v))
                want = (Ed[i] if (i == j and pidx[k] >= 0) else 0.0)
                if Fraction(zero[k, i, j]) - Fraction(one[k, i, j]) != Fraction(want):
                    ok = False
    # the kernel reads Q[j, i] for Q[i, j]: the exact quadrics must be symmetric
    ok = ok and all(Fraction(zero[k, i, j]) == Fraction(zero[k, j, i])
                    for k in range(m) for i in range(_N) for j in range(i))
    enc = FamilyEnclosure(Amid, Arad, Ed, pidx, bool(ok and np.all(np.isfinite(Amid))))
    _ENCLOSURES[family] = enc
    return enc


def parameter_enclosure(lengths: npt.ArrayLike, scale: float) -> tuple[FloatArray, FloatArray]:
    """Enclose the exact parameters ``(L / scale)^2`` of float lengths: midpoints and radii.

    Parameters
    ----------
    lengths : (n, p) float
    scale : float
        A power of two.

    Returns
    -------
    pm, pr : (n, p) float
        ``|(L / scale)^2 - pm| <= pr`` (as exact rationals); ``pr`` is infinite where ``L / scale``
        is not exact (underflow), so such a row is never certified.

    Examples
    --------
    >>> pm, pr = parameter_enclosure(np.array([[3.0, 0.1]]), 1.0)
    >>> float(pm[0, 0]), bool(pr[0, 0] < 1e-15)
    (9.0, True)
    """
    L = np.atleast_2d(np.asarray(lengths, dtype=float))
    with np.errstate(all="ignore"):
        lv = L / scale
        pm = lv * lv
        # |l^2 - fl(l^2)| <= u |fl(l^2)| + eta; the product by 2^-53 is exact or loses < eta
        pr = np.abs(pm) * _U + 2 * _ETA
        # L / scale not exact (underflow) or not finite: never certified
        pr = np.where((lv * scale == L) & np.isfinite(pm), pr, np.inf)
    return np.ascontiguousarray(pm), np.ascontiguousarray(pr)


# ----------------------------------------------------------------------------- compiled kernel

@njit(cache=True, fastmath=_PROPOSAL_MATH)
def _lu(M, piv):
    """In-place LU with partial pivoting (8 x 8 complex); False on a zero pivot (proposals only)."""
    n = M.shape[0]
    for k in range(n):
        p = k
        big = abs(M[k, k].real) + abs(M[k, k].imag)
        for i in range(k + 1, n):
            a = abs(M[i, k].real) + abs(M[i, k].imag)
            if a > big:
                big = a
                p = i
        piv[k] = p
        if not big > 0.0:
            return False
        if p != k:
            for j in range(n):
                tmp = M[k, j]
                M[k, j] = M[p, j]
                M[p, j] = tmp
        inv = 1.0 / M[k, k]
        for i in range(k + 1, n):
            f = M[i, k] * inv
            M[i, k] = f
            for j in range(k + 1, n):
                M[i, j] -= f * M[k, j]
    return True


@njit(cache=True, fastmath=_PROPOSAL_MATH)
def _lu_solve(M, piv, b, out):
    n = M.shape[0]
    for i in range(n):
        out[i] = b[i]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = out[k]
            out[k] = out[p]
            out[p] = tmp
    for k in range(n):
        for i in range(k + 1, n):
            out[i] -= M[i, k] * out[k]
    for i in range(n - 1, -1, -1):
        acc = out[i]
        for j in range(i + 1, n):
            acc -= M[i, j] * out[j]
        out[i] = acc / M[i, i]


@njit(cache=True, fastmath=_PROPOSAL_MATH)
def _lu_inverse(M, piv, Y):
    """``Y = A^-1`` from the factors of :func:`_lu` (all columns at once; proposals only)."""
    n = M.shape[0]
    for i in range(n):
        for c in range(n):
            Y[i, c] = 1.0 if i == c else 0.0
    for k in range(n):
        p = piv[k]
        if p != k:
            for c in range(n):
                tmp = Y[k, c]
                Y[k, c] = Y[p, c]
                Y[p, c] = tmp
    for k in range(n):
        for i in range(k + 1, n):
            f = M[i, k]
            for c in range(n):
                Y[i, c] -= f * Y[k, c]
    for i in range(n - 1, -1, -1):
        for j in range(i + 1, n):
            f = M[i, j]
            for c in range(n):
                Y[i, c] -= f * Y[j, c]
        inv = 1.0 / M[i, i]
        for c in range(n):
            Y[i, c] = Y[i, c] * inv


@njit(cache=True, fastmath=_PROPOSAL_MATH)
def _float_system(z, Qm, r, G, J):
    """Float ``G(z)`` and ``J(z)`` (proposals only)."""
    for k in range(7):
        acc = 0j
        for i in range(_N):
            w = 0j
            for j in range(_N):
                w += Qm[k, i, j] * z[j]
            acc += z[i] * w
            J[k, i] = 2.0 * w
        G[k] = acc
    acc = -1.0 + 0j
    for j in range(4):
        acc += r[j] * z[j]
        J[7, j] = r[j]
        J[7, 4 + j] = 0j
    G[7] = acc


@njit(cache=True)
def _polish(z, Qm, r, real, steps, G, J, piv, dz):
    """Float Newton steps in the chart (keeping ``z`` real when ``real``); False on failure."""
    for _ in range(steps):
        _float_system(z, Qm, r, G, J)
        if not _lu(J, piv):
            return False
        _lu_solve(J, piv, G, dz)
        for i in range(_N):
            z[i] -= dz[i]
            if real:
                z[i] = complex(z[i].real, 0.0)
    for i in range(_N):
        if not (np.isfinite(z[i].real) and np.isfinite(z[i].imag)):
            return False
    return True


@njit(cache=True)
def _row_quadrics(Amid, Arad, Ed, pidx, pm, pr, Qm, Qr, T):
    """The row's quadric enclosure ``Qm +- Qr`` and ``T_k >= sum |Q_k|`` (entries)."""
    for k in range(7):
        q = pidx[k]
        t = 0.0
        for i in range(_N):
            for j in range(_N):
                v = Amid[k, i, j]
                e = Arad[k, i, j]
                if i == j and q >= 0 and Ed[i] != 0.0:
                    v = Amid[k, i, i] - pm[q]
                    # rounded up: (1 + 2^-50) (1 - u)^3 > 1, so the entry is itself rigorous
                    e = ((e + pr[q]) + _U * abs(v)) * (1.0 + 2.0 ** -50)
                Qm[k, i, j] = v
                Qr[k, i, j] = e
                t += abs(v) + e
        T[k] = t


@njit(cache=True)
def _krawczyk_bounds(m, Qm, Qr, T, r, Y, w, ew, g, eg, F, M):
    """Rigorous ``(beta, kappa, mu)`` for the box norm at ``m`` with the matrix ``Y``.

    Work arrays: ``w`` (7, 8) complex receives ``Q_k m``, ``ew`` (7, 8, 2) its error bounds,
    ``g`` (8,) complex ``G(m)``, ``eg`` (8, 2) its error bounds (index 0: real part, 1: imaginary
    part), ``F`` (16, 8) and ``M`` (4, 8, 8) float scratch. The quadrics are symmetric (checked by
    :func:`family_enclosure`), so ``Q_k[j, i]`` is read for ``Q_k[i, j]``. Inner loops run over
    independent accumulators (one per output entry, each summed in a fixed order), so they
    vectorise without reassociation. A real ``m`` with a real ``Y`` skips the imaginary parts,
    which are then exactly zero. Returns ``beta = -1`` when a magnitude guard fails.
    """
    real = True
    for i in range(_N):
        if not (abs(m[i].real) <= _BIG and abs(m[i].imag) <= _BIG):
            return -1.0, 0.0, 0.0
        if m[i].imag != 0.0:
            real = False
        for j in range(_N):
            if not (abs(Y[i, j].real) <= _BIG and abs(Y[i, j].imag) <= _BIG):
                return -1.0, 0.0, 0.0
            if Y[i, j].imag != 0.0:
                real = False
    for k in range(7):
        if not T[k] <= _BIG:
            return -1.0, 0.0, 0.0
    mr = F[0]
    mi = F[1]
    amr = F[2]
    ami = F[3]
    for j in range(_N):
        mr[j] = m[j].real
        mi[j] = m[j].imag
        amr[j] = abs(mr[j])
        ami[j] = abs(mi[j])
    wr = F[4]
    wi = F[5]
    br = F[6]
    bi = F[7]
    cr = F[8]
    ci = F[9]
    Jr = M[0]
    Ji = M[1]
    AJr = M[2]      # gamma_16 |Re J| + err(Re J): what one product term contributes to an error
    AJi = M[3]
    # w_k = Q_k m: |exact - fl| <= gamma_8 sum |Qm||m| + sum Qr |m| + 8 eta (each part)
    for k in range(7):
        for i in range(_N):
            wr[i] = 0.0
            wi[i] = 0.0
            br[i] = 0.0
            bi[i] = 0.0
            cr[i] = 0.0
            ci[i] = 0.0
        for j in range(_N):
            a = mr[j]
            b = mi[j]
            aa = amr[j]
            ab = ami[j]
            for i in range(_N):
                q = Qm[k, j, i]
                aq = abs(q)
                rq = Qr[k, j, i]
                wr[i] += q * a
                br[i] += aq * aa
                cr[i] += rq * aa
                if not real:
                    wi[i] += q * b
                    bi[i] += aq * ab
                    ci[i] += rq * ab
        gr = 0.0
        gi = 0.0
        sr = 0.0
        si = 0.0
        for i in range(_N):
            e0 = _G8 * br[i] + cr[i] + 8 * _ETA
            e1 = (_G8 * bi[i] + ci[i] + 8 * _ETA) if not real else 0.0
            w[k, i] = complex(wr[i], wi[i])
            ew[k, i, 0] = e0
            ew[k, i, 1] = e1
            Jr[k, i] = 2.0 * wr[i]
            Ji[k, i] = 2.0 * wi[i]
            AJr[k, i] = _G16 * abs(Jr[k, i]) + 2.0 * e0
            AJi[k, i] = _G16 * abs(Ji[k, i]) + 2.0 * e1
            # G_k = sum_i m_i w_i (16 real products a part) and the propagated errors of w
            gr += mr[i] * wr[i] - mi[i] * wi[i]
            gi += mr[i] * wi[i] + mi[i] * wr[i]
            sr += amr[i] * (abs(wr[i]) * _G16 + e0) + ami[i] * (abs(wi[i]) * _G16 + e1)
            si += amr[i] * (abs(wi[i]) * _G16 + e1) + ami[i] * (abs(wr[i]) * _G16 + e0)
        g[k] = complex(gr, gi)
        eg[k, 0] = sr + 16 * _ETA
        eg[k, 1] = (si + 16 * _ETA) if not real else 0.0
    # the chart row r . x - 1 (r small integers; J's row (r, 0) exact)
    gr = -1.0
    gi = 0.0
    sr = 1.0
    si = 0.0
    for j in range(4):
        gr += r[j] * mr[j]
        gi += r[j] * mi[j]
        sr += abs(r[j]) * amr[j]
        si += abs(r[j]) * ami[j]
    g[7] = complex(gr, gi)
    eg[7, 0] = _G5 * sr + 5 * _ETA
    eg[7, 1] = (_G4 * si + 4 * _ETA) if not real else 0.0
    for j in range(_N):
        Jr[7, j] = float(r[j]) if j < 4 else 0.0
        Ji[7, j] = 0.0
        AJr[7, j] = _G16 * abs(Jr[7, j])
        AJi[7, j] = 0.0
    # beta >= ||Y G(m)||: v = Y g (16 real products a part)
    beta = 0.0
    for i in range(_N):
        vr = 0.0
        vi = 0.0
        er = 0.0
        ei = 0.0
        for k in range(_N):
            yr = Y[i, k].real
            yi = Y[i, k].imag
            vr += yr * g[k].real - yi * g[k].imag
            vi += yr * g[k].imag + yi * g[k].real
            er += _G16 * (abs(yr) * abs(g[k].real) + abs(yi) * abs(g[k].imag)) + \
                abs(yr) * eg[k, 0] + abs(yi) * eg[k, 1]
            ei += _G16 * (abs(yr) * abs(g[k].imag) + abs(yi) * abs(g[k].real)) + \
                abs(yr) * eg[k, 1] + abs(yi) * eg[k, 0]
        a = abs(vr) + (er + 16 * _ETA)
        b = abs(vi) + (ei + 16 * _ETA)
        beta = max(beta, max(a, b))
    # kappa >= ||I - Y J(m)||: P = Y J row by row, one accumulator per column
    pr = F[10]
    pi = F[11]
    er = F[12]
    ei = F[13]
    kappa = 0.0
    for i in range(_N):
        for j in range(_N):
            pr[j] = 0.0
            pi[j] = 0.0
            er[j] = 0.0
            ei[j] = 0.0
        for k in range(_N):
            yr = Y[i, k].real
            ayr = abs(yr)
            if real:
                for j in range(_N):
                    pr[j] += yr * Jr[k, j]
                    er[j] += ayr * AJr[k, j]
            else:
                yi = Y[i, k].imag
                ayi = abs(yi)
                for j in range(_N):
                    pr[j] += yr * Jr[k, j] - yi * Ji[k, j]
                    pi[j] += yr * Ji[k, j] + yi * Jr[k, j]
                    er[j] += ayr * AJr[k, j] + ayi * AJi[k, j]
                    ei[j] += ayr * AJi[k, j] + ayi * AJr[k, j]
        row = 0.0
        for j in range(_N):
            e_r = er[j] + 16 * _ETA
            if i == j:
                c = 1.0 - pr[j]
                e_r += _U * abs(c)
            else:
                c = -pr[j]
            row += abs(c) + e_r
            if not real:
                row += abs(pi[j]) + (ei[j] + 16 * _ETA)
        kappa = max(kappa, row)
    # mu >= max_i sum_k |Y_ik|_1 T_k
    mu = 0.0
    for i in range(_N):
        acc = 0.0
        for k in range(7):
            acc += (abs(Y[i, k].real) + abs(Y[i, k].imag)) * T[k]
        mu = max(mu, acc)
    return beta * _SLACK + _FLOOR, kappa * _SLACK + _FLOOR, mu * _SLACK + _FLOOR


@njit(cache=True)
def _null_excluded(m, rho):
    """True when ``x . x != 0`` on the box ``m +- rho`` (rigorous)."""
    sr = 0.0
    si = 0.0
    ar = 0.0
    ai = 0.0
    d = 0.0
    for j in range(4):
        a = m[j].real
        b = m[j].imag
        sr += a * a - b * b
        si += 2.0 * a * b
        ar += a * a + b * b
        ai += 2.0 * abs(a) * abs(b)
        d += rho * (2.0 * abs(a) + 2.0 * abs(b) + 2.0 * rho)
    er = (_G8 * ar + 8 * _ETA + d) * _SLACK + _FLOOR
    ei = (_G4 * ai + 4 * _ETA + d) * _SLACK + _FLOOR
    return abs(sr) > er or abs(si) > ei


@njit(cache=True)
def _certify_point(m, real, Qm, Qr, T, r, J, Y, piv, w, ew, g, eg, F, M):
    """Krawczyk at the polished point ``m``: (proved, real flag 1/0/-1, rho, displacement).

    ``J`` and ``piv`` hold the LU factors of the last Newton step (:func:`_polish`)."""
    # Y: the inverse of the last Newton step's Jacobian (J holds its LU factors): any matrix
    # will do for the proof, and this one is within a Newton step of J(m)^-1
    _lu_inverse(J, piv, Y)
    if real:
        for i in range(_N):
            for c in range(_N):
                Y[i, c] = complex(Y[i, c].real, 0.0)
    beta, kappa, mu = _krawczyk_bounds(m, Qm, Qr, T, r, Y, w, ew, g, eg, F, M)
    if not (beta > 0.0 and kappa < 1.0):
        return False, -1, 0.0, False
    rho = 2.0 * beta / (1.0 - kappa)
    rho = rho * _SLACK + _FLOOR                 # any rho will do; this one is near the smallest
    lhs = (beta + kappa * rho + 2.0 * mu * rho * rho) * _SLACK
    if not lhs < rho:
        return False, -1, 0.0, False
    if not (kappa + 4.0 * mu * rho) * _SLACK < 1.0:
        return False, -1, 0.0, False
    if real:
        return True, 1, rho, True
    flag = -1
    for j in range(_N):
        if abs(m[j].imag) > rho:
            flag = 0
            break
    return True, flag, rho, _null_excluded(m, rho)


@njit(cache=True)
def _disjoint(pts, rho, ok, k):
    """Every pair of proved boxes separated in some real coordinate part (rigorous)."""
    for a in range(k):
        if not ok[a]:
            continue
        for b in range(a + 1, k):
            if not ok[b]:
                continue
            need = (rho[a] + rho[b]) * (1.0 + 2.0 ** -50)
            sep = False
            for i in range(_N):
                # |fl(x - y)| <= (1 + u) |x - y|
                if abs(pts[a, i].real - pts[b, i].real) * (1.0 - 2.0 ** -50) > need or \
                        abs(pts[a, i].imag - pts[b, i].imag) * (1.0 - 2.0 ** -50) > need:
                    sep = True
                    break
            if not sep:
                return False
    return True


@njit(cache=True)
def _choose_chart(Zr, ok, charts):
    k = Zr.shape[0]
    for c in range(charts.shape[0]):
        nr = 0.0
        for j in range(4):
            nr += float(charts[c, j]) ** 2
        nr = np.sqrt(nr)
        good = True
        for p in range(k):
            if not ok[p]:
                continue
            dot = 0j
            nx = 0.0
            for j in range(4):
                dot += charts[c, j] * Zr[p, j]
                nx += Zr[p, j].real ** 2 + Zr[p, j].imag ** 2
            if not abs(dot) >= _CHART_MIN * nr * np.sqrt(nx):
                good = False
                break
        if good:
            return c
    return -1


@njit(cache=True, parallel=True)
def _certify_rows(Z, status, rows_ok, pm, pr, Amid, Arad, Ed, pidx, charts, target,
                  pts, rho, cert, real, null_ok, chart_used, complete, nreal):
    n, k = status.shape
    blocks = min(n, _BLOCKS)
    for blk in prange(blocks):
        Qm = np.zeros((7, _N, _N))
        Qr = np.zeros((7, _N, _N))
        T = np.zeros(7)
        G = np.zeros(_N, dtype=np.complex128)
        J = np.zeros((_N, _N), dtype=np.complex128)
        Y = np.zeros((_N, _N), dtype=np.complex128)
        piv = np.zeros(_N, dtype=np.int64)
        dz = np.zeros(_N, dtype=np.complex128)
        z = np.zeros(_N, dtype=np.complex128)
        w = np.zeros((7, _N), dtype=np.complex128)
        ew = np.zeros((7, _N, 2))
        eg = np.zeros((_N, 2))
        F = np.zeros((16, _N))
        M = np.zeros((4, _N, _N))
        r = np.zeros(4, dtype=np.int64)
        okp = np.zeros(k, dtype=np.bool_)
        for row in range(blk * n // blocks, (blk + 1) * n // blocks):
            complete[row] = False
            nreal[row] = 0
            chart_used[row] = -1
            for j in range(k):
                cert[row, j] = False
                real[row, j] = -1
                null_ok[row, j] = False
                rho[row, j] = 0.0
            if not rows_ok[row]:
                continue
            for j in range(k):
                okp[j] = status[row, j] == 0
            _row_quadrics(Amid, Arad, Ed, pidx, pm[row], pr[row], Qm, Qr, T)
            c = _choose_chart(Z[row], okp, charts)
            if c < 0:
                continue
            chart_used[row] = c
            for j in range(4):
                r[j] = charts[c, j]
            for j in range(k):
                if not okp[j]:
                    continue
                dot = 0j
                for i in range(4):
                    dot += r[i] * Z[row, j, i]
                for i in range(_N):
                    z[i] = Z[row, j, i] / dot
                # one Newton step, the test; where it fails (slow Newton near a double mode)
                # more steps and the test again
                for attempt in range(2):
                    steps = _POLISH if attempt == 0 else _POLISH_RETRY
                    if not _polish(z, Qm, r, False, steps, G, J, piv, dz):
                        break
                    size = 0.0
                    im = 0.0
                    for i in range(_N):
                        size = max(size, abs(z[i]))
                        im = max(im, abs(z[i].imag))
                    is_real = im <= _REAL_PROPOSAL * (1.0 + size)
                    if is_real:
                        for i in range(_N):
                            z[i] = complex(z[i].real, 0.0)
                        if not _polish(z, Qm, r, True, steps, G, J, piv, dz):
                            break
                    for i in range(_N):
                        pts[row, j, i] = z[i]
                    ok, flag, rr, disp = _certify_point(z, is_real, Qm, Qr, T, r, J, Y, piv,
                                                        w, ew, G, eg, F, M)
                    cert[row, j] = ok
                    real[row, j] = flag
                    rho[row, j] = rr
                    null_ok[row, j] = disp
                    if ok and flag >= 0 and disp:
                        break
            count = 0
            decided = True
            nr = 0
            for j in range(k):
                if cert[row, j]:
                    count += 1
                    if real[row, j] < 0 or not null_ok[row, j]:
                        decided = False
                    if real[row, j] == 1:
                        nr += 1
            nreal[row] = nr
            if count == target and decided:
                complete[row] = _disjoint(pts[row], rho[row], cert[row], k)


@dataclass(frozen=True)
class FastCertificate:
    """The compiled certificate of many rows (see the module docstring for what it proves).

    Attributes
    ----------
    points : (n, k, 8) complex
        The polished box centres in the chart ``charts[chart[i]] . x = 1``.
    radii : (n, k) float
    certified : (n, k) bool
        A unique non-singular solution in the box.
    real : (n, k) int8
        1 proven real, 0 proven not real, -1 not decided.
    displacement : (n, k) bool
        ``x . x != 0`` proven on the box.
    chart : (n,) int
        Index into :data:`CHARTS` (-1: none found).
    complete : (n,) bool
        ``target`` pairwise disjoint boxes, every one proven, decided and a displacement.
    real_count : (n,) int
    """

    points: np.ndarray
    radii: np.ndarray
    certified: np.ndarray
    real: np.ndarray
    displacement: np.ndarray
    chart: np.ndarray
    complete: np.ndarray
    real_count: np.ndarray


def certify_endpoints(enclosure: FamilyEnclosure, Z: npt.NDArray[np.complex128], status: npt.NDArray[np.integer], pm: FloatArray,
                      pr: FloatArray, target: int, rows: Optional[npt.NDArray[np.bool_]] = None) -> FastCertificate:
    """Run the compiled certificate on tracked endpoints.

    Parameters
    ----------
    enclosure : FamilyEnclosure
    Z : (n, k, 8) complex
        Endpoints (any scaling).
    status : (n, k) int
        0 where the path arrived.
    pm, pr : (n, p) float
        The parameters' enclosure (:func:`parameter_enclosure`).
    target : int
        How many distinct solutions make a row complete (a theorem's bound).
    rows : (n,) bool, optional
        Rows to certify (others: not complete).

    Returns
    -------
    FastCertificate

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.spatial.homotopy import track_parameters
    >>> gs, L = isp.examples.dietmaier_1998()
    >>> fam = gs.family()
    >>> Z, st, _ = track_parameters(gs.start_system, (np.asarray(L)[None] / fam.scale) ** 2)
    >>> pm, pr = parameter_enclosure(np.asarray(L)[None], fam.scale)
    >>> c = certify_endpoints(family_enclosure(fam), Z, st, pm, pr, 40)
    >>> bool(c.complete[0]), int(c.real_count[0])
    (True, 40)
    """
    Z = np.ascontiguousarray(Z, dtype=np.complex128)
    n, k = Z.shape[:2]
    status = np.ascontiguousarray(status, dtype=np.int64)
    rows = np.ones(n, np.bool_) if rows is None else np.ascontiguousarray(rows, dtype=np.bool_)
    pts = np.zeros((n, k, _N), np.complex128)
    rho = np.zeros((n, k))
    cert = np.zeros((n, k), np.bool_)
    real = np.zeros((n, k), np.int8)
    null_ok = np.zeros((n, k), np.bool_)
    chart = np.zeros(n, np.int64)
    complete = np.zeros(n, np.bool_)
    nreal = np.zeros(n, np.int64)
    if n and k and enclosure.ok:
        _certify_rows(Z, status, rows, np.ascontiguousarray(pm, dtype=float),
                      np.ascontiguousarray(pr, dtype=float), enclosure.Amid, enclosure.Arad,
                      enclosure.Ed, enclosure.pidx, CHARTS, int(target), pts, rho, cert, real,
                      null_ok, chart, complete, nreal)
    return FastCertificate(pts, rho, cert, real, null_ok, chart, complete, nreal)
