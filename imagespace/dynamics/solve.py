"""Kinematics along a task trajectory, drive singularities, the consistency condition, inverse
dynamics through the singularity (seed 000 eqs. 5, 8, 10-13, corrected), and the independent checks
(power balance, forward simulation).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._validate import as_flag, as_float_array
from ..exceptions import InputError
from ..tolerances import TOLERANCES
from . import checks
from .model import OpenTreeModel
from .timelaw import TimeLaw, sextic_through
from .._html import dataclass_html, dataclass_repr

__all__ = ["LinePath", "TrajectoryState", "state", "drive_singularity", "DriveSingularity",
           "consistent_acceleration", "plan_consistent_law", "InverseDynamicsResult", "inverse_dynamics",
           "power_balance", "simulate"]

CONSISTENCY_RTOL = TOLERANCES.dynamics_consistency
"""The default of :attr:`Tolerances.dynamics_consistency <imagespace.tolerances.Tolerances>` (1e-6):
a crossing of the drive singularity satisfies the consistency condition when
``|nu . (M etaddot - R)| <= dynamics_consistency * |M etaddot - R|`` there (dimensionless). The
decision reads ``model.tolerances.dynamics_consistency``."""

NEWTON_STOP = 1e-13
"""Newton on the loop and task equations stops once the largest residual is below this (a
stopping rule; whether the result is accepted is ``Tolerances.dynamics_residual``)."""

NEWTON_STEPS = 50
"""The most Newton steps taken on the loop and task equations."""

BISECTION_WIDTH = 1e-13
"""The drive singularity's bisection stops once its bracket in ``s`` is narrower than this."""

TIME_STEP = 1e-6
"""The central-difference step in time for ``alphadot`` and ``mudot`` inside the band."""

CROSSING_SAMPLES = 2049
"""Samples of ``s(t) - s_sing`` over the trajectory's time domain that bracket its crossings of the
drive singularity before bisection (independent of the caller's time grid)."""


@dataclass(frozen=True)
class LinePath:
    """A straight task path ``x(s) = x0 + s e`` (``n``-vectors).

    Raises
    ------
    TypeError
        For non-numeric ``x0`` or ``e``.
    InputError
        For an empty ``x0``, an ``e`` of another length, a non-finite entry, or ``e = 0``.

    Examples
    --------
    >>> from imagespace.dynamics.solve import LinePath
    >>> LinePath([0.0, 1.0], [1.0, 0.0]).e.tolist()
    [1.0, 0.0]
    """

    x0: np.ndarray
    e: np.ndarray

    def __post_init__(self):
        x0 = checks.vector(self.x0, "x0")
        if len(x0) == 0:
            raise InputError("x0 must have at least one task coordinate, got shape (0,)")
        e = checks.vector(self.e, "e", len(x0))
        if not np.any(e):
            raise InputError("e must be a non-zero direction, got the zero vector")
        object.__setattr__(self, "x0", x0)
        object.__setattr__(self, "e", e)


@dataclass(frozen=True)
class TrajectoryState:
    """``eta`` and its first three time derivatives at one instant."""

    t: float
    eta: np.ndarray
    d1: np.ndarray
    d2: np.ndarray
    d3: np.ndarray

    # short summaries (arrays as shape and dtype) for the terminal and Jupyter; see imagespace._html
    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html


def _newton(model, x, guess):
    eta = np.array(guess, float)
    for _ in range(NEWTON_STEPS):
        F = np.concatenate([model.loop(eta), model.task(eta) - x])
        if np.max(np.abs(F)) < NEWTON_STOP:
            return eta
        try:
            eta = eta - np.linalg.solve(model.Gamma(eta), F)
        except np.linalg.LinAlgError:
            raise InputError(f"the kinematics failed at x = {np.round(x, 6).tolist()}: Gamma is singular at "
                             f"eta = {np.round(eta, 6).tolist()}; give a guess near the intended "
                             "assembly") from None
    F = np.concatenate([model.loop(eta), model.task(eta) - x])
    if np.max(np.abs(F)) > model.tolerances.dynamics_residual:
        raise InputError(f"the kinematics did not converge at x = {np.round(x, 6).tolist()} "
                         f"(residual {np.max(np.abs(F)):.1e}); out of reach or at an inverse-kinematic singularity")
    return eta


