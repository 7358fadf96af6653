r"""Certified solutions of quadric systems in Study coordinates (Krawczyk's operator in arb).

The system is ``z^T Q_k z = 0`` (``k = 0..6``, ``Q_k`` with EXACT rational entries: the user's
floats as binary rationals) on the real affine chart ``r . x = 1`` (``r`` a small integer vector,
``x = (x0, x1, x2, x3)``), i.e. ``G(z) = (z^T Q_0 z, ..., z^T Q_6 z, r . x - 1)`` in ``C^8``.

For a box ``X`` (an arb complex ball per coordinate) around a float point ``m``, Krawczyk's operator

.. math::

    K(X) = m - Y G(m) + (I - Y J(X)) (X - m)

(``Y`` any matrix, here a float inverse of ``J(m)``; ``J`` the Jacobian, linear in ``z`` for
quadrics so ``J(X)`` encloses every Jacobian on ``X``) contained in the interior of ``X`` proves
that ``X`` holds exactly one solution, and that it is non-singular (Krawczyk 1969, Moore 1977).

* **Real.** If ``m`` is real and ``X`` symmetric under conjugation, the unique solution ``z`` in ``X``
  and its conjugate (also a solution, ``G`` has real coefficients, also in ``X``) coincide: ``z`` is
  real.
* **Not real.** If some coordinate's imaginary part in ``X`` excludes zero, ``z`` is not real.
* **A displacement.** ``x . x != 0``: automatic for a real solution (``r . x = 1``); for a
  non-real one, ``x . x`` is enclosed on the box and must exclude 0.
* **Complete.** Pairwise disjoint boxes hold distinct solutions. A Gough-Stewart platform has at most
  40 isolated solutions with ``x . x != 0`` (Raghavan 1993; Ronga & Vust, Lazard, Mourrain 1992-93;
  Morgan & Sommese's coefficient-parameter theorem carries the generic count to every member of the
  family), a 6-3, 3-3 or 3-RPS at most 16: that many certified disjoint boxes of displacements are
  all of them, so the number of real ones is the number of real modes.

Centres are float points polished by Newton's method; where no box around one contracts (a solution
whose Jacobian has condition ~1e7, near a double mode), the centre is refined by Newton's method in
arb at :data:`CERT_PRECISION` bits and tiny boxes around the refined centre are tried.

Everything decided here is decided in ball arithmetic on the exact input; floats only propose.

References
----------
R. Krawczyk, Newton-Algorithmen zur Bestimmung von Nullstellen mit Fehlerschranken, Computing 4,
1969, doi:10.1007/BF02234758.
R. E. Moore, A test for existence of solutions to nonlinear systems, SIAM J. Numer. Anal. 14(4),
1977, doi:10.1137/0714040.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Optional

import numpy as np
import numpy.typing as npt

__all__ = ["KrawczykResult", "exact_matrix", "choose_chart", "krawczyk_certify", "CERT_PRECISION"]

#: bits of the arb working precision (the exact entries are dyadic; balls absorb any rounding)
CERT_PRECISION = 128
# numerical choices that propose boxes (a failed proposal is reported, never decides):
_RADII = (1e-11, 1e-8, 1e-13)    # box half-widths tried, relative to 1 + |m|
_REAL_PROPOSAL = 1e-7            # |Im m| below this (relative) proposes a real solution
_CHART_MIN = 0.05                # the chart vector must satisfy |r . x| >= this * |x| on every solution
_CHART_TRIES = 40
_POLISH = 6                      # float Newton iterations in the chart before the proof
_REFINE = 4                      # Newton iterations at CERT_PRECISION for a point the float boxes miss
_REFINED_RADII = (1e-24, 1e-18)  # box half-widths tried around a refined centre, relative to 1 + |m|
_MID_ROUNDING = 2.0 ** -50       # bounds rounding a refined centre to complex floats (2**-53 relative a part)


@dataclass(frozen=True)
class KrawczykResult:
    """The outcome of :func:`krawczyk_certify` for one system.

    Attributes
    ----------
    points : (k, 8) complex
        The box centres in the chart ``r . x = 1``.
    radii : (k,) float
        The box half-widths (per real and imaginary part of each coordinate).
    certified : (k,) bool
        Krawczyk proved a unique non-singular solution in the box.
    real : (k,) int8
        ``1`` proven real, ``0`` proven not real, ``-1`` not decided.
    disjoint : bool
        All certified boxes are pairwise disjoint (distinct solutions).
    chart : (4,) int
        The chart vector ``r``.
    displacement : (k,) bool
        ``x . x != 0`` is proven on the box (not a null rotation); None: not computed.
    """

    points: np.ndarray
    radii: np.ndarray
    certified: np.ndarray
    real: np.ndarray
    disjoint: bool
    chart: np.ndarray
    displacement: Optional[np.ndarray] = None

    @property
    def distinct_certified(self) -> int:
        """Number of certified solutions, if their boxes are disjoint (else 0)."""
        return int(self.certified.sum()) if self.disjoint else 0

    @property
    def real_count(self) -> int:
        """Number of certified real solutions."""
        return int(np.sum(self.certified & (self.real == 1)))

    def complete(self, bound: int) -> bool:
        """True when ``bound`` distinct solutions are certified, each decided real or not and each
        a displacement (``x . x != 0``)."""
        disp = True if self.displacement is None else bool(np.all(self.displacement[self.certified]))
        return (self.distinct_certified == bound and bool(np.all(self.real[self.certified] >= 0))
                and disp)


def exact_matrix(Q: Any) -> npt.NDArray[np.object_]:
    """An exact rational copy (nested lists of :class:`fractions.Fraction`) of float or sympy matrices.

    Parameters
    ----------
    Q : (..., 8, 8) float or nested sympy Rationals

    Returns
    -------
    numpy object array of Fraction

    Examples
    --------
    >>> exact_matrix(np.array([[0.5, 0.1]]))[0, 1] == Fraction(0.1)
    True
    """
    arr = np.asarray(Q, dtype=object)
    out = np.empty(arr.shape, dtype=object)
    for idx, v in np.ndenumerate(arr):
        if isinstance(v, Fraction):
            out[idx] = v
        elif isinstance(v, (float, np.floating)):
            out[idx] = Fraction(float(v))
        elif isinstance(v, (int, np.integer)):
            out[idx] = Fraction(int(v))
        else:                                   # a sympy Rational
            out[idx] = Fraction(int(v.p), int(v.q))
    return out


def choose_chart(Z: npt.ArrayLike, seed: int = 0) -> Optional[npt.NDArray[np.integer]]:
    """A small integer chart vector ``r``, far from orthogonal to every point's rotation part ``x``.

    Far means ``|r·x| >= 0.05 |r| |x|`` (``x`` the first four coordinates).

    Parameters
    ----------
    Z : (k, 8) complex
    seed : int

    Returns
    -------
    (4,) int or None
        None if no vector is found in the tries allowed.

    Examples
    --------
    >>> choose_chart(np.array([[1, 0, 0, 0, 0, 0, 0, 0]], dtype=complex)).shape
    (4,)
    """
    X = np.asarray(Z)[:, :4]
    nx = np.linalg.norm(X, axis=1)
    rng = np.random.default_rng(seed)
    candidates = [np.array([1, 0, 0, 0])] + [rng.integers(-3, 4, size=4) for _ in range(_CHART_TRIES)]
    for r in candidates:
        if not np.any(r):
            continue
        if np.all(np.abs(X @ r) >= _CHART_MIN * np.linalg.norm(r) * nx):
            return r
    return None


def _float_system(Qf, r, z):
    G = np.array([z @ Qf[k] @ z for k in range(Qf.shape[0])] + [r @ z[:4] - 1.0])
    J = np.vstack([2.0 * (Qf @ z), np.concatenate([r, np.zeros(4)])[None].astype(complex)])
    return G, J


def krawczyk_certify(Q_exact: npt.NDArray[np.object_], Z: npt.ArrayLike, chart: Optional[npt.ArrayLike] = None,
                     seed: int = 0, radii: Optional[npt.ArrayLike] = None) -> KrawczykResult:
    """Prove solutions of ``z^T Q_k z = 0`` near float approximations ``Z`` (Krawczyk in arb).

    Parameters
    ----------
    Q_exact : (7, 8, 8) object array of Fraction
        The exact quadrics (:func:`exact_matrix`).
    Z : (k, 8) complex
        Approximate solutions in any scaling (projective points).
    chart : (4,) int, optional
        The real chart ``r . x = 1``; by default :func:`choose_chart` picks one.
    seed : int
    radii : (k,) float, optional
        Box half-widths to try first for each point (in the chart's scaling; e.g. those of the
        compiled certificate, :mod:`imagespace.spatial.fastcert`), before the default relative
        ones. Only proposals: arb proves whatever box it is given or reports failure.

    Returns
    -------
    KrawczykResult

    Raises
    ------
    ImportError
        If python-flint is missing.

    Examples
    --------
    >>> from imagespace.spatial.study import study_point
    >>> from imagespace.spatial.quadrics import sphere_quadric, study_quadric_matrix
    >>> rng = np.random.default_rng(0)
    >>> a, b = rng.integers(-3, 4, size=(6, 3)), rng.integers(-3, 4, size=(6, 3))
    >>> s = study_point([1.0, 0, 0, 0], [0.5, 0.25, 2.0])
    >>> L2 = [float(np.sum((b[i] + [0.5, 0.25, 2.0] - a[i]) ** 2)) for i in range(6)]
    >>> Q = np.concatenate([sphere_quadric(a, b, np.sqrt(L2)), study_quadric_matrix()[None]])
    >>> res = krawczyk_certify(exact_matrix(Q), s[None].astype(complex))
    >>> bool(res.certified[0]), int(res.real[0])
    (True, 1)
    """
    import flint

    Z = np.atleast_2d(np.asarray(Z, dtype=complex))
    k = Z.shape[0]
    m_eq = Q_exact.shape[0]
    proposals = None if radii is None else np.asarray(radii, dtype=float)
    if chart is None:
        chart = choose_chart(Z, seed) if k else np.array([1, 0, 0, 0])
        if chart is None:
            return KrawczykResult(Z, np.zeros(k), np.zeros(k, bool), -np.ones(k, np.int8), False,
                                  np.array([1, 0, 0, 0]), np.zeros(k, bool))
    r = np.asarray(chart, dtype=np.int64)
    Qf = np.array([[float(v) for v in row] for row in Q_exact.reshape(-1, 8)]).reshape(m_eq, 8, 8)
    old = flint.ctx.prec
    flint.ctx.prec = CERT_PRECISION
    try:
        Qs = flint.acb_mat([[flint.acb(flint.fmpq(v.numerator, v.denominator)) for v in row]
                            for row in Q_exact.reshape(-1, 8)])           # (7*8, 8), exact dyadics
        rrow = [flint.acb(int(v)) for v in r] + [flint.acb(0)] * 4
        points = np.zeros((k, 8), complex)
        radii = np.zeros(k)
        certified = np.zeros(k, bool)
        real = -np.ones(k, np.int8)
        displacement = np.zeros(k, bool)
        for i in range(k):
            z = Z[i] / (r @ Z[i, :4])
            for _ in range(_POLISH):
                G, J = _float_system(Qf, r, z)
                try:
                    z = z - np.linalg.solve(J, G)
                except np.linalg.LinAlgError:
                    break
            if not np.all(np.isfinite(z)):
                continue
            if np.abs(z.imag).max() <= _REAL_PROPOSAL * (1 + np.abs(z).max()):
                z = z.real.astype(complex)
                for _ in range(2):
                    G, J = _float_system(Qf, r, z)
                    try:
                        z = (z - np.linalg.solve(J, G)).real.astype(complex)
                    except np.linalg.LinAlgError:
                        break
            points[i] = z
            _, Jm = _float_system(Qf, r, z)
            try:
                Y = np.linalg.inv(Jm)
            except np.linalg.LinAlgError:
                continue
            tries = [rel * (1.0 + np.abs(z).max()) for rel in _RADII]
            if proposals is not None and proposals[i] > 0:
                tries = [float(proposals[i]), 4.0 * float(proposals[i])] + tries
            for rho in tries:
                ok, is_real, disp = _krawczyk_once(flint, Qs, rrow, m_eq, z, rho, Y)
                if ok:
                    certified[i] = True
                    radii[i] = rho
                    real[i] = is_real
                    displacement[i] = disp
                    break
            if not certified[i]:
                # an ill-conditioned solution (Jacobian condition ~1e7 near a double mode): the float
                # centre is too far off for any box the float Jacobian contracts; its centre refined
                # by Newton in arb at CERT_PRECISION bits, tiny boxes around it
                mid = _refine(flint, Qs, rrow, m_eq, z)
                if mid is not None:
                    size = 1.0 + np.abs(z).max()
                    for rel in _REFINED_RADII:
                        rho = rel * size
                        ok, is_real, disp = _krawczyk_once(flint, Qs, rrow, m_eq, z, rho, Y, mid=mid)
                        if ok:
                            # the float centre recorded is the refined one rounded: the radius
                            # recorded covers that rounding (disjointness is checked on it)
                            points[i] = np.array([complex(float(v.real.mid()), float(v.imag.mid())) for v in mid])
                            radii[i] = rho + _MID_ROUNDING * (1.0 + np.abs(points[i]).max())
                            certified[i] = True
                            real[i] = is_real
                            displacement[i] = disp
                            break
    finally:
        flint.ctx.prec = old
    disjoint = _pairwise_disjoint(points[certified], radii[certified])
    return KrawczykResult(points, radii, certified, real, disjoint, r, displacement)


def _stacked(flint, Qs, pts):
    """The acb column of ``pts`` and ``Q_k pts`` for every quadric, stacked ``(7*8, 1)``."""
    P = flint.acb_mat([[v] for v in pts])
    return P, Qs * P


def _values(flint, QP, rrow, m_eq, pts):
    """The chart's system ``(z^T Q_k z, r . x - 1)`` at ``pts`` (``QP`` from :func:`_stacked`)."""
    G = [sum((pts[j] * QP[8 * q + j, 0] for j in range(8)), flint.acb(0)) for q in range(m_eq)]
    G.append(sum((rrow[j] * pts[j] for j in range(8)), flint.acb(0)) - 1)
    return flint.acb_mat([[g] for g in G])


