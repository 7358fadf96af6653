r"""The one-path tracker of the spatial fast path (:mod:`imagespace.spatial.homotopy`): a compiled
predictor-corrector for the homotopies ``H(z, s)`` of a quadric family on the affine patch
``c.z = 1`` of ``P^7``, one path at a time, from ``s = 1`` to ``s = 0``.

Its numerical knobs and path status codes are public names (outside ``__all__``) because the
lockstep twin, :mod:`imagespace.spatial.lanes`, takes the same decisions with them; the
homotopies themselves (start system, parameter homotopy, classification) are in
:mod:`imagespace.spatial.homotopy`.
"""

from __future__ import annotations

import numpy as np

from ..core._numba import njit, prange

__all__ = ["PATH_OK", "PATH_FAILED"]

#: path status codes
PATH_OK = 0
PATH_FAILED = 1          # the step size fell below the minimum or the step budget ran out

# numerical knobs of the tracker (they steer the integration, they decide nothing about an answer:
# every endpoint is checked afterwards, by Newton residuals and by the certificate)
DIM = 8                  # homogeneous Study coordinates
STEP_FIRST = 0.1         # first step in s (an Euler step)
STEP_MIN = 1e-9          # smallest step before a path is given up
STEP_MAX = 1.0           # largest step
STEP_GROW = 2.0          # growth after a step whose corrector converged in one iteration
STEP_KEEP = 1.25         # ... in two
STEP_SHRINK = 0.7        # ... in three
STEP_CUT = 0.5           # after a step whose corrector failed
MAX_STEPS = 3000         # step budget of a path (then PATH_FAILED)
NEWTON_STEPS = 3         # corrector iterations per step
# corrector converged: |dz| <= CORRECT_TOL * |z| (loose: the endpoint is polished at s = 0, and two
# paths that meet end at one endpoint, which the distinctness check reports; 17 evaluations a path
# instead of 21 at 1e-5)
CORRECT_TOL = 1e-4
FIRST_CORRECTION = 0.01  # the first corrector update must be below this times |z| (against path jumping)
FINAL_NEWTON = 4         # polishing iterations at the target
FINAL_TOL = 1e-15        # ... stopped once |dz| <= FINAL_TOL * (1 + |z|) (a few units in the last place)
DIVERGED = 1e8           # |z| beyond this on the patch: the path runs to the degenerate component
_BLOCKS = 256            # parallel blocks of (row, path) jobs


@njit(cache=True, fastmath=True)
def _lu(M, piv):
    """LU factorisation in place (8 x 8 complex, partial pivoting on ``|re| + |im|``); False on a
    zero pivot."""
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
        if big == 0.0:
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


@njit(cache=True, fastmath=True)
def _lu_solve(M, piv, b, out, sign):
    """``out = sign * M^{-1} b`` from the factors of :func:`_lu`."""
    n = M.shape[0]
    for i in range(n):
        out[i] = sign * b[i]
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


@njit(cache=True, fastmath=True)
def _evaluate(z, s, mode, A, E, pidx, p0, p1, U, A1, c, gamma, H, J, Hs, Ez, Az):
    """Value ``H``, Jacobian ``J`` and ``dH/ds`` of the homotopy at ``(z, s)``.

    mode 0 (parameters): ``H_k = z^T A_k z - p_k(s) z^T E z`` with ``p(s) = (1 - s) p0 + s p1``.
    mode 1 (start): ``H = (1 - s) F(z; p1) + s gamma G(z)``, ``G_k = (u_k . z)^2 - (c . z)^2``.
    mode 2 (coefficients): ``H = (1 - s) F(z; p1) + s gamma G(z)``, ``G_k = z^T A1_k z - p0_k z^T E z``
    (another member of a family linear in its coefficients: the gamma trick between two members).
    ``F(z; p)_k = z^T A_k z - p_k z^T E z``. The last row is the patch ``c . z - 1``.
    """
    m = A.shape[0]
    # E is diagonal (x . x for legs): Ez = diag(E) z
    for i in range(DIM):
        Ez[i] = E[i, i] * z[i]
    zEz = 0j
    for i in range(DIM):
        zEz += z[i] * Ez[i]
    cz = 0j
    for i in range(DIM):
        cz += c[i] * z[i]
    for k in range(m):
        # A is real: real and imaginary parts separately (half the multiplications)
        for i in range(DIM):
            ar = 0.0
            ai = 0.0
            for j in range(DIM):
                a = A[k, i, j]
                ar += a * z[j].real
                ai += a * z[j].imag
            Az[i] = complex(ar, ai)
        zAz = 0j
        for i in range(DIM):
            zAz += z[i] * Az[i]
        q = pidx[k]
        if mode == 0:
            if q >= 0:
                pk = (1.0 - s) * p0[q] + s * p1[q]
                dp = p1[q] - p0[q]
            else:
                pk = 0j
                dp = 0j
            H[k] = zAz - pk * zEz
            Hs[k] = -dp * zEz
            for i in range(DIM):
                J[k, i] = 2.0 * (Az[i] - pk * Ez[i])
        elif mode == 1:
            pk = p1[q] if q >= 0 else 0j
            F = zAz - pk * zEz
            uz = 0j
            for i in range(DIM):
                uz += U[k, i] * z[i]
            G = uz * uz - cz * cz
            H[k] = (1.0 - s) * F + s * gamma * G
            Hs[k] = gamma * G - F
            for i in range(DIM):
                dF = 2.0 * (Az[i] - pk * Ez[i])
                dG = 2.0 * (uz * U[k, i] - cz * c[i])
                J[k, i] = (1.0 - s) * dF + s * gamma * dG
        else:
            pk = p1[q] if q >= 0 else 0j
            gk = p0[q] if q >= 0 else 0j
            F = zAz - pk * zEz
            G = -gk * zEz
            for i in range(DIM):
                ar = 0.0
                ai = 0.0
                for j in range(DIM):
                    a = A1[k, i, j]
                    ar += a * z[j].real
                    ai += a * z[j].imag
                w = complex(ar, ai)
                G += z[i] * w
                # J row: the start member's gradient part, then the target's below
                J[k, i] = s * gamma * 2.0 * (w - gk * Ez[i])
            H[k] = (1.0 - s) * F + s * gamma * G
            Hs[k] = gamma * G - F
            for i in range(DIM):
                J[k, i] += (1.0 - s) * 2.0 * (Az[i] - pk * Ez[i])
    H[m] = cz - 1.0
    Hs[m] = 0j
    for i in range(DIM):
        J[m, i] = c[i]


