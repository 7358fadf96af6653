r"""The four dyad constraints as quadrics of the kinematic image space.

Every dyad constraint has the form

.. math::

    Q = c\,(x_2^2 + x_3^2) + x_2\,(a_0 x_0 + a_1 x_1) + x_3\,(b_0 x_0 + b_1 x_1)
        + k_0 x_0^2 + k_1 x_0 x_1 + k_2 x_1^2 ,

so a :class:`Quadric` stores the eight coefficients ``(c, a0, a1, b0, b1, k0, k1, k2)``: ``c``,
the two linear forms and the binary quadratic form. The coefficients may be
sympy expressions (exact or in symbols) or numpy arrays (one quadric per row of a batch); the
formulas below are written once, in plain arithmetic, and serve both.

Derivation (complex notation of :mod:`imagespace.kinematic_map`: ``z = x0 + i x1``,
``u = x3 - i x2``, platform point ``p`` lands at ``(z**2 p + 2 u z)/|z|**2``):

* RR, platform point ``p`` on the circle (centre ``M``, radius ``rho``):
  ``|z p + 2u - conj(z) M|**2 - rho**2 |z|**2 = 0`` (the common factor ``|z|**2`` of
  ``|z(zp + 2u) - |z|**2 M|**2`` removed). A hyperboloid; ``c = 4``.
* PR, platform point ``p`` on the base line ``n . X = d``:
  ``Re(conj(n) z (z p + 2u)) - d |z|**2 = 0``. A hyperbolic paraboloid; ``c = 0``.
* RP, platform line ``m . p = e`` through the base point ``B``: the base point seen from the
  platform is ``conj(z)(conj(z) B - 2u)/|z|**2``, so ``Re(conj(m) conj(z)(conj(z) B - 2u)) - e |z|**2 = 0``.
* PP, platform orientation fixed at ``phi_c``: ``Im(z**2 exp(-i phi_c)) = 0``, i.e.
  ``2 x0 x1 cos(phi_c) - (x0**2 - x1**2) sin(phi_c) = 0``: the pair of planes ``phi = phi_c`` and
  ``phi = phi_c + pi``. Only the first is the dyad; callers that need the distinction check the
  leg's inverse kinematics (as :meth:`PlanarParallel.direct_kinematics` does).

Checked against eqs. (5)-(7) of Stigger & Husty in ``tests/test_constraints.py``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

__all__ = [
    "Quadric",
    "rr_quadric",
    "pr_quadric",
    "rp_quadric",
    "pp_quadric",
    "image_symbols",
]

_X = sp.symbols("x0:4", real=True)


def image_symbols():
    """The sympy symbols ``(x0, x1, x2, x3)`` used by every symbolic expression of imagespace.

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.image_symbols()
    (x0, x1, x2, x3)
    """
    return _X


@dataclass(frozen=True)
class Quadric:
    """A dyad constraint ``c (x2^2+x3^2) + x2 (a0 x0 + a1 x1) + x3 (b0 x0 + b1 x1) + k0 x0^2 + k1 x0 x1 + k2 x1^2``.

    Attributes
    ----------
    kind : str
        ``"RR"``, ``"PR"``, ``"RP"`` or ``"PP"``.
    c, a0, a1, b0, b1, k0, k1, k2 : sympy expression, float or (n,) float array
        The coefficients (arrays for a batch of quadrics, one per row).
    """

    kind: str
    c: Any
    a0: Any
    a1: Any
    b0: Any
    b1: Any
    k0: Any
    k1: Any
    k2: Any

    def coefficients(self):
        """The eight coefficients ``(c, a0, a1, b0, b1, k0, k1, k2)`` as a tuple.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.pp_quadric(1, 0).coefficients()
        (0, 0, 0, 0, 0, 0, 2, 0)
        """
        return (self.c, self.a0, self.a1, self.b0, self.b1, self.k0, self.k1, self.k2)

    def expr(self, x=None):
        """The quadric as a sympy expression in ``x`` (default :func:`image_symbols`).

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.rr_quadric((0, 0), 100, (0, 0)).expr()
        -100*x0**2 - 100*x1**2 + 4*x2**2 + 4*x3**2
        """
        x0, x1, x2, x3 = _X if x is None else x
        c, a0, a1, b0, b1, k0, k1, k2 = (sp.sympify(v) for v in self.coefficients())
        return sp.expand(c * (x2**2 + x3**2) + x2 * (a0 * x0 + a1 * x1) + x3 * (b0 * x0 + b1 * x1)
                         + k0 * x0**2 + k1 * x0 * x1 + k2 * x1**2)

    def evaluate(self, points):
        """Value at image points ``(..., 4)`` (numeric coefficients only).

        Examples
        --------
        >>> import imagespace as isp
        >>> float(isp.rr_quadric((0, 0), 4.0, (0, 0)).evaluate([1.0, 0.0, 0.0, 1.0]))
        0.0
        """
        p = np.asarray(points, dtype=float)
        x0, x1, x2, x3 = (p[..., i] for i in range(4))
        c, a0, a1, b0, b1, k0, k1, k2 = (np.asarray(v, dtype=float) for v in self.coefficients())
        return (c * (x2**2 + x3**2) + x2 * (a0 * x0 + a1 * x1) + x3 * (b0 * x0 + b1 * x1)
                + k0 * x0**2 + k1 * x0 * x1 + k2 * x1**2)

    def gradient(self, points):
        """Gradient with respect to ``(x0, x1, x2, x3)`` at image points, shape ``(..., 4)``.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.rr_quadric((0, 0), 4.0, (0, 0)).gradient([1.0, 0.0, 0.0, 1.0])
        array([-8.,  0.,  0.,  8.])
        """
        p = np.asarray(points, dtype=float)
        x0, x1, x2, x3 = (p[..., i] for i in range(4))
        c, a0, a1, b0, b1, k0, k1, k2 = (np.asarray(v, dtype=float) for v in self.coefficients())
        g0 = a0 * x2 + b0 * x3 + 2 * k0 * x0 + k1 * x1
        g1 = a1 * x2 + b1 * x3 + k1 * x0 + 2 * k2 * x1
        g2 = 2 * c * x2 + a0 * x0 + a1 * x1
        g3 = 2 * c * x3 + b0 * x0 + b1 * x1
        return np.stack(np.broadcast_arrays(g0, g1, g2, g3), axis=-1)


def rr_quadric(centre, radius_squared, point):
    """RR dyad: the platform point ``point`` stays on the base circle (``centre``, radius**2).

    Parameters
    ----------
    centre : (2,) numbers, sympy expressions or (n,) arrays per coordinate
    radius_squared : number, sympy expression or (n,) array
        The squared radius (kept squared so that no square root enters the algebra).
    point : (2,)
        The platform point in the moving frame.

    Returns
    -------
    Quadric

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.rr_quadric((7, 0), 232, (5, 0)).expr()
    -228*x0**2 - 8*x0*x3 - 88*x1**2 - 48*x1*x2 + 4*x2**2 + 4*x3**2
    """
    mx, my = centre
    px, py = point
    r0, r1 = px - mx, -(py + my)
    i0, i1 = py - my, px + mx
    return Quadric("RR", 4 + 0 * px, -4 * i0, -4 * i1, 4 * r0, 4 * r1,
                   r0 * r0 + i0 * i0 - radius_squared, 2 * (r0 * r1 + i0 * i1),
                   r1 * r1 + i1 * i1 - radius_squared)


def pr_quadric(point, line_point, line_direction):
    """PR dyad: the platform point ``point`` stays on the base line through ``line_point``.

    The line is ``n . X = n . line_point`` with ``n`` the direction turned by +90 degrees (not
    normalised: the quadric scales with ``|line_direction|``).

    Returns
    -------
    Quadric

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.pr_quadric((0, 0), (0, 1), (1, 0)).expr()   # the origin of the platform on y = 1
    -x0**2 - 2*x0*x2 - x1**2 + 2*x1*x3
    """
    px, py = point
    wx, wy = line_direction
    nx, ny = -wy, wx
    d = nx * line_point[0] + ny * line_point[1]
    s = px * nx + py * ny
    return Quadric("PR", 0 * px, -2 * ny, 2 * nx, 2 * nx, 2 * ny,
                   s - d, 2 * (px * ny - py * nx), -s - d)


def rp_quadric(line_point, line_direction, base_point):
    """RP dyad: the platform line through ``line_point`` along ``line_direction`` passes through ``base_point``.

    Returns
    -------
    Quadric

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.rp_quadric((0, 0), (1, 0), (0, 0)).expr()   # the platform x axis through the base origin
    2*x0*x2 + 2*x1*x3
    """
    bx, by = base_point
    vx, vy = line_direction
    mx, my = -vy, vx
    e = mx * line_point[0] + my * line_point[1]
    s = bx * mx + by * my
    return Quadric("RP", 0 * bx, 2 * my, 2 * mx, -2 * mx, 2 * my,
                   s - e, 2 * (by * mx - bx * my), -s - e)


def pp_quadric(cos_phi, sin_phi):
    """PP dyad: the platform orientation is ``phi_c`` (given by its cosine and sine).

    The quadric ``2 x0 x1 cos(phi_c) - (x0**2 - x1**2) sin(phi_c)`` is the pair of planes
    ``phi = phi_c`` and ``phi = phi_c + pi``.

    Returns
    -------
    Quadric

    Examples
    --------
    >>> import imagespace as isp
    >>> isp.pp_quadric(0, 1).expr()      # phi_c = pi/2
    -x0**2 + x1**2
    """
    z = 0 * cos_phi
    return Quadric("PP", z, z, z, z, z, -sin_phi, 2 * cos_phi, sin_phi)
