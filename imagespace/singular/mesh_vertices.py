"""The vertex step of the mesher: every marching-cubes vertex moved onto the surface and
certified by a proven sign change within the wanted distance (see
:mod:`imagespace.singular.meshing` for what "certified" means and how signs are known).

A vertex on a grid edge is located along its edge, first from a polynomial fit where the function
is a polynomial in the edge's variable, then by a safeguarded Newton iteration kept inside a
bracket of proven signs; a vertex its edge does not certify is searched along the other grid
directions, the gradient and the cube diagonals, and the bracket found is bisected on proven
signs. Split from :mod:`imagespace.singular.meshing` (issue [15]). Not public API.
"""

from __future__ import annotations

import numpy as np

from .proven_sign import UNIT_ROUNDOFF

__all__: list = []

# numerical knobs of the vertex step (index units are grid cells)
_NEWTON_STEPS = 200               # safeguarded Newton / bisection steps along an edge
_NEWTON_SMALL = 0.25              # a Newton step below this fraction of the wanted width has converged
_SEARCH_STEPS = (0.25, 0.5, 1.0)  # neighbourhood search: points at these multiples of a cell on each side
_BISECT_TRIES = (0.5, 0.375, 0.625, 0.25, 0.75)  # tried in turn while a bisection point's sign is undecided
_BISECT_STEPS = 80                # bisection steps of the neighbourhood search (2 cells -> tol needs ~25)
_FIT_MAX_DEGREE = 8               # edges are located from a polynomial fit up to this degree in the edge variable


def certify_vertices(func, verts, origin, h, tol_abs, budget, on_grid, grid):
    """Move marching-cubes vertices onto the surface and certify each (the vertex step of
    :func:`imagespace.singular.meshing.mesh_implicit`; not public API).

    ``verts`` are in grid-index units, ``origin`` and ``h`` the grid's corner and cell sizes,
    ``tol_abs`` the wanted distance bound, ``budget`` an :class:`ArbBudget`, ``on_grid`` the
    tolerance ``mesh_on_grid`` (grid cells), ``grid`` the function's values on the grid.

    Returns ``(V, bound, resid, searched)``: the vertices ``(n, 3)``, the certified distance bound
    per vertex (``inf`` where no proven sign change within ``tol_abs`` was found; the vertex is
    then left at its marching-cubes place), the largest ``|F|/|grad F|``, and how many vertices
    needed the neighbourhood search.
    """
    n = len(verts)
    frac = np.abs(verts - np.round(verts))
    # a vertex on a grid node (marching cubes interpolated next to a tiny value) starts at the node
    P0 = origin + np.where((frac <= on_grid).all(axis=1)[:, None], np.round(verts), verts) * h
    V = P0.copy()
    bound = np.full(n, np.inf)
    if n == 0:
        return V, bound, 0.0, 0
    on_edge = (frac > on_grid).sum(axis=1) == 1          # between grid planes along exactly one axis
    axis = np.argmax(frac, axis=1)
    k = np.flatnonzero(on_edge)
    if k.size:
        # edges along a variable F is a polynomial in: its restriction, fitted per edge
        Ve, be = _project_edges_polynomial(func, verts[k], axis[k], origin, h, tol_abs, grid)
        V[k], bound[k] = Ve, be
        k = k[~(be <= tol_abs)]
    if k.size:
        Ve, be = _project_edges(func, verts[k], axis[k], origin, h, tol_abs, budget)
        V[k], bound[k] = Ve, be
    first = np.where(on_edge, axis, -1)
    rest = np.flatnonzero(~(bound <= tol_abs))
    if rest.size:
        Vs, bs = _search(func, P0[rest], first[rest], h, tol_abs, budget)
        V[rest], bound[rest] = Vs, bs
    f, g = func.value_and_gradient(V)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.abs(f) / _norm3(g)
    r = np.where((f == 0) | ~np.isfinite(bound), 0.0, r)
    resid = float(np.nanmax(r)) if np.any(np.isfinite(r)) else 0.0
    return V, bound, resid, int(rest.size)


