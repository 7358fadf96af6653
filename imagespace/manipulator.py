"""PlanarParallel: three legs, inverse kinematics, constraint equations and direct kinematics."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np
import sympy as sp

import warnings

from ._memory import check_memory
from ._validate import as_count, as_exact, as_flag, as_float_array, is_symbolic
from .core.mechanism import Mechanism, form_coefficients
from .core.quadrics import Quadric, dk_system as _system
from .core.certify import exact_is_zero, certify_real_roots, certify_real_roots_batch, inclusion_discs
from .solve.certified import plan_roots
from .core.elimination import bf_eval, eliminate
from .exceptions import DegenerateDesignError, InputError, NearSingularWarning
from .core.kinematic_map import pose_of as _pose_of
from .core.kinematic_map import representative_sign
from .core.roots import real_half_angles

__all__ = ["PlanarParallel", "AssemblyMode", "DKBatchResult", "CertifiedModes"]

_MAX_MODES = 6
_KERNEL_MIN_ROWS = 2000
#: Peak bytes per row of a batch, measured with tracemalloc on 20,000 rows of the general 3-RPR
#: (2026-12-01: numpy path 4.2 kB, kernel 0.7 kB, result 0.49 kB; certify=True adds 3.5 kB),
#: rounded up; the memory check before a batch multiplies them by the rows.
BATCH_PEAK_BYTES_PER_ROW = {"numpy": 5000, "kernel": 1000, "certify": 4000}


@dataclass(frozen=True)
class AssemblyMode:
    """One solution of the direct kinematics.

    Attributes
    ----------
    image_point : (4,) float
        Normalised image point ``(x0, x1, x2, x3)``: ``x0**2 + x1**2 = 1``, ``x0 > 0`` (or
        ``x1 > 0`` at the half-turn). Complex for complex modes.
    pose : (3,) float
        ``(x, y, phi)``, ``phi`` in ``(-pi, pi]`` (NaN for complex modes).
    residual : float
        Largest deviation of a leg's inverse kinematics from the given joint value: radians for
        revolute joints, relative ``|dq| / max(|q|, L)`` for prismatic joints, ``L`` the length
        scale of the design and joint values (so the same in any unit).
    aspect : int
        Sign of ``det J`` at the normalised image point, ``J`` the Jacobian of the three
        constraint quadrics and ``x0**2 + x1**2 - 1`` with respect to ``x0..x3`` (the
        determinant is a quartic form, even, so the sign does not depend on the representative).
        Modes of opposite aspect cannot be joined without crossing the singularity surface.
        ``0`` at a singular pose (``multiplicity > 1``) or for complex modes.
    is_real : bool
    multiplicity : int
        On the certified path: the multiplicity of the root of the kinematic polynomial that
        this mode is (``> 1``: a singular mode where several modes have merged, reported once).
        ``1`` on the floating-point paths, which cannot tell.
    """

    image_point: np.ndarray
    pose: np.ndarray
    residual: float
    aspect: int
    is_real: bool = True
    multiplicity: int = 1

    @property
    def singular(self):
        """True for a mode of multiplicity > 1 (several modes merged: a singular pose)."""
        return self.multiplicity > 1

    def __repr__(self):
        if not self.is_real:
            return f"AssemblyMode(complex, image_point={np.round(self.image_point, 6)})"
        x, y, phi = self.pose
        mult = f", singular (multiplicity {self.multiplicity})" if self.multiplicity > 1 else ""
        return (f"AssemblyMode(x={x:.6g}, y={y:.6g}, phi={phi:.6g}, aspect={self.aspect:+d}, "
                f"residual={self.residual:.1e}{mult})")


class CertifiedModes(list):
    """The list of assembly modes with the certificate of the real-root count.

    The semantics, on every certified path (per call and batch rows re-solved by it): the
    modes are computed *from* the certified roots (:mod:`imagespace.solve.certified`), never
    matched to them afterwards.

    * A root where the Cramer denominator is proven non-zero carries exactly one mode; if the
      root has multiplicity ``k > 1`` that mode is singular and reported once with
      ``.multiplicity == k`` (``aspect`` 0).
    * The genuine exceptions: a root where the Cramer denominator vanishes (case (b)) or a
      design where it vanishes identically (case (a), e.g. the collinear 3-RPR) fixes an
      orientation that carries 0, 1 or 2 modes, solved at that orientation; the spurious
      ``phi_c + pi`` root of a PP dyad carries none (the legs' inverse kinematics reject it).
    * ``sum(modes_per_root) == len(modes)`` always.
    * A continuum of modes raises :class:`DegenerateDesignError`.

    Attributes
    ----------
    certificate : RealRootCertificate
        Proven number of distinct real roots of :meth:`PlanarParallel.kinematic_polynomial`
        at the (exact) joint values, with isolating intervals, multiplicities and the method.
    modes_per_root : tuple of int
        For each certified real root (finite ones in ascending ``t = x1/x0``, then the
        half-turn root if any), how many reported modes it carries.
    root_of_mode : tuple of int
        For each mode (in list order), the index of its root in the certificate.
    """

    def __init__(self, modes, certificate, modes_per_root, root_of_mode=()):
        super().__init__(modes)
        self.certificate = certificate
        self.modes_per_root = tuple(modes_per_root)
        self.root_of_mode = tuple(root_of_mode)

    def __repr__(self):
        return (f"CertifiedModes({list.__repr__(self)}, real roots={self.certificate.count}, "
                f"method={self.certificate.method!r})")


@dataclass
class DKBatchResult:
    """Direct kinematics of a batch of joint vectors.

    Attributes
    ----------
    image_points : (n, 6, 4) float
        Normalised image points of the real modes, NaN in unused slots.
    poses : (n, 6, 3) float
    valid : (n, 6) bool
        Which slots hold a mode (valid slots come first, sorted by ``phi``).
    count : (n,) int
        Number of real assembly modes per row.
    aspect : (n, 6) int
    row_ok : (n,) bool
        False for rows that could not be solved (non-finite input, a joint value outside its
        domain, a degenerate design at those joint values); see ``errors``.
    errors : dict
        Row index -> message for every row with ``row_ok`` False.
    special : (n,) bool
        Rows that needed the careful per-row path (Cramer denominator vanishing identically or
        at a root, polynomial identically zero; with the kernel also a root touching the axis).
    residual : (n, 6) float
        Joint-space residual of each mode: from the legs' inverse kinematics on the numpy path,
        to first order ``max_i |Q_i| / |dQ_i/dq_i|`` on the kernel path.
    solver : (n,) str
        Which path answered each row: ``"kernel"`` (compiled one-pass kernel), ``"numpy"``
        (vectorised numpy path), ``"certified"`` (per-row certified path), ``"invalid"``.
    certified_roots : (n,) int, only with ``certify=True``
        Proven number of distinct real roots of the kinematic polynomial per row (-1 where the
        row is not valid).
    certificate_path : (n,) str, only with ``certify=True``
        ``"discs"`` (vectorised inclusion discs), ``"flint"`` (exact isolation) or ``"invalid"``.
    consistent : (n,) bool, only with ``certify=True``
        The row's modes are accounted for by its certificate: either every certified real root
        (all simple, inclusion discs) holds exactly one float mode and no mode lies outside
        them, or the row was solved again root by root by ``direct_kinematics(q, certify=True)``
        (``solver == "certified"``). False only where no certificate could be had (masked rows,
        irrational coefficients with a multiple root).
    near_singular : (n,) bool
        The floating-point answer of this row may have the wrong count: the roots of its
        kinematic polynomial could not be separated by inclusion discs, or the modes found do
        not account for the real roots (compiled kernel: a root pair closer than
        ``Tolerances.near_singular_gap``, or an odd count). Rows answered by the certified path
        and, with ``certify=True``, every ``consistent`` row are never near-singular (their count
        is proven).
    multiplicity : (n, 6) int
        Multiplicity of each mode's root (1 except on rows solved by the certified path).

    Certified semantics (``certify=True``): as for :class:`CertifiedModes`, on every row.
    """

    image_points: np.ndarray
    poses: np.ndarray
    valid: np.ndarray
    count: np.ndarray
    residual: np.ndarray
    aspect: np.ndarray
    row_ok: np.ndarray
    errors: dict = field(default_factory=dict)
    special: Optional[np.ndarray] = None
    solver: Optional[np.ndarray] = None
    certified_roots: Optional[np.ndarray] = None
    certificate_path: Optional[np.ndarray] = None
    consistent: Optional[np.ndarray] = None
    near_singular: Optional[np.ndarray] = None
    multiplicity: Optional[np.ndarray] = None

    def modes(self, i):
        """The modes of row ``i`` as a list of :class:`AssemblyMode`.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> len(m.direct_kinematics_batch([m.q_example_float]).modes(0))
        6
        """
        mult = self.multiplicity
        return [AssemblyMode(self.image_points[i, j], self.poses[i, j], float(self.residual[i, j]),
                             int(self.aspect[i, j]), True, 1 if mult is None else int(mult[i, j]))
                for j in np.flatnonzero(self.valid[i])]


# --------------------------------------------------------------------------- numeric helpers

def _coef_array(quadrics, n):
    """(n, 3, 8) float coefficient array of three numeric quadrics."""
    C = np.empty((n, 3, 8))
    for i, q in enumerate(quadrics):
        for k, v in enumerate(q.coefficients()):
            C[:, i, k] = np.broadcast_to(np.asarray(v, dtype=float), (n,))
    return C


def _newton(C, X, tol):
    """Newton on [Q1, Q2, Q3, x0^2 + x1^2 - 1]; each candidate stops once its step is below
    ``tol.newton_stop`` of its size (or its Jacobian is singular), so converged rows cost nothing
    more. C are balanced coefficients (see :func:`_balance`), so the sizes are comparable."""
    X = X.copy()
    active = np.all(np.isfinite(X), axis=-1)
    for _ in range(int(tol.newton_steps)):
        idx = np.nonzero(active)
        if idx[0].size == 0:
            break
        Ca = C[idx[0]][:, None]                     # (m, 1, 3, 8)
        Fv, J = _system(Ca[:, 0], X[idx][:, None, :])
        Fv, J = Fv[:, 0], J[:, 0]
        det = np.linalg.det(J)
        scale = np.prod(np.linalg.norm(J, axis=-1), axis=-1)
        solvable = np.abs(det) > tol.newton_stop * scale
        step = np.zeros((idx[0].size, 4))
        if np.any(solvable):
            step[solvable] = np.linalg.solve(J[solvable], -Fv[solvable][..., None])[..., 0]
        X[idx] = X[idx] + step
        size = np.maximum(1.0, np.max(np.abs(X[idx]), axis=-1))
        done = ~solvable | (np.max(np.abs(step), axis=-1) <= 0.1 * tol.newton_stop * size)
        # one more step after the first tiny one is pointless: retire converged candidates
        active[idx[0][done], idx[1][done]] = False
    return X


def _balance(C):
    """Balance raw quadric coefficients to the row's length scale.

    ``C`` (n, 3, 8) are coefficients ``(c, a0, a1, b0, b1, k0, k1, k2)`` in ``x0..x3``. With the
    length scale ``L`` of each row (from the quadrics themselves: ``sqrt(|k|/|c|)`` and
    ``|a, b|/|c|`` of circles, ``|k|/|a, b|`` of lines), the substitution ``x2 = L x2'``,
    ``x3 = L x3'`` gives coefficients ``(c L^2, a L, b L, k)``, each quadric then scaled to max
    coefficient 1. Solving in the primed coordinates makes every threshold relative: the same
    robot in millimetres or kilometres meets the same decisions. Returns ``(C', L)``.
    """
    c = np.abs(C[..., 0])
    ab = np.max(np.abs(C[..., 1:5]), axis=-1)
    k = np.max(np.abs(C[..., 5:8]), axis=-1)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        cands = np.stack([np.where(c > 0, np.sqrt(k / c), 0.0), np.where(c > 0, ab / c, 0.0),
                          np.where((c == 0) & (ab > 0), k / ab, 0.0)], axis=-1)
    cands = np.where(np.isfinite(cands), cands, 0.0)
    L = np.max(cands, axis=(-1, -2))
    L = np.where(L > 0, L, 1.0)
    B = C.copy()
    B[..., 0] *= (L * L)[:, None]
    B[..., 1:5] *= L[:, None, None]
    B = B / np.maximum(np.max(np.abs(B), axis=2, keepdims=True), 1e-300)
    return B, L


def _normalize_rows(X):
    n = np.sqrt(X[..., 0]**2 + X[..., 1]**2)
    s = representative_sign(X[..., 0], X[..., 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        return X * (s / n)[..., None]


# --------------------------------------------------------------------------- the manipulator

class PlanarParallel(Mechanism):
    """A planar 3-DOF parallel manipulator: a base and a platform joined by three legs.

    Parameters
    ----------
    legs : sequence of three Leg
        E.g. ``[isp.RPR(...), isp.RPR(...), isp.PPR(...)]``; each leg's actuated joint is one
        input of the manipulator.
    name : str, optional
    tolerances : Tolerances, optional

    Examples
    --------
    >>> import imagespace as isp
    >>> m = isp.PlanarParallel([isp.RPR(base=(0, 0), platform=(0, 0)),
    ...                         isp.RPR(base=(4, 0), platform=(2, 0)),
    ...                         isp.RPR(base=(0, 4), platform=(0, 2))])
    >>> q = m.inverse_kinematics([1.0, 1.0, 0.2])
    >>> modes = m.direct_kinematics(q)
    >>> any(abs(mode.pose - [1.0, 1.0, 0.2]).max() < 1e-9 for mode in modes)
    True
    """

    def __repr__(self):
        return f"PlanarParallel({self.name!r}, legs={list(self.legs)!r})"

    # -- symbols and quadrics ---------------------------------------------------
    # -- singularities ----------------------------------------------------------
    def singularity_surface(self, q=None, working_modes=None):
        """The singularity surface, compiled and labelled; see :func:`imagespace.singularity_surface`.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.examples.general_3rpr().singularity_surface().kind
        'joint-free'
        """
        from .singular.surface import singularity_surface

        return singularity_surface(self, q=q, working_modes=working_modes)

    def singularity_surfaces(self):
        """Every image-space singularity surface, one per working mode; see
        :func:`imagespace.singularity_surfaces`.

        Examples
        --------
        >>> import imagespace as isp
        >>> [S.kind for S in isp.examples.general_3rpr().singularity_surfaces()]
        ['joint-free']
        """
        from .singular.surface import singularity_surfaces

        return singularity_surfaces(self)

    def jacobians(self, pose, q=None, working_modes=None):
        """Seed 003's ``Jx``, ``Jq``, ``J`` and the singularity type; see :func:`imagespace.jacobians`.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.stigger_husty()
        >>> m.jacobians(m.direct_kinematics(m.q_example)[0].pose).kind.tolist()
        ['regular']
        """
        from .singular.surface import jacobians

        return jacobians(self, pose, q=q, working_modes=working_modes)

    # -- inverse kinematics -----------------------------------------------------
    # -- direct kinematics ------------------------------------------------------
    def direct_kinematics(self, q, include_complex=False, certify=False):
        """All real assembly modes for the joint values ``q``.

        Parameters
        ----------
        q : (3,) float or exact numbers
        include_complex : bool
            Also return the complex solutions (back-substituted, not polished; ``is_real`` False).
        certify : bool
            Prove the answer at the exact joint values (floats taken as the binary rationals
            they are, sympy values as given): the real roots of the exact kinematic polynomial
            are isolated and refined (:func:`imagespace.core.certify.certify_real_roots`) and every
            mode is computed from its root (:mod:`imagespace.solve.certified`): one mode per
            simple root, a multiple root once as a singular mode with ``.multiplicity``, two
            modes even where they are closer than double precision can show. See
            :class:`CertifiedModes` for the semantics and their exceptions.

        Returns
        -------
        list of AssemblyMode, or CertifiedModes (a list with ``.certificate``) if ``certify``
            Sorted by ``phi``; empty when no real mode exists.

        Raises
        ------
        DegenerateDesignError
            When the design at these joint values has infinitely many modes (a continuum).

        Warns
        -----
        NearSingularWarning
            Without ``certify``: the floating-point count may be wrong (roots closer than the
            float path can separate, or modes that do not account for the real roots).

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.stigger_husty()
        >>> len(m.direct_kinematics(m.q_example))
        6
        >>> cm = m.direct_kinematics(m.q_example, certify=True)
        >>> cm.certificate.count, sum(cm.modes_per_root)
        (6, 6)
        """
        include_complex = as_flag(include_complex, "include_complex")
        certify = as_flag(certify, "certify")
        qf = self.check_q(q)          # exact sympy numbers pass, free symbols are refused by name
        if qf.ndim != 1:
            raise InputError(f"q must have shape (3,), got {qf.shape}; use direct_kinematics_batch")
        if certify:
            modes = self._certified(q, qf)
        else:
            res = self._solve(qf[None, :], raise_degenerate=True)
            modes = res.modes(0)
            if res.near_singular[0]:
                warnings.warn(
                    f"{self.name} at q = {qf.tolist()}: the floating-point direct kinematics could "
                    f"not separate the roots of the kinematic polynomial (a singular or nearly "
                    f"singular configuration); the {len(modes)} mode(s) returned may not be all. "
                    "Use direct_kinematics(q, certify=True) for the proven answer.",
                    NearSingularWarning, stacklevel=2)
        if include_complex:
            modes += self._complex_modes(qf)
        return modes

    def _fast_exact_forms(self, q_exact):
        """``(P, D, X2, X3)`` exact coefficient lists (sympy numbers) at rational ``q`` from the
        general-q derivation (no sympy elimination per call), or None where that route does not
        apply (symbolic or irrational input, trigonometric features, or a Cramer case at this
        ``q`` that the general formulas do not see: then ``_exact_forms`` decides)."""
        if not all(v.is_Rational for v in q_exact) or any(leg.actuated_is_angle for leg in self.legs):
            return None                 # cos/sin of an actuated angle: not rational, sympy decides
        if "exact_evaluators" not in self._symbolic_cache:
            ev = None
            if not set().union(*(leg.free_symbols for leg in self.legs)):
                from .core.codegen import CoefficientEnclosure

                _, el, case_a = self._exact_forms(None)
                if not case_a:
                    ev = (CoefficientEnclosure(self.kinematic_polynomial(), self.joint_symbols),
                          CoefficientEnclosure(list(el.D) + list(el.X2) + list(el.X3), self.joint_symbols))
            self._symbolic_cache["exact_evaluators"] = ev
        ev = self._symbolic_cache["exact_evaluators"]
        if ev is None:
            return None
        if ev[0].rational and ev[1].rational:
            from fractions import Fraction

            qq = [Fraction(int(v.p), int(v.q)) for v in q_exact]
            P, rest = ev[0].exact(qq), ev[1].exact(qq)
            P = [sp.Rational(v.numerator, v.denominator) for v in P]
            rest = [sp.Rational(v.numerator, v.denominator) for v in rest]
        else:
            P, rest = ev[0].exact_sympy(q_exact), ev[1].exact_sympy(q_exact)
        D, X2, X3 = rest[:3], rest[3:7], rest[7:11]
        if all(v == 0 for v in D) or all(exact_is_zero(v) for v in P):
            return None
        return P, D, X2, X3

    def _certified(self, q, qf):
        """The certified per-call path: modes computed root by root from the exact certificate."""
        items = list(q) if is_symbolic(q) else list(np.ravel(np.asarray(q, dtype=object)))
        q_exact = [as_exact(v, f"q[{i}]") for i, v in enumerate(items)]
        fast = self._fast_exact_forms(q_exact)
        if fast is not None:
            P, D, X2, X3 = fast
            case_a = False
            cert = certify_real_roots(P)
        else:
            Pp, el, case_a = self._exact_forms(q_exact)
            P = form_coefficients(Pp)
            D, X2, X3 = list(el.D), list(el.X2), list(el.X3)
            cert = certify_real_roots(Pp)
        if not cert.certified:
            res = self._solve(qf[None, :], raise_degenerate=True)
            warnings.warn(f"{self.name} at q = {qf.tolist()}: the real roots could not be "
                          f"certified ({cert.method}); the floating-point modes are returned",
                          NearSingularWarning, stacklevel=3)
            return CertifiedModes(res.modes(0), cert, (), ())
        plans = plan_roots(P, D, X2, X3, cert, case_a)
        C, _, L = self._scaled_quadrics(qf[None, :])
        quads = self._row_quadrics(C[0])
        tol = self.tolerances
        per_root = [[] for _ in plans]
        cramer = [p for p in plans if p.kind == "cramer"]
        if cramer:
            X = np.array([p.image_point for p in cramer])
            poses = _pose_of(X)
            resid = np.atleast_1d(self.joint_residual(poses, np.tile(qf, (len(cramer), 1)), length=L[0]))
            Xs = X.copy()
            Xs[:, 2:] /= L[0]
            _, J = _system(np.repeat(C, len(cramer), axis=0), Xs[:, None, :])
            det = np.linalg.det(J[:, 0])
            for j, plan in enumerate(cramer):
                if not resid[j] <= tol.joint_residual:
                    continue                            # e.g. the spurious root of a PP dyad
                aspect = 0 if plan.multiplicity > 1 else int(np.sign(det[j]))
                per_root[plan.index] = [AssemblyMode(X[j], poses[j], float(resid[j]), aspect, True,
                                                     plan.multiplicity)]
        for plan in plans:
            if plan.kind == "cramer":
                continue
            cand = self._solve_orientation(qf, quads, plan.x0, plan.x1, L[0])
            if not cand:
                continue
            arr = np.full((1, max(len(cand), _MAX_MODES), 4), np.nan)
            arr[0, :len(cand)] = cand
            sub = self._finish(qf[None, :], C, arr, np.array([True]), {}, np.array([True]), L)
            found = sub.modes(0)
            if plan.multiplicity > 1:       # a multiple orientation root: its modes are singular
                found = [AssemblyMode(mm.image_point, mm.pose, mm.residual, 0, True, plan.multiplicity)
                         for mm in found]
            per_root[plan.index] = found
        tagged = [(mm, k) for k, lst in enumerate(per_root) for mm in lst]
        tagged.sort(key=lambda item: item[0].pose[2])
        return CertifiedModes([mm for mm, _ in tagged], cert, [len(lst) for lst in per_root],
                              [k for _, k in tagged])

    def direct_kinematics_batch(self, Q, certify=False, method="auto"):
        """Direct kinematics of many joint vectors at once.

        Parameters
        ----------
        Q : (n, 3) float
            One joint vector per row. Rows with NaN or out-of-domain values are masked
            (``row_ok`` False), not raised.
        certify : bool
            Also prove the number of real roots per row (:func:`~imagespace.core.certify.certify_real_roots_batch`
            on the compiled kinematic polynomial, floats taken as exact binary rationals) and
            hold the modes to it; rows that disagree are re-solved per row with the certified
            path. Fills ``certified_roots``, ``certificate_path`` and ``consistent``.
        method : {"auto", "kernel", "numpy"}
            ``"kernel"``: the compiled one-pass kernel of :mod:`imagespace.solve.kernel` (numba; real
            roots only, no eigenvalues); rows it cannot decide in floating point are handed to
            the numpy path (``special``) or, for a root touching the axis, to the certified
            per-row path. ``"numpy"``: the vectorised numpy path (companion eigenvalues,
            Newton, every mode checked by the legs' inverse kinematics). ``"auto"``: the kernel
            for batches of at least 2,000 rows when numba is installed and the design suits it
            (no PP dyad, Cramer denominator not identically zero), else numpy. The first kernel
            call for a design compiles it (a few seconds).

        Returns
        -------
        DKBatchResult
            ``solver`` says per row which path answered.

        Examples
        --------
        >>> import imagespace as isp
        >>> import numpy as np
        >>> m = isp.examples.stigger_husty()
        >>> r = m.direct_kinematics_batch(np.array([m.q_example_float, [np.nan, 1, 1]]))
        >>> r.count.tolist(), r.row_ok.tolist(), r.solver.tolist()
        ([6, 0], [True, False], ['numpy', 'invalid'])
        """
        Q = as_float_array(Q, "Q", last=3, finite=False)
        certify = as_flag(certify, "certify")
        if Q.ndim == 1:
            Q = Q[None, :]
        if not isinstance(method, str) or method not in ("auto", "kernel", "numpy"):
            raise InputError(f"method must be 'auto', 'kernel' or 'numpy', got {method!r}")
        kernel = None
        if method == "kernel" or (method == "auto" and Q.shape[0] >= _KERNEL_MIN_ROWS):
            kernel = self._kernel()
            if kernel is None and method == "kernel":
                raise InputError(
                    f"method='kernel' is not available for {self.name}: "
                    + ("numba is not installed" if not _have_numba() else
                       "the design has a PP dyad or a Cramer denominator vanishing identically")
                    + "; use method='numpy' or 'auto'")
        per_row = (BATCH_PEAK_BYTES_PER_ROW["kernel" if kernel is not None else "numpy"]
                   + (BATCH_PEAK_BYTES_PER_ROW["certify"] if certify else 0))
        check_memory(Q.shape[0] * per_row, f"direct_kinematics_batch of {Q.shape[0]:,} rows",
                     f"use direct_kinematics_chunks(Q, chunk_size=...) to solve it chunk by chunk "
                     f"(a chunk of 65,536 rows needs about {65536 * per_row / 1e9:.2g} GB)")
        res = self._solve_kernel(Q, kernel) if kernel is not None else self._solve(Q, raise_degenerate=False)
        if certify:
            self._certify_batch(Q, res)
        return res

    def direct_kinematics_chunks(self, Q, chunk_size=65536, certify=False, method="auto"):
        """Direct kinematics of a large batch, chunk by chunk (memory bounded by the chunk).

        Parameters
        ----------
        Q : (n, 3) float array (a numpy memmap works)
        chunk_size : int
            Rows per chunk; the result of one chunk of 65,536 rows takes ~26 MB.
        certify, method
            As in :meth:`direct_kinematics_batch`.

        Yields
        ------
        (start, DKBatchResult)
            The rows ``start : start + len(result.count)`` of ``Q``.

        Examples
        --------
        >>> import imagespace as isp
        >>> import numpy as np
        >>> m = isp.examples.general_3rpr()
        >>> Q = np.tile(m.q_example_float, (5, 1))
        >>> [(s, r.count.tolist()) for s, r in m.direct_kinematics_chunks(Q, chunk_size=2)]
        [(0, [6, 6]), (2, [6, 6]), (4, [6])]
        """
        chunk_size = as_count(chunk_size, "chunk_size")
        certify = as_flag(certify, "certify")
        if not isinstance(method, str) or method not in ("auto", "kernel", "numpy"):
            raise InputError(f"method must be 'auto', 'kernel' or 'numpy', got {method!r}")
        if not isinstance(Q, np.ndarray):               # a memmap is validated chunk by chunk
            Q = as_float_array(Q, "Q", last=3, finite=False)
        elif Q.dtype.kind not in "iuf":
            raise TypeError(f"Q must be a real float or integer array, got dtype {Q.dtype}")
        if Q.ndim != 2 or Q.shape[-1] != 3:
            raise InputError(f"Q must have shape (n, 3), got {Q.shape}")
        return self._chunks(Q, chunk_size, certify, method)    # validated now, solved lazily

    def _chunks(self, Q, chunk_size, certify, method):
        for start in range(0, Q.shape[0], chunk_size):
            yield start, self.direct_kinematics_batch(Q[start:start + chunk_size], certify, method)

    def _kernel(self):
        """The compiled batch kernel of this design (built once), or None where it does not apply."""
        if "kernel" not in self._symbolic_cache:
            free = set().union(*(leg.free_symbols for leg in self.legs))
            if free or not _have_numba():
                self._symbolic_cache["kernel"] = None
            else:
                from .solve.kernel import build_kernel          # numba is imported on the first kernel only

                self._symbolic_cache["kernel"] = build_kernel(self)
        return self._symbolic_cache["kernel"]

    def _row_check(self, Q):
        """Rows with finite joint values inside every actuated joint's domain, and messages."""
        errors = {}
        row_ok = np.all(np.isfinite(Q), axis=1)
        for i in np.flatnonzero(~row_ok):
            errors[int(i)] = f"Q[{i}] is not finite: {Q[i].tolist()}"
        for j, leg in enumerate(self.legs):
            bad = row_ok & ~leg.joint_values_ok(np.where(row_ok, Q[:, j], 0.0))
            for i in np.flatnonzero(bad):
                row_ok[i] = False
                errors[int(i)] = (f"Q[{i}, {j}] = {Q[i, j]} is outside the domain of the actuated "
                                  f"joint {leg.actuated_name} of {leg.joints}")
        return row_ok, errors

    def _solve_kernel(self, Q, kernel):
        n = Q.shape[0]
        tol = self.tolerances
        row_ok, errors = self._row_check(Q)
        ok = np.flatnonzero(row_ok)
        if ok.size == n:                       # the usual case: the kernel's arrays are the result
            X, P, R, A8, cnt, flag = kernel(Q)
        else:                                  # masked rows stay NaN / 0
            X = np.full((n, _MAX_MODES, 4), np.nan)
            P = np.full((n, _MAX_MODES, 3), np.nan)
            R = np.full((n, _MAX_MODES), np.nan)
            A8 = np.zeros((n, _MAX_MODES), dtype=np.int8)
            cnt = np.zeros(n, dtype=np.int64)
            flag = np.zeros(n, dtype=np.int8)
            if ok.size:
                X[ok], P[ok], R[ok], A8[ok], cnt[ok], flag[ok] = kernel(Q[ok])
        A = A8.astype(int)
        solver = np.where(row_ok, "kernel", "invalid").astype("<U9")
        special = row_ok & (flag != 0)
        valid = np.arange(_MAX_MODES) < cnt[:, None]
        # cheap indicators of a count the kernel may have got wrong: a real root pair closer
        # than near_singular_gap (in the half-angle), or an odd count (the kinematic polynomial
        # has even degree and real coefficients: an odd number of distinct real roots means a
        # multiple root)
        with np.errstate(invalid="ignore"):
            half = np.where(valid, np.arctan2(X[..., 1], X[..., 0]), np.nan)
            hs = np.sort(np.where(valid, half, np.inf), axis=1)
            gaps = np.diff(hs, axis=1)
            wrap = hs[:, 0] + np.pi - np.max(np.where(np.isfinite(hs), hs, -np.inf), axis=1)
        close = np.any(np.where(np.isfinite(gaps), gaps, np.inf) < tol.near_singular_gap, axis=1)
        close |= (cnt > 1) & (wrap < tol.near_singular_gap)
        near = row_ok & ((cnt % 2 == 1) | close)
        res = DKBatchResult(X, P, valid, cnt, R, A, row_ok, errors, special,
                            near_singular=near, multiplicity=np.ones((n, _MAX_MODES), dtype=np.int8))
        # rows the kernel could not decide in floating point (flag 1: Cramer denominator small
        # at a root, Newton not converging; flag 2: a root touching the axis) take the numpy path,
        # which solves case (b) per row and computes its own near_singular mask
        careful = np.flatnonzero(row_ok & (flag != 0))
        if careful.size:
            sub = self._solve(Q[careful], raise_degenerate=False)
            for name in ("image_points", "poses", "valid", "count", "residual", "aspect", "row_ok",
                         "near_singular"):
                getattr(res, name)[careful] = getattr(sub, name)
            for k, msg in sub.errors.items():   # only DegenerateDesignError messages (q stated)
                errors[int(careful[k])] = msg
            solver[careful] = "numpy"
        solver[~res.row_ok] = "invalid"
        res.solver = solver
        return res

    @staticmethod
    def _store_modes(res, i, modes):
        """Write a list of AssemblyMode into row ``i`` of a DKBatchResult."""
        k = min(len(modes), res.valid.shape[1])
        res.image_points[i], res.poses[i], res.residual[i] = np.nan, np.nan, np.nan
        res.valid[i], res.aspect[i] = False, 0
        if res.multiplicity is not None:
            res.multiplicity[i] = 1
        for j, mm in enumerate(modes[:k]):
            res.image_points[i, j], res.poses[i, j] = mm.image_point, mm.pose
            res.residual[i, j], res.aspect[i, j], res.valid[i, j] = mm.residual, mm.aspect, True
            if res.multiplicity is not None:
                res.multiplicity[i, j] = mm.multiplicity
        res.count[i] = k

    def _certify_batch(self, Q, res):
        """Certified counts per row on the exact input, and modes held to them (see DKBatchResult)."""
        n = Q.shape[0]
        enc = self._enclosure()
        Qs = np.where(res.row_ok[:, None], Q, 0.0)
        F, E = enc.evaluate(Qs)
        F = np.where(res.row_ok[:, None], F, np.nan)

        def exact(i):
            vals = enc.exact(Q[i])
            if vals is not None:
                return [sp.Rational(v.numerator, v.denominator) for v in vals]
            return _general_at(self.kinematic_polynomial(), self.joint_symbols,
                               [as_exact(float(v), "q") for v in Q[i]])

        if n:
            counts, path, ivals = certify_real_roots_batch(F, E, exact, return_intervals=True)
        else:
            counts, path, ivals = np.zeros(0, int), np.zeros(0, str), np.zeros((0, enc.degree, 2))
        consistent = np.zeros(n, dtype=bool)
        # disc-certified rows: every real root simple; each must hold exactly one float mode, and
        # no float mode may lie outside them (t = x1/x0 of the normalised image point)
        disc = np.flatnonzero(res.row_ok & (path == "discs"))
        if disc.size:
            X = res.image_points[disc]
            with np.errstate(divide="ignore", invalid="ignore"):
                t = X[..., 1] / X[..., 0]
            lo, hi = ivals[disc, :, 0], ivals[disc, :, 1]            # (m, d)
            inside = (t[:, :, None] >= lo[:, None, :]) & (t[:, :, None] <= hi[:, None, :])
            inside &= res.valid[disc][:, :, None]
            per_root = inside.sum(axis=1)                              # (m, d)
            per_mode = inside.sum(axis=2)                              # (m, 6)
            real_slot = np.isfinite(lo)
            ok_rows = (np.all(np.where(real_slot, per_root == 1, per_root == 0), axis=1)
                       & np.all(np.where(res.valid[disc], per_mode == 1, True), axis=1)
                       & (res.count[disc] == counts[disc]))
            consistent[disc[ok_rows]] = True
        for i in np.flatnonzero(res.row_ok & ~consistent):
            try:
                modes = self.direct_kinematics(Q[i], certify=True)
            except DegenerateDesignError as e:
                res.row_ok[i] = False
                res.errors[int(i)] = str(e)
                counts[i] = -1
                path[i] = "continuum"
                self._store_modes(res, i, [])
                if res.solver is not None:
                    res.solver[i] = "invalid"
                continue
            self._store_modes(res, i, modes)
            if res.solver is not None:
                res.solver[i] = "certified"
            cert = modes.certificate
            counts[i] = cert.count if cert.certified else -1
            if path[i] != "flint":
                path[i] = "flint" if cert.certified and cert.exact else (
                    "arb" if cert.certified else "uncertified")
            consistent[i] = bool(cert.certified)
            res.near_singular[i] = not cert.certified
        res.near_singular = res.near_singular & ~consistent      # proven rows are not in doubt
        res.certified_roots, res.certificate_path, res.consistent = counts, path, consistent

    # .. internals ..............................................................
    def _solve(self, Q, raise_degenerate):
        n = Q.shape[0]
        tol = self.tolerances
        row_ok, errors = self._row_check(Q)
        Qs = np.where(row_ok[:, None], Q, 0.0)
        C, cq, L = self._scaled_quadrics(Qs)
        el = eliminate(cq, self._plan)
        Darr = np.stack(np.broadcast_arrays(*el.D), axis=1)
        Farr = np.stack(np.broadcast_arrays(*el.F), axis=1)
        X2 = np.stack(np.broadcast_arrays(*el.X2), axis=1)
        X3 = np.stack(np.broadcast_arrays(*el.X3), axis=1)
        dnorm = np.max(np.abs(Darr), axis=1)
        fnorm = np.max(np.abs(Farr), axis=1)
        special = row_ok & ((dnorm <= tol.cramer_identically_zero) | (fnorm <= tol.degenerate))
        Fn = Farr / np.where(fnorm > 0, fnorm, 1.0)[:, None]
        with np.errstate(invalid="ignore", divide="ignore"):
            theta, ok = real_half_angles(Fn, tol.real_root_imag)
        x0, x1 = np.cos(theta), np.sin(theta)
        Dv = bf_eval([c[:, None] for c in Darr.T], x0, x1)
        small_d = np.isfinite(theta) & (np.abs(Dv) <= tol.cramer_small * dnorm[:, None])
        special |= row_ok & np.any(small_d, axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            x2 = bf_eval([c[:, None] for c in X2.T], x0, x1) / Dv
            x3 = bf_eval([c[:, None] for c in X3.T], x0, x1) / Dv
        cand = np.stack([x0, x1, x2, x3], axis=-1)
        cand[~(row_ok & ~special)] = np.nan
        width = max(cand.shape[1], _MAX_MODES)
        if cand.shape[1] < width:
            pad = np.full((n, width - cand.shape[1], 4), np.nan)
            cand = np.concatenate([cand, pad], axis=1)
        # separation of the roots (inclusion discs on the normalised float polynomial, in the
        # chart of its largest leading coefficient): where they overlap the count is not trusted
        separated, n_real = _separated(Fn)
        # careful path for special rows
        extra = {}
        near_special = {}
        for i in np.flatnonzero(special):
            try:
                extra[i], near_special[i] = self._special_candidates(Q[i], C[i], L[i])
            except DegenerateDesignError as e:
                if raise_degenerate:
                    raise
                row_ok[i] = False
                errors[int(i)] = str(e)
        if extra:
            width = max(width, max(len(v) for v in extra.values()))
            if cand.shape[1] < width:
                cand = np.concatenate([cand, np.full((n, width - cand.shape[1], 4), np.nan)], axis=1)
            for i, lst in extra.items():
                cand[i] = np.nan
                for j, x in enumerate(lst):
                    cand[i, j] = x
        res = self._finish(Q, C, cand, row_ok, errors, special, L)
        half = np.arctan2(res.image_points[..., 1], res.image_points[..., 0])
        distinct = _distinct_orientations_batch(half, res.valid, tol.duplicate)
        # the spurious orientation phi_c + pi of a PP dyad is a root that carries no mode
        n_real = n_real - self._spurious_roots(C, theta)
        near = row_ok & ~special & (~separated | (distinct != n_real))
        for i, (flag, clusters) in near_special.items():
            # a cluster of k roots the discs cannot separate must carry k modes (case (b): a
            # double root with two positions); anything else is a count not to be trusted
            hv = half[i][res.valid[i]]
            for theta_c, rad, size in clusters:
                dist = np.abs(np.remainder(hv - theta_c + np.pi / 2, np.pi) - np.pi / 2)
                flag = flag or int(np.sum(dist <= rad + tol.near_singular_gap)) != size
            near[i] = row_ok[i] and (flag or bool(res.near_singular[i]))
            if near[i]:
                # a continuum hides behind a Cramer case seen in floating point: decide exactly
                try:
                    self._certified(Q[i], Q[i])
                except DegenerateDesignError as e:
                    if raise_degenerate:
                        raise
                    row_ok[i] = False
                    errors[int(i)] = str(e)
                    self._store_modes(res, i, [])
                    res.solver[i] = "invalid"
                    near[i] = False
        res.near_singular = near
        return res

    def _spurious_roots(self, C, theta):
        """Per row, how many of the real half-angles ``theta`` (n, k) are the spurious
        orientation ``phi_c + pi`` of a PP dyad (its quadric ``sin(2 theta - phi_c)`` up to scale
        has the roots ``theta = phi_c / 2`` and ``phi_c / 2 + pi / 2``; the first is the one)."""
        n = C.shape[0]
        out = np.zeros(n, dtype=int)
        for j, kind in enumerate(self._kinds):
            if kind != "PP":
                continue
            phi_c = np.arctan2(-C[:, j, 5], C[:, j, 6] / 2)
            spur = phi_c / 2 + np.pi / 2
            d = np.abs(np.remainder(theta - spur[:, None] + np.pi / 2, np.pi) - np.pi / 2)
            out += np.sum(np.isfinite(theta) & (d <= self.tolerances.near_singular_gap), axis=1)
        return out

    def _finish(self, Q, C, cand, row_ok, errors, special, L):
        """Polish candidates (balanced coordinates), check them with the legs, sort; ``L`` (n,)
        is the length scale the candidates' ``x2, x3`` are divided by (see :func:`_balance`)."""
        tol = self.tolerances
        n, k, _ = cand.shape
        X = _newton(C, _normalize_rows(cand), tol)
        X = _normalize_rows(X)
        finite = np.all(np.isfinite(X), axis=-1)
        # duplicates (balanced coordinates): a later candidate close to an earlier valid one
        Xw = X * np.concatenate([np.ones((n, 1, 2)), np.repeat(L[:, None, None], 2, axis=2)], axis=2)
        poses = np.full((n, k, 3), np.nan)
        if np.any(finite):
            poses[finite] = _pose_of(Xw[finite])
        resid = np.full((n, k), np.inf)
        if np.any(finite):
            rows = np.nonzero(finite)[0]
            resid[finite] = self.joint_residual(poses[finite], Q[rows], length=L[rows])
        valid = finite & (resid <= tol.joint_residual)
        for j in range(1, k):
            for i0 in range(j):
                dist = np.minimum(np.max(np.abs(X[:, j] - X[:, i0]), axis=-1),
                                  np.max(np.abs(X[:, j] + X[:, i0]), axis=-1))
                valid[:, j] &= ~(valid[:, i0] & (dist <= tol.duplicate * (1 + np.max(np.abs(X[:, j]), axis=-1))))
        _, J = _system(C, np.where(finite[..., None], X, 0.0))
        detJ = np.linalg.det(J)
        aspect = np.where(finite, np.sign(detJ), 0).astype(int)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.abs(detJ) / np.prod(np.linalg.norm(J, axis=-1), axis=-1)
        X = Xw
        # sort valid first, by phi
        key = np.where(valid, poses[..., 2], np.inf)
        order = np.argsort(key, axis=1, kind="stable")
        take = lambda a: np.take_along_axis(a, order.reshape(order.shape + (1,) * (a.ndim - 2)), axis=1)
        X, poses, valid, resid, aspect = take(X), take(poses), take(valid), take(resid), take(aspect)
        ill = np.any(valid & ~(take(ratio) > tol.near_singular_condition), axis=1)
        count = valid.sum(axis=1)
        if np.any(count > _MAX_MODES):
            raise DegenerateDesignError(f"more than {_MAX_MODES} assembly modes found; the design is degenerate")
        w = _MAX_MODES
        X, poses, valid, resid, aspect = X[:, :w], poses[:, :w], valid[:, :w], resid[:, :w], aspect[:, :w]
        X = np.where(valid[..., None], X, np.nan)
        poses = np.where(valid[..., None], poses, np.nan)
        resid = np.where(valid, resid, np.nan)
        aspect = np.where(valid, aspect, 0)
        solver = np.where(row_ok, "numpy", "invalid").astype("<U9")
        return DKBatchResult(X, poses, valid, count, resid, aspect, row_ok, errors, special,
                             solver=solver, near_singular=ill & row_ok,
                             multiplicity=np.ones((n, w), dtype=np.int8))

    def _scaled_quadrics(self, Q):
        """Balanced float quadrics for joint vectors Q (n, 3): see :func:`_balance`.

        Returns the (n, 3, 8) coefficient array in the balanced coordinates, the matching list of
        three Quadric (rows as arrays) and the length scale ``L`` (n,) of each row.
        """
        quads = [leg.dyad(Q[:, j]) for j, leg in enumerate(self.legs)]
        C, L = _balance(_coef_array(quads, Q.shape[0]))
        return C, [Quadric(self._kinds[j], *(C[:, j, k] for k in range(8))) for j in range(3)], L

    def _row_quadrics(self, c_row):
        """The three scalar quadrics of one row of a (n, 3, 8) coefficient array."""
        return [Quadric(self._kinds[j], *(c_row[j, k] for k in range(8))) for j in range(3)]

    def _special_candidates(self, q, C, L):
        """Candidates (balanced coordinates) for one row whose Cramer denominator vanishes
        (identically or at a root), and whether the orientations could not be separated."""
        tol = self.tolerances
        quads = self._row_quadrics(C)
        el = eliminate(quads, self._plan)
        D = np.array(el.D, dtype=float)
        F = np.array(el.F, dtype=float)
        thetas = []
        clusters = []
        if np.max(np.abs(D)) <= tol.cramer_identically_zero:
            E1, E2 = el.rows[0], el.rows[1]
            M = np.array([[*E1.A, *E1.B], [*E2.A, *E2.B]], dtype=float)
            U, S, _ = np.linalg.svd(M)
            forms = []
            if S[0] <= tol.rank:
                forms = [np.array(E1.K, float), np.array(E2.K, float)]
            else:
                lam = U[:, -1]
                forms = [lam[0] * np.array(E1.K, float) + lam[1] * np.array(E2.K, float)]
            forms = [g for g in forms if np.max(np.abs(g)) > tol.rank]
            if not forms:
                self._confirm_degenerate(q)
            for g in forms:
                gn = (g / np.max(np.abs(g)))[None, :]
                th, ok = real_half_angles(gn, tol.real_root_imag)
                thetas += [t for t in th[0] if np.isfinite(t)]
        else:
            if np.max(np.abs(F)) <= tol.degenerate:
                poly = self._exact_polynomial(q)
                F = np.array([float(c) for c in form_coefficients(poly)], dtype=float)
            Fn = (F / np.max(np.abs(F)))[None, :]
            th, ok = real_half_angles(Fn, tol.real_root_imag)
            thetas = [t for t in th[0] if np.isfinite(t)]
            clusters = _root_clusters(Fn[0])
        out = []
        flags = []
        for t in thetas:
            out += self._solve_orientation(q, quads, np.cos(t), np.sin(t), L, flags)
        return out, (bool(flags), clusters)

    def _exact_polynomial(self, q):
        return self.kinematic_polynomial([sp.Rational(float(v)) for v in q])

    def _confirm_degenerate(self, q):
        self._exact_polynomial(q)  # raises DegenerateDesignError when identically zero
        raise DegenerateDesignError(
            f"{self.name} at q = {np.asarray(q).tolist()}: the constraints leave a continuum of "
            "assembly modes (architecture singularity)")

    def _solve_orientation(self, q, quads, x0, x1, L, flags=None):
        """Positions (x2, x3) for a fixed orientation (x0, x1): candidate image points in the
        balanced coordinates of ``quads`` (length scale ``L``). ``flags`` (a list) receives an
        entry when two positions are about to merge (a near-zero discriminant)."""
        tol = self.tolerances
        rows = []
        for qd in quads:
            c, a0, a1, b0, b1, k0, k1, k2 = (float(v) for v in qd.coefficients())
            rows.append((c, a0 * x0 + a1 * x1, b0 * x0 + b1 * x1, k0 * x0**2 + k1 * x0 * x1 + k2 * x1**2))
        circles = [r for r in rows if r[0] != 0]
        lin = [r[1:] for r in rows if r[0] == 0]
        if circles:
            c0 = circles[0]
            lin += [tuple(r[j] - c0[j] * r[0] / c0[0] for j in (1, 2, 3)) for r in circles[1:]]
        L2 = np.array([[r[0], r[1]] for r in lin]) if lin else np.zeros((0, 2))
        rhs = np.array([-r[2] for r in lin]) if lin else np.zeros(0)
        S = np.linalg.svd(L2, compute_uv=False) if len(lin) else np.zeros(0)
        rank = int(np.sum(S > tol.rank * max(1.0, S[0] if len(S) else 0.0)))
        if rank == 2:
            p = np.linalg.lstsq(L2, rhs, rcond=None)[0]
            out = [np.array([x0, x1, p[0], p[1]])]
            if circles and S[1] <= tol.cramer_small * S[0]:
                # nearly case (b): the two positions of the line-circle treatment are candidates
                # too (Newton and the legs' check keep the true ones, duplicates are dropped)
                out += self._line_circle(L2, rhs, circles[0], x0, x1, tol, flags, strict=False)
            return out
        if rank == 1:
            p0 = np.linalg.lstsq(L2, rhs, rcond=None)[0]
            if np.max(np.abs(L2 @ p0 - rhs), initial=0.0) > 10 * tol.rank * max(1.0, np.max(np.abs(rhs), initial=0.0)):
                return []
            if not circles:
                return self._continuum(q, np.array([x0, x1, p0[0], p0[1]]), L)
            return self._line_circle(L2, rhs, circles[0], x0, x1, tol, flags)
        consistent = all(abs(r) <= tol.rank for r in rhs)
        if not consistent:
            return []
        if circles:
            c, al, be, ka = circles[0]
            centre = np.array([-al, -be]) / (2 * c)
            r2 = centre @ centre - ka / c
            if r2 < 0:
                return []
            return self._continuum(q, np.array([x0, x1, centre[0] + np.sqrt(r2), centre[1]]), L)
        return self._continuum(q, np.array([x0, x1, 0.0, 0.0]), L)

    @staticmethod
    def _line_circle(L2, rhs, circle, x0, x1, tol, flags=None, strict=True):
        """The (up to two) points of the circle row on the line of the rank-1 linear rows."""
        U, S, Vt = np.linalg.svd(L2)
        # the rank-1 least-squares point and the line's direction
        p0 = Vt[0] * ((U[:, 0] @ rhs) / S[0])
        d = Vt[1]
        c, al, be, ka = circle
        A2 = c * (d @ d)
        A1 = 2 * c * (p0 @ d) + al * d[0] + be * d[1]
        A0 = c * (p0 @ p0) + al * p0[0] + be * p0[1] + ka
        disc = A1 * A1 - 4 * A2 * A0
        if strict and flags is not None and abs(disc) <= tol.near_singular_condition * (A1 * A1 + abs(4 * A2 * A0)):
            flags.append("merging positions")   # the count is not to be trusted
        if disc < -tol.rank * max(1.0, A1 * A1):
            return []
        r = np.sqrt(max(disc, 0.0))
        return [np.array([x0, x1, *(p0 + t * d)]) for t in ((-A1 + r) / (2 * A2), (-A1 - r) / (2 * A2))]

    def _continuum(self, q, X, L):
        Xw = np.array([X[0], X[1], X[2] * L, X[3] * L])
        pose = _pose_of(Xw)
        if self.joint_residual(pose, q, length=L) <= self.tolerances.joint_residual:
            raise DegenerateDesignError(
                f"{self.name} at q = {np.asarray(q).tolist()}: a continuum of assembly modes at "
                f"phi = {pose[2]:.6g} (architecture singularity or singular joint values)")
        return []

    def _complex_modes(self, q):
        poly = self.kinematic_polynomial([sp.Rational(float(v)) for v in q])
        coeffs = np.array([complex(c) for c in form_coefficients(poly)])
        d = len(coeffs) - 1
        roots = np.roots(coeffs[::-1]) if d > 0 else []
        out = []
        quads = self.quadrics(np.asarray(q, float))
        el = eliminate(quads, self._plan)
        for t in roots:
            if abs(t.imag) <= self.tolerances.real_root_imag * (1 + abs(t)):
                continue
            x0, x1 = 1.0 + 0j, complex(t)
            Dv = bf_eval([complex(v) for v in el.D], x0, x1)
            if Dv == 0:
                continue
            x2 = bf_eval([complex(v) for v in el.X2], x0, x1) / Dv
            x3 = bf_eval([complex(v) for v in el.X3], x0, x1) / Dv
            out.append(AssemblyMode(np.array([x0, x1, x2, x3]), np.full(3, np.nan), np.nan, 0, False))
        return out

    # -- drawing helpers --------------------------------------------------------
def _have_numba():
    """Whether numba is installed, without importing it (its import alone takes ~0.3 s)."""
    import importlib.util

    return importlib.util.find_spec("numba") is not None






def _rotated_with_bound(Fn):
    """Each form in the chart of its largest leading coefficient
    (:func:`imagespace.core.roots.rotated_forms`), with a generous bound on the rounding of the
    rotation for every rotated coefficient: ``(G, ok, gamma, E)``."""
    from .core.roots import rotated_forms

    G, ok, gamma = rotated_forms(Fn)
    d = G.shape[1] - 1
    E = (4 * d + 8) * 2.0**-53 * np.max(np.abs(G), axis=1, keepdims=True) * np.ones_like(G)
    return G, ok, gamma, E


def _separated(Fn):
    """Inclusion-disc separation of the roots of float binary forms ``Fn`` (n, d+1), in the
    chart where each form's leading coefficient is largest. Returns ``(separated (n,), real
    roots (n,))``: where ``separated`` is False, roots could not be told apart in floating point."""
    n = Fn.shape[0]
    sep = np.zeros(n, dtype=bool)
    nreal = np.zeros(n, dtype=int)
    G, ok, _, E = _rotated_with_bound(Fn)
    d = G.shape[1] - 1
    if d < 1:
        return ok, nreal
    use = ok & (np.abs(G[:, d]) > E[:, d])
    if np.any(use):
        good, real, _, _ = inclusion_discs(G[use], E[use])
        sep[use] = good
        nreal[use] = np.where(good, real.sum(axis=1), 0)
    return sep, nreal


def _root_clusters(Fn):
    """Clusters of roots that inclusion discs cannot separate, for one float binary form ``Fn``
    (d+1,): a list of ``(theta, radius, size)`` (half-angle centre, half-angle radius, number of
    roots) for each group of two or more overlapping discs that meets the real axis."""
    G, ok, gamma, E = _rotated_with_bound(Fn[None, :])
    d = G.shape[1] - 1
    if not ok[0] or d < 2:
        return []
    gamma = float(gamma[0])
    good, real, z, hull_r = inclusion_discs(G, E)
    if good[0]:
        return []
    z = z[0]
    r = hull_r[0] - np.abs(z.imag)                 # the inclusion radius of each disc
    if not np.all(np.isfinite(z)):
        return [(0.0, np.pi, d)]
    parent = list(range(d))

    def find(a):
        while parent[a] != a:
            a = parent[a]
        return a

    for a in range(d):
        for b in range(a + 1, d):
            if abs(z[a] - z[b]) <= r[a] + r[b]:
                parent[find(a)] = find(b)
    out = []
    for root in set(find(a) for a in range(d)):
        members = [a for a in range(d) if find(a) == root]
        if len(members) < 2 or min(abs(z[a].imag) - r[a] for a in members) > 0:
            continue
        c = float(np.mean([z[a].real for a in members]))
        rad = max(abs(z[a].real - c) + r[a] + abs(z[a].imag) for a in members)
        out.append((gamma + float(np.arctan(c)), float(rad), len(members)))
    return out


def _general_at(P, symbols, q_exact):
    """Exact coefficients of the general-q polynomial ``P`` at exact joint values."""
    sub = dict(zip(symbols, q_exact))
    return [sp.expand(c.subs(sub)) for c in form_coefficients(P)]


def _distinct_orientations_batch(half, valid, tol):
    """Per row, the number of distinct orientations among the valid half-angles (n, k) in
    (-pi/2, pi/2] (the ends identified): gaps above ``tol`` separate them (vectorised)."""
    with np.errstate(invalid="ignore"):
        h = np.sort(np.where(valid, half, np.inf), axis=1)
        cnt = valid.sum(axis=1)
        first = h[:, 0]
        nxt = np.concatenate([h[:, 1:], np.full((h.shape[0], 1), np.inf)], axis=1)
        idx = np.arange(h.shape[1])
        # the gap after the last valid angle wraps around to the first one + pi
        nxt = np.where(idx[None, :] == (cnt - 1)[:, None], first[:, None] + np.pi, nxt)
        gaps = np.where(idx[None, :] < cnt[:, None], nxt - h, -np.inf)
    return np.where(cnt > 0, np.maximum(1, np.sum(gaps > tol, axis=1)), 0)

