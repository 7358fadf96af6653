r"""Rigorous enclosures of binary forms in double precision, vectorised over rows.

Three tools, each a proof on every row it answers (rounding bounded by ``gamma_k = k u / (1 - k u)``,
``u = 2**-53``, and the coefficient uncertainty the caller passes):

* :func:`inclusion_discs` -- discs that each hold exactly one root of a polynomial known up to a
  coefficient box (the Gerschgorin-type bound ``d |p(z_i)| / (|a_d| prod |z_i - z_j|)``), real or
  non-real decided by the disc's position;
* :func:`form_signs_on` -- the sign of a form over an interval of the projective line;
* :func:`no_common_real_root` -- two forms proven to share no real root (the Cramer denominator of
  the back substitution against the kinematic form).

A row that cannot be decided is reported as such (``good`` False, sign 0, not proven); it is never
a claim about the row.
"""

from __future__ import annotations

import numpy as np

__all__ = ["inclusion_discs", "form_signs_on", "no_common_real_root"]

#: the unit roundoff of IEEE double precision
UNIT_ROUNDOFF = 2.0**-53
_U = UNIT_ROUNDOFF


def inclusion_discs(F, E=None):
    """Inclusion discs of the roots of float polynomials known up to ``E``, with rounding bounds.

    The vectorised core of :func:`imagespace.core.certify.certify_real_roots_batch` (see there for the theorem and the
    rounding bounds); also the near-singularity test of the floating-point paths.

    Parameters
    ----------
    F : (n, d+1) float
        ``F[:, k]`` multiplies ``t**k``; the leading coefficients must exceed ``E[:, d]``.
    E : (n, d+1) float, optional
        Coefficient uncertainty (default 0).

    Returns
    -------
    good : (n,) bool
        The discs are pairwise disjoint and each is decided (real or non-real).
    real : (n, d) bool
        Which discs hold a real (then simple) root, where ``good``.
    z : (n, d) complex
        Disc centres.
    hull_r : (n, d) float
        Radius of the disc centred on the real axis that covers a disc and its mirror image.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.form_bounds import inclusion_discs
    >>> good, real, z, r = inclusion_discs(np.array([[-2.0, 0.0, 1.0], [1.0, -2.0, 1.0]]))
    >>> good.tolist(), real[0].tolist()
    ([True, False], [True, True])
    """
    F = np.asarray(F, dtype=float)
    E = np.zeros_like(F) if E is None else np.asarray(E, dtype=float)
    n, d1 = F.shape
    d = d1 - 1
    comp = np.zeros((n, d, d))
    if d > 1:
        comp[:, np.arange(1, d), np.arange(d - 1)] = 1.0
    with np.errstate(all="ignore"):
        comp[:, :, d - 1] = -F[:, :d] / F[:, d][:, None]
        if d > 1:
            fin = np.all(np.isfinite(comp), axis=(1, 2))
            z = np.full((n, d), np.nan + 0j)
            if np.any(fin):
                z[fin] = np.linalg.eigvals(comp[fin])
        else:
            z = -(F[:, 0] / F[:, 1])[:, None].astype(complex)
        # Horner on the float coefficients, with its rounding bound and the coefficient box
        val = np.zeros_like(z)
        absum = np.zeros(z.shape)
        errsum = np.zeros(z.shape)
        az = np.abs(z)
        for k in range(d, -1, -1):
            val = val * z + F[:, k][:, None]
            absum = absum * az + np.abs(F[:, k])[:, None]
            errsum = errsum * az + E[:, k][:, None]
        gamma = (4 * d + 4) * _U / (1 - (4 * d + 4) * _U)   # complex Horner, generous
        pbound = (np.abs(val) * (1 + 4 * _U) + 2 * gamma * absum + errsum) * (1 + 4 * _U)
        diff = z[:, :, None] - z[:, None, :]
        diff[:, np.arange(d), np.arange(d)] = 1.0
        lead = (np.abs(F[:, d]) - E[:, d]) * (1 - 2 * _U)
        denom = lead[:, None] * np.prod(np.abs(diff), axis=2)
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
    return good, real, z, hull_r