def _model_path(model, path):
    checks.instance(model, OpenTreeModel, "model", " (e.g. seed000_model())")
    checks.instance(path, LinePath, "path", " (LinePath(x0, e))")
    if len(path.x0) != model.n:
        raise InputError(f"path must have {model.n} task coordinates like the model, got {len(path.x0)}")


def _guess(model, guess):
    return checks.vector(guess, "guess", model.m)


def state(model, path, s, sd=0.0, sdd=0.0, sddd=0.0, guess=None, t=0.0):
    """``eta, etadot, etaddot, etadddot`` for the path parameter and its time derivatives.

    Newton on the loop and task equations from ``guess`` (zeros if None); the result is accepted
    when the residual is at most ``model.tolerances.dynamics_residual``.

    Raises
    ------
    TypeError
        For a ``model`` that is not an OpenTreeModel or a ``path`` that is not a LinePath, or
        non-numeric values.
    InputError
        For a path of another dimension, a malformed ``guess``, a singular ``Gamma`` on the way,
        or no convergence (out of reach, or at an inverse-kinematic singularity).

    Examples
    --------
    >>> from imagespace.dynamics.seed000 import seed000_model, seed000_path, SEED000
    >>> from imagespace.dynamics.solve import LinePath, state
    >>> model = seed000_model(); x0, e = seed000_path()
    >>> st = state(model, LinePath(x0, e), 0.0, guess=[0.69, 2.2, 2.46, 0.36, 0.0])
    >>> bool(abs(model.task(st.eta) - x0).max() < 1e-12)
    True
    """
    _model_path(model, path)
    s, sd, sdd, sddd, t = (checks.scalar(v, name) for v, name in
                           zip((s, sd, sdd, sddd, t), ("s", "sd", "sdd", "sddd", "t")))
    guess = np.zeros(model.m) if guess is None else _guess(model, guess)
    x = path.x0 + s * path.e
    eta = _newton(model, x, guess)
    k = model.m - model.n
    G = model.Gamma(eta)
    rhs1 = np.concatenate([np.zeros(k), path.e * sd])
    d1 = np.linalg.solve(G, rhs1)
    Gd = model.Gamma_dot(eta, d1)
    d2 = np.linalg.solve(G, np.concatenate([np.zeros(k), path.e * sdd]) - Gd @ d1)
    Gdd = model.Gamma_ddot(eta, d1, d2)
    d3 = np.linalg.solve(G, np.concatenate([np.zeros(k), path.e * sddd]) - 2 * Gd @ d2 - Gdd @ d1)
    return TrajectoryState(t, eta, d1, d2, d3)


def _at(model, path, law, t, guess):
    """The state at time ``t`` of the trajectory ``x0 + s(t) e``."""
    return state(model, path, law(t), law(t, 1), law(t, 2), law(t, 3), guess=guess, t=t)


def _left_null(AT):
    u, s, vt = np.linalg.svd(AT.T)
    return vt[-1], s[-1] / s[0]


@dataclass(frozen=True)
class DriveSingularity:
    """Where a path meets ``|A| = 0``.

    Attributes
    ----------
    s : float
        Path parameter (bisection to ``BISECTION_WIDTH`` = 1e-13).
    eta : (m,) float
    nu : (m,) float
        Left null vector of ``A^T`` (``nu^T A^T = 0``): row ``s_row`` of ``A^T`` equals
        ``sum_p alpha_p row_p`` with ``alpha_p = -nu_p / nu_s``.
    s_row : int
    alpha : (m,) float
        ``alpha_p`` (zero for ``p = s_row`` and rows not involved).
    """

    s: float
    eta: np.ndarray
    nu: np.ndarray
    s_row: int
    alpha: np.ndarray


