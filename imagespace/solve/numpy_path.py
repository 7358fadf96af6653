"""The vectorised numpy path of the batch direct kinematics: companion eigenvalues, Newton on
the balanced system, every mode checked by the legs' inverse kinematics, and the careful
per-orientation solves of the Cramer cases (a)/(b).

The functions take the mechanism ``m`` (a :class:`~imagespace.PlanarParallel`) first. The
non-underscore functions are the stages :mod:`imagespace.solve.certified` and
:mod:`imagespace.solve.planar` reuse; they are not public API (``__all__`` is empty)."""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..core.form_bounds import inclusion_discs
from ..core.elimination import bf_eval, eliminate
from ..core.kinematic_map import pose_of as _pose_of, representative_sign
from ..core.elimination import form_coefficients
from ..core.quadrics import Quadric, dk_system as _system
from ..core.roots import real_half_angles
from ..exceptions import DegenerateDesignError
from .continuum import decide_continuum
from .proof import modes_match_roots, proven_roots
from .results import AssemblyMode, DKBatchResult, MAX_MODES, SOLVER_NAMES

__all__: list[str] = []


def _coef_array(quadrics, n):
    """(n, 3, 8) float coefficient array of three numeric quadrics."""
    C = np.empty((n, 3, 8))
    for i, q in enumerate(quadrics):
        for k, v in enumerate(q.coefficients()):
            C[:, i, k] = np.broadcast_to(np.asarray(v, dtype=float), (n,))
    return C


def _newton(C, X, tol):
    """Newton on [Q1, Q2, Q3, x0^2 + x1^2 - 1]; each candidate stops once its step is below
    ``tol.newton_stop`` of its size (or its Jacobian is singular), so converged rows cost nothing
    more. C are balanced coefficients (see :func:`_balance`), so the sizes are comparable."""
    X = X.copy()
    active = np.all(np.isfinite(X), axis=-1)
    last = np.full(active.shape, np.inf)          # each candidate's previous step (max norm)
    for _ in range(int(tol.newton_steps)):
        idx = np.nonzero(active)
        if idx[0].size == 0:
            break
        Ca = C[idx[0]][:, None]                     # (m, 1, 3, 8)
        Fv, J = _system(Ca[:, 0], X[idx][:, None, :])
        Fv, J = Fv[:, 0], J[:, 0]
        det = np.linalg.det(J)
        scale = np.prod(np.linalg.norm(J, axis=-1), axis=-1)
        solvable = np.abs(det) > tol.newton_stop * scale
        step = np.zeros((idx[0].size, 4))
        if np.any(solvable):
            step[solvable] = np.linalg.solve(J[solvable], -Fv[solvable][..., None])[..., 0]
        X[idx] = X[idx] + step
        size = np.maximum(1.0, np.max(np.abs(X[idx]), axis=-1))
        norm = np.max(np.abs(step), axis=-1)
        # a step no smaller than the one before: rounding noise (at a near-double root Newton
        # halves its step each time, then wanders at the noise level) -- more steps change nothing
        stalled = norm >= last[idx]
        last[idx] = norm
        done = ~solvable | stalled | (norm <= 0.1 * tol.newton_stop * size)
        # one more step after the first tiny one is pointless: retire converged candidates
        active[idx[0][done], idx[1][done]] = False
    return X


def _balance(C):
    """Balance raw quadric coefficients to the row's length scale.

    ``C`` (n, 3, 8) are coefficients ``(c, a0, a1, b0, b1, k0, k1, k2)`` in ``x0..x3``. With the
    length scale ``L`` of each row (from the quadrics themselves: ``sqrt(|k|/|c|)`` and
    ``|a, b|/|c|`` of circles, ``|k|/|a, b|`` of lines), the substitution ``x2 = L x2'``,
    ``x3 = L x3'`` gives coefficients ``(c L^2, a L, b L, k)``, each quadric then scaled to max
    coefficient 1. Solving in the primed coordinates makes every threshold relative: the same
    robot in millimetres or kilometres meets the same decisions. Returns ``(C', L)``.
    """
    c = np.abs(C[..., 0])
    ab = np.max(np.abs(C[..., 1:5]), axis=-1)
    k = np.max(np.abs(C[..., 5:8]), axis=-1)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        cands = np.stack([np.where(c > 0, np.sqrt(k / c), 0.0), np.where(c > 0, ab / c, 0.0),
                          np.where((c == 0) & (ab > 0), k / ab, 0.0)], axis=-1)
    cands = np.where(np.isfinite(cands), cands, 0.0)
    L = np.max(cands, axis=(-1, -2))
    L = np.where(L > 0, L, 1.0)
    B = C.copy()
    B[..., 0] *= (L * L)[:, None]
    B[..., 1:5] *= L[:, None, None]
    B = B / np.maximum(np.max(np.abs(B), axis=2, keepdims=True), 1e-300)
    return B, L


