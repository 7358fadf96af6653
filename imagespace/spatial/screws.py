"""Screw theory: twists, wrenches, reciprocity, and constraint singularities (seed 001).

A screw is six Plücker coordinates about a reference point: a **twist** ``(omega; v)`` (angular
velocity; velocity of the body point at the reference point) and a **wrench** ``(f; m)`` (force;
moment about the reference point). A revolute joint with unit axis ``u`` through ``p`` has the
twist ``(u; p x u)``, a prismatic joint along ``u`` the twist ``(0; u)``, a helical joint of pitch
``h`` the twist ``(u; p x u + h u)``. The **reciprocal product** of a twist and a wrench is the
power ``omega . m + v . f`` - not the plain dot product of the two 6-vectors - and it does not
depend on the reference point (tested).

Seed 001's algorithm for constraint singularities: (1) a unit twist for every joint, (2) Plücker
coordinates about one point, (3) for each leg the wrenches reciprocal to all its joint twists
(its constraint wrenches), (4) stack them: rank below ``6 - n`` (``n`` the platform's DOF) means the
constraints degenerate and the platform gains a freedom - the twists reciprocal to the stacked
constraints beyond the intended ones. Locking the actuated joints adds the actuation wrenches
(reciprocal to a leg's passive joints but not to its actuated one); their rank deficiency together
with the constraints is the actuation (direct-kinematic) singularity; a leg whose own twists lose
rank is an inverse-kinematic (leg) singularity.

Symbolic (sympy matrices, exact nullspace) and numeric (numpy, batched, SVD with a rank tolerance)
faces share the formulas.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Optional, Sequence, Union, overload

import numpy as np
import numpy.typing as npt
import sympy as sp

import numbers

from .._validate import _short, as_count, as_exact, as_float_array, as_index, is_symbolic, as_scalar
from ..exceptions import InputError, InputTypeError
from ..core.mechanism import check_mechanism

if TYPE_CHECKING:
    from ..core.kinematic_map import FloatArray, NumericInput
    from ..core.planar import PlanarMechanism

__all__ = ["revolute", "prismatic", "helical", "transfer", "reciprocal_product", "reciprocal_system",
           "ConstraintAnalysis", "constraint_analysis", "TranslationalFiveR", "planar_leg_wrenches",
           "singularity_fractions"]


def _tol(tol):
    t = as_scalar(tol, "tol")
    if not 0 < t < 1:
        raise InputError(f"tol must be a relative tolerance in (0, 1), got {tol!r}")
    return t


def _vec3(v, name):
    if is_symbolic(v):
        if not isinstance(v, (list, tuple, np.ndarray, sp.MatrixBase)):
            raise InputTypeError(f"{name} must be a 3-vector, got {_short(v)}")
        items = list(v)
        if len(items) != 3:
            raise InputError(f"{name} must have 3 components, got {len(items)}")
        return sp.Matrix([as_exact(x, f"{name}[{i}]") for i, x in enumerate(items)])
    a = as_float_array(v, name, last=3)
    return a


def _same_batch(a, b, name_a, name_b):
    """Two numeric batches must have the same length (or one of them a single vector)."""
    if isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and a.ndim == 2 and b.ndim == 2 \
            and len(a) != len(b) and 1 not in (len(a), len(b)):
        raise InputError(f"{name_a} and {name_b} must have the same number of rows (or one row), got "
                         f"shapes {a.shape} and {b.shape}")


def _unit(u, name):
    if isinstance(u, sp.MatrixBase):
        n = sp.sqrt(u.dot(u))
        if n == 0:
            raise InputError(f"{name} must not be the zero vector")
        return u / n
    m = np.abs(u).max(axis=-1, keepdims=True)
    if np.any(m == 0):
        raise InputError(f"{name} must not be the zero vector, got {np.asarray(u).tolist()}")
    us = u / m                                      # scaled first: no overflow or underflow in the norm
    return us / np.linalg.norm(us, axis=-1, keepdims=True)


def _in_range(out, names, what):
    """``out`` if finite, else an InputError: the result left the float range."""
    if isinstance(out, np.ndarray) and not np.all(np.isfinite(out)):
        raise InputError(f"{names} is too large: {what} is outside the float range (about 1.8e308); "
                         "expected coordinates of the size of the mechanism")
    return out


def _cross(a, b):
    if isinstance(a, sp.MatrixBase) or isinstance(b, sp.MatrixBase):
        return sp.Matrix(a).cross(sp.Matrix(b))
    return np.cross(a, b)


def _join(w, v):
    if isinstance(w, sp.MatrixBase) or isinstance(v, sp.MatrixBase):
        return sp.Matrix.vstack(sp.Matrix(w), sp.Matrix(v))
    w, v = np.broadcast_arrays(w, v)
    return np.concatenate([w, v], axis=-1)


@overload
def revolute(axis: NumericInput, point: NumericInput) -> FloatArray: ...
@overload
def revolute(axis: Any, point: Any) -> Any: ...
def revolute(axis, point):
    """Unit twist of a revolute joint: ``(u; p x u)``.

    Parameters
    ----------
    axis : (3,) or (n, 3) float, or sympy
    point : (3,) or (n, 3) float, or sympy
        A point of the axis.

    Returns
    -------
    (6,) / (n, 6) float or sympy Matrix (6, 1)

    Raises
    ------
    TypeError
        For non-numeric (or string) input.
    InputError
        For vectors that are not 3-vectors, a zero axis, or batches of different lengths.

    Examples
    --------
    >>> from imagespace.spatial.screws import revolute
    >>> revolute([0, 0, 1], [1, 0, 0]).tolist()
    [0.0, 0.0, 1.0, 0.0, -1.0, 0.0]
    """
    u = _unit(_vec3(axis, "axis"), "axis")
    p = _vec3(point, "point")
    _same_batch(u, p, "axis", "point")
    with np.errstate(over="ignore", invalid="ignore"):
        return _in_range(_join(u, _cross(p, u)), "point", "the moment p x u")


@overload
def prismatic(axis: NumericInput) -> FloatArray: ...
@overload
def prismatic(axis: Any) -> Any: ...
def prismatic(axis):
    """Unit twist of a prismatic joint: ``(0; u)``.

    Raises
    ------
    TypeError
        For non-numeric (or string) input.
    InputError
        For an axis that is not a 3-vector, or a zero axis.

    Examples
    --------
    >>> from imagespace.spatial.screws import prismatic
    >>> prismatic([0, 2, 0]).tolist()
    [0.0, 0.0, 0.0, 0.0, 1.0, 0.0]
    """
    u = _unit(_vec3(axis, "axis"), "axis")
    zero = sp.zeros(3, 1) if isinstance(u, sp.MatrixBase) else np.zeros_like(u)
    return _join(zero, u)


@overload
def helical(axis: NumericInput, point: NumericInput, pitch: Union[float, NumericInput]) -> FloatArray: ...
@overload
def helical(axis: Any, point: Any, pitch: Any) -> Any: ...
def helical(axis, point, pitch):
    """Unit twist of a helical joint of pitch ``h``: ``(u; p x u + h u)``.

    Raises
    ------
    TypeError
        For non-numeric (or string) input, or several pitches with a symbolic axis.
    InputError
        For vectors that are not 3-vectors, a zero axis, batches of different lengths, or a
        pitch that is neither one number nor one per axis.

    Examples
    --------
    >>> from imagespace.spatial.screws import helical
    >>> helical([0, 0, 1], [0, 0, 0], 0.5).tolist()
    [0.0, 0.0, 1.0, 0.0, 0.0, 0.5]
    """
    u = _unit(_vec3(axis, "axis"), "axis")
    p = _vec3(point, "point")
    _same_batch(u, p, "axis", "point")
    if isinstance(u, sp.MatrixBase) or isinstance(p, sp.MatrixBase) or is_symbolic(pitch):
        if isinstance(pitch, (list, tuple, np.ndarray)):
            raise InputTypeError(f"pitch must be one number or sympy expression with a symbolic axis, got {_short(pitch)}")
        u, p = sp.Matrix(u), sp.Matrix(p)
        return _join(u, _cross(p, u) + as_exact(pitch, "pitch") * u)
    h = as_float_array(pitch, "pitch")
    try:
        with np.errstate(over="ignore", invalid="ignore"):
            return _in_range(_join(u, _cross(p, u) + h[..., None] * u), "point or pitch", "the moment p x u + h u")
    except ValueError:
        raise InputError(f"pitch must be a number or one per axis, got shape {h.shape} for axes of shape "
                         f"{u.shape}") from None


def _check_screw(s, name):
    if isinstance(s, sp.MatrixBase):
        if s.shape != (6, 1):
            raise InputError(f"{name} must be a 6-vector, got shape {s.shape}")
        return s
    a = as_float_array(s, name, last=6)
    if np.any(np.all(a == 0, axis=-1)):
        raise InputError(f"{name} has zero direction and zero moment: not a screw")
    return a


@overload
def transfer(screw: NumericInput, point: NumericInput, kind: str = ...) -> FloatArray: ...
@overload
def transfer(screw: Any, point: Any, kind: str = ...) -> Any: ...
def transfer(screw, point, kind="twist"):
    """Re-express a screw about another reference point ``r`` (coordinates of ``r`` in the old frame).

    A twist's velocity becomes ``v - r x omega`` (= ``v + omega x r``); a wrench's moment
    ``m - r x f``.

    Parameters
    ----------
    screw : (6,) or (n, 6)
    point : (3,)
    kind : {"twist", "wrench"}

    Raises
    ------
    TypeError
        For non-numeric (or string) input.
    InputError
        For a screw that is not a 6-vector (or is zero), a point that is not one 3-vector, or an unknown ``kind``.

    Examples
    --------
    >>> from imagespace.spatial.screws import transfer, revolute
    >>> transfer(revolute([0, 0, 1], [1, 0, 0]), [1, 0, 0]).tolist()
    [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
    """
    s = _check_screw(screw, "screw")
    r = _vec3(point, "point")
    if isinstance(r, np.ndarray) and r.ndim != 1:
        raise InputError(f"point must be one reference point of shape (3,), got shape {r.shape}")
    if not isinstance(kind, str) or kind not in ("twist", "wrench"):
        raise InputError(f"kind must be 'twist' or 'wrench', got {kind!r}")
    if isinstance(s, sp.MatrixBase):
        a, b = s[:3, 0], s[3:, 0]
        return _join(a, b - _cross(r, a))
    a, b = s[..., :3], s[..., 3:]
    with np.errstate(over="ignore", invalid="ignore"):
        return _in_range(np.concatenate([a, b - np.cross(r, a)], axis=-1), "screw or point",
                         "the transferred moment")


@overload
def reciprocal_product(twist: NumericInput, wrench: NumericInput) -> Union[float, FloatArray]: ...
@overload
def reciprocal_product(twist: Any, wrench: Any) -> Any: ...
def reciprocal_product(twist, wrench):
    """The power ``dot(omega, m) + dot(v, f)`` of a wrench on a twist (not the plain dot product).

    Raises
    ------
    TypeError
        For non-numeric (or string) input.
    InputError
        For a screw that is not a 6-vector (or is zero), or batches of different lengths.

    Examples
    --------
    >>> from imagespace.spatial.screws import reciprocal_product, revolute
    >>> float(reciprocal_product(revolute([0, 0, 1], [0, 0, 0]), [0, 0, 0, 0, 0, 2.0]))
    2.0
    """
    t = _check_screw(twist, "twist")
    w = _check_screw(wrench, "wrench")
    _same_batch(t, w, "twist", "wrench")
    if isinstance(t, sp.MatrixBase) or isinstance(w, sp.MatrixBase):
        t, w = sp.Matrix(t), sp.Matrix(w)
        return sp.simplify(t[:3, 0].dot(w[3:, 0]) + t[3:, 0].dot(w[:3, 0]))
    # a bilinear form: evaluated on scaled copies, the scales multiplied back (out of range only when
    # the value is; an underflow to zero would read as "reciprocal", so it is refused too)
    mt, mw = np.abs(t).max(axis=-1), np.abs(w).max(axis=-1)
    ts, ws = t / mt[..., None], w / mw[..., None]
    unit = np.einsum("...i,...i->...", ts[..., :3], ws[..., 3:]) + np.einsum("...i,...i->...", ts[..., 3:], ws[..., :3])
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        out = unit * mt * mw
    if not np.all(np.isfinite(out)) or np.any((out == 0) & (unit != 0)):
        raise InputError("twist or wrench is out of range: their reciprocal product is outside the float "
                         "range (about 1e-308 .. 1.8e308); expected screws of the size of the mechanism")
    return out


_SWAP = np.block([[np.zeros((3, 3)), np.eye(3)], [np.eye(3), np.zeros((3, 3))]])


@overload
def reciprocal_system(twists: NumericInput, tol: float = ...) -> FloatArray: ...
@overload
def reciprocal_system(twists: Any, tol: float = ...) -> Any: ...
def reciprocal_system(twists, tol=1e-9):
    """The wrenches reciprocal to every twist of a list (a leg's constraint wrenches).

    Parameters
    ----------
    twists : (k, 6) float, or a list of sympy 6-vectors
        ``k <= 6`` joint twists.
    tol : float
        Numeric rank tolerance, relative to the largest singular value.

    Returns
    -------
    (6 - rank, 6) float, or list of sympy Matrix (6, 1)
        A basis; its size is checked against ``6 - rank``.

    Raises
    ------
    TypeError
        For non-numeric twists or ``tol``.
    InputError
        More than six twists, a twist that is not a 6-vector or is zero, or ``tol`` outside
        ``(0, 1)``.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.screws import reciprocal_system, revolute
    >>> W = reciprocal_system([revolute([1, 0, 0], [0, 0, 0]), revolute([0, 1, 0], [0, 0, 0]),
    ...                        revolute([0, 0, 1], [0, 0, 0])])
    >>> W.shape                                       # a spherical joint: the three forces through it
    (3, 6)
    """
    if isinstance(twists, (list, tuple)) and twists and all(isinstance(t, sp.MatrixBase) for t in twists):
        if len(twists) > 6:
            raise InputError(f"a leg has at most 6 joints, got {len(twists)}")
        T = sp.Matrix.hstack(*[_check_screw(t, f"twists[{k}]") for k, t in enumerate(twists)]).T
        M = T * sp.Matrix(_SWAP.astype(int))
        basis = M.nullspace(simplify=True)
        rank = M.rank(simplify=True)
        if len(basis) != 6 - rank:
            raise InputError(f"reciprocal system of dimension {len(basis)} but 6 - rank = {6 - rank}")
        return [sp.simplify(b) for b in basis]
    tol = _tol(tol)
    T = as_float_array(twists, "twists", last=6)
    T = np.atleast_2d(T)
    if len(T) > 6:
        raise InputError(f"a leg has at most 6 joints, got {len(T)}")
    if np.any(np.all(T == 0, axis=1)):
        raise InputError("a twist has zero direction and zero moment: not a screw")
    return _reciprocal(T, tol)


def _reciprocal(T, tol):
    """The reciprocal basis of any number of (non-zero) screws ``T (k, 6)``."""
    M = T @ _SWAP
    _, s, vt = np.linalg.svd(M, full_matrices=True)
    rank = int(np.sum(s > tol * (s[0] if len(s) else 1.0)))
    W = vt[rank:]
    assert W.shape[0] == 6 - rank
    return W


@dataclass(frozen=True)
class ConstraintAnalysis:
    """Singularity picture of a parallel mechanism at one configuration (seed 001).

    Attributes
    ----------
    constraint_wrenches : (c, 6) float
        All legs' constraint wrenches, stacked.
    constraint_rank : int
    expected_rank : int
        ``6 - dof``.
    constraint_singular : bool
        ``constraint_rank < expected_rank``.
    gained_twists : (g, 6) float
        The platform's extra freedoms at a constraint singularity: twists reciprocal to the
        stacked constraints and outside the span of ``intended`` (without ``intended``: the
        basis vectors beyond the first ``dof``). All platform twists are in ``platform_twists``.
    platform_twists : (6 - constraint_rank, 6) float
    actuation_rank : int
        Rank of constraints + actuation wrenches (6 when the locked mechanism is rigid).
    actuation_singular : bool
        ``actuation_rank < 6`` without a constraint singularity: the direct-kinematic type.
    leg_singular : list of bool
        A leg's own twists lose rank (inverse-kinematic type).
    measures : dict
        Dimensionless closeness to each type (smallest singular value over the largest).
    kind : str
        ``"regular"``, ``"constraint"``, ``"actuation"``, ``"leg"`` or combinations joined by ``+``.
    """

    constraint_wrenches: np.ndarray
    constraint_rank: int
    expected_rank: int
    constraint_singular: bool
    gained_twists: np.ndarray
    platform_twists: np.ndarray
    actuation_rank: int
    actuation_singular: bool
    leg_singular: list
    measures: dict
    kind: str


def _beyond(P, intended, dof, tol):
    """Platform twists outside the span of the intended ones (an orthonormal basis)."""
    if len(P) <= dof:
        return np.zeros((0, 6))
    if intended is None:
        return P[dof:]
    I = np.atleast_2d(np.asarray(intended, float))
    Q, _ = np.linalg.qr(I.T)                       # (6, dof) orthonormal basis of the intended span
    R = P - (P @ Q) @ Q.T
    u, s, vt = np.linalg.svd(R)
    k = int(np.sum(s > tol * max(1.0, s[0] if len(s) else 1.0)))
    return vt[:k]


def constraint_analysis(legs: Sequence[npt.ArrayLike], dof: int, actuated: Optional[Sequence[int]] = None,
                        tol: float = 1e-9, intended: Optional[npt.ArrayLike] = None) -> ConstraintAnalysis:
    """Seed 001's four steps, plus actuation and leg singularities.

    Parameters
    ----------
    legs : sequence of (k_i, 6) float
        Each leg's joint twists about one common reference point.
    dof : int
        The platform's intended degrees of freedom ``n``.
    actuated : sequence of int, optional
        The actuated joint of each leg (index into its twists).
    tol : float
        Relative rank tolerance.
    intended : (dof, 6) float, optional
        A basis of the platform's intended twists (e.g. the three translations ``(0; e_k)`` of a
        translational mechanism): the classical input-output Jacobian is then the matrix of
        reciprocal products of the actuation wrenches with it, and ``measures["input_output"]``
        its smallest-over-largest singular value - the only singularity measure an analysis that
        ignores the constraints would see.

    Returns
    -------
    ConstraintAnalysis

    Raises
    ------
    TypeError
        For ``legs`` that is not a sequence of twist arrays, non-numeric twists, ``tol`` or
        ``intended``, or ``actuated`` that is not a sequence of joint indices.
    InputError
        For ``dof`` outside ``1..6``, no legs, a leg of more than six joints, an ``intended``
        not of shape ``(dof, 6)``, ``actuated`` not naming one joint of every leg, or ``tol``
        outside ``(0, 1)``.

    Examples
    --------
    >>> from imagespace.spatial.screws import TranslationalFiveR, constraint_analysis
    >>> mech = TranslationalFiveR()
    >>> a = constraint_analysis(mech.leg_twists([0.1, 0.2, 0.3]), 3, actuated=[0, 0, 0])
    >>> a.kind, a.constraint_rank
    ('regular', 3)
    """
    dof = as_count(dof, "dof")
    if not 1 <= dof <= 6:
        raise InputError(f"dof must be an int in 1..6, got {dof!r}")
    tol = _tol(tol)
    if legs is None or isinstance(legs, (str, bytes, numbers.Number)) or not hasattr(legs, "__iter__"):
        raise InputTypeError(f"legs must be a sequence of (k_i, 6) twist arrays, got {type(legs).__name__} {_short(legs)}")
    Ts = [np.atleast_2d(as_float_array(t, f"legs[{i}]", last=6)) for i, t in enumerate(legs)]
    if not Ts:
        raise InputError("legs must hold at least one leg, got an empty sequence")
    if intended is not None:
        intended = np.atleast_2d(as_float_array(intended, "intended", last=6))
        if intended.shape != (dof, 6):
            raise InputError(f"intended must be ({dof}, 6), got {intended.shape}")
    if actuated is not None:
        if isinstance(actuated, (str, bytes)) or not hasattr(actuated, "__iter__"):
            raise InputTypeError(f"actuated must be a sequence of joint indices, one per leg, got "
                                 f"{type(actuated).__name__} {_short(actuated)}")
        actuated = [as_count(k, f"actuated[{i}]", 0) for i, k in enumerate(actuated)]
    Ws, leg_sing, leg_meas = [], [], []
    for i, T in enumerate(Ts):
        if len(T) > 6:
            raise InputError(f"legs[{i}] has {len(T)} joints; a leg has at most 6")
        W = reciprocal_system(T, tol)
        Ws.append(W)
        s = np.linalg.svd(T, compute_uv=False)
        leg_sing.append(bool(np.sum(s > tol * s[0]) < len(T)))
        leg_meas.append(float(s[-1] / s[0]))
    C = np.vstack(Ws) if Ws else np.zeros((0, 6))
    expected = 6 - dof
    rc = int(np.linalg.matrix_rank(C, tol=tol * max(1.0, np.abs(C).max()))) if len(C) else 0
    # platform twists: reciprocal to every constraint wrench
    # platform twists: reciprocal to every constraint wrench (the product is symmetric in its roles)
    P = _reciprocal(C, tol) if len(C) else np.eye(6)
    gained = _beyond(P, intended, dof, tol)
    sc = np.linalg.svd(C, compute_uv=False) if len(C) else np.zeros(0)
    c_meas = float(sc[expected - 1] / sc[0]) if len(sc) >= expected and expected > 0 and sc[0] > 0 else 0.0
    act_rank, a_meas, io_meas = 6, 1.0, None
    if actuated is not None:
        if len(actuated) != len(Ts):
            raise InputError(f"actuated must name one joint per leg ({len(Ts)}), got {list(actuated)}")
        A = []
        for i, (T, k) in enumerate(zip(Ts, actuated)):
            if not 0 <= k < len(T):
                raise InputError(f"actuated[{i}] = {k} is not a joint of legs[{i}] ({len(T)} joints)")
            passive = np.delete(T, k, axis=0)
            Wp = reciprocal_system(passive, tol)
            # the actuation wrench: reciprocal to the passive joints, not to the actuated one
            pw = reciprocal_product(T[k][None, :], Wp)
            if np.max(np.abs(pw)) > tol * max(1.0, np.abs(Wp).max()):
                A.append(Wp[int(np.argmax(np.abs(pw)))])
        if intended is not None and A:
            I = np.atleast_2d(as_float_array(intended, "intended", last=6))
            if I.shape != (dof, 6):
                raise InputError(f"intended must be ({dof}, 6), got {I.shape}")
            Jio = np.array([[float(reciprocal_product(t, w)) for t in I] for w in A])
            sio = np.linalg.svd(Jio, compute_uv=False)
            io_meas = float(sio[-1] / sio[0]) if sio[0] > 0 else 0.0
        full = np.vstack([C] + ([np.array(A)] if A else []))
        sa = np.linalg.svd(full, compute_uv=False)
        act_rank = int(np.sum(sa > tol * sa[0]))
        a_meas = float(sa[5] / sa[0]) if len(sa) >= 6 else 0.0
    c_sing = rc < expected
    a_sing = (act_rank < 6) and not c_sing
    kinds = [k for k, flag in (("constraint", c_sing), ("actuation", a_sing), ("leg", any(leg_sing))) if flag]
    return ConstraintAnalysis(C, rc, expected, c_sing, gained, P, act_rank, a_sing, leg_sing,
                              {"constraint": c_meas, "actuation": a_meas, "legs": leg_meas,
                               "input_output": io_meas},
                              "+".join(kinds) if kinds else "regular")


def _small_index(value, name, size, what):
    """:func:`as_index` with the wording ``{name} must be {what}``."""
    try:
        return as_index(value, name, size)
    except TypeError:
        raise InputTypeError(f"{name} must be {what}, got {type(value).__name__} {_short(value)}") from None
    except InputError:
        raise InputError(f"{name} must be {what}, got {_short(value)}") from None


def _branch(value, name):
    return _small_index(value, name, 2, "0 or 1")


def _leg_index(i):
    return _small_index(i, "i", 3, "the leg index 0, 1 or 2")


@dataclass(frozen=True)
class TranslationalFiveR:
    """The 3-DOF translational parallel mechanism of seed 001: three legs of five revolute joints.

    Leg ``i`` (``e_i`` = the ``i``-th coordinate axis) has its first axis along ``e_i`` through the base
    point ``A_i``; the first joint angle ``theta_i`` turns the leg's plane so that the next three axes
    are parallel to ``d_i(theta_i)``; the last axis is again along ``e_i``, at the platform point
    ``C_i = P + c_i``. The leg's constraint wrench is then the pure couple along ``e_i x d_i``:
    ``(0,0,0, 0, sin t1, -cos t1)``, ``(0,0,0, -cos t2, 0, sin t2)``, ``(0,0,0, sin t3, -cos t3, 0)``
    as printed in the seed, with ``d_1 = (0, cos t1, sin t1)``, ``d_2 = (sin t2, 0, cos t2)``,
    ``d_3 = (cos t3, sin t3, 0)``.

    The seed does not give the dimensions; chosen here (base ``a``, offset ``b``, platform ``c``,
    links ``l1, l2``): ``A_i = -a e_i + b e_(i+1)``, ``c_i = -c e_i``. (With ``b = 0`` every leg
    plane would contain the line through the origin along ``P``, all ``d_i`` would be normal to
    ``P`` and the actuation would be singular everywhere: the offset is needed.) joints 2-4 a planar 2R (lengths ``l1``, ``l2``) from ``A_i`` to
    ``C_i`` in the plane through ``A_i`` normal to ``d_i``, joints 4 and 5 both at ``C_i``. The leg's
    inverse kinematics: ``theta_i`` makes ``C_i - A_i`` normal to ``d_i`` (two solutions, ``pi`` apart)
    and the 2R elbow (two branches). The first joints are actuated.

    Parameters
    ----------
    a, b, c, l1, l2 : float

    Raises
    ------
    TypeError
        For a non-numeric dimension.
    InputError
        For a non-finite dimension or a non-positive link length.

    Examples
    --------
    >>> from imagespace.spatial.screws import TranslationalFiveR
    >>> TranslationalFiveR(l1=1.2).l1
    1.2
    """

    a: float = 1.0
    b: float = 0.5
    c: float = 0.2
    l1: float = 1.0
    l2: float = 1.0

    def __post_init__(self):
        for name in ("a", "b", "c", "l1", "l2"):
            object.__setattr__(self, name, as_scalar(getattr(self, name), name))
        for name in ("l1", "l2"):
            if not getattr(self, name) > 0:
                raise InputError(f"{name} must be a positive link length, got {getattr(self, name)!r}")

    @staticmethod
    def d(i: int, theta: npt.ArrayLike) -> FloatArray:
        """The direction of joints 2-4 of leg ``i`` (``(3,)`` or ``(n, 3)``).

        Raises
        ------
        TypeError
            For a leg index that is not a whole number.
        InputError
            For a leg index other than 0, 1 or 2.

        Examples
        --------
        >>> from imagespace.spatial.screws import TranslationalFiveR
        >>> TranslationalFiveR.d(2, 0.0).tolist()
        [1.0, 0.0, 0.0]
        """
        i = _leg_index(i)
        t = np.asarray(theta, float)
        c, s = np.cos(t), np.sin(t)
        z = np.zeros_like(t)
        return np.stack([(z, c, s), (s, z, c), (c, s, z)][i], axis=-1)

    def base(self, i: int) -> FloatArray:
        """The base point ``A_i`` of leg ``i``.

        Raises
        ------
        TypeError
            For a leg index that is not a whole number.
        InputError
            For a leg index other than 0, 1 or 2.

        Examples
        --------
        >>> from imagespace.spatial.screws import TranslationalFiveR
        >>> TranslationalFiveR().base(0).tolist()
        [-1.0, 0.5, 0.0]
        """
        i = _leg_index(i)
        E = np.eye(3)
        return -self.a * E[i] + self.b * E[(i + 1) % 3]

    @staticmethod
    def couple_condition(theta: npt.ArrayLike) -> FloatArray:
        """Seed 001's closed form: the couple block ``det = s1 s2 s3 - c1 c2 c3`` (``(n,)``).

        Raises
        ------
        TypeError
            For non-numeric ``theta``.
        InputError
            For ``theta`` not of shape ``(3,)`` or ``(n, 3)``.

        Notes
        -----
        A row with a NaN or infinite angle gives NaN (the other rows of a batch are kept).

        Examples
        --------
        >>> import numpy as np
        >>> from imagespace.spatial.screws import TranslationalFiveR
        >>> TranslationalFiveR.couple_condition([0.0, 0.0, 0.0]).tolist()
        [-1.0]
        """
        t = np.atleast_2d(as_float_array(theta, "theta", last=3, finite=False))
        with np.errstate(invalid="ignore"):                 # sin(inf) is NaN: that row's answer
            s, c = np.sin(t), np.cos(t)
        return s[:, 0] * s[:, 1] * s[:, 2] - c[:, 0] * c[:, 1] * c[:, 2]

    def thetas(self, P: npt.ArrayLike, branch: int = 0) -> FloatArray:
        """First joint angles at platform positions ``P`` ``(n, 3)``: ``(n, 3)``.

        Raises
        ------
        TypeError
            For non-numeric ``P`` or a ``branch`` that is not a whole number.
        InputError
            For ``P`` not of shape ``(3,)``/``(n, 3)`` or not finite, or ``branch`` not 0 or 1.

        Examples
        --------
        >>> from imagespace.spatial.screws import TranslationalFiveR
        >>> TranslationalFiveR().thetas([0.0, 0.1, 0.0]).shape
        (1, 3)
        """
        P = np.atleast_2d(as_float_array(P, "P", last=3))
        branch = _branch(branch, "branch")
        out = np.empty((len(P), 3))
        E = np.eye(3)
        for i in range(3):
            r = (P - self.c * E[i]) - self.base(i)                       # C_i - A_i
            # d_i(theta) . r = 0: d = cos t * f + sin t * g with (f, g) from the definition
            f = self.d(i, 0.0)
            g = self.d(i, np.pi / 2)
            out[:, i] = np.arctan2(-(r @ f), r @ g) + branch * np.pi
        return out

    def leg_twists(self, P: npt.ArrayLike, branch: int = 0, elbow: int = 0) -> list[FloatArray]:
        """Joint twists of the three legs at platform position ``P`` ``(3,)``, about the origin.

        Raises
        ------
        TypeError
            For non-numeric ``P`` or a ``branch``/``elbow`` that is not a whole number.
        InputError
            For ``P`` not of shape ``(3,)`` or not finite, ``branch``/``elbow`` not 0 or 1, or a
            position out of reach of a leg.

        Examples
        --------
        >>> from imagespace.spatial.screws import TranslationalFiveR
        >>> [T.shape for T in TranslationalFiveR().leg_twists([0.0, 0.1, 0.0])]
        [(5, 6), (5, 6), (5, 6)]
        """
        P = as_float_array(P, "P", last=3, allow_batch=False)
        elbow = _branch(elbow, "elbow")
        th = self.thetas(P, branch)[0]
        E = np.eye(3)
        legs = []
        for i in range(3):
            A = self.base(i)
            C = P - self.c * E[i]
            d = self.d(i, th[i])
            r = C - A
            with np.errstate(over="ignore"):
                L = np.linalg.norm(r)                  # inf far out of reach: refused just below
            if L > self.l1 + self.l2 or L < abs(self.l1 - self.l2) or L == 0:
                raise InputError(f"P = {P.tolist()} is out of reach of leg {i}")
            # elbow in the leg's plane (normal d): along r and the in-plane normal n = d x r / L
            x = (self.l1**2 - self.l2**2 + L**2) / (2 * L)
            h = np.sqrt(max(float(self.l1**2 - x**2), 0.0)) * (1 if elbow == 0 else -1)
            nrm = np.cross(d, r) / L
            Eb = A + x * r / L + h * nrm
            legs.append(np.array([revolute(E[i], A), revolute(d, A), revolute(d, Eb), revolute(d, C),
                                  revolute(E[i], C)]))
        return legs


MAX_SAMPLES = 1_000_000
"""The largest ``n`` :func:`singularity_fractions` accepts (one constraint analysis per position)."""


def singularity_fractions(mechanism: TranslationalFiveR, box: float = 0.4, n: int = 2000, eps: float = 0.05,
                          seed: int = 0) -> dict[str, Any]:
    """Fractions of a sampled workspace lost near each singularity type (seed 001's comparison).

    Positions are drawn uniformly (seeded) in the cube ``[-box, box]^3``; those every leg reaches
    form the sampled workspace; a position counts as lost to a type when that type's measure
    (:attr:`ConstraintAnalysis.measures`, a smallest-over-largest singular value ratio) is below
    ``eps``.

    Parameters
    ----------
    mechanism : TranslationalFiveR
    box, eps : float
    n : int
    seed : int

    Returns
    -------
    dict
        ``reachable`` (count) and the lost fractions: ``constraint``, ``input_output`` (the
        classical 3x3 Jacobian of the actuation forces on the translations), ``leg``,
        ``ignoring_constraints`` (input-output or leg: what an analysis blind to constraint
        singularities reports) and ``all``.

    Raises
    ------
    TypeError
        For a ``mechanism`` that is not a TranslationalFiveR, non-numeric ``box``/``eps``, or a
        non-integer ``n``/``seed``.
    InputError
        For ``eps`` outside ``(0, 1)``, a non-positive ``box``, ``n`` above ``MAX_SAMPLES`` or
        below 1, or a negative ``seed``.

    Examples
    --------
    >>> from imagespace.spatial.screws import TranslationalFiveR, singularity_fractions
    >>> f = singularity_fractions(TranslationalFiveR(), n=200)
    >>> 0 <= f["constraint"] <= 1
    True
    """
    if not isinstance(mechanism, TranslationalFiveR):
        raise InputTypeError(f"mechanism must be a TranslationalFiveR, got {type(mechanism).__name__} {_short(mechanism)}")
    eps = as_scalar(eps, "eps")
    if not 0 < eps < 1:
        raise InputError(f"eps must be in (0, 1), got {eps!r}")
    box = as_scalar(box, "box")
    if not box > 0:
        raise InputError(f"box must be a positive half-width, got {box!r}")
    n = as_count(n, "n")
    if n > MAX_SAMPLES:
        raise InputError(f"n must be at most MAX_SAMPLES = {MAX_SAMPLES} positions, got {n}")
    seed = as_count(seed, "seed", 0)
    rng = np.random.default_rng(seed)
    P = rng.uniform(-box, box, (n, 3))
    translations = np.hstack([np.zeros((3, 3)), np.eye(3)])
    keys = ("constraint", "input_output", "leg", "ignoring_constraints", "all")
    lost = dict.fromkeys(keys, 0)
    count = 0
    for p in P:
        try:
            legs = mechanism.leg_twists(p)
        except InputError:
            continue
        count += 1
        a = constraint_analysis(legs, 3, actuated=[0, 0, 0], intended=translations)
        c = a.measures["constraint"] < eps
        io = a.measures["input_output"] < eps
        leg = min(a.measures["legs"]) < eps
        lost["constraint"] += c
        lost["input_output"] += io
        lost["leg"] += leg
        lost["ignoring_constraints"] += io or leg
        lost["all"] += c or io or leg
    out = {k: v / count if count else float("nan") for k, v in lost.items()}
    out["reachable"] = count
    return out


def planar_leg_wrenches(manipulator: PlanarMechanism, pose: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Unit planar wrenches ``(f_x, f_y, m_z)`` along the legs of a 3-RPR at a pose (moments about the origin).

    For an RPR leg the constraint on the platform with the prismatic joint locked is a force
    along the leg; the three wrenches are dependent exactly when the leg lines are concurrent or
    parallel, which is the image-space quartic's zero set: at constraint-satisfying poses
    ``S(image_point(pose)) = -128 d1 d2 d3 det W`` (``det Jx = 8 d1 d2 d3 det W``, row ``i`` of
    ``Jx`` being ``2 d_i`` times the wrench with its moment about the platform origin, a change of
    reference point that leaves the determinant unchanged).

    Parameters
    ----------
    manipulator : PlanarParallel
        All legs RPR.
    pose : (3,) float

    Returns
    -------
    W : (3, 3) float
    lengths : (3,) float

    Raises
    ------
    TypeError
        For a ``manipulator`` that is not a PlanarParallel, or a non-numeric ``pose``.
    InputError
        For a ``pose`` not of shape ``(3,)``, a leg that is not RPR, or a leg of zero length at
        the pose.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.spatial.screws import planar_leg_wrenches
    >>> W, d = planar_leg_wrenches(isp.examples.general_3rpr(), [0.5, 1.0, 0.2])
    >>> W.shape
    (3, 3)
    """
    check_mechanism(manipulator)
    p = as_float_array(pose, "pose", last=3, allow_batch=False)
    rows, lengths = [], []
    for i, leg in enumerate(manipulator.legs):
        if leg.joints != "RPR":
            raise InputError(f"legs[{i}] is {leg.joints}; planar_leg_wrenches needs RPR legs")
        g = leg.geometry(exact=False)
        A = np.array(g["base"], float)
        c, s = np.cos(p[2]), np.sin(p[2])
        Pw = p[:2] + np.array([[c, -s], [s, c]]) @ np.array(g["platform"], float)
        u = Pw - A
        L = float(np.hypot(u[0], u[1]))             # no overflow for a far pose
        if L == 0:
            raise InputError(f"leg {i} has zero length at pose {p.tolist()}: its line is undefined")
        u = u / L
        rows.append([u[0], u[1], Pw[0] * u[1] - Pw[1] * u[0]])
        lengths.append(L)
    return np.array(rows), np.array(lengths)