def drive_singularity(model, path, s_range, guess, samples=400):
    """Locate the drive singularity ``det A = 0`` on the path (sign change, then bisection).

    A rank drop of more than one is judged with ``model.tolerances.dynamics_rank``; coefficients
    ``alpha_p`` below ``model.tolerances.dynamics_alpha_zero`` are zero.

    Raises
    ------
    TypeError
        For a ``model`` that is not an OpenTreeModel or a ``path`` that is not a LinePath, or
        non-numeric values.
    InputError
        If ``det A`` does not change sign on ``s_range`` (the path never crosses a drive
        singularity), or the rank of ``A`` drops by more than one there; for equal ends of
        ``s_range``, a malformed ``guess`` or ``samples``, or kinematics that fail on the way.

    Examples
    --------
    >>> from imagespace.dynamics import *
    >>> model = seed000_model(); x0, e = seed000_path(); path = LinePath(x0, e)
    >>> eta0 = state(model, path, 0.0, guess=[0.69, 2.2, 2.46, 0.36, 0.0]).eta
    >>> sing = drive_singularity(model, path, (0.0, 1.5), eta0)
    >>> round(float(sing.s), 6), sing.s_row
    (0.662, 4)
    """
    _model_path(model, path)
    sr = checks.vector(s_range, "s_range", 2)
    if sr[0] == sr[1]:
        raise InputError(f"s_range must be two different path parameters, got {sr.tolist()}")
    eta = _guess(model, guess)
    samples = checks.count(samples, "samples", 2)
    ss = np.linspace(sr[0], sr[1], samples)
    prev = None
    for s in ss:
        eta = state(model, path, s, guess=eta).eta
        d = np.linalg.det(model.A_T(eta))
        if prev is not None and np.sign(d) != np.sign(prev[1]):
            a, b, ea = prev[0], s, prev[2]
            da = prev[1]
            for _ in range(100):
                mid = 0.5 * (a + b)
                em = state(model, path, mid, guess=ea).eta
                dm = np.linalg.det(model.A_T(em))
                if np.sign(dm) == np.sign(da):
                    a, ea, da = mid, em, dm
                else:
                    b = mid
                if b - a < BISECTION_WIDTH:
                    break
            s_star = 0.5 * (a + b)
            e_star = state(model, path, s_star, guess=ea).eta
            AT = model.A_T(e_star)
            sv = np.linalg.svd(AT, compute_uv=False)
            if sv[-2] < model.tolerances.dynamics_rank * sv[0]:
                raise InputError(f"rank(A) < m - 1 at the singularity (singular values {sv}); "
                                 "the modified equation needs a rank drop of exactly one")
            nu, _ = _left_null(AT)
            k = int(np.argmax(np.abs(nu)))
            alpha = -nu / nu[k]
            alpha[k] = 0.0
            alpha[np.abs(alpha) < model.tolerances.dynamics_alpha_zero] = 0.0
            return DriveSingularity(float(s_star), e_star, nu, k, alpha)
        prev = (s, d, eta.copy())
    raise InputError(f"the path never reaches a drive singularity on s in {list(s_range)}: det A keeps its sign")


def consistent_acceleration(model, path, sing, v):
    """The path acceleration ``a = s''(T_d)`` that satisfies the consistency condition at the
    singularity with path speed ``v`` (seed 000 eq. 8/20): ``nu . (M etaddot - R) = 0`` with
    ``etaddot = eta' a + (eta'' v^2)``; linear in ``a``.

    Raises
    ------
    TypeError
        For a ``model`` that is not an OpenTreeModel or a ``path`` that is not a LinePath, a
        ``sing`` that is not a DriveSingularity, or a non-numeric ``v``.
    InputError
        When the condition does not involve ``a`` (its slope below
        ``model.tolerances.dynamics_consistency_slope`` times ``max(1, |base|)``), or the
        kinematics fail.

    Examples
    --------
    >>> from imagespace.dynamics import *
    >>> model = seed000_model(); x0, e = seed000_path(); path = LinePath(x0, e)
    >>> eta0 = state(model, path, 0.0, guess=[0.69, 2.2, 2.46, 0.36, 0.0]).eta
    >>> sing = drive_singularity(model, path, (0.0, 1.5), eta0)
    >>> bool(abs(consistent_acceleration(model, path, sing, 1.7)) < 100)
    True
    """
    _model_path(model, path)
    checks.instance(sing, DriveSingularity, "sing", " (from drive_singularity)")
    v = checks.scalar(v, "v")
    st0 = state(model, path, sing.s, v, 0.0, guess=sing.eta)
    st1 = state(model, path, sing.s, v, 1.0, guess=sing.eta)
    M = model.M(st0.eta)
    R = model.R(st0.eta, st0.d1)
    base = sing.nu @ (M @ st0.d2 - R)
    slope = sing.nu @ (M @ (st1.d2 - st0.d2))
    if abs(slope) < model.tolerances.dynamics_consistency_slope * max(1.0, abs(base)):
        raise InputError("the consistency condition does not involve the path acceleration here")
    return -base / slope


