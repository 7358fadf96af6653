"""Seed 000's example: the 2-RPR actuated at revolute A and both prismatic joints, opened at D.

``eta = (theta1, zeta1, theta2, zeta2, theta3)``: leg 1 from ``A`` to ``B`` (``zeta1 = AB``), the
platform hinged at ``B`` (angle ``theta3``), leg 2 from ``C`` to ``D`` (``zeta2 = CD``), the loop
closed at ``D = B + b u(theta3)``: ``phi = A + zeta1 u(theta1) + b u(theta3) - C - zeta2 u(theta2)``
(this reproduces the printed ``A^T`` of eq. 19 exactly). Task: ``P = B + c u(theta3 + alpha)`` and
``theta3``. Bodies as in eq. 17: leg-1 cylinder (``m1, I1``, centre ``g1`` from A), leg-1 piston
(``m2, I2``, centre at ``zeta1 - g2``), leg-2 cylinder (``m3, I3, g3`` from C), leg-2 piston
(``m4, I4``, at ``zeta2 - g4``), platform (``m5, I5``, centre ``g5`` from B at the angle ``beta``).

The seed gives neither masses nor dimensions: the values below are chosen, and stated; the
geometry is chosen so that the straight path of ``P`` (direction 200°, length 1.5 m, ``theta3``
constant) crosses the drive singularity ``theta2 = theta3 + pi`` at ``s = 0.662 m`` as in the seed.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from .._validate import as_exact
from ..exceptions import InputError, InputTypeError
from . import checks
from .model import Body, OpenTreeModel

__all__ = ["SEED000", "seed000_model", "seed000_path"]

SEED000 = dict(
    A=(-0.8, -1.2), C=(1.5, 0.0), b=0.3, c=0.2, alpha=np.pi / 2,
    m1=3.0, I1=0.10, g1=0.25, m2=2.0, I2=0.05, g2=0.25,
    m3=1.0, I3=0.05, g3=0.25, m4=0.5, I4=0.02, g4=0.25,
    m5=4.0, I5=0.06, g5=0.15, beta=np.pi / 2, gravity=9.81,
    direction_deg=200.0, L=1.5, Ld=0.662, theta3=0.0,
)
"""Chosen data (SI units): anchors A, C; platform BD = b, BP = c at angle alpha; masses, inertias and
centre offsets of the five bodies; the path of P (direction, length), the crossing ``Ld`` and
``theta3``. ``B`` starts where the path reaches the singularity at ``s = Ld``."""


def _params(params):
    """Check overrides of :data:`SEED000`: known names, real numbers (pairs for ``A`` and ``C``)."""
    if params is None:
        return {}
    if not isinstance(params, dict):
        raise InputTypeError(f"params must be a dict of SEED000 names -> values, got {type(params).__name__}")
    out = {}
    for k, v in params.items():
        if k not in SEED000:
            raise InputError(f"params names {k!r}, not one of SEED000's {sorted(SEED000)}")
        if k in ("A", "C"):
            out[k] = tuple(float(x) for x in checks.vector(v, f"params[{k!r}]", 2))
        elif isinstance(v, sp.Basic) and not v.free_symbols:
            out[k] = as_exact(v, f"params[{k!r}]")            # an exact number stays exact
        else:
            out[k] = checks.scalar(v, f"params[{k!r}]")
    return out


def seed000_model(params=None, tolerances=None):
    """The seed's mechanism as an :class:`OpenTreeModel` (symbolic derivation, compiled; the default
    model is built once per process and shared).

    Parameters
    ----------
    params : dict, optional
        Overrides of :data:`SEED000`.
    tolerances : Tolerances, optional
        The model's decision thresholds (``None``: the defaults); the shared compiled model is
        reused with them.

    Raises
    ------
    TypeError
        For ``params`` that is not a dict or holds a non-numeric value, or ``tolerances`` that is
        not a :class:`~imagespace.tolerances.Tolerances`.
    InputError
        For a name that is not one of :data:`SEED000`'s, or a malformed value.

    Examples
    --------
    >>> from imagespace.dynamics.seed000 import seed000_model
    >>> model = seed000_model()
    >>> model.actuated
    (0, 1, 3)
    """
    params = _params(params)
    tolerances = checks.tolerances(tolerances)
    if not params:
        if "model" not in _CACHE:
            _CACHE["model"] = _build(dict(SEED000))
        model = _CACHE["model"]
        return model if tolerances is model.tolerances else model.with_tolerances(tolerances)
    return _build(dict(SEED000, **params)).with_tolerances(tolerances)


_CACHE: dict[str, OpenTreeModel] = {}


def _build(p):
    t1, z1, t2, z2, t3 = sp.symbols("theta1 zeta1 theta2 zeta2 theta3", real=True)
    u = lambda a: sp.Matrix([sp.cos(a), sp.sin(a)])
    A = sp.Matrix(list(p["A"]))
    C = sp.Matrix(list(p["C"]))
    B = A + z1 * u(t1)
    phi = A + z1 * u(t1) + p["b"] * u(t3) - C - z2 * u(t2)
    P = B + p["c"] * u(t3 + p["alpha"])
    bodies = [
        Body(p["m1"], p["I1"], tuple(A + p["g1"] * u(t1)), t1, "leg-1 cylinder"),
        Body(p["m2"], p["I2"], tuple(A + (z1 - p["g2"]) * u(t1)), t1, "leg-1 piston"),
        Body(p["m3"], p["I3"], tuple(C + p["g3"] * u(t2)), t2, "leg-2 cylinder"),
        Body(p["m4"], p["I4"], tuple(C + (z2 - p["g4"]) * u(t2)), t2, "leg-2 piston"),
        Body(p["m5"], p["I5"], tuple(B + p["g5"] * u(t3 + p["beta"])), t3, "platform"),
    ]
    return OpenTreeModel((t1, z1, t2, z2, t3), list(phi), [P[0], P[1], t3], (0, 1, 3), bodies,
                         gravity=(0.0, -p["gravity"]))


def seed000_path(params=None):
    """The straight task path: ``x(s) = x0 + s e``, ``e = (cos 200°, sin 200°, 0)``, with ``x0``
    chosen so that at ``s = Ld`` the points B, D, C are collinear with D between (``theta2 = theta3 + pi``).

    Returns
    -------
    x0 : (3,) float
    e : (3,) float

    Raises
    ------
    TypeError
        For ``params`` that is not a dict or holds a non-numeric value.
    InputError
        For a name that is not one of :data:`SEED000`'s, or a malformed value.

    Examples
    --------
    >>> from imagespace.dynamics.seed000 import seed000_path
    >>> x0, e = seed000_path()
    >>> round(float(e[0]), 4)
    -0.9397
    """
    p = dict(SEED000, **_params(params))
    d = np.radians(p["direction_deg"])
    e = np.array([np.cos(d), np.sin(d), 0.0])
    t3 = p["theta3"]
    # at s = Ld: B on the line through C along u(theta3), left of C by (b + 0.9)
    B_sing = np.array(p["C"]) - (p["b"] + 0.9) * np.array([np.cos(t3), np.sin(t3)])
    P_sing = B_sing + p["c"] * np.array([np.cos(t3 + p["alpha"]), np.sin(t3 + p["alpha"])])
    x0 = np.array([P_sing[0], P_sing[1], t3]) - p["Ld"] * e
    return x0, e