def form_signs_on(F, E, lo, hi, chart=None):
    """Proven signs of binary forms over intervals of the projective line, vectorised.

    Row ``i`` is a binary form ``sum F[i, k] x0**(d-k) x1**k`` known up to ``E`` (the exact form
    lies in ``F +- E``); slot ``j`` an interval ``[lo[i, j], hi[i, j]]`` of ``t = x1/x0``
    (``chart`` 0) or of ``s = x0/x1`` (``chart`` 1). The form is evaluated in that chart at the
    interval's midpoint by Horner, and the value enlarged by a rigorous bound on the rounding
    (``gamma_{4d+4}`` times ``sum |F_k| |m|**k``), the coefficient uncertainty
    (``sum E_k A**k``, ``A`` the largest ``|u|`` on the interval) and the variation over the
    interval (the derivative bound ``sum k (|F_k| + E_k) A**(k-1)`` times its half width): a sign
    is returned only when that box excludes zero, for every form in ``F +- E``. For a form of
    even degree this is the sign of the form at every point of the interval's arc of the
    projective line.

    Parameters
    ----------
    F, E : (n, d+1) float
    lo, hi : (n, k) float
        NaN in unused slots.
    chart : (n, k) int, optional
        Default 0 everywhere; -1 marks an unused slot.

    Returns
    -------
    (n, k) int8
        +1 or -1 where proven, 0 where undecided or unused.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.form_bounds import form_signs_on
    >>> F = np.array([[-1.0, 0.0, 1.0]])                 # x1^2 - x0^2: negative for |t| < 1
    >>> form_signs_on(F, np.zeros_like(F), np.array([[0.0, 2.0, 0.9]]), np.array([[0.5, 3.0, 1.1]])).tolist()
    [[-1, 1, 0]]
    """
    F = np.asarray(F, dtype=float)
    E = np.asarray(E, dtype=float)
    lo = np.asarray(lo, dtype=float)
    hi = np.asarray(hi, dtype=float)
    n, d1 = F.shape
    d = d1 - 1
    chart = np.zeros(lo.shape, dtype=np.int8) if chart is None else np.asarray(chart)
    gamma = (4 * d + 4) * _U / (1 - (4 * d + 4) * _U)
    out = np.zeros(lo.shape, dtype=np.int8)
    with np.errstate(all="ignore"):
        for c in (0, 1):
            G = F if c == 0 else F[:, ::-1]                  # the chart's coefficients of u**k
            H = E if c == 0 else E[:, ::-1]
            use = (chart == c) & np.isfinite(lo) & np.isfinite(hi) & (lo <= hi)
            mid = np.where(use, lo + (hi - lo) / 2, 0.0)
            mid = np.clip(mid, lo, hi)
            rad = np.maximum(hi - mid, mid - lo) * (1 + 4 * _U)
            A = np.maximum(np.abs(lo), np.abs(hi)) * (1 + 2 * _U)
            am = np.abs(mid)
            val = np.zeros(lo.shape)
            absum = np.zeros(lo.shape)
            err = np.zeros(lo.shape)
            slope = np.zeros(lo.shape)
            for k in range(d, -1, -1):
                g, h = G[:, k][:, None], H[:, k][:, None]
                val = val * mid + g
                absum = absum * am + np.abs(g)
                err = err * A + h
                if k >= 1:
                    slope = slope * A + k * (np.abs(g) + h)
                # slope accumulates sum_k k (|g_k| + h_k) A**(k-1) by Horner on the k >= 1 terms
            bound = (2 * gamma * absum + err + slope * rad) * (1 + 8 * (d + 2) * _U) + 2.0 ** -1000
            sign = np.where(val > bound, 1, np.where(val < -bound, -1, 0))
            ok = use & np.isfinite(bound) & np.isfinite(val)
            out = np.where(ok, sign, out).astype(np.int8)
    return out


def no_common_real_root(F, EF, D, ED):
    """Rows whose binary forms ``F`` and ``D`` (known up to ``EF``, ``ED``) are proven to have no
    common real root on the projective line, vectorised.

    The real roots of ``D`` are enclosed by inclusion discs (:func:`inclusion_discs`) in a chart
    where its leading coefficient is proven non-zero (``t = x1/x0``, else ``s = x0/x1``), so every
    real root of ``D`` lies in one of the intervals found; ``F`` is then proven non-zero on each
    (:func:`form_signs_on`). A row whose ``D`` vanishes within its bounds, has a root the discs do
    not separate, or meets a root of ``F`` is not proven (False): it is not a claim that a common
    root exists.

    Parameters
    ----------
    F, EF : (n, d+1) float
    D, ED : (n, e+1) float

    Returns
    -------
    (n,) bool

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.form_bounds import no_common_real_root
    >>> F = np.array([[-1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]])        # x1^2 - x0^2: t = -1, 1
    >>> D = np.array([[-2.0, 1.0], [-1.0, 1.0]])                  # x1 - 2 x0 (t = 2); x1 - x0 (t = 1)
    >>> no_common_real_root(F, np.zeros_like(F), D, np.zeros_like(D)).tolist()
    [True, False]
    """
    F, EF, D, ED = (np.asarray(a, dtype=float) for a in (F, EF, D, ED))
    n, e1 = D.shape
    out = np.zeros(n, dtype=bool)
    todo = np.all(np.isfinite(D) & np.isfinite(ED), axis=1) & np.all(np.isfinite(F) & np.isfinite(EF), axis=1)
    for c in (0, 1):
        Dc, Ec = (D, ED) if c == 0 else (D[:, ::-1], ED[:, ::-1])
        rows = np.flatnonzero(todo & (np.abs(Dc[:, -1]) > Ec[:, -1]))
        if not rows.size:
            continue
        todo[rows] = False
        good, real, z, hull_r = inclusion_discs(Dc[rows], Ec[rows])
        grow = 1 + 8 * _U
        lo = (z.real - hull_r * grow) - np.abs(z.real) * 4 * _U
        hi = (z.real + hull_r * grow) + np.abs(z.real) * 4 * _U
        lo, hi = np.where(real, lo, np.nan), np.where(real, hi, np.nan)
        chart = np.where(real, c, -1).astype(np.int8)
        signs = form_signs_on(F[rows], EF[rows], lo, hi, chart)
        out[rows] = good & np.all(~real | (signs != 0), axis=1)
    return out