def plan_consistent_law(model, path, sing, T, L, Td=None, v=None):
    """The sixth-degree time law through the singularity that satisfies the consistency condition.

    With ``Td`` and ``v`` given, they are used (the result says whether ``s`` is monotone); with
    either missing, a grid of candidates is searched and the first monotone law returned.

    Returns
    -------
    (TimeLaw, dict)
        The law and ``{"Td", "v", "a", "monotone"}``.

    Raises
    ------
    TypeError
        For a ``model`` that is not an OpenTreeModel or a ``path`` that is not a LinePath, a
        ``sing`` that is not a DriveSingularity, or non-numeric values.
    InputError
        For a non-positive ``T``, a ``Td`` outside ``(0, T)``, or a failure of
        :func:`consistent_acceleration`.

    Examples
    --------
    >>> from imagespace.dynamics import *
    >>> model = seed000_model(); x0, e = seed000_path(); path = LinePath(x0, e)
    >>> eta0 = state(model, path, 0.0, guess=[0.69, 2.2, 2.46, 0.36, 0.0]).eta
    >>> sing = drive_singularity(model, path, (0.0, 1.5), eta0)
    >>> law, info = plan_consistent_law(model, path, sing, 1.0, 1.5)
    >>> info["monotone"]
    True
    """
    _model_path(model, path)
    checks.instance(sing, DriveSingularity, "sing", " (from drive_singularity)")
    T = checks.scalar(T, "T", positive=True)
    L = checks.scalar(L, "L")
    Td = None if Td is None else checks.scalar(Td, "Td")
    v = None if v is None else checks.scalar(v, "v")
    Tds = [Td] if Td is not None else list(np.linspace(0.35, 0.75, 41) * T)
    vs = [v] if v is not None else list(np.linspace(0.5, 3.0, 51) * L / T)
    best = None
    for td in Tds:
        for vv in vs:
            a = consistent_acceleration(model, path, sing, vv)
            law = sextic_through(T, L, td, sing.s, vv, a)
            info = {"Td": float(td), "v": float(vv), "a": float(a),
                    "monotone": law.is_monotone(tolerances=model.tolerances)}
            if info["monotone"]:
                return law, info
            best = best or (law, info)
    return best


@dataclass(frozen=True)
class InverseDynamicsResult:
    """Forces along a trajectory.

    Attributes
    ----------
    t : (k,) float
    mu : (k, m) float
        ``[lambda; T]``: loop forces, then actuator efforts (in the order of ``actuated``).
    branch : (k,) str
        ``"eq5"`` (regular) or ``"eq11"`` (modified equation inside the band ``|g| < eps``).
    condition : (k,) float
        Condition number of the matrix solved.
    g : (k,) float
        ``det A / (product of the row norms of A^T)``, the dimensionless singularity measure.
    states : list of TrajectoryState
    consistent : bool
        False when the trajectory crosses the singularity without satisfying the consistency
        condition at a crossing (forces there are then unbounded and set to NaN at the samples
        inside the band around that crossing). Judged at the crossings themselves, found by
        bisection of ``s(t) = s_sing`` over the law's whole domain ``[0, T]`` (and the span of
        ``t``), whatever the time grid; True when there is no crossing.
    consistency_residual : float
        ``|nu . (M etaddot - R)|`` at the crossing, relative to ``|M etaddot - R|`` (the largest
        over the crossings; 0 when there is none).
    crossings : (j,) float
        The crossing instants (bisected, to rounding).
    """

    t: np.ndarray
    mu: np.ndarray
    branch: np.ndarray
    condition: np.ndarray
    g: np.ndarray
    states: list
    consistent: bool
    consistency_residual: float
    crossings: np.ndarray = field(default_factory=lambda: np.zeros(0))

    # short summaries (arrays as shape and dtype) for the terminal and Jupyter; see imagespace._html
    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html


