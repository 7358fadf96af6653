"""Ready-made mechanisms of the seed papers.

* :func:`stigger_husty` -- the 2RPR-PPR six-solution example of Stigger & Husty (seed 002).
* :func:`collinear_3rpr` -- the 3-RPR with collinear base and platform anchors (seed 003).
* :func:`choi_3ppr` -- the symmetric 3-PPR of Choi (seed 004).
* :func:`general_3rpr` -- a general 3-RPR with six real assembly modes.
* :func:`dietmaier_1998` -- Dietmaier's Gough-Stewart platform with 40 real assembly modes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt
import sympy as sp

from ._validate import as_exact, as_float_array, check_positive
from .exceptions import InputError
from .core.legs import PPR, RPR
from .design.indices import global_indices
from ._validate import as_tolerances as check_tolerances
from .design.workspace import dexterous_workspace, reachable_workspace
from .manipulator import PlanarParallel

if TYPE_CHECKING:  # imported where used: the spatial side loads only for a spatial example
    from .spatial.gough_stewart import GoughStewart

__all__ = ["stigger_husty", "collinear_3rpr", "choi_3ppr", "general_3rpr", "dietmaier_1998",
           "collinear_3rpr_closed_form",
           "choi_3ppr_closed_form", "choi_det_jh", "choi_rotation_limits", "choi_3ppr_indices"]


def stigger_husty() -> PlanarParallel:
    """The planar 2RPR-PPR manipulator of Stigger & Husty with its six-solution joint values.

    Geometry (``docs/references.md``, errata; checked against eqs. (5)-(7) of the paper; the paper's tables give
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


def collinear_3rpr(R=2, r=1) -> PlanarParallel:
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

    Raises
    ------
    TypeError
        For ``R`` or ``r`` that is not a real number or sympy expression.
    InputError
        For a non-positive or non-finite ``R`` or ``r``.

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


def choi_3ppr(R=1, r=sp.Rational(1, 2), alpha=7 * sp.pi / 18) -> PlanarParallel:
    """The symmetric 3-PPR of Choi (seed 004).

    Outer equilateral triangle with inscribed radius ``R``; slider ``i`` runs on side ``i``
    (``theta_i = 2 (i-1) pi / 3``, direction ``u_i``, inward normal ``v_i``, foot
    ``O_i = -R v_i``); a link at the angle ``alpha`` to the side carries the passive slider to the
    platform vertex ``B_i = r (sin theta_i, -cos theta_i)`` (moving frame, circumradius ``r``).
    Each leg is a :class:`~imagespace.core.legs.PPR` with base ``O_i``, axis ``u_i``, platform
    ``B_i`` and angle ``alpha``.

    Parameters
    ----------
    R, r : positive numbers
    alpha : angle in ``(0, pi)``

    Returns
    -------
    PlanarParallel

    Raises
    ------
    TypeError
        For ``R``, ``r`` or ``alpha`` that is not a real number or sympy expression.
    InputError
        For a non-positive or non-finite ``R`` or ``r``, or a non-finite ``alpha``.

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


def general_3rpr() -> PlanarParallel:
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


def dietmaier_1998() -> tuple[GoughStewart, npt.NDArray[np.float64]]:
    """Dietmaier's general 6-6 Gough-Stewart platform with 40 real assembly modes.

    The design that settled the question "can all 40 complex solutions be real?" (Dietmaier 1998).
    The six-decimal data are as quoted, with the convention ``L_i^2 = |R b_i + t - a_i|^2`` of
    :class:`~imagespace.spatial.GoughStewart`, in Martyushev's collection of Gough-Stewart test
    designs (github.com/martyushev/fkSGP, ``python/genSGP.py``, case 100). The decimals enter as
    the nearest doubles; for those, msolve on an independent quaternion formulation confirms 40
    real poses (``tests/spatial/test_gough_stewart_reference.py``).

    Returns
    -------
    gs : GoughStewart
    lengths : (6,) float

    References
    ----------
    P. Dietmaier, The Stewart-Gough platform of general geometry can have 40 real postures,
    Advances in Robot Kinematics: Analysis and Control, Kluwer 1998, 7-16,
    doi:10.1007/978-94-015-9064-8_1.

    Examples
    --------
    >>> import imagespace as isp
    >>> gs, L = isp.examples.dietmaier_1998()
    >>> res = gs.direct_kinematics(L, certify=True)
    >>> res.count, res.complex_count, res.certified
    (40, 40, True)
    """
    from .spatial.gough_stewart import GoughStewart

    base: list[list[float]] = [[0, 0, 0], [1.107915, 0, 0], [0.549094, 0.756063, 0],
                               [0.735077, -0.223935, 0.525991], [0.514188, -0.526063, -0.368418],
                               [0.590473, 0.094733, -0.205018]]
    platform: list[list[float]] = [[0, 0, 0], [0.542805, 0, 0], [0.956919, -0.528915, 0],
                                   [0.665885, -0.353482, 1.402538], [0.478359, 1.158742, 0.107672],
                                   [-0.137087, -0.235121, 0.353913]]
    lengths = np.array([1.0, 0.645275, 1.086284, 1.503439, 1.281933, 0.771071])
    return GoughStewart(base, platform), lengths


# The rounding allowance of the closed forms below is Tolerances.closed_form_ulps (default 16), in
# units of the machine epsilon times the magnitude of the terms summed: a quantity that decides a
# count (``1 - |cos theta|``, ``1 - |sin psi|``, a line-circle discriminant) and lies within
# ``closed_form_ulps * eps * scale`` of zero is taken as exactly zero (the input is on the boundary
# within the rounding of the arithmetic and of the input's own computation, e.g. joint values
# obtained by inverse kinematics of a pose on the boundary).


def _within_rounding(value, scale, tol):
    """``|value| <= tol.closed_form_ulps * eps * scale``: zero within the rounding of its terms."""
    return abs(value) <= tol.closed_form_ulps * np.finfo(float).eps * scale


def collinear_3rpr_closed_form(d, R=2.0, r=1.0, tolerances=None):
    """Seed 003's closed-form direct kinematics of the collinear 3-RPR (an independent check).

    The notes: ``cos(theta) = [2 (d2^2 + R^2 + r^2) - d1^2 - d3^2] / (4 r R)``, then the line
    ``y = a x + b`` with ``a = (R - r cos theta) / (r sin theta)``,
    ``b = (d3^2 - d1^2) / (4 r sin theta)`` (leg 3 minus leg 1), and the circle
    ``x^2 + y^2 = d2^2`` (leg 2). The line is used here multiplied by ``r sin(theta)``,
    ``(R - r cos theta) x - r sin(theta) y = (d1^2 - d3^2) / 4``, whose normal
    ``(R - r cos theta, -r sin theta)`` never vanishes for ``R != r``: the same step then holds at
    ``sin(theta) = 0`` (concurrent legs, a direct-kinematic singularity), where the notes'
    formula divides by zero and the line is ``x = (d1^2 - d3^2) / (4 (R -+ r))``.

    Decisions. ``1 - cos(theta)`` and ``1 + cos(theta)`` are computed as
    ``[d1^2 + d3^2 - 2 d2^2 - 2 (R - r)^2] / (4 r R)`` and
    ``[2 d2^2 + 2 (R + r)^2 - d1^2 - d3^2] / (4 r R)`` (no cancellation near ``theta = 0, pi``),
    and ``theta = +-2 atan2(sqrt(1 - cos), sqrt(1 + cos))``. A value within rounding of zero
    (``tolerances.closed_form_ulps``) is zero: ``theta = 0`` (or ``pi``) is then the one orientation, a
    double root of the orientation equation, and its two positions ``(x, +-y)`` are returned once
    each (so orientations ``+-theta`` with ``|theta|`` below about 1e-7 are reported as
    ``theta = 0``, with joint residuals of the order of the rounding); a negative value beyond
    rounding means no real solution. The line-circle discriminant is decided the same way: within
    rounding of zero, the one tangent position.

    Parameters
    ----------
    d : (3,) float
        Leg lengths ``d1, d2, d3``.
    R, r : float
        Positive, ``R != r``.
    tolerances : Tolerances, optional
        ``closed_form_ulps``, the rounding allowance of the decisions (``None``: the defaults).

    Returns
    -------
    (k, 3) float
        Poses ``(x, y, theta)``, ``theta`` in ``(-pi, pi]``; ``k = 4`` generically (mirror
        pairs ``(x, y, theta)``, ``(x, -y, -theta)``), ``k = 2`` at ``sin(theta) = 0``
        (``theta = 0`` or ``pi``, positions ``(x, +-y)``), ``k = 0`` when no real solution;
        ``k = 1`` or ``2`` also where the line touches the circle.

    Raises
    ------
    TypeError
        For non-numeric ``d``, ``R`` or ``r``, or a ``tolerances`` that is not a Tolerances.
    InputError
        ``R`` or ``r`` not positive, or ``R == r``; ``d`` not of shape ``(3,)`` or not finite.

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.examples.collinear_3rpr_closed_form([3.0, 2.0, 2.0]).shape
    (4, 3)
    >>> isp.examples.collinear_3rpr_closed_form([1.25, 0.75, 1.25])    # theta = 0: concurrent legs
    array([[ 0.  ,  0.75,  0.  ],
           [ 0.  , -0.75,  0.  ]])
    """
    d1, d2, d3 = as_float_array(d, "d", last=3, allow_batch=False)
    R, r = float(check_positive(R, "R")), float(check_positive(r, "r"))
    tol = check_tolerances(tolerances)
    if R == r:
        raise InputError(f"R and r must differ (equal R = r = {R} make the legs' line equation vanish "
                         "at theta = 0)")
    terms = d1**2 + d3**2 + 2 * d2**2 + 2 * (R + r) ** 2          # magnitude of the sums below
    u = d1**2 + d3**2 - 2 * d2**2 - 2 * (R - r) ** 2               # 4 r R (1 - cos theta)
    w = 2 * d2**2 + 2 * (R + r) ** 2 - d1**2 - d3**2               # 4 r R (1 + cos theta)
    if _within_rounding(u, terms, tol):
        thetas = [0.0]
    elif _within_rounding(w, terms, tol):
        thetas = [np.pi]
    elif u < 0 or w < 0:
        return np.zeros((0, 3))
    else:
        th = 2 * np.arctan2(np.sqrt(u), np.sqrt(w))
        thetas = [th, -th]
    h = (d1**2 - d3**2) / 4
    out = []
    for th in thetas:
        n = np.array([R - r * np.cos(th), -r * np.sin(th)])
        nn = n @ n                                                  # >= (R - r)^2 > 0
        p0 = h * n / nn                                             # foot of the line from the origin
        disc = d2**2 - h**2 / nn                                    # (half chord)^2
        if _within_rounding(disc, d2**2 + h**2 / nn, tol):
            ts = [0.0]
        elif disc < 0:
            continue
        else:
            ts = [np.sqrt(disc), -np.sqrt(disc)]
        tangent = np.array([-n[1], n[0]]) / np.sqrt(nn)
        for t in ts:
            x, y = p0 + t * tangent
            out.append([x, y, th])
    return np.array(out).reshape(-1, 3)


def choi_3ppr_closed_form(rho, R=1.0, r=0.5, alpha=7 * np.pi / 18, tolerances=None):
    """Closed-form direct kinematics of Choi's 3-PPR (seed 004), derived from its IK.

    With ``k = cot(alpha)`` the IK is ``rho_i = a_i . (x, y) + r (sin phi + k cos phi) - R k`` and
    the three vectors ``a_i = (cos theta_i + k sin theta_i, sin theta_i - k cos theta_i)`` sum to
    zero, so summing the three equations leaves one in ``phi``: with ``psi = phi - (alpha - pi/2)``,
    ``r sin(psi) = sin(alpha) (rho_1 + rho_2 + rho_3)/3 + R cos(alpha)`` - the paper's
    ``C1 + C2 cos + C3 sin = 0``. Its two solutions ``psi`` and ``pi - psi`` give the rotations
    ``phi`` and ``2 alpha - phi``, and two of the linear equations give the same ``(x, y)`` for both.

    The boundary ``|sin psi| = 1`` (``psi = +-pi/2``, i.e. ``phi = alpha`` or ``alpha - pi``) is
    the singularity ``det J_h^-1 = 0``: the two rotations coincide there, a double solution, and
    one pose is returned. It is decided on ``r (1 -+ sin psi)`` computed as
    ``r -+ (sin(alpha) sum(rho)/3 + R cos(alpha))``: within rounding of zero (``closed_form_ulps``
    times eps times the magnitude of the terms, which covers joint values obtained by the IK of a
    pose on the boundary, whose ``sin psi`` evaluates to ``1.0000000000000002``) the input is on the
    boundary; beyond it, no solution (``|sin psi| > 1``) or two. So two rotations closer than
    ``2 sqrt(2 closed_form_ulps eps scale / r)`` (about 2e-7 rad for the default design) are
    reported as the one at the boundary; its joint residual is then of the order of the rounding. Away from the boundary
    ``psi = pi/2 - 2 atan2(sqrt(1 - sin psi), sqrt(1 + sin psi))``, accurate near ``+-pi/2``.

    Parameters
    ----------
    rho : (3,) float
        Slider positions.
    R, r, alpha : float
    tolerances : Tolerances, optional
        ``closed_form_ulps``, the rounding allowance of the boundary decision (``None``: the
        defaults).

    Returns
    -------
    (k, 3) float
        Poses ``(x, y, phi)``, ``phi`` in ``[-pi, pi)``; ``k = 2``, or 1 at the singular
        ``psi = +-pi/2``, or 0 when ``|sin psi| > 1``.

    Raises
    ------
    TypeError
        For non-numeric ``rho`` or a ``tolerances`` that is not a Tolerances.
    InputError
        For ``rho`` not of shape ``(3,)`` or not finite.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> m = isp.examples.choi_3ppr()
    >>> isp.examples.choi_3ppr_closed_form(m.q_example_float).round(6)[0]
    array([ 0.1 , -0.05,  0.2 ])
    >>> q = m.inverse_kinematics(np.array([0.1, -0.05, 7 * np.pi / 18]))    # phi = alpha
    >>> isp.examples.choi_3ppr_closed_form(q).round(6)
    array([[ 0.1    , -0.05   ,  1.22173]])
    """
    rho = as_float_array(rho, "rho", last=3, allow_batch=False)
    R, r, alpha = float(R), float(r), float(alpha)
    tol = check_tolerances(tolerances)
    sa, ca = np.sin(alpha), np.cos(alpha)
    k = ca / sa
    v = sa * rho.sum() / 3 + R * ca                                 # r sin(psi)
    terms = r + abs(sa) * np.abs(rho).sum() / 3 + R * abs(ca)
    u, w = r - v, r + v                                             # r (1 - sin psi), r (1 + sin psi)
    if _within_rounding(u, terms, tol):
        psis = [np.pi / 2]
    elif _within_rounding(w, terms, tol):
        psis = [-np.pi / 2]
    elif u < 0 or w < 0:
        return np.zeros((0, 3))
    else:
        psi = np.pi / 2 - 2 * np.arctan2(np.sqrt(u), np.sqrt(w))
        psis = [psi, np.pi - psi]
    phi0 = alpha - np.pi / 2
    th = np.array([0.0, 2 * np.pi / 3, 4 * np.pi / 3])
    A = np.column_stack([np.cos(th) + k * np.sin(th), np.sin(th) - k * np.cos(th)])
    out = []
    for psi in psis:
        phi = np.remainder(psi + phi0 + np.pi, 2 * np.pi) - np.pi
        rhs = rho - r * (np.sin(phi) + k * np.cos(phi)) + R * k
        xy = np.linalg.lstsq(A, rhs, rcond=None)[0]
        out.append([xy[0], xy[1], phi])
    return np.array(out)


def choi_det_jh(psi, r_over_R, alpha):
    """Seed 004's ``det J_h^-1 = (3 sqrt(3) / 2) (r / R) cos(psi) / sin(alpha)**3``.

    Independent of ``(x, y)``; zero (a singularity) at ``psi = +-pi/2``. ``J_h^-1`` in the seed's
    notation is :meth:`PoseJacobians.homogeneous` here.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> round(float(isp.examples.choi_det_jh(0.0, 0.5, np.pi / 2)), 6)
    1.299038
    """
    return 1.5 * np.sqrt(3.0) * r_over_R * np.cos(psi) / np.sin(alpha) ** 3


def choi_rotation_limits(alpha):
    """The rotation range of Choi's 3-PPR: ``psi = phi - (alpha - pi/2)`` in ``[-5 pi/6, 5 pi/6]``.

    The link of leg ``i`` leaves the plate vertex ``B_i`` towards its slider along ``-w_i``,
    ``w_i = (cos(theta_i + alpha), sin(theta_i + alpha))``; the plate's inward bisector at ``B_i``
    points along ``theta_i + phi + pi/2``, so the link makes the angle ``pi - |psi|`` with it and
    stays out of the plate's 60-degree corner exactly while ``|psi| <= 5 pi/6``.

    Parameters
    ----------
    alpha : float

    Returns
    -------
    (float, float)
        The limits of ``phi``.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> [round(v, 6) for v in isp.examples.choi_rotation_limits(np.pi / 2)]
    [-2.617994, 2.617994]
    """
    phi0 = float(alpha) - np.pi / 2
    return (phi0 - 5 * np.pi / 6, phi0 + 5 * np.pi / 6)


def choi_3ppr_indices(alpha, r_over_R, psi_max=17 * np.pi / 36, n_psi=73):
    """The five design indices of seed 004 for one design (``R = 1``, strokes ``+-sqrt(3) R``).

    ``D``: dexterous area, ``S``: reachable minus dexterous area (both over
    ``psi in [-psi_max, psi_max]``, exact polygons), and the global (mean over the same ``psi``
    range) manipulability ``M``, resistivity ``R`` and isotropy ``I`` (``sigma_min/sigma_max`` of
    ``J_h``, characteristic length ``R``; they do not depend on the position for this design).

    Parameters
    ----------
    alpha : float
        Link angle.
    r_over_R : float
    psi_max : float
    n_psi : int

    Returns
    -------
    dict

    Raises
    ------
    TypeError
        For a non-numeric ``alpha``/``r_over_R`` or a non-integer ``n_psi``.
    InputError
        For a non-positive ``r_over_R``, or a ``psi_max``/``n_psi`` the workspaces and global
        indices refuse.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> ind = isp.examples.choi_3ppr_indices(7 * np.pi / 18, 0.5)
    >>> sorted(ind), ind["D"] > 0
    (['D', 'I', 'M', 'R', 'S'], True)
    """
    m = choi_3ppr(1, sp.nsimplify(float(r_over_R), rational=True), sp.nsimplify(float(alpha) / np.pi, rational=True) * sp.pi)
    phi0 = float(alpha) - np.pi / 2
    rng = (phi0 - psi_max, phi0 + psi_max)
    lim = [[-np.sqrt(3), np.sqrt(3)]] * 3
    D = dexterous_workspace(m, rng, lim).area
    Rw = reachable_workspace(m, rng, lim).area
    g = global_indices(m, (0.0, 0.0), rng, 1.0, n=n_psi)
    return {"D": D, "S": Rw - D, "M": g["manipulability"], "R": g["resistivity"], "I": g["isotropy"]}
