r"""Roots of binary forms on the real projective line, batched.

A binary form ``F(x0, x1)`` of degree ``d`` has ``d`` roots ``(x0 : x1)`` on the complex projective
line; the real ones are the orientations of assembly modes (``x1/x0 = tan(phi/2)``), with
``x0 = 0`` (the half-turn) an ordinary root. To avoid a privileged chart, each form is first
rotated, ``(x0, x1) = R(gamma) (y0, y1)``, so that the point sent to infinity is the one of eight
fixed directions where ``|F|`` is largest (a degree-6 form has at most six roots, so at least two
of the eight directions are away from every root); the roots of the rotated form in ``t = y1/y0``
are then eigenvalues of a well-scaled companion matrix, and a real root ``t`` is the
half-angle ``gamma + arctan(t)``.

Floating-point roots are candidates: the callers polish them (Newton here and on the full
constraint system) and check every reported mode.
"""

from __future__ import annotations

import numpy as np

from .elimination import bf_add, bf_mul, bf_scale
from ..tolerances import TOLERANCES

__all__ = ["projective_roots", "rotated_forms", "real_half_angles", "polish_half_angles", "bf_eval_angle"]

_GAMMAS = np.arange(8) * (np.pi / 8)


def _rotate(F, c, s):
    """Coefficients of F(c y0 - s y1, s y0 + c y1) (F: list of (n,) arrays)."""
    d = len(F) - 1
    lx0, lx1 = [c, -s], [s, c]
    out = [np.zeros_like(c)] * (d + 1)
    for k, fk in enumerate(F):
        term = [np.ones_like(c)]
        for _ in range(d - k):
            term = bf_mul(term, lx0)
        for _ in range(k):
            term = bf_mul(term, lx1)
        out = bf_add(out, bf_scale(term, fk))
    return out


def bf_eval_angle(F, theta):
    """Values of binary forms ``F`` ((n, d+1) array) at ``(cos theta, sin theta)``, broadcast.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.roots import bf_eval_angle
    >>> bf_eval_angle(np.array([[1.0, 0.0, 1.0]]), np.array([[0.3]]))   # x0^2 + x1^2
    array([[1.]])
    """
    F = np.asarray(F, dtype=float)
    d = F.shape[-1] - 1
    c, s = np.cos(theta), np.sin(theta)
    # homogeneous Horner: (((f_d s + f_(d-1) c) s + f_(d-2) c^2) s + ...)
    acc = np.broadcast_to(F[..., d][..., None], np.broadcast_shapes(F.shape[:-1] + (1,), c.shape)).copy()
    cp = np.ones_like(acc)
    for k in range(d - 1, -1, -1):
        cp = cp * c
        acc = acc * s + F[..., k][..., None] * cp
    return acc


def _bf_derivative_angle(F, theta):
    # d/dtheta F(cos, sin) = (-x1 dF/dx0 + x0 dF/dx1) at (cos, sin): a binary form of degree d
    # with coefficients g_j = (j + 1) f_(j+1) - (d - j + 1) f_(j-1)
    d = F.shape[-1] - 1
    j = np.arange(d + 1)
    up = np.concatenate([F[..., 1:], np.zeros(F.shape[:-1] + (1,))], axis=-1) * (j + 1)
    down = np.concatenate([np.zeros(F.shape[:-1] + (1,)), F[..., :-1]], axis=-1) * (d - j + 1)
    return bf_eval_angle(up - down, theta)


_ROTATIONS: dict[int, np.ndarray] = {}


def _rotation_matrices(d):
    """(8, d+1, d+1): row k of matrix j holds the coefficients of ``x0^(d-k) x1^k`` after the
    substitution by the rotation ``_GAMMAS[j]`` (so rotated forms are one matrix product)."""
    if d not in _ROTATIONS:
        c, s = np.cos(_GAMMAS), np.sin(_GAMMAS)
        mats = np.zeros((8, d + 1, d + 1))
        for k in range(d + 1):
            unit = [np.full(8, float(j == k)) for j in range(d + 1)]
            mats[:, k, :] = np.stack(_rotate(unit, c, s), axis=1)
        _ROTATIONS[d] = mats
    return _ROTATIONS[d]


def _rotated(F):
    F = np.asarray(F, dtype=float)
    n, d1 = F.shape
    vals = np.abs(bf_eval_angle(F, (_GAMMAS + np.pi / 2)[None, :].repeat(n, 0)))
    j = np.argmax(np.nan_to_num(vals, nan=-1.0), axis=1)
    gamma = _GAMMAS[j]
    scale = np.max(np.abs(F), axis=1)
    best = vals[np.arange(n), j]
    ok = np.isfinite(scale) & (best > 0) & np.all(np.isfinite(F), axis=1)
    with np.errstate(invalid="ignore", over="ignore"):
        G = np.einsum("nk,nkl->nl", F, _rotation_matrices(d1 - 1)[j])   # (n, d+1)
    return G, ok, gamma


