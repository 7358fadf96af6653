"""An independent direct-kinematics solver for the tests: Euclidean geometry, no image space.

At a fixed orientation phi, legs 1 and 2 confine the translation t to a circle or a line
(written here from the leg definitions); their intersection points form at most two branches
t(phi). Leg 3's signed residual along each branch is sampled on a fine phi grid and every sign
change is refined by Brent's method.
"""

import numpy as np
from scipy.optimize import brentq

import imagespace as isp


def rot(phi, p):
    c, s = np.cos(phi), np.sin(phi)
    return np.array([c * p[0] - s * p[1], s * p[0] + c * p[1]])


def locus(leg, q, phi):
    """('circle', centre, radius) or ('line', point, direction) for the translation t."""
    g = leg.geometry(exact=False)
    kind = leg.joints
    if kind == "RPR":
        A, a = np.array(g["base"]), np.array(g["platform"])
        return ("circle", A - rot(phi, a), q)
    if kind == "RRR":
        A, a, (l1, l2) = np.array(g["base"]), np.array(g["platform"]), g["lengths"]
        return ("circle", A + l1 * np.array([np.cos(q), np.sin(q)]) - rot(phi, a), l2)
    if kind == "PRR":
        A, uu, a = np.array(g["base"]), np.array(g["axis"]), np.array(g["platform"])
        return ("circle", A + q * uu - rot(phi, a), g["length"])
    if kind == "PPR":
        C, uu, c, w = (np.array(g[k]) for k in ("base", "axis", "platform", "second_axis"))
        return ("line", C + q * uu - rot(phi, c), w)
    raise NotImplementedError(kind)


def residual(leg, q, phi, t):
    kind, P, r = locus(leg, q, phi)
    if kind == "circle":
        return np.sum((t - P) ** 2) - r * r
    n = np.array([-r[1], r[0]])
    return n @ (t - P)


def intersections(L1, L2):
    """Two branches (NaN where absent) of the intersection of two loci."""
    out = [np.full(2, np.nan), np.full(2, np.nan)]
    if L1[0] == "line" and L2[0] == "circle":
        L1, L2 = L2, L1
    if L1[0] == "circle" and L2[0] == "circle":
        (_, c1, r1), (_, c2, r2) = L1, L2
        d = np.linalg.norm(c2 - c1)
        if d == 0:
            return out
        along = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
        h2 = r1 * r1 - along * along
        if h2 < 0:
            return out
        ex = (c2 - c1) / d
        ey = np.array([-ex[1], ex[0]])
        h = np.sqrt(h2)
        return [c1 + along * ex + h * ey, c1 + along * ex - h * ey]
    if L1[0] == "circle":
        (_, c, r), (_, p, w) = L1, L2
        w = w / np.linalg.norm(w)
        bq = w @ (p - c)
        disc = bq * bq - (p - c) @ (p - c) + r * r
        if disc < 0:
            return out
        s = np.sqrt(disc)
        return [p + (-bq + s) * w, p + (-bq - s) * w]
    (_, p1, w1), (_, p2, w2) = L1, L2
    M = np.column_stack([w1, -w2])
    if abs(np.linalg.det(M)) < 1e-14:
        return out
    s = np.linalg.solve(M, p2 - p1)
    return [p1 + s[0] * w1, out[1]]


def brute_force_dk(m, q, samples=20000):
    """All real poses (x, y, phi) found by the sweep; q: three joint values."""
    legs = m.legs

    def branch_value(phi, k):
        pts = intersections(locus(legs[0], q[0], phi), locus(legs[1], q[1], phi))
        t = pts[k]
        if np.any(np.isnan(t)):
            return np.nan, t
        return residual(legs[2], q[2], phi, t), t

    phis = np.linspace(-np.pi, np.pi, samples + 1)
    found = []
    for k in (0, 1):
        vals = np.array([branch_value(p, k)[0] for p in phis])
        for i in range(samples):
            lo, hi = phis[i], phis[i + 1]
            f0, f1 = vals[i], vals[i + 1]
            if np.isfinite(f0) != np.isfinite(f1):
                # the branch ends inside this cell: bisect for its end and use it as the bracket end
                inside, outside = (lo, hi) if np.isfinite(f0) else (hi, lo)
                for _ in range(60):
                    mid = 0.5 * (inside + outside)
                    if np.isfinite(branch_value(mid, k)[0]):
                        inside = mid
                    else:
                        outside = mid
                if np.isfinite(f0):
                    hi, f1 = inside, branch_value(inside, k)[0]
                else:
                    lo, f0 = inside, branch_value(inside, k)[0]
            if not (np.isfinite(f0) and np.isfinite(f1)):
                continue
            if f0 == 0:
                root = lo
            elif f0 * f1 < 0:
                root = brentq(lambda p: branch_value(p, k)[0], lo, hi, xtol=1e-15)
            else:
                continue
            t = branch_value(root, k)[1]
            found.append(np.array([t[0], t[1], np.angle(np.exp(1j * root))]))
    # remove duplicates (roots on the grid counted twice, the seam at +-pi)
    unique = []
    for p in found:
        if not any(np.linalg.norm(p[:2] - u[:2]) < 1e-7 and abs(np.angle(np.exp(1j * (p[2] - u[2])))) < 1e-7
                   for u in unique):
            unique.append(p)
    return unique