def _edge_frames(verts, axis, origin, h):
    """Per marching-cubes vertex: the lower grid node ``a`` of its edge, the edge vector ``e`` and
    the vertex's edge parameter ``s`` in ``[0, 1]``."""
    n = len(verts)
    rows = np.arange(n)
    lo_idx = np.round(verts).astype(float)
    lo_idx[rows, axis] = np.floor(verts[rows, axis])
    a = origin + lo_idx * h
    e = np.zeros((n, 3))
    e[rows, axis] = h[axis]
    s = verts[rows, axis] - lo_idx[rows, axis]
    return a, e, s


def _project_edges_polynomial(func, verts, axis, origin, h, tol_abs, G):
    """Vertices on edges along a variable in which ``func`` is a polynomial of degree ``d``
    (:meth:`Implicit.degree_in`): its restriction to the grid line through the edge is the
    interpolant of ``d + 1`` consecutive grid values ``G`` on that line (the edge's two nodes among
    them), its root in the edge located by safeguarded Newton on that interpolant, and the vertex
    certified exactly as in :func:`_project_edges`, by proven opposite signs of ``func`` itself at
    two points about ``tol_abs / 2`` on either side. The interpolant only proposes where to look.
    Returns ``(V, bound)`` with ``bound = inf`` where this found no certificate (those go through
    :func:`_project_edges`)."""
    n = len(verts)
    G = np.ascontiguousarray(G, dtype=float)            # flat indices below assume C order
    a, e, s0 = _edge_frames(verts, axis, origin, h)
    node = np.round((a - origin) / h).astype(np.int64)
    V = a + np.clip(s0, 0.0, 1.0)[:, None] * e
    bound = np.full(n, np.inf)
    for k in range(3):
        d = func.degree_in(k)
        rows = np.flatnonzero(axis == k)
        N = G.shape[k]
        if d is None or d < 1 or d > _FIT_MAX_DEGREE or d + 1 > N or rows.size == 0:
            continue
        i = node[rows, k]
        start = np.clip(i - (d - 1) // 2, 0, N - 1 - d)
        off = start - i                                    # the window's first node, relative to the edge's
        stride = G.strides[k] // G.itemsize
        flat = np.ravel_multi_index(tuple(node[rows].T), G.shape) + off * stride
        Gf = G.reshape(-1)
        F = np.stack([Gf[flat + j * stride] for j in range(d + 1)], axis=-1)
        f0 = F[np.arange(rows.size), -off]
        f1 = F[np.arange(rows.size), 1 - off]
        ok = np.isfinite(F).all(axis=1) & (f0 != 0) & (f1 != 0) & (np.sign(f0) != np.sign(f1))
        rows, F, off, f0 = rows[ok], F[ok], off[ok], f0[ok]
        if rows.size == 0:
            continue
        C = np.empty_like(F)                               # power basis in the edge parameter
        for o in np.unique(off):
            sel = off == o
            # by einsum, not a BLAS product (its threads keep spinning after small products)
            C[sel] = np.einsum("ij,kj->ik", F[sel], np.linalg.inv(np.vander(o + np.arange(d + 1.0), increasing=True)))
        ak, ek = a[rows], e[rows]
        sg_lo = np.sign(f0)
        delta = tol_abs / h[k]
        s = np.clip(s0[rows], 0.0, 1.0)
        lo, hi = np.zeros(rows.size), np.ones(rows.size)
        act = np.arange(rows.size)
        full = True                                        # whole arrays while most rows still move
        for _ in range(_NEWTON_STEPS):
            if act.size == 0:
                break
            if full and 4 * act.size < rows.size:
                full = False
            if full:
                act = np.arange(rows.size)
            sa, Ca = s[act], C[act]
            p = Ca[:, d].copy()
            dp = np.zeros(act.size)
            for j in range(d - 1, -1, -1):                # Horner for the value and the derivative
                dp = dp * sa + p
                p = p * sa + Ca[:, j]
            same = np.sign(p) == sg_lo[act]
            lo[act] = np.where(same, sa, lo[act])
            hi[act] = np.where(~same & (p != 0), sa, hi[act])
            with np.errstate(divide="ignore", invalid="ignore"):
                sn = sa - p / dp
            inside = np.isfinite(sn) & (sn > lo[act]) & (sn < hi[act])
            sn = np.where(p == 0, sa, np.where(inside, sn, 0.5 * (lo[act] + hi[act])))
            s[act] = sn
            act = act[~((np.abs(sn - sa) < _NEWTON_SMALL * delta) | (p == 0) | (hi[act] - lo[act] <= delta))]
        pl = np.maximum(s - 0.5 * delta, 0.0)
        ph = np.minimum(s + 0.5 * delta, 1.0)
        Pl, Ph = ak + pl[:, None] * ek, ak + ph[:, None] * ek
        f, b, _ = func.value_bound(np.concatenate([Pl, Ph]))
        m = rows.size
        fl, fh, bl, bh = f[:m], f[m:], b[:m], b[m:]
        proven = (np.abs(fl) > bl) & (np.abs(fh) > bh) & (np.sign(fl) * np.sign(fh) < 0)
        Vk = ak + (0.5 * (pl + ph))[:, None] * ek
        # the three points differ in coordinate k only (the others are ak's, exactly): the
        # distances are the differences there
        bk = np.maximum(np.abs(Vk[:, k] - Pl[:, k]), np.abs(Vk[:, k] - Ph[:, k])) * (1 + 8 * UNIT_ROUNDOFF)
        good = proven & (bk <= tol_abs)
        V[rows[good]], bound[rows[good]] = Vk[good], bk[good]
    return V, bound


def _project_edges(func, verts, axis, origin, h, tol_abs, budget):
    """Safeguarded Newton along the marching-cubes edge of each vertex, certified by two points
    about ``tol_abs / 2`` on either side whose signs are proven (:meth:`Implicit.proven_sign`).
    Returns ``(V, bound)``."""
    n = len(verts)
    a, e, s = _edge_frames(verts, axis, origin, h)
    delta = tol_abs / h[axis]                    # wanted bracket width in the edge parameter

    lo, hi = np.zeros(n), np.ones(n)
    pair = np.full((n, 2), np.nan)               # edge parameters of a pair with proven opposite signs
    f_lo = func.value(a)
    f_hi = func.value(a + e)
    sg_lo = np.sign(f_lo)
    done = (f_lo == 0) | (f_hi == 0)
    s = np.where(f_lo == 0, 0.0, np.where(f_hi == 0, 1.0, s))
    lo[done] = hi[done] = s[done]
    bad = ~done & (np.sign(f_hi) == sg_lo)       # no float sign change along the edge
    done |= bad
    act = np.flatnonzero(~done)
    for _ in range(_NEWTON_STEPS):
        if act.size == 0:
            break
        P = a[act] + s[act, None] * e[act]
        f, g = func.value_and_gradient(P)
        df = np.einsum("ij,ij->i", g, e[act])
        zero = f == 0
        same = np.sign(f) == sg_lo[act]
        lo[act] = np.where(same & ~zero, s[act], lo[act])
        hi[act] = np.where(~same & ~zero, s[act], hi[act])
        with np.errstate(divide="ignore", invalid="ignore"):
            sn = s[act] - f / df
        inside = np.isfinite(sn) & (sn > lo[act]) & (sn < hi[act])
        sn = np.where(inside, sn, 0.5 * (lo[act] + hi[act]))
        small = inside & (np.abs(sn - s[act]) < _NEWTON_SMALL * delta[act])
        # a converged Newton step: test the points delta/2 on either side of it. Proven opposite
        # signs there certify the vertex at once; otherwise their float signs shrink the bracket.
        certified = np.zeros(act.size, dtype=bool)
        if small.any():
            k = act[small]
            pl = np.maximum(sn[small] - 0.5 * delta[k], 0.0)
            ph = np.minimum(sn[small] + 0.5 * delta[k], 1.0)
            fl, bl, _ = func.value_bound(a[k] + pl[:, None] * e[k])
            fh, bh, _ = func.value_bound(a[k] + ph[:, None] * e[k])
            ok = (np.abs(fl) > bl) & (np.abs(fh) > bh) & (np.sign(fl) * np.sign(fh) < 0)
            pair[k[ok]] = np.stack([pl[ok], ph[ok]], axis=-1)
            certified[small] = ok
            for p_, f_ in ((pl, fl), (ph, fh)):
                sm = np.sign(f_) == sg_lo[k]
                lo[k] = np.where(sm & (f_ != 0), np.maximum(lo[k], p_), lo[k])
                hi[k] = np.where(~sm & (f_ != 0), np.minimum(hi[k], p_), hi[k])
                hit = f_ == 0
                lo[k[hit]] = hi[k[hit]] = p_[hit]
        s[act] = np.where(zero, s[act], sn)
        lo[act[zero]] = hi[act[zero]] = s[act[zero]]
        fin = ((hi[act] - lo[act]) <= delta[act]) | certified
        act = act[~fin]
    proven = ~np.isnan(pair[:, 0])
    s = np.where(bad, s, np.where(proven, 0.5 * (pair[:, 0] + pair[:, 1]), 0.5 * (lo + hi)))
    V = a + s[:, None] * e
    # the certificate: proven signs at two float points about delta/2 on either side of the vertex
    # (inside the edge): the pair proven in the loop, else the points at s -+ delta/2. Not the float
    # bracket's own ends: Newton leaves one of them within rounding of the root, where no sign can
    # be proven.
    P_lo = a + np.where(proven, pair[:, 0], np.maximum(s - 0.5 * delta, 0.0))[:, None] * e
    P_hi = a + np.where(proven, pair[:, 1], np.minimum(s + 0.5 * delta, 1.0))[:, None] * e
    bound = np.full(n, np.inf)
    if proven.any():
        b = np.maximum(np.linalg.norm(V[proven] - P_lo[proven], axis=1),
                       np.linalg.norm(V[proven] - P_hi[proven], axis=1)) * (1 + 8 * UNIT_ROUNDOFF)
        bound[proven] = np.where(b <= tol_abs, b, np.inf)
    check = np.flatnonzero(~bad & ~(bound <= tol_abs))
    if check.size:
        sg, known = func.proven_sign(np.concatenate([P_lo[check], P_hi[check]]), budget)
        s1, s2 = sg[:check.size], sg[check.size:]
        k1, k2 = known[:check.size], known[check.size:]
        Vc = V[check]
        d1 = np.linalg.norm(Vc - P_lo[check], axis=1)
        d2 = np.linalg.norm(Vc - P_hi[check], axis=1)
        b = np.full(check.size, np.inf)
        crossing = k1 & k2 & (s1 * s2 < 0)
        b = np.where(crossing, np.maximum(d1, d2), b)
        b = np.where(k1 & (s1 == 0), np.minimum(b, d1), b)     # a proven zero at a bracket end
        b = np.where(k2 & (s2 == 0), np.minimum(b, d2), b)
        b = b * (1 + 8 * UNIT_ROUNDOFF)
        bound[check] = np.where(b <= tol_abs, b, np.inf)
    return V, bound


def _norm3(g):
    """Row norms of ``(n, 3)`` gradients without overflow in the squares (gradients of 1e200)."""
    return np.hypot(np.hypot(g[:, 0], g[:, 1]), g[:, 2])


def _directions(func, P0, first, h):
    """Candidate search directions per vertex, ``(8, m, 3)``: the vertex's own edge axis first
    (if any), the other grid axes, the gradient (scaled to the smallest cell side; NaN where it
    vanishes), the four cube diagonals."""
    m = len(P0)
    axes = np.where(first[:, None] >= 0, (first[:, None] + np.arange(3)[None, :]) % 3, np.arange(3)[None, :])
    D = np.full((8, m, 3), np.nan)
    for i in range(3):
        D[i] = 0.0
        D[i, np.arange(m), axes[:, i]] = h[axes[:, i]]
    _, g = func.value_and_gradient(P0)
    gn = _norm3(g)
    with np.errstate(divide="ignore", invalid="ignore"):
        D[3] = np.where((gn > 0)[:, None] & np.isfinite(g), g / gn[:, None] * h.min(), np.nan)
    for i, sgn in enumerate(((1, 1, 1), (1, 1, -1), (1, -1, 1), (-1, 1, 1))):
        D[4 + i] = np.asarray(sgn) * h
    return D


def _search(func, P0, first, h, tol_abs, budget):
    """Certify vertices whose own edge gave no proven bracket: a proven zero at the vertex, or the
    nearest proven sign change along the candidate directions (points at ``_SEARCH_STEPS`` cells on
    both sides), bisected on proven signs. Returns ``(V, bound)``; ``V = P0`` and ``bound = inf``
    where nothing was found."""
    m = len(P0)
    V, bound = P0.copy(), np.full(m, np.inf)
    s0, k0 = func.proven_sign(P0, budget)
    bound[k0 & (s0 == 0)] = 0.0
    D = _directions(func, P0, first, h)
    t = np.concatenate([-np.asarray(_SEARCH_STEPS)[::-1], [0.0], np.asarray(_SEARCH_STEPS)])
    i0 = len(_SEARCH_STEPS)
    # no two distinct floats near P0 are closer than this: a shorter bracket cannot exist there
    hopeless = tol_abs < 0.5 * np.spacing(np.abs(P0)).min(axis=1)
    for Dk in D:
        todo = np.flatnonzero(~(bound <= tol_abs) & ~hopeless & np.isfinite(Dk).all(axis=1))
        if todo.size == 0:
            continue
        pts = P0[todo, None, :] + t[None, :, None] * Dk[todo, None, :]
        pts[:, i0] = P0[todo]
        sg, kn = func.proven_sign(pts.reshape(-1, 3), budget)
        sg, kn = sg.reshape(len(todo), len(t)), kn.reshape(len(todo), len(t))
        lo_pt, hi_pt, s_lo, owner = [], [], [], []
        for r, j in enumerate(todo):
            best = None                                   # (radius, lo index, hi index or None)
            idx = np.flatnonzero(kn[r])
            for a_, b_ in zip(idx[:-1], idx[1:]):
                if sg[r, a_] * sg[r, b_] < 0:
                    rad = max(abs(t[a_]), abs(t[b_]))
                    if best is None or rad < best[0]:
                        best = (rad, a_, b_)
            for a_ in idx[sg[r, idx] == 0]:
                if best is None or abs(t[a_]) <= best[0]:
                    best = (abs(t[a_]), a_, None)
            if best is None:
                continue
            if best[2] is None:                           # a proven zero
                V[j], bound[j] = pts[r, best[1]], 0.0
                continue
            lo_pt.append(pts[r, best[1]])
            hi_pt.append(pts[r, best[2]])
            s_lo.append(sg[r, best[1]])
            owner.append(j)
        if owner:
            Vb, bb = _bisect(func, np.array(lo_pt), np.array(hi_pt), np.array(s_lo), tol_abs, budget)
            owner = np.array(owner)
            ok = bb <= tol_abs
            V[owner[ok]], bound[owner[ok]] = Vb[ok], bb[ok]
    return V, bound


def _bisect(func, lo, hi, s_lo, tol_abs, budget):
    """Bisect brackets ``[lo, hi]`` (points with proven signs ``s_lo`` and ``-s_lo``) on proven
    signs until shorter than ``tol_abs``; an undecided midpoint is replaced by the next point of
    ``_BISECT_TRIES``. Returns ``(V, bound)`` with ``bound = inf`` where the bisection got stuck."""
    k = len(lo)
    lo, hi = lo.copy(), hi.copy()
    zero_at = np.full((k, 3), np.nan)
    stuck = np.zeros(k, dtype=bool)
    for _ in range(_BISECT_STEPS):
        act = np.flatnonzero(~stuck & np.isnan(zero_at[:, 0]) & (np.linalg.norm(hi - lo, axis=1) > tol_abs))
        if act.size == 0:
            break
        pending = act
        for tr in _BISECT_TRIES:
            if pending.size == 0:
                break
            P = lo[pending] + tr * (hi[pending] - lo[pending])
            # a point that rounds onto an end of its bracket tells nothing: the bracket is as short
            # as the float spacing allows
            fresh = np.any(P != lo[pending], axis=1) & np.any(P != hi[pending], axis=1)
            stuck[pending[~fresh]] = True
            pending, P = pending[fresh], P[fresh]
            sg, kn = func.proven_sign(P, budget)
            z = kn & (sg == 0)
            zero_at[pending[z]] = P[z]
            same = kn & (sg == s_lo[pending])
            opp = kn & (sg == -s_lo[pending])
            lo[pending[same]] = P[same]
            hi[pending[opp]] = P[opp]
            pending = pending[~kn]
        stuck[pending] = True
    V = 0.5 * (lo + hi)
    bound = np.maximum(np.linalg.norm(V - lo, axis=1), np.linalg.norm(V - hi, axis=1)) * (1 + 8 * UNIT_ROUNDOFF)
    z = ~np.isnan(zero_at[:, 0])
    V[z], bound[z] = zero_at[z], 0.0
    bound[~z & (stuck | (bound > tol_abs))] = np.inf
    return V, bound