@njit(cache=True, fastmath=True)
def complex_norm(v):
    """The 2-norm of a complex vector (compiled; shared with the classification in
    :mod:`imagespace.spatial.homotopy`).

    Examples
    --------
    >>> import numpy as np
    >>> float(complex_norm(np.array([3.0 + 0j, 4j])))
    5.0
    """
    acc = 0.0
    for i in range(v.shape[0]):
        acc += v[i].real * v[i].real + v[i].imag * v[i].imag
    return np.sqrt(acc)


@njit(cache=True, fastmath=True)
def _track(z0, mode, A, E, pidx, p0, p1, U, A1, c, gamma, z, V, J, piv):
    """Track one path from ``s = 1`` to ``s = 0``; ``z`` receives the endpoint. Returns (status,
    Jacobian evaluations). ``V`` (10, 8) complex, ``J`` (8, 8) complex and ``piv`` (8,) int are
    work arrays (allocated once per thread by the caller).

    Predictor: cubic Hermite extrapolation through the last two accepted points and their tangents
    (Euler for the first step); the tangent at an accepted point reuses the LU factors of the
    corrector's last Jacobian. Corrector: Newton, at most ``NEWTON_STEPS`` iterations.
    """
    H = V[0]
    Hs = V[1]
    dz = V[2]
    dzp = V[3]
    zp = V[4]
    w = V[5]
    step = V[6]
    Ez = V[7]
    Az = V[8]
    for i in range(DIM):
        z[i] = z0[i]
    s = 1.0
    _evaluate(z, s, mode, A, E, pidx, p0, p1, U, A1, c, gamma, H, J, Hs, Ez, Az)
    if not _lu(J, piv):
        return PATH_FAILED, 0
    _lu_solve(J, piv, Hs, dz, -1.0)
    sp = 1.0
    have_prev = False
    h = STEP_FIRST
    steps = 0
    evals = 1
    while s > 0.0:
        steps += 1
        if steps > MAX_STEPS:
            return PATH_FAILED, steps
        if h > s:
            h = s
        t = s - h
        if have_prev:
            d = s - sp
            tau = (t - sp) / d
            t2 = tau * tau
            t3 = t2 * tau
            h00 = 2.0 * t3 - 3.0 * t2 + 1.0
            h10 = t3 - 2.0 * t2 + tau
            h01 = -2.0 * t3 + 3.0 * t2
            h11 = t3 - t2
            for i in range(DIM):
                w[i] = h00 * zp[i] + h10 * d * dzp[i] + h01 * z[i] + h11 * d * dz[i]
        else:
            for i in range(DIM):
                w[i] = z[i] - h * dz[i]
        converged = False
        used = 0
        for it in range(NEWTON_STEPS):
            used = it + 1
            evals += 1
            _evaluate(w, t, mode, A, E, pidx, p0, p1, U, A1, c, gamma, H, J, Hs, Ez, Az)
            if not _lu(J, piv):
                break
            _lu_solve(J, piv, H, step, 1.0)
            for i in range(DIM):
                w[i] -= step[i]
            nd, nw = complex_norm(step), complex_norm(w)
            if it == 0 and nd > FIRST_CORRECTION * (1.0 + nw):
                break
            if nd <= CORRECT_TOL * (1.0 + nw):
                converged = True
                break
        if converged:
            if complex_norm(w) > DIVERGED:
                return PATH_FAILED, steps
            for i in range(DIM):
                zp[i] = z[i]
                dzp[i] = dz[i]
                z[i] = w[i]
            sp = s
            s = t
            _lu_solve(J, piv, Hs, dz, -1.0)
            have_prev = True
            # step control from the corrector's effort: one iteration -> grow, three -> shrink
            if used == 1:
                h = min(h * STEP_GROW, STEP_MAX)
            elif used == 2:
                h = min(h * STEP_KEEP, STEP_MAX)
            else:
                h *= STEP_SHRINK
        else:
            h *= STEP_CUT
            if h < STEP_MIN:
                return PATH_FAILED, steps
    for it in range(FINAL_NEWTON):
        _evaluate(z, 0.0, mode, A, E, pidx, p0, p1, U, A1, c, gamma, H, J, Hs, Ez, Az)
        if not _lu(J, piv):
            break
        _lu_solve(J, piv, H, step, 1.0)
        for i in range(DIM):
            z[i] -= step[i]
        if complex_norm(step) <= FINAL_TOL * (1.0 + complex_norm(z)):
            break
    return PATH_OK, evals


