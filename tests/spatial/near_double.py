"""Seeded spatial rows near double modes (for the tests of ``reliable`` and the certificates).

A double mode is a real solution where the system's Jacobian is singular. The generator walks
along a curve of real poses ``z(t)`` on the design's pose manifold (Study's quadric, the
parameter-free quadrics such as the 3-RPS planes, ``x . x = 1``), each point a Gauss-Newton
projection of ``z0 + t v``, and bisects the sign of

    det [ 2 (A_k - p_k(z) E) z  (k = 0..6) ;  (x, 0) ],      p_k(z) = z^T A_k z / z^T E z,

the Jacobian of the system at the parameters the pose itself has. At a sign change the pose is a
singular solution of its own lengths ``L* = scale sqrt(p(z*))``: two real modes meet there. Rows
are ``L*`` moved by ``10^-e |L*|`` (``e = 2 .. 13``) in random directions: near the double mode
the real count changes, and the closest rows are at the double mode to within the rounding of
``L*`` itself. Nothing here uses the code under test beyond the family's float matrices.
"""

from __future__ import annotations

import numpy as np

import imagespace as isp
from imagespace.spatial.study import study_point

OFFSETS = 10.0 ** -np.arange(2, 14)


def _fixed(fam):
    return [k for k in range(fam.A.shape[0]) if fam.pidx[k] < 0]


def _params(fam, z):
    zEz = z @ fam.E @ z
    return np.array([z @ fam.A[k] @ z / zEz for k in range(fam.A.shape[0]) if fam.pidx[k] >= 0])


def _project(fam, z, steps=30):
    """Gauss-Newton onto the fixed quadrics and x . x = 1 (family scaling)."""
    fixed = _fixed(fam)
    for _ in range(steps):
        F = np.array([z @ fam.A[k] @ z for k in fixed] + [z[:4] @ z[:4] - 1.0])
        J = np.array([2 * fam.A[k] @ z for k in fixed] + [np.r_[2 * z[:4], np.zeros(4)]])
        dz = np.linalg.lstsq(J, F, rcond=None)[0]
        z = z - dz
        if np.abs(dz).max() < 1e-16:
            break
    return z


def _det(fam, z):
    p = _params(fam, z)
    rows = []
    for k in range(fam.A.shape[0]):
        Q = fam.A[k] - (p[fam.pidx[k]] * fam.E if fam.pidx[k] >= 0 else 0)
        rows.append(2 * Q @ z)
    rows.append(np.r_[z[:4], np.zeros(4)])
    J = np.array(rows)
    return np.linalg.det(J) / np.prod(np.linalg.norm(J, axis=1))


def singular_lengths(platform, z0, rng, span=0.6, grid=60):
    """Lengths of a singular pose on a random curve through ``z0`` (a real pose in the family's
    scaling), or None when the curve crosses no singularity."""
    fam = platform.family()
    v = rng.normal(size=8)
    ts = np.linspace(0.0, span, grid)
    zs = [_project(fam, z0.copy())]
    for t in ts[1:]:
        zs.append(_project(fam, zs[-1] + (ts[1] - ts[0]) * v))
    vals = np.array([_det(fam, z) for z in zs])
    k = np.flatnonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) < 0)
    if not k.size:
        return None
    i = int(k[0])
    za, zb = zs[i], zs[i + 1]
    fa = vals[i]
    for _ in range(80):
        zm = _project(fam, 0.5 * (za + zb))
        fm = _det(fam, zm)
        if np.sign(fm) == np.sign(fa):
            za, fa = zm, fm
        else:
            zb = zm
        if np.abs(za - zb).max() < 1e-16:
            break
    p = _params(fam, za)
    if np.any(p <= 0):
        return None
    return np.sqrt(p) * fam.scale


def real_pose(platform, rng, pool=None):
    """A real pose of the design in the family's scaling: a random pose for a Gough-Stewart
    platform, otherwise a mode from ``pool`` (:func:`mode_pool`)."""
    fam = platform.family()
    if isinstance(platform, isp.GoughStewart):
        s = study_point(rng.normal(size=4), rng.uniform(-0.3, 0.3, 3) + [0, 0, 1.2])
        z = s / np.linalg.norm(s[:4])
        z[4:] /= fam.scale
        return z
    if pool is None or not len(pool):
        return None
    z = pool[rng.integers(len(pool))].copy()
    z[4:] /= fam.scale
    return z / np.linalg.norm(z[:4])


def mode_pool(platform, rng, rows=64):
    """Real modes of random lengths (one batch), the starting poses of designs with fixed quadrics."""
    if isinstance(platform, isp.GoughStewart):
        return None
    L = rng.uniform(0.8, 3.0, (rows, platform.leg_count))
    return platform.direct_kinematics_batch(L).study_points


def near_double_rows(platform, rng, points, offsets=OFFSETS):
    """``points`` singular length vectors of the design, each moved by every offset in a random
    direction: an array ``(points * len(offsets), legs)``."""
    rows = []
    tries = 0
    pool = mode_pool(platform, rng)
    while len(rows) < points * len(offsets) and tries < 20 * points:
        tries += 1
        z0 = real_pose(platform, rng, pool)
        if z0 is None:
            continue
        L = singular_lengths(platform, z0, rng)
        if L is None:
            continue
        for e in offsets:
            u = rng.normal(size=L.shape[0])
            rows.append(L * (1 + e * u / np.linalg.norm(u)))
    return np.array(rows)


def design_66(seed):
    rng = np.random.default_rng(seed)
    return isp.GoughStewart(rng.integers(-8, 9, (6, 3)) / 8.0, rng.integers(-8, 9, (6, 3)) / 16.0)


def design_63(seed):
    rng = np.random.default_rng(seed)
    base = rng.integers(-16, 17, (6, 3)) / 8.0
    tri = rng.integers(-16, 17, (3, 3)) / 16.0
    return isp.GoughStewart(base, tri[[0, 1, 1, 2, 2, 0]])


def design_36(seed):
    rng = np.random.default_rng(seed)
    tri = rng.integers(-16, 17, (3, 3)) / 8.0
    plat = rng.integers(-16, 17, (6, 3)) / 16.0
    return isp.GoughStewart(tri[[0, 0, 1, 1, 2, 2]], plat)


def design_33(seed):
    rng = np.random.default_rng(seed)
    btri = rng.integers(-16, 17, (3, 3)) / 8.0
    ptri = rng.integers(-16, 17, (3, 3)) / 16.0
    return isp.GoughStewart(btri[[0, 0, 1, 1, 2, 2]], ptri[[0, 1, 1, 2, 2, 0]])


def design_3rps(seed):
    rng = np.random.default_rng(seed)
    return isp.ThreeRPS(rng.integers(-4, 5, (3, 3)) / 2.0, rng.integers(-4, 5, (3, 3)) / 4.0,
                        base_axes=rng.integers(-3, 4, (3, 3)))


FAMILIES = {"6-6": design_66, "6-3": design_63, "3-6": design_36, "3-3": design_33, "3-RPS": design_3rps}