def _normalize_rows(X):
    """Image points scaled to ``x0**2 + x1**2 = 1`` with the normalised sign (see
    :func:`~imagespace.core.kinematic_map.representative_sign`)."""
    n = np.sqrt(X[..., 0]**2 + X[..., 1]**2)
    s = representative_sign(X[..., 0], X[..., 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        return X * (s / n)[..., None]


def _rotated_with_bound(Fn):
    """Each form in the chart of its largest leading coefficient
    (:func:`imagespace.core.roots.rotated_forms`), with a generous bound on the rounding of the
    rotation for every rotated coefficient: ``(G, ok, gamma, E)``."""
    from ..core.roots import rotated_forms

    G, ok, gamma = rotated_forms(Fn)
    d = G.shape[1] - 1
    E = (4 * d + 8) * 2.0**-53 * np.max(np.abs(G), axis=1, keepdims=True) * np.ones_like(G)
    return G, ok, gamma, E


def _separated(Fn):
    """Inclusion-disc separation of the roots of float binary forms ``Fn`` (n, d+1), in the
    chart where each form's leading coefficient is largest. Returns ``(separated (n,), real
    roots (n,))``: where ``separated`` is False, roots could not be told apart in floating point."""
    n = Fn.shape[0]
    sep = np.zeros(n, dtype=bool)
    nreal = np.zeros(n, dtype=int)
    G, ok, _, E = _rotated_with_bound(Fn)
    d = G.shape[1] - 1
    if d < 1:
        return ok, nreal
    use = ok & (np.abs(G[:, d]) > E[:, d])
    if np.any(use):
        good, real, _, _ = inclusion_discs(G[use], E[use])
        sep[use] = good
        nreal[use] = np.where(good, real.sum(axis=1), 0)
    return sep, nreal


def _root_clusters(Fn):
    """Clusters of roots that inclusion discs cannot separate, for one float binary form ``Fn``
    (d+1,): a list of ``(theta, radius, size)`` (half-angle centre, half-angle radius, number of
    roots) for each group of two or more overlapping discs that meets the real axis."""
    G, ok, gamma, E = _rotated_with_bound(Fn[None, :])
    d = G.shape[1] - 1
    if not ok[0] or d < 2:
        return []
    gamma = float(gamma[0])
    good, real, z, hull_r = inclusion_discs(G, E)
    if good[0]:
        return []
    z = z[0]
    r = hull_r[0] - np.abs(z.imag)                 # the inclusion radius of each disc
    if not np.all(np.isfinite(z)):
        return [(0.0, np.pi, d)]
    parent = list(range(d))

    def find(a):
        while parent[a] != a:
            a = parent[a]
        return a

    for a in range(d):
        for b in range(a + 1, d):
            if abs(z[a] - z[b]) <= r[a] + r[b]:
                parent[find(a)] = find(b)
    out = []
    for root in set(find(a) for a in range(d)):
        members = [a for a in range(d) if find(a) == root]
        if len(members) < 2 or min(abs(z[a].imag) - r[a] for a in members) > 0:
            continue
        c = float(np.mean([z[a].real for a in members]))
        rad = max(abs(z[a].real - c) + r[a] + abs(z[a].imag) for a in members)
        out.append((gamma + float(np.arctan(c)), float(rad), len(members)))
    return out


def _distinct_orientations_batch(half, valid, tol):
    """Per row, the number of distinct orientations among the valid half-angles (n, k) in
    (-pi/2, pi/2] (the ends identified): gaps above ``tol`` separate them (vectorised)."""
    with np.errstate(invalid="ignore"):
        h = np.sort(np.where(valid, half, np.inf), axis=1)
        cnt = valid.sum(axis=1)
        first = h[:, 0]
        nxt = np.concatenate([h[:, 1:], np.full((h.shape[0], 1), np.inf)], axis=1)
        idx = np.arange(h.shape[1])
        # the gap after the last valid angle wraps around to the first one + pi
        nxt = np.where(idx[None, :] == (cnt - 1)[:, None], first[:, None] + np.pi, nxt)
        gaps = np.where(idx[None, :] < cnt[:, None], nxt - h, -np.inf)
    return np.where(cnt > 0, np.maximum(1, np.sum(gaps > tol, axis=1)), 0)


def check_rows(m, Q):
    """Input stage of the batch direct kinematics: :meth:`Mechanism.joint_rows` (which rows of
    ``Q`` (n, 3) hold finite joint values inside every actuated joint's domain, as
    ``(row_ok, errors)``)."""
    return m.joint_rows(Q, warn=False)


def store_modes(res, i, modes):
    """Output stage: overwrite row ``i`` (or the rows ``i``, with one list of modes each) of a
    :class:`~imagespace.solve.results.DKBatchResult` with lists of
    :class:`~imagespace.solve.results.AssemblyMode` (at most the row's width), in one rebuild of
    the ragged modes (:meth:`~imagespace.solve.results.DKBatchResult.set_modes`). Used by the
    numpy path for rows solved one by one and by the certified batch
    (:func:`imagespace.solve.certified.certify_batch`) for rows held to their certified count."""
    res.set_modes(i, modes)


def solve_batch(m, Q, raise_degenerate, exact_check=None):
    """The numpy path for a batch ``Q`` (n, 3): balanced quadrics, the kinematic polynomial's
    coefficients, companion eigenvalues in the well-conditioned chart, back-substitution,
    Newton, the legs' check; Cramer cases go row by row to :func:`_special_candidates`; returns
    a :class:`~imagespace.solve.results.DKBatchResult`.

    The whole numpy stage of the batch direct kinematics, called by the dispatch (method
    ``"numpy"``, the kernel's careful rows) and by the certified per-call path as its float first
    guess. With ``raise_degenerate`` a degenerate design raises
    :class:`~imagespace.exceptions.DegenerateDesignError` instead of being recorded per row."""
    n = Q.shape[0]
    tol = m.tolerances
    row_ok, errors = check_rows(m, Q)
    Qs = np.where(row_ok[:, None], Q, 0.0)
    C, cq, L = scaled_quadrics(m, Qs)
    el = eliminate(cq, m.elimination_plan)
    Darr = np.stack(np.broadcast_arrays(*el.D), axis=1)
    Farr = np.stack(np.broadcast_arrays(*el.F), axis=1)
    X2 = np.stack(np.broadcast_arrays(*el.X2), axis=1)
    X3 = np.stack(np.broadcast_arrays(*el.X3), axis=1)
    dnorm = np.max(np.abs(Darr), axis=1)
    fnorm = np.max(np.abs(Farr), axis=1)
    special = row_ok & ((dnorm <= tol.cramer_identically_zero) | (fnorm <= tol.degenerate))
    Fn = Farr / np.where(fnorm > 0, fnorm, 1.0)[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        theta, ok = real_half_angles(Fn, tol.real_root_imag)
    x0, x1 = np.cos(theta), np.sin(theta)
    Dv = bf_eval([c[:, None] for c in Darr.T], x0, x1)
    small_d = np.isfinite(theta) & (np.abs(Dv) <= tol.cramer_small * dnorm[:, None])
    special |= row_ok & np.any(small_d, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        x2 = bf_eval([c[:, None] for c in X2.T], x0, x1) / Dv
        x3 = bf_eval([c[:, None] for c in X3.T], x0, x1) / Dv
    cand = np.stack([x0, x1, x2, x3], axis=-1)
    cand[~(row_ok & ~special)] = np.nan
    width = max(cand.shape[1], MAX_MODES)
    if cand.shape[1] < width:
        pad = np.full((n, width - cand.shape[1], 4), np.nan)
        cand = np.concatenate([cand, pad], axis=1)
    # careful path for special rows
    extra = {}
    near_special = {}
    for i in np.flatnonzero(special):
        try:
            extra[i], near_special[i] = _special_candidates(m, Q[i], C[i], L[i])
        except DegenerateDesignError as e:
            if raise_degenerate:
                raise
            row_ok[i] = False
            errors[int(i)] = str(e)
    if extra:
        width = max(width, max(len(v) for v in extra.values()))
        if cand.shape[1] < width:
            cand = np.concatenate([cand, np.full((n, width - cand.shape[1], 4), np.nan)], axis=1)
        for i, lst in extra.items():
            cand[i] = np.nan
            for j, x in enumerate(lst):
                cand[i, j] = x
    res = finish_candidates(m, Q, C, cand, row_ok, errors, special, L)
    # the half-angle atan2(x1, x0) of each mode's normalised image point: phi / 2 (pose_of)
    half = res.poses[..., 2] / 2
    # the count is trusted only where the modes sit one per proven real root of the exact
    # kinematic polynomial (proof.py: bounded isolation in the kernel or on the enclosure)
    proof = _proof(m, Q, row_ok)
    if proof is not None:
        examined = np.full((n, max([len(v[2]) for v in near_special.values()] + [1])), np.nan)
        for i, (_, _, thetas) in near_special.items():
            examined[i, :len(thetas)] = thetas
        near = row_ok & ~modes_match_roots(half, res.valid, proof, _spurious_half_angles(m, C),
                                           special, examined)
    else:
        # no proof for this design: separation of the float roots by inclusion discs and the
        # distinct orientations against them (the spurious root of a PP dyad carries no mode)
        separated, n_real = _separated(Fn)
        distinct = _distinct_orientations_batch(half, res.valid, tol.duplicate)
        n_real = n_real - _spurious_roots(m, C, theta)
        near = row_ok & ~special & (~separated | (distinct != n_real))
    for i, (flag, clusters, _) in near_special.items():
        # a cluster of k roots the discs cannot separate must carry k modes (case (b): a
        # double root with two positions); anything else is a count not to be trusted
        hv = half[i][res.valid[i]]
        for theta_c, rad, size in clusters:
            dist = np.abs(np.remainder(hv - theta_c + np.pi / 2, np.pi) - np.pi / 2)
            flag = flag or int(np.sum(dist <= rad + tol.near_singular_gap)) != size
        near[i] = row_ok[i] and (near[i] or flag or bool(res.near_singular[i]))
    # a continuum of positions sits on a multiple root of the kinematic polynomial (continuum.py)
    # and hides behind a flagged row whose proof found no simple roots only, or a Cramer case:
    # decide those exactly
    undecided = np.ones(n, dtype=bool) if proof is None else proof[0] < 0
    continuum = []
    for i in np.flatnonzero(near & (undecided | special)):
        message = _continuum_message(m, Q[i], bool(special[i]), exact_check)
        if message is None:
            continue
        if raise_degenerate:
            raise DegenerateDesignError(message)
        row_ok[i] = False
        errors[int(i)] = message
        continuum.append(int(i))
        near[i] = False
    if continuum:                          # one rebuild for every row found degenerate
        store_modes(res, continuum, [[] for _ in continuum])
        res.set_solver(continuum, "invalid")
    res.near_singular = near
    res.release_padded()                   # poses and valid were read above: keep only the modes
    return res


def _proof(m, Q, row_ok):
    """:func:`~imagespace.solve.proof.proven_roots` of the valid rows of ``Q``, spread over all
    rows (undecided, -1, elsewhere), or None when the design has no proof."""
    n = Q.shape[0]
    ok = np.flatnonzero(row_ok)
    sub = proven_roots(m, Q[ok]) if ok.size else None
    if sub is None:
        return None if ok.size else (np.full(n, -1), np.full((n, 6), np.nan), np.full((n, 6), np.nan),
                                     np.full((n, 6), -1, dtype=np.int8))
    counts = np.full(n, -1, dtype=int)
    lo = np.full((n, 6), np.nan)
    hi = np.full((n, 6), np.nan)
    chart = np.full((n, 6), -1, dtype=np.int8)
    counts[ok], lo[ok], hi[ok], chart[ok] = sub
    return counts, lo, hi, chart


def _continuum_message(m, q, special, exact_check=None):
    """The message of a continuum of assembly modes at ``q`` (decided exactly by
    :func:`~imagespace.solve.continuum.continuum_at`), or None. Where the exact test cannot
    decide (irrational coefficients) a Cramer-case row is decided by ``exact_check(m, q)`` (the
    caller's certified per-row path, which raises
    :class:`~imagespace.exceptions.DegenerateDesignError` on a continuum), where given."""
    verdict, phi = decide_continuum(m, q)
    if verdict:
        return (f"{m.name} at q = {np.asarray(q, dtype=float).tolist()}: a continuum of assembly "
                f"modes at phi = {phi:.6g} (the positions at that orientation form a curve: "
                f"architecture singularity or singular joint values)")
    if verdict is None and special and exact_check is not None:
        try:
            exact_check(m, q)
        except DegenerateDesignError as e:
            return str(e)
    return None


def _spurious_half_angles(m, C):
    """(n, p) half-angles of the spurious orientation ``phi_c + pi`` of each PP dyad (see
    :func:`_spurious_roots`); shape (n, 0) without one."""
    cols = []
    for j, kind in enumerate(m.kinds):
        if kind == "PP":
            cols.append(np.arctan2(-C[:, j, 5], C[:, j, 6] / 2) / 2 + np.pi / 2)
    return np.stack(cols, axis=1) if cols else np.zeros((C.shape[0], 0))


def _spurious_hits(m, C, theta):
    """Per real half-angle of ``theta`` (n, k), how many PP dyads it is (within
    ``near_singular_gap``) the spurious orientation ``phi_c + pi`` of (the dyad's quadric
    ``sin(2 theta - phi_c)`` up to scale has the roots ``theta = phi_c / 2`` and
    ``phi_c / 2 + pi / 2``; the first is the one)."""
    out = np.zeros(theta.shape, dtype=int)
    for j, kind in enumerate(m.kinds):
        if kind != "PP":
            continue
        phi_c = np.arctan2(-C[:, j, 5], C[:, j, 6] / 2)
        spur = phi_c / 2 + np.pi / 2
        d = np.abs(np.remainder(theta - spur[:, None] + np.pi / 2, np.pi) - np.pi / 2)
        out += np.isfinite(theta) & (d <= m.tolerances.near_singular_gap)
    return out


def _spurious_roots(m, C, theta):
    """Per row, how many of the real half-angles ``theta`` (n, k) are the spurious orientation
    of a PP dyad, counted once per dyad (:func:`_spurious_hits`)."""
    return np.sum(_spurious_hits(m, C, theta), axis=1)


def finish_candidates(m, Q, C, cand, row_ok, errors, special, L):
    """Polish candidates (balanced coordinates), check them with the legs, sort; ``L`` (n,)
    is the length scale the candidates' ``x2, x3`` are divided by (see :func:`_balance`).

    The polishing and checking stage after the candidates are found (Newton, duplicates, the
    legs' inverse kinematics, sorting) that turns (n, k, 4) candidates into a
    :class:`~imagespace.solve.results.DKBatchResult`; shared by :func:`solve_batch` and the
    certified path's orientation-by-orientation solve. Raises
    :class:`~imagespace.exceptions.DegenerateDesignError` when a row has more than
    ``MAX_MODES`` modes."""
    tol = m.tolerances
    n, k, _ = cand.shape
    X = _newton(C, _normalize_rows(cand), tol)
    X = _normalize_rows(X)
    finite = np.all(np.isfinite(X), axis=-1)
    # duplicates (balanced coordinates): a later candidate close to an earlier valid one
    Xw = X * np.concatenate([np.ones((n, 1, 2)), np.repeat(L[:, None, None], 2, axis=2)], axis=2)
    poses = np.full((n, k, 3), np.nan)
    if np.any(finite):
        poses[finite] = _pose_of(Xw[finite])
    resid = np.full((n, k), np.inf)
    if np.any(finite):
        rows = np.nonzero(finite)[0]
        resid[finite] = m.joint_residual(poses[finite], Q[rows], length=L[rows])
    Fv, J = _system(C, np.where(finite[..., None], X, 0.0))
    on_system = finite & (np.max(np.abs(Fv[..., :3]), axis=-1)
                          <= tol.kernel_residual * (1 + np.sum(X[..., 2:] ** 2, axis=-1)))
    # a point on the system where a leg's inverse kinematics is undefined (its actuated joint is
    # free at that pose: a leg singularity, e.g. a PRP's lines coincide) is a mode the IK check
    # cannot confirm: kept, and its row marked near_singular
    ik_free = on_system & ~np.isfinite(resid)
    valid = finite & ((resid <= tol.joint_residual) | ik_free)
    dup = np.zeros_like(valid)
    for j in range(1, k):
        for i0 in range(j):
            dist = np.minimum(np.max(np.abs(X[:, j] - X[:, i0]), axis=-1),
                              np.max(np.abs(X[:, j] + X[:, i0]), axis=-1))
            dup[:, j] |= valid[:, i0] & (dist <= tol.duplicate * (1 + np.max(np.abs(X[:, j]), axis=-1)))
            valid[:, j] &= ~dup[:, j]
    # a real candidate refused by the IK check that is neither a duplicate nor a PP dyad's
    # spurious orientation: the row's count may be short of the truth (a near-fold pose the float
    # Newton cannot pin down); the row says so instead of returning a silently short count
    refused = finite & ~valid & ~dup & ~ik_free
    spurious = _spurious_hits(m, C, np.arctan2(X[..., 1], X[..., 0])) > 0
    doubtful = np.any(refused & ~spurious, axis=1) | np.any(ik_free & valid, axis=1)
    detJ = np.linalg.det(J)
    aspect = np.where(finite, np.sign(detJ), 0).astype(int)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.abs(detJ) / np.prod(np.linalg.norm(J, axis=-1), axis=-1)
    # sort valid first, by phi (the image points are not kept: the result derives them from the poses)
    key = np.where(valid, poses[..., 2], np.inf)
    order = np.argsort(key, axis=1, kind="stable")
    take = lambda a: np.take_along_axis(a, order.reshape(order.shape + (1,) * (a.ndim - 2)), axis=1)
    poses, valid, resid, aspect = take(poses), take(valid), take(resid), take(aspect)
    ill = np.any(valid & ~(take(ratio) > tol.near_singular_condition), axis=1) | doubtful
    count = valid.sum(axis=1)
    if np.any(count > MAX_MODES):
        raise DegenerateDesignError(f"more than {MAX_MODES} assembly modes found; the design is degenerate")
    w = MAX_MODES
    poses, valid, resid, aspect = poses[:, :w], valid[:, :w], resid[:, :w], aspect[:, :w]
    solver = np.where(row_ok, SOLVER_NAMES.index("numpy"), SOLVER_NAMES.index("invalid")).astype(np.uint8)
    return DKBatchResult.from_padded(poses, valid, resid, aspect, row_ok, count=count, errors=errors,
                                     special=special, solver=solver, near_singular=ill & row_ok)


def scaled_quadrics(m, Q):
    """Balanced float quadrics for joint vectors Q (n, 3): see :func:`_balance`.

    Returns the (n, 3, 8) coefficient array in the balanced coordinates, the matching list of
    three Quadric (rows as arrays) and the length scale ``L`` (n,) of each row.

    The set-up stage of every float solve (numpy path and certified path's float steps): the
    legs' dyads at ``Q``, balanced to the design's length scale so that all tolerances are
    relative.
    """
    quads = [leg.dyad(Q[:, j]) for j, leg in enumerate(m.legs)]
    C, L = _balance(_coef_array(quads, Q.shape[0]))
    return C, [Quadric(m.kinds[j], *(C[:, j, k] for k in range(8))) for j in range(3)], L


def row_quadrics(m, c_row):
    """The three scalar quadrics of one row of a (n, 3, 8) coefficient array: the per-row
    stage shared by the Cramer cases of the numpy path and the certified path."""
    return [Quadric(m.kinds[j], *(c_row[j, k] for k in range(8))) for j in range(3)]


def _special_candidates(m, q, C, L):
    """Candidates (balanced coordinates) for one row whose Cramer denominator vanishes
    (identically or at a root), and ``(flag, clusters, thetas)``: whether the orientations could
    not be separated, the root clusters the discs could not separate, and the half-angles of the
    orientations solved."""
    tol = m.tolerances
    quads = row_quadrics(m, C)
    el = eliminate(quads, m.elimination_plan)
    D = np.array(el.D, dtype=float)
    F = np.array(el.F, dtype=float)
    thetas = []
    clusters = []
    if np.max(np.abs(D)) <= tol.cramer_identically_zero:
        E1, E2 = el.rows[0], el.rows[1]
        M = np.array([[*E1.A, *E1.B], [*E2.A, *E2.B]], dtype=float)
        U, S, _ = np.linalg.svd(M)
        forms = []
        if S[0] <= tol.rank:
            forms = [np.array(E1.K, float), np.array(E2.K, float)]
        else:
            lam = U[:, -1]
            forms = [lam[0] * np.array(E1.K, float) + lam[1] * np.array(E2.K, float)]
        forms = [g for g in forms if np.max(np.abs(g)) > tol.rank]
        if not forms:
            _confirm_degenerate(m, q)
        for g in forms:
            gn = (g / np.max(np.abs(g)))[None, :]
            th, ok = real_half_angles(gn, tol.real_root_imag)
            thetas += [t for t in th[0] if np.isfinite(t)]
    else:
        if np.max(np.abs(F)) <= tol.degenerate:
            poly = _exact_polynomial(m, q)
            F = np.array([float(c) for c in form_coefficients(poly)], dtype=float)
        Fn = (F / np.max(np.abs(F)))[None, :]
        th, ok = real_half_angles(Fn, tol.real_root_imag)
        thetas = [t for t in th[0] if np.isfinite(t)]
        clusters = _root_clusters(Fn[0])
    out = []
    flags = []
    for t in thetas:
        out += solve_orientation(m, q, quads, np.cos(t), np.sin(t), L, flags)
    return out, (bool(flags), clusters, [float(t) for t in thetas])


def _exact_polynomial(m, q):
    """The exact kinematic polynomial at ``q`` (floats as binary rationals)."""
    return m.kinematic_polynomial([sp.Rational(float(v)) for v in q])


def _confirm_degenerate(m, q):
    """Raise :class:`~imagespace.DegenerateDesignError` if the exact polynomial at ``q``
    vanishes identically (a continuum of modes)."""
    _exact_polynomial(m, q)  # raises DegenerateDesignError when identically zero
    raise DegenerateDesignError(
        f"{m.name} at q = {np.asarray(q).tolist()}: the constraints leave a continuum of "
        "assembly modes (architecture singularity)")


def solve_orientation(m, q, quads, x0, x1, L, flags=None):
    """Positions (x2, x3) for a fixed orientation (x0, x1): candidate image points in the
    balanced coordinates of ``quads`` (length scale ``L``). ``flags`` (a list) receives an
    entry when two positions are about to merge (a near-zero discriminant).

    The fixed-orientation stage: used for the Cramer cases (a)/(b) of the numpy path and for
    each certified orientation of the certified path."""
    tol = m.tolerances
    rows = []
    for qd in quads:
        c, a0, a1, b0, b1, k0, k1, k2 = (float(v) for v in qd.coefficients())
        rows.append((c, a0 * x0 + a1 * x1, b0 * x0 + b1 * x1, k0 * x0**2 + k1 * x0 * x1 + k2 * x1**2))
    circles = [r for r in rows if r[0] != 0]
    lin = [r[1:] for r in rows if r[0] == 0]
    if circles:
        c0 = circles[0]
        lin += [tuple(r[j] - c0[j] * r[0] / c0[0] for j in (1, 2, 3)) for r in circles[1:]]
    L2 = np.array([[r[0], r[1]] for r in lin]) if lin else np.zeros((0, 2))
    rhs = np.array([-r[2] for r in lin]) if lin else np.zeros(0)
    S = np.linalg.svd(L2, compute_uv=False) if len(lin) else np.zeros(0)
    rank = int(np.sum(S > tol.rank * max(1.0, S[0] if len(S) else 0.0)))
    if rank == 2:
        p = np.linalg.lstsq(L2, rhs, rcond=None)[0]
        out = [np.array([x0, x1, p[0], p[1]])]
        if circles and S[1] <= tol.cramer_small * S[0]:
            # nearly case (b): the two positions of the line-circle treatment are candidates
            # too (Newton and the legs' check keep the true ones, duplicates are dropped)
            out += _line_circle(L2, rhs, circles[0], x0, x1, tol, flags, strict=False)
        return out
    if rank == 1:
        p0 = np.linalg.lstsq(L2, rhs, rcond=None)[0]
        if np.max(np.abs(L2 @ p0 - rhs), initial=0.0) > 10 * tol.rank * max(1.0, np.max(np.abs(rhs), initial=0.0)):
            return []
        if not circles:
            return _continuum(m, q, np.array([x0, x1, p0[0], p0[1]]), L, flags)
        return _line_circle(L2, rhs, circles[0], x0, x1, tol, flags)
    consistent = all(abs(r) <= tol.rank for r in rhs)
    if not consistent:
        return []
    if circles:
        c, al, be, ka = circles[0]
        centre = np.array([-al, -be]) / (2 * c)
        r2 = centre @ centre - ka / c
        if r2 < 0:
            return []
        return _continuum(m, q, np.array([x0, x1, centre[0] + np.sqrt(r2), centre[1]]), L, flags)
    return _continuum(m, q, np.array([x0, x1, 0.0, 0.0]), L, flags)


def _line_circle(L2, rhs, circle, x0, x1, tol, flags=None, strict=True):
    """The (up to two) points of the circle row on the line of the rank-1 linear rows."""
    U, S, Vt = np.linalg.svd(L2)
    # the rank-1 least-squares point and the line's direction
    p0 = Vt[0] * ((U[:, 0] @ rhs) / S[0])
    d = Vt[1]
    c, al, be, ka = circle
    A2 = c * (d @ d)
    A1 = 2 * c * (p0 @ d) + al * d[0] + be * d[1]
    A0 = c * (p0 @ p0) + al * p0[0] + be * p0[1] + ka
    disc = A1 * A1 - 4 * A2 * A0
    if strict and flags is not None and abs(disc) <= tol.near_singular_condition * (A1 * A1 + abs(4 * A2 * A0)):
        flags.append("merging positions")   # the count is not to be trusted
    if disc < -tol.rank * max(1.0, A1 * A1):
        return []
    r = np.sqrt(max(disc, 0.0))
    return [np.array([x0, x1, *(p0 + t * d)]) for t in ((-A1 + r) / (2 * A2), (-A1 - r) / (2 * A2))]


def _continuum(m, q, X, L, flags=None):
    """The positions at a fixed orientation form a continuum within the float tolerance (the
    linear part's rank drops, see ``Tolerances.rank``): raise
    :class:`~imagespace.exceptions.DegenerateDesignError` when the exact test
    (:func:`~imagespace.solve.continuum.continuum_at`, at ``q`` as binary rationals) proves a
    continuum; otherwise the row is only near one (a joint an ulp away from a self-motion has
    isolated modes): no candidates from this orientation, and ``flags`` (a list) receives an entry
    so the count is not trusted."""
    Xw = np.array([X[0], X[1], X[2] * L, X[3] * L])
    pose = _pose_of(Xw)
    if m.joint_residual(pose, q, length=L) <= m.tolerances.joint_residual:
        verdict, phi = decide_continuum(m, q)
        if verdict:
            raise DegenerateDesignError(
                f"{m.name} at q = {np.asarray(q).tolist()}: a continuum of assembly modes at "
                f"phi = {phi:.6g} (architecture singularity or singular joint values)")
        if flags is not None:
            flags.append("near a continuum" if verdict is False else "continuum undecided")
    return []


def complex_modes(m, q):
    """The complex solutions at ``q`` (for ``include_complex``): non-real roots of the kinematic
    polynomial with their back-substituted positions.

    The complex stage of the per-call direct kinematics (``include_complex=True`` in
    :func:`imagespace.solve.front.direct_kinematics`)."""
    poly = m.kinematic_polynomial([sp.Rational(float(v)) for v in q])
    coeffs = np.array([complex(c) for c in form_coefficients(poly)])
    d = len(coeffs) - 1
    roots = np.roots(coeffs[::-1]) if d > 0 else []
    out = []
    quads = m.quadrics(np.asarray(q, float))
    el = eliminate(quads, m.elimination_plan)
    for t in roots:
        if abs(t.imag) <= m.tolerances.real_root_imag * (1 + abs(t)):
            continue
        x0, x1 = 1.0 + 0j, complex(t)
        Dv = bf_eval([complex(v) for v in el.D], x0, x1)
        if Dv == 0:
            continue
        x2 = bf_eval([complex(v) for v in el.X2], x0, x1) / Dv
        x3 = bf_eval([complex(v) for v in el.X3], x0, x1) / Dv
        out.append(AssemblyMode(np.array([x0, x1, x2, x3]), np.full(3, np.nan), np.nan, 0, False))
    return out