@njit(cache=True, parallel=True)
def track_many(starts, mode, A, E, pidx, P0, p1, U, A1, c, gamma, Z, status, steps):
    """Track every (row, path) pair, one path at a time: row ``r`` takes the start points
    ``starts`` to the parameters ``P0[r]`` (compiled, parallel over blocks of pairs).

    Parameters
    ----------
    starts : (k, 8) complex
        Start points on the patch.
    mode : int
        0: the parameter homotopy ``p(s) = (1 - s) P0[r] + s p1``; 1: the total-degree homotopy
        from ``(u_k . z)^2 - (c . z)^2`` to the family at ``p1`` (``P0`` unused); 2: the
        coefficient homotopy from the member ``(A1, P0[r])`` (at ``s = 1``) to ``(A, p1)``, both
        of one family linear in its coefficients (``gamma`` times the start member).
    A : (m, 8, 8) float
    E : (8, 8) float
        Diagonal (only its diagonal is read).
    pidx : (m,) int
    P0 : (n, p) complex
    p1 : (p,) complex
    U : (m, 8) complex
        The start system's linear forms (mode 1).
    A1 : (m, 8, 8) float
        The start member's parameter-free parts (mode 2; any array of that shape otherwise).
    c : (8,) complex
        The patch.
    gamma : complex
        The gamma-trick constant (mode 1).
    Z : (n, k, 8) complex
        Receives the endpoints.
    status : (n, k) int
        Receives :data:`PATH_OK` or :data:`PATH_FAILED`.
    steps : (n, k) int
        Receives the Jacobian evaluations of an arrived path, the steps of a failed one.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.homotopy import solve_start_system
    >>> from imagespace.spatial.quadrics import sphere_quadric, study_quadric_matrix
    >>> rng = np.random.default_rng(1)
    >>> A = np.concatenate([sphere_quadric(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)), 0.0),
    ...                     study_quadric_matrix()[None]])
    >>> st = solve_start_system(A, np.diag([1.0, 1, 1, 1, 0, 0, 0, 0]), np.r_[np.arange(6), -1], 6,
    ...                         expected=40)
    >>> Z = np.zeros((1, 40, 8), complex)
    >>> status, steps = np.zeros((1, 40), np.int64), np.zeros((1, 40), np.int64)
    >>> track_many(st.solutions, 0, st.A, st.E, st.pidx, np.full((1, 6), 4.0 + 0j), st.p_star,
    ...            np.zeros((7, 8), complex), st.A, st.patch, 1 + 0j, Z, status, steps)
    >>> bool(np.all(status == PATH_OK))
    True
    """
    n = P0.shape[0]
    k = starts.shape[0]
    jobs = n * k
    blocks = min(jobs, _BLOCKS)
    for b in prange(blocks):
        # one set of work arrays per block: no allocation per path (allocations in parallel
        # threads serialise on the allocator)
        V = np.zeros((10, DIM), dtype=np.complex128)
        J = np.zeros((DIM, DIM), dtype=np.complex128)
        piv = np.zeros(DIM, dtype=np.int64)
        for job in range(b * jobs // blocks, (b + 1) * jobs // blocks):
            r = job // k
            j = job % k
            st, ns = _track(starts[j], mode, A, E, pidx, P0[r], p1, U, A1, c, gamma, Z[r, j], V, J, piv)
            status[r, j] = st
            steps[r, j] = ns
