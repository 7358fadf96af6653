"""Loops of joint vectors around a cusp: walking one assembly mode around it changes the mode
without crossing the singularity surface (the paths side of :mod:`imagespace.singular.cusps`).

References: the cusp loops of Stigger & Husty (seed 002), Abb. 6; see docs/references.md.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import _short, as_count, as_scalar
from ..core.mechanism import check_mechanism
from ..exceptions import InputError, InputTypeError
from ..singular.cusps import Cusp, free_joints, half_angle_gap
from .._html import dataclass_html, dataclass_repr
from ..solve import front

__all__ = ["CuspLoop", "cusp_loop", "MAX_STEPS"]

MAX_STEPS = 1_000_000
"""The largest ``steps`` :func:`cusp_loop` accepts (one direct-kinematics batch row per step)."""

@dataclass(frozen=True)
class CuspLoop:
    """A circle of joint vectors around a cusp, walked with one assembly mode followed by continuation.

    Attributes
    ----------
    q : (n, 3) float
        The loop (closed: first = last).
    poses : (n, 3) float
        The followed mode at each joint vector.
    start_mode, end_mode : int
        Index (in ``direct_kinematics(q[0])``) of the mode at the start and where the walk ends.
    changed : bool
        ``end_mode != start_mode``: the loop changed the assembly mode.
    aspects : (n,) int
        Sign of det J along the walk (constant: the walk never meets a singularity).
    winding : float
        Winding number of the loop around the cusp in the section (1 for the circle).
    continuous : bool
        No step of the walk jumped (a step more than ``Tolerances.loop_jump_ratio`` = 20 times the
        median would mean the followed mode was lost - it met a singularity - and another one was
        picked up).
    """

    q: np.ndarray
    poses: np.ndarray
    start_mode: int
    end_mode: int
    changed: bool
    aspects: np.ndarray
    winding: float = 1.0
    continuous: bool = True

    def certified_path(self, manipulator, every=8):
        """The followed modes as an image-space polyline, with its exact certificate.

        A polyline through every ``every``-th pose of the walk (signs of the representatives
        aligned); it joins the start mode to the end mode, and :func:`imagespace.paths.check.check_path`
        decides exactly whether it touches the singularity surface. If it does, the polyline is
        refined (``every`` halved, down to every pose) before the answer is returned.

        Returns
        -------
        (ImagePath, PathCheck)

        Raises
        ------
        TypeError
            ``manipulator`` not a design; ``every`` not a whole number.
        InputError
            ``every`` below 1.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.singular.cusps import cusps
        >>> from imagespace.paths.cusp_loops import cusp_loop
        >>> m = isp.examples.general_3rpr()
        >>> loop = cusp_loop(m, cusps(m, 2, 10.0, [(8, 14), (2, 8)], 60)[0], 2, 0.05)
        >>> path, chk = loop.certified_path(m)
        >>> chk.singularity_free
        True
        """
        from ..core.kinematic_map import image_point
        from .check import check_path, polyline

        check_mechanism(manipulator)
        every = min(as_count(every, "every"), len(self.poses))      # larger steps all mean "ends only"
        while True:
            idx = np.unique(np.append(np.arange(0, len(self.poses), every), len(self.poses) - 1))
            X = image_point(self.poses[idx])
            for k in range(1, len(X)):
                if X[k, :2] @ X[k - 1, :2] < 0:
                    X[k] = -X[k]
            path = polyline(X)
            chk = check_path(manipulator, path)
            if chk.singularity_free or every == 1:
                return path, chk
            every = max(1, every // 2)          # chords cut corners near the surface: refine

    # short summaries (arrays as shape and dtype) for the terminal and Jupyter; see imagespace._html
    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html


def cusp_loop(manipulator, cusp, fixed, radius, steps=720):
    """Walk a circle of radius ``radius`` around a cusp in the section and follow a mode.

    The walk starts in the middle of the arc of the circle with the most real modes (inside the
    cusp's wedge, where the three modes that merge at the cusp are all real) and follows, by
    continuation, each of the three modes nearest to the cusp's orientation; the first that comes
    back as another mode is returned (the classical non-singular assembly-mode change), otherwise
    the walk of the nearest one.

    Parameters
    ----------
    manipulator : PlanarParallel
    cusp : Cusp
    fixed : int
        The section's fixed joint (as given to :func:`cusps`).
    radius : float
    steps : int

    Returns
    -------
    CuspLoop

    Raises
    ------
    TypeError
        ``manipulator`` not a design; ``cusp`` not a :class:`Cusp`; ``fixed`` or ``steps``
        not a whole number; non-numeric ``radius``.
    InputError
        ``fixed`` not 0, 1 or 2; ``radius`` not positive; ``steps`` outside 8..MAX_STEPS; a
        loop that loses every real mode.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.cusps import cusps
    >>> from imagespace.paths.cusp_loops import cusp_loop
    >>> m = isp.examples.general_3rpr()
    >>> c = cusps(m, 2, 10.0, [(8, 14), (2, 8)], 60)[0]
    >>> loop = cusp_loop(m, c, 2, 0.05)
    >>> loop.changed, loop.continuous, bool(np.all(loop.aspects == loop.aspects[0]))
    (True, True, True)
    """
    check_mechanism(manipulator)
    if not isinstance(cusp, Cusp):
        raise InputTypeError(f"cusp must be a Cusp (an item of cusps(...)), got {type(cusp).__name__} {_short(cusp)}")
    fa, fb = free_joints(fixed)
    radius = as_scalar(radius, "radius")
    if not radius > 0:
        raise InputError(f"radius must be positive, got {radius!r}")
    steps = as_count(steps, "steps", 8)
    if steps > MAX_STEPS:
        raise InputError(f"steps must be at most MAX_STEPS = {MAX_STEPS}, got {_short(steps)}")
    ang = np.linspace(0, 2 * np.pi, steps + 1)[:-1]
    Q = np.repeat(cusp.q[None], steps, axis=0)
    Q[:, fa] += radius * np.cos(ang)
    Q[:, fb] += radius * np.sin(ang)
    res = front.direct_kinematics_batch(manipulator, Q, method="numpy")
    count = np.where(res.row_ok, res.count.astype(np.int64), -1)     # count is uint8: widen before -1
    top = count == count.max()
    # the middle of the longest run of maximal count (cyclically)
    idx = np.flatnonzero(top)
    if len(idx) == len(top):
        k0 = 0
    else:
        start = idx[np.flatnonzero(~top[(idx - 1) % len(top)])]
        runs = [(int(np.sum(top[np.arange(a, a + len(top)) % len(top)].cumprod())), a) for a in start]
        length, a = max(runs)
        k0 = (a + length // 2) % len(top)
    order = np.append(np.roll(np.arange(steps), -k0), k0)
    Qo = Q[order]
    v0 = res.valid[k0]                          # modes numbered among the valid ones, as in ``end``
    modes0 = list(enumerate(zip(res.image_points[k0][v0], res.poses[k0][v0], res.aspect[k0][v0])))
    modes0 = [(j, X, P, asp) for j, (X, P, asp) in modes0]
    near = sorted(modes0, key=lambda mm: half_angle_gap(mm[2][2], cusp.theta))[:3]
    walks = []
    tols = manipulator.tolerances
    for j0, X0, P0, a0 in near:
        X, poses, aspects, jumps = X0, [P0], [int(a0)], []
        for k in order[1:]:
            cand = res.image_points[k][res.valid[k]]
            if len(cand) == 0:
                break
            d = np.minimum(np.linalg.norm(cand - X, axis=1), np.linalg.norm(cand + X, axis=1))
            j = int(np.argmin(d))
            jumps.append(d[j])
            X = cand[j]
            poses.append(res.poses[k][res.valid[k]][j])
            aspects.append(int(res.aspect[k][res.valid[k]][j]))
        if len(poses) < len(order):
            continue
        d0 = [min(np.linalg.norm(Y - X), np.linalg.norm(Y + X)) for Y in res.image_points[k0][v0]]
        end = int(np.argmin(d0))
        start_j = j0
        jumps = np.array(jumps)
        continuous = bool(jumps.max() <= max(tols.loop_jump_ratio * np.median(jumps), tols.loop_jump_floor))
        loop = CuspLoop(Qo, np.array(poses), start_j, end, end != start_j, np.array(aspects),
                        continuous=continuous)
        if loop.changed and loop.continuous and np.all(loop.aspects == loop.aspects[0]):
            return loop
        walks.append(loop)
    if not walks:
        raise InputError("the loop loses every real mode; choose a smaller radius")
    return walks[0]


