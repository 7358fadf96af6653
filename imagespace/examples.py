"""Ready-made mechanisms of the seed papers.

* :func:`stigger_husty` -- the 2RPR-PPR six-solution example of Stigger & Husty (seed 002).
* :func:`collinear_3rpr` -- the 3-RPR with collinear base and platform anchors (seed 003).
* :func:`choi_3ppr` -- the symmetric 3-PPR of Choi (seed 004).
* :func:`general_3rpr` -- a general 3-RPR with six real assembly modes.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ._validate import as_exact, check_positive
from .legs import PPR, RPR
from .manipulator import PlanarParallel

__all__ = ["stigger_husty", "collinear_3rpr", "choi_3ppr", "general_3rpr"]


def stigger_husty():
    """The planar 2RPR-PPR manipulator of Stigger & Husty with its six-solution joint values.

    Geometry (SEEDS.md, checked against eqs. (5)-(7) of the paper; the paper's tables give
    ``b = (0, 5)`` and radius 12.56, which do not reproduce eq. (6)):

    * leg A: RPR, base ``(0, 0)``, platform ``(0, 0)``, length 10;
    * leg B: RPR, base ``(7, 0)``, platform ``(5, 0)``, length ``sqrt(232)``;
    * leg C: PPR, first slider from ``C = (10, 9)`` towards ``A`` (axis ``(-10, -9)``), travel
      ``13.25``; the passive slider perpendicular; platform point ``c = (7, 10)``.

    Exact (sympy) geometry; ``q_example = (10, sqrt(232), 53/4)``.

    Returns
    -------
    PlanarParallel

    References
    ----------
    T. Stigger, M. L. Husty, "Kinematische Analyse eines ebenen 2RPR-PPR-Manipulators".

    Examples
    --------
    >>> import imagespace as isp
    >>> m = isp.examples.stigger_husty()
    >>> m.q_example
    (10, 2*sqrt(58), 53/4)
    """
    m = PlanarParallel([RPR(base=(0, 0), platform=(0, 0)),
                        RPR(base=(7, 0), platform=(5, 0)),
                        PPR(base=(10, 9), axis=(-10, -9), platform=(7, 10), angle=sp.pi / 2)],
                       name="2RPR-PPR (Stigger-Husty)")
    m.q_example = (sp.Integer(10), sp.sqrt(232), sp.Rational(53, 4))
    return m


def collinear_3rpr(R=2, r=1):
    """The 3-RPR of seed 003: base ``(-R, 0), (0, 0), (R, 0)``, platform ``(-r, 0), (0, 0), (r, 0)``.

    The Cramer denominator of the elimination vanishes identically for this design (case (a)):
    the orientations follow from ``cos(theta) = [2(d2^2 + R^2 + r^2) - d1^2 - d3^2] / (4 r R)``,
    two positions each, four modes in all. ``q_example = (3R/2, R, R)`` (four real modes for the
    default ``R = 2, r = 1``, where ``cos(theta) = 5/8``).

    Parameters
    ----------
    R, r : positive numbers (exact or float), ``R != r``

    Returns
    -------
    PlanarParallel

    Examples
    --------
    >>> import imagespace as isp
    >>> m = isp.examples.collinear_3rpr(2, 1)
    >>> len(m.direct_kinematics(m.q_example))
    4
    """
    R = check_positive(as_exact(R, "R"), "R")
    r = check_positive(as_exact(r, "r"), "r")
    m = PlanarParallel([RPR(base=(-R, 0), platform=(-r, 0)),
                        RPR(base=(0, 0), platform=(0, 0)),
                        RPR(base=(R, 0), platform=(r, 0))], name="collinear 3-RPR")
    # q_example = (3R/2, R, R): cos(theta) = (3R^2/4 + 2r^2) / (4rR), four real modes for R=2, r=1
    m.q_example = (sp.Rational(3, 2) * R, R, R)
    return m


def choi_3ppr(R=1, r=sp.Rational(1, 2), alpha=7 * sp.pi / 18):
    """The symmetric 3-PPR of Choi (seed 004).

    Outer equilateral triangle with inscribed radius ``R``; slider ``i`` runs on side ``i``
    (``theta_i = 2 (i-1) pi / 3``, direction ``u_i``, inward normal ``v_i``, foot
    ``O_i = -R v_i``); a link at the angle ``alpha`` to the side carries the passive slider to the
    platform vertex ``B_i = r (sin theta_i, -cos theta_i)`` (moving frame, circumradius ``r``).
    Each leg is a :class:`~imagespace.legs.PPR` with base ``O_i``, axis ``u_i``, platform
    ``B_i`` and angle ``alpha``.

    Parameters
    ----------
    R, r : positive numbers
    alpha : angle in ``(0, pi)``

    Returns
    -------
    PlanarParallel

    Examples
    --------
    >>> import imagespace as isp
    >>> m = isp.examples.choi_3ppr()
    >>> len(m.direct_kinematics(m.q_example))
    2
    """
    R = check_positive(as_exact(R, "R"), "R")
    r = check_positive(as_exact(r, "r"), "r")
    alpha = as_exact(alpha, "alpha")
    legs = []
    for i in range(3):
        th = 2 * i * sp.pi / 3
        u = (sp.cos(th), sp.sin(th))
        v = (-sp.sin(th), sp.cos(th))
        legs.append(PPR(base=(-R * v[0], -R * v[1]), axis=u,
                        platform=(r * sp.sin(th), -r * sp.cos(th)), angle=alpha))
    m = PlanarParallel(legs, name="3-PPR (Choi)")
    # joint values of the pose (0.1 R, -0.05 R, 0.2)
    pose = np.array([0.1 * float(R), -0.05 * float(R), 0.2])
    m.q_example = tuple(sp.Float(v, 17) for v in m.inverse_kinematics(pose))
    return m


def general_3rpr():
    """A general 3-RPR with six real assembly modes at ``q_example``.

    Base anchors ``(7, -5), (-8, -4), (-2, 7)``; platform anchors ``(-1, -7), (-3, 2), (5, 4)``;
    ``q_example = (11, 5, 10)`` (found by a seeded search over integer designs and leg lengths).

    Returns
    -------
    PlanarParallel

    Examples
    --------
    >>> import imagespace as isp
    >>> m = isp.examples.general_3rpr()
    >>> len(m.direct_kinematics(m.q_example))
    6
    """
    m = PlanarParallel([RPR(base=(7, -5), platform=(-1, -7)),
                        RPR(base=(-8, -4), platform=(-3, 2)),
                        RPR(base=(-2, 7), platform=(5, 4))], name="general 3-RPR")
    m.q_example = (sp.Integer(11), sp.Integer(5), sp.Integer(10))
    return m
