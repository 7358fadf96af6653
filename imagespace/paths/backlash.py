"""Joint backlash: play in one actuated joint, the released motion, and unwanted mode changes.

Seed 002, section 6: with play ``+-delta`` in the actuated joint of leg ``i``, that leg no longer
fixes its constraint exactly. Releasing it, the other two legs (joints locked) leave a one-degree-
of-freedom mechanism whose configurations form a curve in image space (the intersection of their
two quadrics; for seed 002 the platform point of the PPR leg runs on the coupler curve of the
remaining four-bar). The poses compatible with the joint values inside the play are the points of
that curve where leg ``i``'s inverse kinematics stays within ``+-delta`` of its nominal value (a
band). An arc of the curve inside the band that contains two assembly modes lets the platform
travel from one to the other: an unwanted assembly-mode change caused by play.

:func:`backlash` samples the curve densely over the half-angle ``theta = phi/2`` (at each
orientation the two quadrics meet in at most two points, found in closed form), links the samples
into the curve's circuits, and computes for every pair of modes the smallest play that connects
them: the minimax (bottleneck) value of ``|q_i - q_i0|`` over the paths between them, the largest
deviation on the best arc, refined by a bounded scalar maximisation around the sampled maximum.
Modes on different circuits are never connected (threshold ``inf``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import numbers

from .._validate import _short, as_count, as_float_array, as_joint_vector
from ..exceptions import InputError, InputTypeError
from ..core.mechanism import check_mechanism
from .._html import dataclass_html, dataclass_repr
from ..solve import front

__all__ = ["BacklashAnalysis", "backlash", "released_curve", "MAX_MEMORY"]

MAX_MEMORY = 2 * 1024**3
"""Default limit (bytes) for the estimated memory of :func:`released_curve` and :func:`backlash`."""
_BYTES_PER_SAMPLE = {"released_curve": 320, "backlash": 1024}
"""Measured peak memory per orientation sample (tracemalloc, 40,000 samples: 273 and 757 bytes)."""


def _check_leg(leg):
    if isinstance(leg, (bool, np.bool_)) or not isinstance(leg, (numbers.Integral, np.integer)):
        raise InputTypeError(f"leg must be the whole number 0, 1 or 2 (the leg with play), got "
                             f"{type(leg).__name__} {_short(leg)}")
    if leg not in (0, 1, 2):
        raise InputError(f"leg must be 0, 1 or 2 (the leg with play), got {leg!r}")
    return int(leg)


def _check_samples(samples, max_memory, what):
    samples = as_count(samples, "samples", 100)
    if isinstance(max_memory, (bool, np.bool_)) or not isinstance(max_memory, numbers.Real):
        raise InputTypeError(f"max_memory must be a number of bytes, got {type(max_memory).__name__} "
                             f"{_short(max_memory)}")
    if not (max_memory > 0 and max_memory < float("inf")):
        raise InputError(f"max_memory must be a positive finite number of bytes, got {max_memory!r}")
    need = samples * _BYTES_PER_SAMPLE[what]                  # exact: samples may be huge
    if need > max_memory:
        size = f"{need / 1e9:.3g}" if need < 1e300 else "more than 1e291"
        raise InputError(f"samples={_short(samples)} needs about {size} GB for {what}, above the limit "
                         f"max_memory={max_memory / 1e9:.3g} GB; lower samples (at most "
                         f"{int(max_memory // _BYTES_PER_SAMPLE[what])}) or raise max_memory")
    return samples


def _pair_points(qa, qb, theta):
    """Intersection points of two dyad quadrics (float coefficients) at half-angles ``theta``:
    ``(n, 2, 4)`` image points (NaN where absent)."""
    x0, x1 = np.cos(theta), np.sin(theta)

    def parts(Q):
        A = Q.a0 * x0 + Q.a1 * x1
        B = Q.b0 * x0 + Q.b1 * x1
        K = Q.k0 * x0**2 + Q.k1 * x0 * x1 + Q.k2 * x1**2
        return float(Q.c), A, B, K

    c1, A1, B1, K1 = parts(qa)
    c2, A2, B2, K2 = parts(qb)
    n = len(theta)
    U = np.full((n, 2, 2), np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        if c1 == 0 and c2 == 0:
            det = A1 * B2 - A2 * B1
            U[:, 0, 0] = (-K1 * B2 + K2 * B1) / det
            U[:, 0, 1] = (-A1 * K2 + A2 * K1) / det
        else:
            al, be, ga = c2 * A1 - c1 * A2, c2 * B1 - c1 * B2, c2 * K1 - c1 * K2
            c, A, B, K = (c1, A1, B1, K1) if c1 != 0 else (c2, A2, B2, K2)
            nn = np.hypot(al, be)
            p0u, p0v = -ga * al / nn**2, -ga * be / nn**2
            du, dv = -be / nn, al / nn
            a2 = c
            a1 = 2 * c * (p0u * du + p0v * dv) + A * du + B * dv
            a0 = c * (p0u**2 + p0v**2) + A * p0u + B * p0v + K
            disc = a1**2 - 4 * a2 * a0
            ok = disc >= 0
            sq = np.sqrt(np.where(ok, disc, np.nan))
            for j, sgn in enumerate((1.0, -1.0)):
                s = (-a1 + sgn * sq) / (2 * a2)
                U[:, j, 0] = p0u + s * du
                U[:, j, 1] = p0v + s * dv
    X = np.empty((n, 2, 4))
    X[:, :, 0] = x0[:, None]
    X[:, :, 1] = x1[:, None]
    X[:, :, 2:] = U
    return X


def released_curve(manipulator, q, leg, samples=20000, max_memory=MAX_MEMORY):
    """The configuration curve of the two legs other than ``leg`` with their joints at ``q``.

    Parameters
    ----------
    manipulator : PlanarParallel
    q : (3,) float
    leg : int
        The released leg.
    samples : int
        Half-angles ``theta`` in ``[-pi/2, pi/2]``.
    max_memory : float
        Limit (bytes) for the estimated memory (about 320 bytes per sample); default
        :data:`MAX_MEMORY`, 2 GiB.

    Returns
    -------
    theta : (samples,) float
    X : (samples, 2, 4) float
        Up to two image points per orientation (``x0**2 + x1**2 = 1``); NaN where absent.

    Raises
    ------
    TypeError
        ``manipulator`` not a design; ``leg`` or ``samples`` not a whole number; non-numeric
        ``q`` or ``max_memory``.
    InputError
        ``leg`` not 0, 1 or 2; ``q`` not ``(3,)`` or outside a joint's domain; ``samples``
        below 100 or above the memory limit; locked legs that are not RR, PR or RP dyads.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.paths.backlash import released_curve
    >>> m = isp.examples.stigger_husty()
    >>> th, X = released_curve(m, m.q_example_float, 2, 1000)
    >>> X.shape
    (1000, 2, 4)
    """
    check_mechanism(manipulator)
    samples = _check_samples(samples, max_memory, "released_curve")
    qf = manipulator.check_q(as_joint_vector(q, "q"))
    leg = _check_leg(leg)
    others = [j for j in range(3) if j != leg]
    quads = [manipulator.legs[j].dyad(float(qf[j])) for j in others]
    if any(Q.kind == "PP" for Q in quads):
        raise InputError("backlash analysis needs the two locked legs to be RR, PR or RP dyads "
                         "(a PP dyad fixes the orientation; its curve is not parametrised by phi)")
    theta = np.linspace(-np.pi / 2, np.pi / 2, samples)
    return theta, _pair_points(quads[0], quads[1], theta)


@dataclass(frozen=True)
class BacklashAnalysis:
    """The result of :func:`backlash`.

    Attributes
    ----------
    leg : int
        The leg with play.
    delta : float
        The play analysed (``connected``, ``mobility``).
    q : (3,) float
    modes : list of AssemblyMode
        The assembly modes at ``q``.
    thresholds : (k, k) float
        Smallest play that connects modes ``a`` and ``b`` along the released curve (``inf`` on
        different circuits, ``0`` on the diagonal).
    connected : (k, k) bool
        ``thresholds < delta`` (pairs the given play connects).
    mobility : (k,) float
        For each mode, the range of ``phi`` (radians) the platform can sweep inside the band.
    theta : (n,) float
    points : (n, 2, 4) float
        The sampled released curve.
    deviation : (n, 2) float
        ``|q_leg - q0|`` along it.
    """

    leg: int
    delta: float
    q: np.ndarray
    modes: list
    thresholds: np.ndarray
    connected: np.ndarray
    mobility: np.ndarray
    theta: np.ndarray
    points: np.ndarray
    deviation: np.ndarray

    # short summaries (arrays as shape and dtype) for the terminal and Jupyter; see imagespace._html
    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html


class _DSU:
    def __init__(self, n):
        self.p = np.arange(n)

    def find(self, a):
        while self.p[a] != a:
            self.p[a] = self.p[self.p[a]]
            a = self.p[a]
        return a

    def union(self, a, b):
        ra, rb = self.find(a), self.find(b)
        if ra != rb:
            self.p[ra] = rb


def _edges(X):
    """Edges between samples of the curve: consecutive orientations (nearest pairing), the two
    points of one orientation where a circuit turns, and the wrap-around ``theta = +-pi/2``
    (where the representative changes sign)."""
    n = len(X)
    valid = np.all(np.isfinite(X), axis=2)
    idx = lambda k, s: 2 * k + s
    edges = []
    for k in range(n - 1):
        a = [s for s in (0, 1) if valid[k, s]]
        b = [s for s in (0, 1) if valid[k + 1, s]]
        if a and b:
            if len(a) == 2 and len(b) == 2:
                d_same = np.linalg.norm(X[k, 0] - X[k + 1, 0]) + np.linalg.norm(X[k, 1] - X[k + 1, 1])
                d_swap = np.linalg.norm(X[k, 0] - X[k + 1, 1]) + np.linalg.norm(X[k, 1] - X[k + 1, 0])
                pairs = [(0, 0), (1, 1)] if d_same <= d_swap else [(0, 1), (1, 0)]
            else:
                pairs = [(sa, min(b, key=lambda sb: np.linalg.norm(X[k, sa] - X[k + 1, sb]))) for sa in a] \
                    if len(a) <= len(b) else \
                    [(min(a, key=lambda sa: np.linalg.norm(X[k, sa] - X[k + 1, sb])), sb) for sb in b]
            edges += [(idx(k, sa), idx(k + 1, sb)) for sa, sb in pairs]
        if len(a) == 2 and len(b) < 2:
            edges.append((idx(k, 0), idx(k, 1)))             # the circuit turns here
        if len(b) == 2 and len(a) < 2:
            edges.append((idx(k + 1, 0), idx(k + 1, 1)))
    for sa in (0, 1):                                        # wrap: theta = pi/2 ~ -pi/2, X ~ -X
        if valid[n - 1, sa]:
            cand = [sb for sb in (0, 1) if valid[0, sb]]
            if cand:
                sb = min(cand, key=lambda c: np.linalg.norm(X[n - 1, sa] + X[0, c]))
                edges.append((idx(n - 1, sa), idx(0, sb)))
    return edges


def backlash(manipulator, q, leg, delta=0.0, samples=20000, max_memory=MAX_MEMORY):
    """Play ``+-delta`` in the actuated joint of ``leg``: which assembly modes it connects, and from what play on.

    Parameters
    ----------
    manipulator : PlanarParallel
    q : (3,) float
        Nominal joint values.
    leg : int
        The leg whose actuated joint has play.
    delta : float
        The play to analyse (``>= 0``).
    samples : int
        Orientations sampled on the released curve.
    max_memory : float
        Limit (bytes) for the estimated memory (about 1 kB per sample); default
        :data:`MAX_MEMORY`, 2 GiB.

    Returns
    -------
    BacklashAnalysis

    Raises
    ------
    InputError
        ``samples`` would need more than ``max_memory`` (the message gives the estimate and the
        largest ``samples`` that fits), fewer than 100 samples, a negative or non-finite
        ``delta``, a ``leg`` other than 0, 1, 2.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.paths.backlash import backlash
    >>> m = isp.examples.stigger_husty()
    >>> res = backlash(m, m.q_example_float, 2, delta=0.5)
    >>> res.thresholds.shape, bool(np.all(np.diag(res.thresholds) == 0))
    ((6, 6), True)
    """
    check_mechanism(manipulator)
    samples = _check_samples(samples, max_memory, "backlash")
    d = as_float_array(delta, "delta", finite=False)
    if d.ndim != 0:
        raise InputError(f"delta must be a single number, got shape {d.shape}")
    if not np.isfinite(d) or d < 0:
        raise InputError(f"delta must be a finite play >= 0, got {delta!r}")
    delta = float(d)
    leg = _check_leg(leg)
    qf = manipulator.check_q(as_joint_vector(q, "q"))
    theta, X = released_curve(manipulator, qf, leg, samples, max_memory=max_memory)
    L = manipulator.legs[leg]
    modes = front.direct_kinematics(manipulator, qf)
    # the released leg's branch: the one reproducing q at the modes
    if modes:
        vals = L.actuated_values(np.array([mm.pose for mm in modes]))
        branch = int(np.argmin(np.nanmin(np.abs(vals - qf[leg]), axis=0)))
    else:
        branch = 0
    from ..core.kinematic_map import pose_of

    flat = X.reshape(-1, 4)
    ok = np.all(np.isfinite(flat), axis=1)
    dev = np.full(len(flat), np.inf)
    poses = np.full((len(flat), 3), np.nan)
    poses[ok] = pose_of(flat[ok])
    with np.errstate(invalid="ignore"):
        qi = L.actuated_values(np.where(np.isfinite(poses), poses, 0.0))[:, branch]
    d = L.joint_distance(qi, qf[leg])
    dev[ok] = np.where(np.isfinite(d[ok]), d[ok], np.inf)
    edges = _edges(X)
    nbr = [[] for _ in range(len(flat))]
    for a, b in edges:
        nbr[a].append(b)
        nbr[b].append(a)
    # the node of each mode: nearest sample (either sign of the representative)
    mode_nodes = []
    for mm in modes:
        Y = mm.image_point / np.hypot(*mm.image_point[:2])
        dist = np.minimum(np.linalg.norm(flat - Y, axis=1), np.linalg.norm(flat + Y, axis=1))
        mode_nodes.append(int(np.nanargmin(np.where(ok, dist, np.inf))))
    k = len(modes)
    thr = np.full((k, k), np.inf)
    np.fill_diagonal(thr, 0.0)
    order = np.argsort(dev)
    dsu = _DSU(len(flat))
    added = np.zeros(len(flat), dtype=bool)
    pending = {(a, b) for a in range(k) for b in range(a + 1, k)}
    for node in order:
        if not np.isfinite(dev[node]) or not pending:
            break
        added[node] = True
        for nb in nbr[node]:
            if added[nb]:
                dsu.union(node, nb)
        for a, b in list(pending):
            if dsu.find(mode_nodes[a]) == dsu.find(mode_nodes[b]) and added[mode_nodes[a]] and added[mode_nodes[b]]:
                thr[a, b] = thr[b, a] = _refine(manipulator, qf, leg, branch, theta, X, node, dev[node])
                pending.discard((a, b))
    connected = thr < delta
    np.fill_diagonal(connected, True)
    mobility = _mobility(dev, nbr, mode_nodes, poses, delta)
    return BacklashAnalysis(leg, float(delta), qf, modes, thr, connected, mobility, theta, X,
                            dev.reshape(len(theta), 2))


def _refine(m, q, leg, branch, theta, X, node, value):
    """Refine a sampled maximum of the deviation by a bounded maximisation over theta."""
    from scipy.optimize import minimize_scalar

    from ..core.kinematic_map import pose_of

    k, s = divmod(node, 2)
    if k == 0 or k == len(theta) - 1:
        return float(value)
    others = [j for j in range(3) if j != leg]
    quads = [m.legs[j].dyad(float(q[j])) for j in others]
    ref = X[k, s]
    L = m.legs[leg]

    def neg_dev(t):
        P = _pair_points(quads[0], quads[1], np.array([t]))[0]
        good = np.all(np.isfinite(P), axis=1)
        if not good.any():
            return -value
        j = int(np.argmin(np.where(good, np.linalg.norm(P - ref, axis=1), np.inf)))
        qi = L.actuated_values(pose_of(P[j]))[branch]
        return -abs(qi - q[leg]) if np.isfinite(qi) else -value

    r = minimize_scalar(neg_dev, bounds=(theta[k - 1], theta[k + 1]), method="bounded",
                        options={"xatol": 1e-13})
    return float(max(value, -r.fun))


def _mobility(dev, nbr, mode_nodes, poses, delta):
    """Range of phi swept inside the band from each mode (flood fill over samples with dev <= delta)."""
    out = []
    for start in mode_nodes:
        seen = {start}
        stack = [start]
        while stack:
            a = stack.pop()
            for b in nbr[a]:
                if b not in seen and dev[b] <= delta:
                    seen.add(b)
                    stack.append(b)
        phi = np.unwrap(np.sort(poses[list(seen), 2]))
        out.append(float(np.ptp(phi)) if len(phi) > 1 else 0.0)
    return np.array(out)