def _jacobian(flint, QP, rrow, m_eq):
    """The chart's Jacobian at the points (or box) whose stacked products are ``QP``."""
    return flint.acb_mat([[2 * QP[8 * q + j, 0] for j in range(8)] for q in range(m_eq)] + [rrow])


def _refine(flint, Qs, rrow, m_eq, z):
    """Newton's iterations on the chart's system at the context precision from the float point
    ``z`` (real points stay real): the centres as exact acb midpoints, or None where a Jacobian is
    not invertible. Only a proposal: the Krawczyk test decides."""
    real_centre = bool(np.all(z.imag == 0.0))
    mid = [flint.acb(float(v.real), float(v.imag)) for v in z]
    for _ in range(_REFINE):
        _, QM = _stacked(flint, Qs, mid)
        try:
            step = _jacobian(flint, QM, rrow, m_eq).solve(_values(flint, QM, rrow, m_eq, mid))
        except ZeroDivisionError:
            return None
        mid = [mid[j] - step[j, 0] for j in range(8)]
        mid = [flint.acb(v.real.mid(), 0 if real_centre else v.imag.mid()) for v in mid]
    return mid


def _krawczyk_once(flint, Qs, rrow, m_eq, z, rho, Y, mid=None):
    """One Krawczyk test on the box ``z +- rho`` (real and imaginary parts; centred at ``mid``,
    exact acb points, when given); (proved, real flag, x . x excludes 0 on the box)."""
    real_centre = bool(np.all(z.imag == 0.0))
    rad = flint.arb(0, rho)
    if mid is None:
        mid = [flint.acb(float(v.real), float(v.imag)) for v in z]
    box = [flint.acb(v.real + rad, v.imag + rad) for v in mid]
    M, QM = _stacked(flint, Qs, mid)
    _, QB = _stacked(flint, Qs, box)
    Gm = _values(flint, QM, rrow, m_eq, mid)
    JX = _jacobian(flint, QB, rrow, m_eq)         # every Jacobian on the box (J is linear in z)
    Ya = flint.acb_mat([[flint.acb(float(v.real), float(v.imag)) for v in row] for row in Y])
    D = flint.acb_mat([[box[j] - mid[j]] for j in range(8)])
    ident = flint.acb_mat([[1 if i == j else 0 for j in range(8)] for i in range(8)])
    K = M - Ya * Gm + (ident - Ya * JX) * D
    for j in range(8):
        if not box[j].contains_interior(K[j, 0]):
            return False, -1, False
    if real_centre:
        return True, 1, True                        # r . x = 1: x real and non-zero
    xx = sum((box[j] * box[j] for j in range(4)), flint.acb(0))
    disp = not (xx.real.contains(0) and xx.imag.contains(0))
    for j in range(8):
        im = box[j].imag
        if not im.contains(0):                      # the whole box is off the real space
            return True, 0, disp
    return True, -1, disp


def _pairwise_disjoint(points, radii):
    """Rigorous: every pair of boxes is separated in some real or imaginary coordinate part."""
    k = points.shape[0]
    if k < 2:
        return True
    parts = np.concatenate([points.real, points.imag], axis=1)          # (k, 16)
    for i in range(k):
        diff = np.abs(parts[i + 1:] - parts[i])                          # fl(a - b) >= |a - b| (1 - u)
        # arb stores a radius as a 30-bit magnitude rounded up: the boxes proven may be wider
        # than ``radii`` by a relative 2^-29; 2^-20 covers it and the float sum
        need = (radii[i + 1:] + radii[i]) * (1 + 2.0 ** -20)
        sep = np.any(diff * (1 - 2.0 ** -50) > need[:, None], axis=1)
        if not np.all(sep):
            return False
    return True