def rotated_forms(F):
    """Each binary form rotated so that the direction of largest ``|F|`` among eight is ``t = oo``.

    Parameters
    ----------
    F : (n, d+1) float

    Returns
    -------
    G : (n, d+1) float
        Coefficients of ``F(c y0 - s y1, s y0 + c y1)``; ``G[:, d]`` (the leading coefficient in
        ``t = y1/y0``) is the largest of the eight values, so the roots are well scaled.
    ok : (n,) bool
        False where the form vanishes identically or is not finite.
    gamma : (n,) float
        The rotation: ``t = y1/y0`` of the rotated form is the half-angle ``gamma + arctan(t)``.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.roots import rotated_forms
    >>> G, ok, gamma = rotated_forms(np.array([[0.0, 1.0, 0.0]]))     # x0 x1
    >>> ok.tolist(), bool(abs(G[0, 2]) > 0)
    ([True], True)
    """
    return _rotated(F)


def projective_roots(F):
    """All complex roots of a batch of binary forms in a well-conditioned rotated chart.

    Parameters
    ----------
    F : (n, d+1) float
        Coefficients, ``F[:, k]`` multiplying ``x0**(d-k) x1**k``.

    Returns
    -------
    t : (n, d) complex
        Roots in the chart ``t = y1/y0`` of the rotated coordinates.
    gamma : (n,) float
        The rotation: a root ``t`` is the point ``(cos g - t sin g : sin g + t cos g)``.
    ok : (n,) bool
        False where the form vanishes identically (or has non-finite coefficients).

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.roots import projective_roots
    >>> t, g, ok = projective_roots(np.array([[0.0, 1.0, 0.0]]))   # x0 x1: roots (1:0), (0:1)
    >>> ok
    array([ True])
    """
    G, ok, gamma = _rotated(F)
    n, d1 = G.shape
    d = d1 - 1
    lead = np.where(ok, G[:, d], 1.0)
    comp = np.zeros((n, d, d))
    if d > 1:
        comp[:, np.arange(1, d), np.arange(d - 1)] = 1.0
    comp[:, :, d - 1] = -np.where(ok[:, None], G[:, :d], 0.0) / lead[:, None]
    t = np.linalg.eigvals(comp) if d > 0 else np.zeros((n, 0), complex)
    return t, gamma, ok


def real_half_angles(F, tol=None):
    """Real roots of binary forms as half-angles ``theta`` (``(x0, x1) = (cos theta, sin theta)``).

    Parameters
    ----------
    F : (n, d+1) float
    tol : float, optional
        Imaginary-part threshold (default ``TOLERANCES.real_root_imag``).

    Returns
    -------
    theta : (n, d) float
        Polished half-angles in ``(-pi/2, pi/2]``, NaN where a root is not (close to) real.
    ok : (n,) bool
        As in :func:`projective_roots`.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.roots import real_half_angles
    >>> th, ok = real_half_angles(np.array([[0.0, 1.0, 0.0]]))   # x0 x1
    >>> np.sort(np.round(th[0], 12))
    array([0.      , 1.570796])
    """
    tol = TOLERANCES.real_root_imag if tol is None else tol
    F = np.asarray(F, dtype=float)
    t, gamma, ok = projective_roots(F)
    real = np.abs(t.imag) <= tol * (1 + np.abs(t))
    theta = np.where(real & ok[:, None], gamma[:, None] + np.arctan(t.real), np.nan)
    theta = polish_half_angles(F, theta)
    # canonical half-angle in (-pi/2, pi/2]
    theta = np.pi / 2 - np.remainder(np.pi / 2 - theta, np.pi)
    return theta, ok


# polish_half_angles: the largest Newton step (radians of the half-angle), a safeguard of the
# method (a step is kept only where it decreases |F|), not a decision
_MAX_POLISH_STEP = 0.05


def polish_half_angles(F, theta, steps=4):
    """A few safeguarded Newton steps on ``F(cos theta, sin theta) = 0`` (NaN entries stay NaN).

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.roots import polish_half_angles
    >>> polish_half_angles(np.array([[1.0, 0.0, -1.0]]), np.array([[0.78]]))   # x0^2 - x1^2
    array([[0.78539816]])
    """
    theta = np.array(theta, dtype=float)
    f = bf_eval_angle(F, theta)
    for _ in range(steps):
        fp = _bf_derivative_angle(F, theta)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(np.abs(fp) > 0, f / fp, 0.0)
        step = np.clip(np.nan_to_num(step), -_MAX_POLISH_STEP, _MAX_POLISH_STEP)
        trial = theta - step
        ft = bf_eval_angle(F, trial)
        # safeguard: a step is taken only where it decreases |F| (near a double root the
        # derivative is rounding noise and an unguarded step would leave the root)
        better = np.abs(ft) < np.abs(f)
        theta = np.where(better, trial, theta)
        f = np.where(better, ft, f)
    return theta