def _measure(AT):
    return float(np.linalg.det(AT) / np.prod(np.linalg.norm(AT, axis=1)))


def inverse_dynamics(model, path, law, times, guess, sing=None, eps=1e-3, mu_dot_correction=True):
    """Actuator and loop forces along ``x(t) = x0 + s(t) e`` (seed 000's algorithm).

    Outside the band ``|g| < eps`` eq. 5 ``A^T mu = M etaddot - R``; inside it the modified
    equation: row ``s`` replaced by ``(Adot_s - alpha_p Adot_p - alphadot_p A_p) mu =
    (M_s - alpha_p M_p) eta''' + (Mdot_s - alpha_p Mdot_p - alphadot_p M_p) eta'' - Rdot_s +
    alpha_p Rdot_p + alphadot_p R_p`` (the seed's eqs. 9-13 with their lost derivative orders
    restored), ``alpha`` from the row dependence (least squares on the involved rows) and
    ``alphadot`` by central differences in time.

    The consistency condition is judged where the trajectory crosses the singularity, at the
    instants where ``s(t) = sing.s`` (bisected over the law's domain), not at the sample of
    ``times`` nearest to it: a grid need not contain ``T_d``.

    Parameters
    ----------
    model : OpenTreeModel
    path : LinePath
    law : TimeLaw
    times : (k,) float
    guess : (m,) float
        ``eta`` near the start (picks the assembly branch).
    sing : DriveSingularity, optional
        Needed for the band.
    eps : float
        Band half-width in ``g``.
    mu_dot_correction : bool
        Inside the band, put back the term ``(A_s - alpha_p A_p) mudot`` that the seed drops
        (its coefficient vanishes only at the singular instant): the forces then join those of
        eq. 5 continuously at the band's
        edges instead of jumping by the neglected term.

    Returns
    -------
    InverseDynamicsResult

    Raises
    ------
    TypeError
        For a ``model`` that is not an OpenTreeModel or a ``path`` that is not a LinePath, a
        ``law`` that is not a TimeLaw, a ``sing`` that is not a DriveSingularity, a
        non-boolean ``mu_dot_correction`` or non-numeric values.
    InputError
        For a non-positive ``eps``, empty ``times`` or times outside ``[0, law.T]``, a malformed
        ``guess``, or kinematics that fail along the way.

    Examples
    --------
    >>> from imagespace.dynamics import *
    >>> model = seed000_model(); x0, e = seed000_path(); path = LinePath(x0, e)
    >>> eta0 = state(model, path, 0.0, guess=[0.69, 2.2, 2.46, 0.36, 0.0]).eta
    >>> sing = drive_singularity(model, path, (0.0, 1.5), eta0)
    >>> law, info = plan_consistent_law(model, path, sing, 1.0, 1.5)
    >>> res = inverse_dynamics(model, path, law, [0.2, info["Td"], 0.8], eta0, sing)
    >>> res.branch.tolist(), res.consistent
    (['eq5', 'eq11', 'eq5'], True)
    >>> res = inverse_dynamics(model, path, law, info["Td"] + np.array([-3e-4, 2e-4]), eta0, sing)
    >>> res.branch.tolist(), res.consistent, bool(np.isfinite(res.mu).all())    # T_d not sampled
    (['eq11', 'eq11'], True, True)
    """
    _model_path(model, path)
    checks.instance(law, TimeLaw, "law", " (cubic_rest_to_rest, sextic_through ...)")
    if sing is not None:
        checks.instance(sing, DriveSingularity, "sing", " (from drive_singularity)")
    eps = checks.scalar(eps, "eps")
    if not eps > 0:
        raise InputError(f"eps must be positive, got {eps!r}")
    mu_dot_correction = as_flag(mu_dot_correction, "mu_dot_correction")
    times = np.atleast_1d(as_float_array(times, "times"))
    if times.ndim != 1 or len(times) == 0:
        raise InputError(f"times must be a non-empty (k,) array, got shape {times.shape}")
    if np.any(times < 0) or np.any(times > law.T):
        raise InputError(f"times must lie in the law's domain [0, T] = [0, {law.T}], got values from "
                         f"{times.min()} to {times.max()}")
    eta = _guess(model, guess)
    mus, branches, conds, gs, states = [], [], [], [], []
    crossed_residual, consistent = 0.0, True
    for t in times:
        st = _at(model, path, law, t, eta)
        eta = st.eta
        AT = model.A_T(st.eta)
        g = _measure(AT)
        M = model.M(st.eta)
        R = model.R(st.eta, st.d1)
        b = M @ st.d2 - R
        if sing is not None and abs(g) < eps:
            D, S = _modified(model, path, law, t, st, sing)
            mu = np.linalg.solve(D, S)
            if mu_dot_correction and abs(g) > model.tolerances.dynamics_mu_dot:
                # restore the dropped term (A_s - alpha_p A_p) mudot; mudot from eq. 5 at t +- h,
                # still well conditioned there (cond ~ 1/|g|); closer than |g| = dynamics_mu_dot
                # (1e-7) the term is below the rounding of eq. 5 itself and is left out
                h = TIME_STEP
                mus_ = []
                for tt in (t - h, t + h):
                    st2 = _at(model, path, law, tt, st.eta)
                    mus_.append(np.linalg.solve(model.A_T(st2.eta),
                                                model.M(st2.eta) @ st2.d2 - model.R(st2.eta, st2.d1)))
                mudot = (mus_[1] - mus_[0]) / (2 * h)
                alpha = _alpha(model, st.eta, sing)
                c = AT[sing.s_row] - alpha @ AT
                S = S.copy()
                S[sing.s_row] -= c @ mudot
                mu = np.linalg.solve(D, S)
            branches.append("eq11")
            conds.append(np.linalg.cond(D))
        else:
            mu = np.linalg.solve(AT, b)
            branches.append("eq5")
            conds.append(np.linalg.cond(AT))
        mus.append(mu)
        gs.append(g)
        states.append(st)
    mus = np.array(mus)
    crossings = np.zeros(0)
    if sing is not None:
        # judge the consistency condition at the crossings themselves (bisected), not at the
        # sample nearest to them: a grid that straddles T_d has no sample where it holds exactly
        crossings = _crossings(law, sing.s, times)
        residuals = []
        for tc in crossings:
            stc = _at(model, path, law, tc, sing.eta)
            b = model.M(stc.eta) @ stc.d2 - model.R(stc.eta, stc.d1)
            residuals.append(abs(sing.nu @ b) / max(np.finfo(float).tiny, np.linalg.norm(b)))
        residuals = np.array(residuals)
        bad = residuals > model.tolerances.dynamics_consistency
        consistent = not bad.any()
        crossed_residual = float(residuals.max()) if len(residuals) else 0.0
        inside = np.flatnonzero(np.abs(np.array(gs)) < eps)
        if len(crossings) and len(inside):
            nearest = np.argmin(np.abs(times[inside, None] - crossings[None, :]), axis=1)
            mus[inside[bad[nearest]]] = np.nan
    return InverseDynamicsResult(times, mus, np.array(branches), np.array(conds), np.array(gs), states,
                                 bool(consistent), float(crossed_residual), crossings)


