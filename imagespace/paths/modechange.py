"""Assembly-mode change: a path between two assembly modes that never touches the singularity surface.

Why a straight segment never works (and the planner starts with two): if ``X`` and ``Y`` are two
normalised solutions of the same constraint system (``Q_i(X) = Q_i(Y) = 0``,
``x0**2 + x1**2 = 1`` for both), then at their midpoint ``M = (X + Y)/2`` the vector ``X - Y`` is
in the kernel of the Jacobian ``J(M)``: for a quadratic form ``grad Q(M) . (X - Y) = Q(X) - Q(Y)
= 0``, and the normalisation row gives ``M0 (X0 - Y0) + M1 (X1 - Y1) = (1 - 1)/2 = 0``. So
``det J(M) = 0``: every chord between two modes (with any signs of the representatives) meets
the singularity surface at its midpoint. Stigger & Husty's two-segment polyline through the
"hole" of the surface is the shortest kind of answer.

The planner (:func:`plan_mode_change`): modes of opposite aspect are refused with the reason (the
sign of ``det J`` is even, hence defined on the projective image space, and continuous, so any
path between opposite signs meets ``det J = 0``). Otherwise it samples intermediate image points
of the right sign (seeded), tests all two-segment polylines ``a -> w -> b`` at once with the
batched certified test :func:`imagespace.paths.check.segments_free`, and, if none is free, searches a
visibility graph of the samples (Dijkstra). The chosen path is certified again by the exact
:func:`imagespace.paths.check.check_path` (which also checks that no leg reaches zero length), and its
loop in joint space is computed by following each leg's inverse-kinematics branch continuously.

References
----------
T. Stigger, M. L. Husty, seed 002, section 5 (Abb. 5, 6).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import numbers

from .._validate import _short, as_box, as_count, as_float_array, as_joint_vector
from ..exceptions import InputError, InputTypeError
from ..core.kinematic_map import image_point, normalize
from ..core.mechanism import check_mechanism
from .check import ImagePath, PathCheck, check_path, polyline, segments_free
from .._html import fmt, html_table, summary
from ..solve import front

__all__ = ["ModeChangePlan", "plan_mode_change", "joint_trajectory"]


@dataclass(frozen=True)
class ModeChangePlan:
    """The answer of :func:`plan_mode_change`.

    Attributes
    ----------
    found : bool
    reason : str
        Why no path exists or none was found; how the path was found otherwise.
    path : ImagePath or None
        Starts at ``mode_a``'s normalised image point, ends at ``mode_b``'s (or its negative,
        the same point of image space).
    check : PathCheck or None
        The exact certificate of ``path`` (``check.singularity_free`` is True).
    poses : (n, 3) float or None
        Poses along the path (``phi`` unwrapped).
    joint_loop : (n, 3) float or None
        Joint values along the path; starts and ends at ``q`` (a closed loop in joint space).
    candidates : int
        How many intermediate points were tried.
    """

    found: bool
    reason: str
    path: ImagePath | None = None
    check: PathCheck | None = None
    poses: np.ndarray | None = None
    joint_loop: np.ndarray | None = None
    candidates: int = 0

    def _summary_items(self):
        items = [("found", fmt(self.found)), ("reason", self.reason)]
        if self.path is not None:
            items.append(("path", f"{len(self.path)} {self.path.kind} piece(s)"))
        if self.check is not None:
            items.append(("check", "singularity-free" if self.check.singularity_free else "meets the surface"))
        for name in ("poses", "joint_loop"):
            value = getattr(self, name)
            if value is not None:
                items.append((name, fmt(value)))
        items.append(("candidates", fmt(self.candidates)))
        return items

    def __repr__(self):
        """Whether and how a path was found, its size, never the sampled poses.

        Examples
        --------
        >>> from imagespace.paths.modechange import ModeChangePlan
        >>> ModeChangePlan(False, "the modes have different aspects")
        ModeChangePlan(found=False, reason='the modes have different aspects', candidates=0)
        """
        return summary("ModeChangePlan", [(k, fmt(v) if k == "reason" else v) for k, v in self._summary_items()])

    def _repr_html_(self):
        """The summary as an HTML table.

        Examples
        --------
        >>> from imagespace.paths.modechange import ModeChangePlan
        >>> "different aspects" in ModeChangePlan(False, "different aspects")._repr_html_()
        True
        """
        return html_table(self._summary_items(), title="ModeChangePlan")


MAX_SAMPLES = 1_000_000
"""The largest ``samples`` :func:`plan_mode_change` accepts (a round draws ``4 * samples`` poses)."""


def joint_trajectory(manipulator, path, q_start, per_piece=64):
    """Joint values along a path, each leg's IK branch followed continuously from ``q_start``.

    Parameters
    ----------
    manipulator : PlanarParallel
    path : ImagePath
    q_start : (3,) float
        Joint values at the path's start (pick the branches).
    per_piece : int

    Returns
    -------
    poses : (n, 3) float
    q : (n, 3) float
        NaN where a leg cannot reach the pose.

    Raises
    ------
    TypeError
        ``manipulator`` not a design; ``path`` not an :class:`ImagePath`; ``per_piece`` not
        a whole number; non-numeric ``q_start``.
    InputError
        ``per_piece`` outside 1..MAX_SAMPLES; ``q_start`` not ``(3,)``; a path that does not
        start at a pose of ``q_start`` (leg residual not below
        ``Tolerances.mode_membership``).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.paths.check import pose_segment
    >>> from imagespace.paths.modechange import joint_trajectory
    >>> m = isp.examples.general_3rpr()
    >>> q0 = m.inverse_kinematics([0.0, 0.0, 0.0])
    >>> P, Q = joint_trajectory(m, pose_segment([0, 0, 0], [1, 0, 0.2]), q0, 4)
    >>> bool(np.allclose(Q[0], q0)), Q.shape
    (True, (5, 3))
    """
    per_piece = as_count(per_piece, "per_piece")
    if per_piece > MAX_SAMPLES:
        raise InputError(f"per_piece must be at most MAX_SAMPLES = {MAX_SAMPLES}, got {_short(per_piece)}")
    check_mechanism(manipulator)
    if not isinstance(path, ImagePath):
        raise InputTypeError(f"path must be an ImagePath (isp.segment, isp.polyline ...), got "
                             f"{type(path).__name__} {_short(path)}")
    q0 = as_joint_vector(q_start, "q_start")
    P = path.poses(per_piece)
    r = manipulator.joint_residual(P[0], q0)
    if not r < manipulator.tolerances.mode_membership:
        raise InputError(f"path does not start at a pose of q_start = {q0.tolist()}: the legs' inverse "
                         f"kinematics at the start pose {np.round(P[0], 6).tolist()} differ by {r:.2e}")
    Q = np.full((len(P), 3), np.nan)
    for i, leg in enumerate(manipulator.legs):
        vals = leg.actuated_values(P)                     # (n, branches)
        prev = q0[i]
        for k in range(len(P)):
            v = vals[k]
            d = leg.joint_distance(v, prev)
            if np.all(np.isnan(d)):
                continue
            j = int(np.nanargmin(d))
            Q[k, i] = v[j] if not leg.actuated_is_angle else prev + leg.joint_difference(v[j], prev)
            prev = Q[k, i]
    return P, Q


def _is_index(value):
    return isinstance(value, (numbers.Integral, np.integer)) and not isinstance(value, (bool, np.bool_))


def _as_image(mode, name):
    X = getattr(mode, "image_point", mode)
    X = as_float_array(X, name, last=4, allow_batch=False)
    if X[0] == 0 and X[1] == 0:
        raise InputError(f"{name} must have (x0, x1) != (0, 0): a point of the absolute line is not a "
                         f"displacement, got {X.tolist()}")
    return normalize(X)


def plan_mode_change(manipulator, q, mode_a, mode_b, seed=0, samples=400, box=None):
    """A certified singularity-free path between two assembly modes of the same joint values.

    Parameters
    ----------
    manipulator : PlanarParallel
        Its singularity surface must not depend on the joint values.
    q : (3,) float
        The joint values both modes belong to.
    mode_a, mode_b : AssemblyMode, (4,) float or int
        A mode, its image point, or its index into ``manipulator.direct_kinematics(q)``.
    seed : int
        The sampling is deterministic for a given seed.
    samples : int
        Intermediate points per round (two rounds at most, then a visibility graph).
    box : (3, 2) float, optional
        Where to sample, in pose coordinates ``(x, y, phi)``; default: the two poses' bounding
        box enlarged by the design's size, all orientations.

    Returns
    -------
    ModeChangePlan

    Raises
    ------
    InputError
        If a mode does not belong to ``q`` (leg residual not below ``Tolerances.mode_membership``,
        default 1e-6), the two are the same (``Tolerances.same_mode``), or an index is not one of
        ``direct_kinematics(q)``.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.paths.modechange import plan_mode_change
    >>> m = isp.examples.stigger_husty()
    >>> modes = m.direct_kinematics(m.q_example)
    >>> plan = plan_mode_change(m, m.q_example_float, modes[0], modes[3])
    >>> plan.found, len(plan.path), plan.check.singularity_free
    (True, 2, True)
    >>> plan_mode_change(m, m.q_example_float, modes[0], modes[1]).found
    False
    >>> plan_mode_change(m, m.q_example_float, 0, 3).found          # indices into direct_kinematics(q)
    True
    """
    check_mechanism(manipulator)
    samples = as_count(samples, "samples")
    if samples > MAX_SAMPLES:
        raise InputError(f"samples must be at most MAX_SAMPLES = {MAX_SAMPLES} (each round draws and tests "
                         f"4 * samples poses), got {_short(samples)}")
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (numbers.Integral, np.integer)):
        raise InputTypeError(f"seed must be a whole number, got {type(seed).__name__} {_short(seed)}")
    if seed < 0:
        raise InputError(f"seed must be a non-negative whole number, got {seed}")
    if box is not None:
        _check_box(box)
    qf = manipulator.check_q(as_joint_vector(q, "q"))
    if any(_is_index(v) for v in (mode_a, mode_b)):
        from .._validate import as_index

        modes = list(front.direct_kinematics(manipulator, qf))

        def pick(v, name):
            if not _is_index(v):
                return v
            try:
                return modes[as_index(v, name, len(modes))]
            except InputError as e:
                raise type(e)(f"{e} (an index into direct_kinematics(q): {len(modes)} real modes "
                              f"at q = {qf.tolist()})") from None

        mode_a, mode_b = pick(mode_a, "mode_a"), pick(mode_b, "mode_b")
    Xa, Xb = _as_image(mode_a, "mode_a"), _as_image(mode_b, "mode_b")
    tols = manipulator.tolerances
    if np.allclose(Xa, Xb, atol=tols.same_mode):
        raise InputError("mode_a and mode_b are the same assembly mode")
    from ..core.kinematic_map import pose_of

    for name, X in (("mode_a", Xa), ("mode_b", Xb)):
        r = manipulator.joint_residual(pose_of(X), qf)
        if not r < tols.mode_membership:
            raise InputError(f"{name} is not an assembly mode of q = {qf.tolist()} (leg residual {r:.2e})")
    S = manipulator.singularity_surface()
    sa, sb = np.sign(S(Xa)), np.sign(S(Xb))
    if sa == 0 or sb == 0:
        return ModeChangePlan(False, "a mode lies on the singularity surface (det J = 0)")
    if sa != sb:
        return ModeChangePlan(False, f"no singularity-free path exists: det J is {sa:+.0f} at mode_a and "
                                     f"{sb:+.0f} at mode_b (opposite aspects); det J is continuous and even, "
                                     "so every path between them meets det J = 0")
    rng = np.random.default_rng(seed)
    Pa, Pb = pose_of(Xa), pose_of(Xb)
    if box is None:
        L = max(1.0, float(np.max(np.abs(np.concatenate([Pa[:2], Pb[:2]])))))
        lo, hi = np.minimum(Pa[:2], Pb[:2]) - L, np.maximum(Pa[:2], Pb[:2]) + L
        box = [(lo[0], hi[0]), (lo[1], hi[1]), (-np.pi, np.pi)]
    b = _check_box(box)
    tried = 0
    pool = np.zeros((0, 4))
    for _round in range(2):
        W = _sample(rng, b, samples, S, sa)
        tried += len(W)
        pool = np.concatenate([pool, W])
        plan = _two_segments(manipulator, S, qf, Xa, Xb, W, tried)
        if plan is not None:
            return plan
    plan = _graph(manipulator, S, qf, Xa, Xb, pool, tried)
    if plan is not None:
        return plan
    return ModeChangePlan(False, f"no certified path found among {tried} sampled points (seed {seed}); "
                                 "try another seed, more samples or a larger box", candidates=tried)


def _check_box(box):
    try:
        return as_box(box, "box")
    except InputError as exc:
        raise type(exc)(f"box must be (3, 2) with min < max per axis; {exc}") from None


def _sample(rng, b, n, S, sign):
    P = np.column_stack([rng.uniform(b[i, 0], b[i, 1], n * 4) for i in range(3)])
    W = normalize(image_point(P))
    W = W[np.sign(S(W)) == sign]
    return W[:n]


def _align(X, ref):
    """The representative of X (+X or -X) on the same side as ref."""
    return X if X[:2] @ ref[:2] >= 0 else -X


def _finish(manipulator, S, q, points, tried, how):
    path = polyline(points)
    chk = check_path(S, path, manipulator=manipulator)
    if not chk.singularity_free or chk.domain_exits:
        return None
    P, Q = joint_trajectory(manipulator, path, q)
    if np.any(np.isnan(Q)):
        return None
    return ModeChangePlan(True, how, path, chk, P, Q, tried)


def _two_segments(manipulator, S, q, Xa, Xb, W, tried):
    if len(W) == 0:
        return None
    Wa = np.array([_align(w, Xa) for w in W])
    Xb2 = _align(Xb, Xa)
    ok1, _ = segments_free(S, np.repeat(Xa[None], len(W), 0), Wa)
    ok2, _ = segments_free(S, Wa, np.repeat(Xb2[None], len(W), 0))
    good = np.flatnonzero(ok1 & ok2)
    if len(good) == 0:
        return None
    length = np.linalg.norm(Wa[good] - Xa, axis=1) + np.linalg.norm(Xb2 - Wa[good], axis=1)
    for k in good[np.argsort(length)][:20]:
        plan = _finish(manipulator, S, q, [Xa, Wa[k], Xb2], tried,
                       f"two segments through an intermediate point (best of {len(good)} free candidates "
                       f"among {tried} samples, shortest first), certified by the exact check")
        if plan is not None:
            return plan
    return None


def _graph(manipulator, S, q, Xa, Xb, pool, tried):
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import dijkstra

    V = np.concatenate([Xa[None], pool, Xb[None]])
    n = len(V)
    I, J = np.triu_indices(n, 1)
    A = V[I]
    B = np.array([_align(V[j], V[i]) for i, j in zip(I, J)])
    ok, _ = segments_free(S, A, B, exact=False)
    w = np.linalg.norm(A - B, axis=1)
    G = csr_matrix((w[ok], (I[ok], J[ok])), shape=(n, n))
    dist, pred = dijkstra(G, directed=False, indices=0, return_predecessors=True)
    if not np.isfinite(dist[n - 1]):
        return None
    chain = [n - 1]
    while chain[-1] != 0:
        chain.append(pred[chain[-1]])
    chain = chain[::-1]
    pts = [V[chain[0]]]
    for k in chain[1:]:
        pts.append(_align(V[k], pts[-1]))
    return _finish(manipulator, S, q, pts, tried,
                   f"visibility graph over {n - 2} sampled points ({ok.sum()} free edges), "
                   f"{len(pts) - 1} segments, certified by the exact check")