def _crossings(law, s_star, times):
    """The instants where ``law(t) = s_star`` on ``[0, law.T]`` and the span of ``times``: sign
    changes on ``CROSSING_SAMPLES`` samples plus ``times``, bisected to rounding; exact zeros kept.
    A trajectory that only touches ``s_star`` between samples without crossing is not found."""
    lo, hi = float(np.min(times)), float(np.max(times))
    T = getattr(law, "T", None)
    if T is not None:
        lo, hi = min(lo, 0.0), max(hi, float(T))
    ts = np.union1d(np.linspace(lo, hi, CROSSING_SAMPLES), times)
    f = np.asarray(law(ts), float) - s_star
    out = list(ts[f == 0])
    for i in np.flatnonzero(f[:-1] * f[1:] < 0):
        a, b, fa = ts[i], ts[i + 1], f[i]
        while True:
            mid = 0.5 * (a + b)
            if not a < mid < b:
                break
            fm = float(law(mid)) - s_star
            if fm == 0:
                a = b = mid
                break
            if np.sign(fm) == np.sign(fa):
                a, fa = mid, fm
            else:
                b = mid
        out.append(0.5 * (a + b))
    return np.sort(np.array(out, float))


def _alpha(model, eta, sing):
    AT = model.A_T(eta)
    s = sing.s_row
    P = np.flatnonzero(sing.alpha != 0)
    coef, *_ = np.linalg.lstsq(AT[P].T, AT[s], rcond=None)
    alpha = np.zeros(model.m)
    alpha[P] = coef
    return alpha


def _modified(model, path, law, t, st, sing, h=TIME_STEP):
    s = sing.s_row
    alpha = _alpha(model, st.eta, sing)
    sp_ = state(model, path, law(t + h), guess=st.eta).eta
    sm_ = state(model, path, law(t - h), guess=st.eta).eta
    alphad = (_alpha(model, sp_, sing) - _alpha(model, sm_, sing)) / (2 * h)
    AT = model.A_T(st.eta)
    ATd = model.A_T_dot(st.eta, st.d1)
    M = model.M(st.eta)
    Md = model.M_dot(st.eta, st.d1)
    R = model.R(st.eta, st.d1)
    Rd = model.R_dot(st.eta, st.d1, st.d2)
    D = AT.copy()
    D[s] = ATd[s] - alpha @ ATd - alphad @ AT
    S = M @ st.d2 - R
    S[s] = (M[s] - alpha @ M) @ st.d3 + (Md[s] - alpha @ Md - alphad @ M) @ st.d2 - Rd[s] + alpha @ Rd + alphad @ R
    return D, S


def _energy(model, st):
    return 0.5 * st.d1 @ model.M(st.eta) @ st.d1 + model.potential(st.eta)


def power_balance(model, path, law, result, h=2e-4):
    """Actuator power minus the rate of change of kinetic + potential energy, at each instant.

    The energy ``1/2 etadot^T M etadot + V`` is differentiated in time by the five-point central
    difference (step ``h``, error ``O(h^4)``), independently of ``R``; the loop forces do no work
    (``Gamma_K etadot = 0``).

    Returns
    -------
    (k,) float
        Residuals relative to the largest actuator power along the trajectory.

    Raises
    ------
    TypeError
        For a ``model`` that is not an OpenTreeModel or a ``path`` that is not a LinePath, a
        ``law`` that is not a TimeLaw, a ``result`` that is not an InverseDynamicsResult, or a
        non-numeric ``h``.
    InputError
        For a non-positive ``h`` or kinematics that fail at ``t +- 2h``.

    Examples
    --------
    >>> from imagespace.dynamics import *
    >>> model = seed000_model(); x0, e = seed000_path(); path = LinePath(x0, e)
    >>> eta0 = state(model, path, 0.0, guess=[0.69, 2.2, 2.46, 0.36, 0.0]).eta
    >>> sing = drive_singularity(model, path, (0.0, 1.5), eta0)
    >>> law, info = plan_consistent_law(model, path, sing, 1.0, 1.5)
    >>> res = inverse_dynamics(model, path, law, [0.2, 0.8], eta0, sing)
    >>> bool(abs(power_balance(model, path, law, res)).max() < 1e-9)
    True
    """
    _model_path(model, path)
    checks.instance(law, TimeLaw, "law")
    checks.instance(result, InverseDynamicsResult, "result", " (from inverse_dynamics)")
    h = checks.scalar(h, "h", positive=True)
    k = model.m - model.n
    res, pw = [], []
    for t, mu, st in zip(result.t, result.mu, result.states):
        P = mu[k:] @ (model.Z @ st.d1)
        E = [_energy(model, _at(model, path, law, t + k_ * h, st.eta)) for k_ in (-2, -1, 1, 2)]
        dE = (E[0] - 8 * E[1] + 8 * E[2] - E[3]) / (12 * h)
        res.append(P - dE)
        pw.append(abs(P))
    scale = max(pw) if pw and max(pw) > 0 else 1.0
    return np.array(res) / scale


def simulate(model, path, law, result, guess, baumgarte=(20.0, 100.0), rtol=1e-10, atol=1e-12):
    """Forward dynamics driven by the computed actuator efforts (interpolated in time), constrained
    by the loop with Baumgarte stabilisation; returns the task-space deviation from the plan.

    Returns
    -------
    (k,) float
        ``|P_simulated - P_planned|`` at ``result.t``.

    Raises
    ------
    TypeError
        For a ``model`` that is not an OpenTreeModel or a ``path`` that is not a LinePath, a
        ``law`` that is not a TimeLaw, a ``result`` that is not an InverseDynamicsResult, or
        non-numeric values.
    InputError
        For a malformed ``guess`` or ``baumgarte``, non-positive ``rtol``/``atol``, or a result
        with fewer than two instants.

    Examples
    --------
    >>> from imagespace.dynamics import *
    >>> model = seed000_model(); x0, e = seed000_path(); path = LinePath(x0, e)
    >>> eta0 = state(model, path, 0.0, guess=[0.69, 2.2, 2.46, 0.36, 0.0]).eta
    >>> sing = drive_singularity(model, path, (0.0, 1.5), eta0)
    >>> law, info = plan_consistent_law(model, path, sing, 1.0, 1.5)
    >>> res = inverse_dynamics(model, path, law, np.linspace(0, 0.3, 31), eta0, sing)
    >>> bool(simulate(model, path, law, res, eta0).max() < 1e-4)
    True
    """
    from scipy.integrate import solve_ivp
    from scipy.interpolate import CubicSpline

    _model_path(model, path)
    checks.instance(law, TimeLaw, "law")
    checks.instance(result, InverseDynamicsResult, "result", " (from inverse_dynamics)")
    _guess(model, guess)
    a1, a0 = checks.vector(baumgarte, "baumgarte", 2)
    rtol, atol = checks.scalar(rtol, "rtol", positive=True), checks.scalar(atol, "atol", positive=True)
    if len(result.t) < 2:
        raise InputError(f"result must hold at least two instants to simulate, got {len(result.t)}")
    k = model.m - model.n
    T_of = CubicSpline(result.t, result.mu[:, k:], axis=0)
    st0 = result.states[0]
    y0 = np.concatenate([st0.eta, st0.d1])

    def rhs(t, y):
        eta, d1 = y[: model.m], y[model.m:]
        M = model.M(eta)
        R = model.R(eta, d1)
        G = model.Gamma(eta)[:k]
        Gd = model.Gamma_dot(eta, d1)[:k]
        phi = model.loop(eta)
        K = np.block([[M, -G.T], [G, np.zeros((k, k))]])
        rhs_ = np.concatenate([R + model.Z.T @ T_of(t), -Gd @ d1 - a1 * (G @ d1) - a0 * phi])
        sol = np.linalg.solve(K, rhs_)
        return np.concatenate([d1, sol[: model.m]])

    out = solve_ivp(rhs, (result.t[0], result.t[-1]), y0, t_eval=result.t, rtol=rtol, atol=atol, method="DOP853")
    dev = []
    for j, st in enumerate(result.states):
        x_sim = model.task(out.y[: model.m, j])
        x_plan = model.task(st.eta)
        dev.append(np.linalg.norm(x_sim[:2] - x_plan[:2]))
    return np.array(dev)
