"""PlanarMechanism: three legs and everything derived from them once.

The planar half of the :class:`~imagespace.core.mechanism.Mechanism` contract, and the core of
:class:`~imagespace.PlanarParallel` (which binds the direct-kinematics back ends on top): the legs
and their dyad quadrics, the joint symbols, the constraint equations, the kinematic polynomial
and its elimination forms, the singularity polynomial, the legs' inverse kinematics, and every
derived or compiled artefact, cached on the object (:meth:`~imagespace.core.mechanism.Mechanism.cached`,
:meth:`~imagespace.core.mechanism.Mechanism.clear_cache`). Imports nothing above :mod:`imagespace.core`.
"""

from __future__ import annotations

import itertools
import warnings
from typing import Any, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt
import sympy as sp

from .._validate import as_exact, as_flag, as_float_array, as_sympy, finite_rows, is_symbolic, warn_angle_units
from ..exceptions import DegenerateDesignError, InputError, InputTypeError, RepeatedLegWarning
from ..tolerances import TOLERANCES, Tolerances
from .certify import reduced_angle
from .elimination import binary_form_poly, eliminate, form_coefficients, orientation_form, plan_elimination
from .legs import Leg
from .mechanism import Mechanism
from .quadrics import Quadric, image_symbols

__all__ = ["PlanarMechanism", "form_coefficients"]


#: Joint values of one configuration: three numbers or sympy expressions (exact faces), or floats.
JointValues = Union[Sequence[Union[sp.Basic, float, int]], npt.NDArray[Any]]
FloatArray = npt.NDArray[np.float64]


def _three_joint_values(q, name="q"):
    """The three entries of one joint vector ``q`` (numbers or sympy expressions), refusing
    other shapes, strings and None by name."""
    if isinstance(q, (str, bytes)) or q is None or isinstance(q, sp.MatrixBase) and min(q.shape) > 1:
        raise InputTypeError(f"{name} must be three joint values, got {type(q).__name__} {q!r:.80}")
    try:
        items = list(q)
    except TypeError:
        raise InputTypeError(f"{name} must be three joint values, got {type(q).__name__} {q!r:.80}") from None
    if len(items) != 3 or any(np.ndim(v) != 0 or isinstance(v, (list, tuple)) for v in items):
        raise InputError(f"{name} must have shape (3,), got {np.shape(np.asarray(q, dtype=object))}")
    return items


def _cache_key(q):
    """Key of the symbolic caches for joint values ``q`` (None: general in the joint symbols).

    Exact: every entry becomes the exact sympy number it denotes (a float its binary rational,
    an int or Fraction itself), so ``2**53 + 1`` and ``2**53``, or ``Fraction(1, 3)`` and
    ``1/3``, are different keys.
    """
    if q is None:
        return None
    items = _three_joint_values(q)
    return tuple(as_sympy(v) if isinstance(v, sp.Basic) else as_exact(v, f"q[{i}]")
                 for i, v in enumerate(items))


def _other_generators(eqs, x):
    """The atoms of ``eqs`` besides ``x`` that polynomial arithmetic treats as generators: symbols,
    functions (``cos(q1)``) and irrational powers (``sqrt(181)``), in a fixed order."""
    found = set()
    for e in eqs:
        found |= e.free_symbols - set(x)
        found |= e.atoms(sp.Function)
        found |= {a for a in e.atoms(sp.Pow) if not a.exp.is_Integer}
        found |= e.atoms(sp.NumberSymbol)
    return sorted(found, key=sp.default_sort_key)


def _jacobian_determinant(eqs, x):
    """``expand(det(d eqs / d x))`` for four equations in the four image coordinates.

    The entries become sparse polynomials over ZZ or QQ in common generators (the image coordinates, the
    joint symbols, and every other atom - ``sqrt(181)``, ``cos(q1)`` - as a generator of its own),
    and the determinant is a Laplace expansion along the first two rows in polynomial arithmetic;
    turning the result back into an expression (where ``sqrt(181)**2`` becomes ``181``) and
    expanding gives the same expression as expanding sympy's Berkowitz determinant of the symbolic
    matrix, 5-40 times faster. Entries with floats or other coefficients (domain RR, EX ...) take
    the Berkowitz route itself.
    """
    from sympy.polys.rings import sring

    try:
        ring, polys = sring(list(eqs), *x, *_other_generators(eqs, x))
    except sp.polys.polyerrors.PolynomialError:
        ring = None
    if ring is None or not (ring.domain.is_ZZ or ring.domain.is_QQ):
        J = sp.Matrix(eqs).jacobian(sp.Matrix(x))
        return sp.expand(J.det(method="berkowitz"))
    gens = ring.gens[:4]
    P = [[p.diff(v) for v in gens] for p in polys]
    total = None
    for c0, c1 in itertools.combinations(range(4), 2):
        r0, r1 = (k for k in range(4) if k not in (c0, c1))
        term = (P[0][c0] * P[1][c1] - P[0][c1] * P[1][c0]) * (P[2][r0] * P[3][r1] - P[2][r1] * P[3][r0])
        if (c0 + c1 + 1) % 2:                  # the sign (-1)**(rows 0+1 + columns c0+c1), 0-based
            term = -term
        total = term if total is None else total + term
    return total.as_expr()


#: (joints, actuated) of the legs whose locked dyad keeps a platform point on a circle about a
#: fixed centre whatever the joint value (the radius moves): two such equal legs never assemble
#: with different values
_CONCENTRIC = {("RPR", 1), ("RRR", 1)}


class PlanarMechanism(Mechanism):
    """Three legs, their quadrics and every derivation from them, each made once and cached.

    The planar image space's side of the :class:`~imagespace.core.mechanism.Mechanism` contract.
    It offers no direct-kinematics back ends of its own (they live above the core, in
    :mod:`imagespace.solve`): :class:`~imagespace.PlanarParallel` binds them.

    Parameters
    ----------
    legs : sequence of three Leg
    name : str, optional
    tolerances : Tolerances, optional

    Raises
    ------
    TypeError
        ``legs`` is not a sequence of Leg objects, ``name`` is not a string, or ``tolerances`` is
        not a Tolerances.
    InputError
        ``legs`` does not hold three legs.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.core.planar import PlanarMechanism
    >>> m = PlanarMechanism(isp.examples.general_3rpr().legs)
    >>> m.kinematic_polynomial().total_degree(), m.kinds
    (6, ('RR', 'RR', 'RR'))
    """

    def __init__(self, legs: Sequence[Leg], name: Optional[str] = None, tolerances: Tolerances = TOLERANCES) -> None:
        if isinstance(legs, (str, bytes)) or legs is None or not (isinstance(legs, Leg) or hasattr(legs, "__iter__")):
            raise InputTypeError(f"legs must be a sequence of three Leg objects (RPR, RRR, PRR, RRP, RPP, "
                                 f"PRP, PPR), got {type(legs).__name__} {legs!r}")
        if not isinstance(tolerances, Tolerances):
            raise InputTypeError(f"tolerances must be an imagespace.Tolerances, got {type(tolerances).__name__} "
                                 f"{tolerances!r}")
        if name is not None and not isinstance(name, str):
            raise InputTypeError(f"name must be a string, got {type(name).__name__} {name!r}")
        legs = list(legs) if not isinstance(legs, Leg) else [legs]
        if len(legs) != 3:
            raise InputError(f"legs must be a sequence of three legs, got {len(legs)}")
        for i, leg in enumerate(legs):
            if not isinstance(leg, Leg):
                raise InputTypeError(f"legs[{i}] must be a Leg (RPR, RRR, PRR, RRP, RPP, PRP, PPR), "
                                     f"got {type(leg).__name__}")
        self.legs = tuple(legs)
        self.name = name or "-".join(leg.joints for leg in legs)
        self.tolerances = tolerances
        self.q_example: Optional[Sequence[Any]] = None
        self._kinds = tuple(leg.dyad(sp.Symbol("_q")).kind for leg in self.legs)
        self._plan = plan_elimination(list(self._kinds))
        self._init_cache()
        self._check_design()

    def _check_design(self):
        """Reject designs that are degenerate for every joint value (coincident anchors, a leg
        given twice)."""
        geometry = [leg.geometry() for leg in self.legs]
        anchors = []
        for i, (leg, g) in enumerate(zip(self.legs, geometry)):
            # legs whose locked dyad keeps one platform point on a circle
            if (leg.joints, leg.actuated) in {("RPR", 1), ("RRR", 0), ("RRR", 1), ("PRR", 0)}:
                anchors.append((i, g["base"], g["platform"]))
        for a in range(len(anchors)):
            for b in range(a + 1, len(anchors)):
                i, A1, a1 = anchors[a]
                j, A2, a2 = anchors[b]
                if A1 == A2 and a1 == a2 and self.legs[i].joints == self.legs[j].joints == "RPR":
                    raise DegenerateDesignError(
                        f"legs[{i}] and legs[{j}] have the same base anchor {A1} and platform anchor "
                        f"{a1}: they impose the same constraint, the design has a continuum of modes")
        if len(anchors) == 3 and anchors[0][2] == anchors[1][2] == anchors[2][2]:
            raise DegenerateDesignError(
                f"all three legs hold the same platform anchor {anchors[0][2]}: the platform can "
                "rotate freely about it (architecture singularity)")
        same = [(i, j) for i in range(3) for j in range(i + 1, 3)
                if (self.legs[i].joints, self.legs[i].actuated) == (self.legs[j].joints, self.legs[j].actuated)
                and geometry[i] == geometry[j]]
        for i, j in same:
            leg = self.legs[i]
            if (leg.joints, leg.actuated) in _CONCENTRIC:
                raise DegenerateDesignError(
                    f"legs[{i}] and legs[{j}] are the same {leg.joints} leg (same joints, actuated joint "
                    f"and geometry): they hold one platform point on concentric circles, so equal joint "
                    f"values give a continuum of modes and different ones no assembly")
            warnings.warn(f"legs[{i}] and legs[{j}] are the same {leg.joints} leg (same joints, actuated "
                          f"joint and geometry): wherever q[{i}] == q[{j}] they impose one constraint and the "
                          f"modes form a continuum", RepeatedLegWarning, stacklevel=3)

    @property
    def joint_symbols(self) -> tuple[sp.Symbol, ...]:
        """The sympy symbols ``(q1, q2, q3)`` of the actuated joints (real).

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.examples.stigger_husty().joint_symbols
        (q1, q2, q3)
        """
        return sp.symbols("q1:4", real=True)

    #: three actuated joints, one per leg
    joint_count = 3
    image_space = "planar"

    @property
    def backends(self) -> Any:
        """None: the derivations have no direct-kinematics back ends of their own
        (:class:`~imagespace.PlanarParallel` binds those of :mod:`imagespace.solve.planar`)."""
        return None

    def joint_rows(self, Q: FloatArray, warn: bool = True) -> tuple[npt.NDArray[np.bool_], dict]:
        """Which rows of a float array ``Q`` (n, 3) hold finite joint values inside every actuated
        joint's domain: ``(ok, errors)``, ``errors`` mapping a refused row to its message (a batch
        never raises on one bad row). With ``warn``, an actuated angle outside ``[-2 pi, 2 pi]``
        (degrees passed as radians?) gives an :class:`~imagespace.exceptions.AngleUnitWarning`.

        Examples
        --------
        >>> import numpy as np, imagespace as isp
        >>> ok, errors = isp.examples.general_3rpr().joint_rows(np.array([[11, 5, 10], [-1, 5, 10.0]]))
        >>> ok.tolist(), errors[1][:8]
        ([True, False], 'Q[1, 0] ')
        """
        Q = np.atleast_2d(as_float_array(Q, "Q", last=3, finite=False))
        warn = as_flag(warn, "warn")
        errors = {}
        row_ok = finite_rows(Q)
        for i in np.flatnonzero(~row_ok):
            errors[int(i)] = f"Q[{i}] is not finite: {Q[i].tolist()}"
        for j, leg in enumerate(self.legs):
            bad = row_ok & ~leg.joint_values_ok(np.where(row_ok, Q[:, j], 0.0))
            for i in np.flatnonzero(bad):
                row_ok[i] = False
                errors[int(i)] = (f"Q[{i}, {j}] = {Q[i, j]} is outside the domain of the actuated "
                                  f"joint {leg.actuated_name} of {leg.joints}")
        if warn:
            warn_angle_units(np.where(row_ok[:, None], Q, 0.0), [leg.actuated_is_angle for leg in self.legs], "Q")
        return row_ok, errors

    def check_q(self, q: npt.ArrayLike, name: str = "q") -> FloatArray:
        """Joint values ``q`` ``(3,)`` or ``(n, 3)`` as a checked float array: real, finite, inside
        every actuated joint's domain; the error names ``name``.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.examples.general_3rpr().check_q([11, 5, 10]).tolist()
        [11.0, 5.0, 10.0]
        """
        arr = as_float_array(q, name, last=3)
        if arr.ndim == 1 and is_symbolic(q):
            # an exact actuated angle beyond a half-turn (20000000000*pi) and its float are
            # different angles: the float stages get the float of its exact remainder mod 2 pi
            for i, (leg, v) in enumerate(zip(self.legs, np.asarray(q, dtype=object))):
                if (leg.actuated_is_angle and isinstance(v, sp.Basic) and not v.is_Rational
                        and abs(arr[i]) > np.pi):
                    arr[i] = reduced_angle(v)
        for i, leg in enumerate(self.legs):
            leg.check_joint_value(arr[..., i], f"{name}[{i}]")
        warn_angle_units(arr, [leg.actuated_is_angle for leg in self.legs], name)
        return arr

    def quadrics(self, q: Optional[JointValues] = None) -> list[Quadric]:
        """The three dyad quadrics at the joint values ``q``.

        Parameters
        ----------
        q : None, (3,) sympy/exact numbers, (3,) float or (n, 3) float
            ``None``: general in :attr:`joint_symbols`; exact/sympy: exact coefficients;
            floats: float coefficients (arrays for a batch).

        Returns
        -------
        list of three Quadric

        Raises
        ------
        InputError
            ``q`` does not have three entries (or is not a valid joint vector).

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.stigger_husty()
        >>> [qd.kind for qd in m.quadrics()]
        ['RR', 'RR', 'PR']
        """
        if q is None:
            q = self.joint_symbols
        if is_symbolic(q) or all(isinstance(v, (int, np.integer)) for v in np.ravel(np.array(q, dtype=object))):
            items = list(q)
            if len(items) != 3:
                raise InputError(f"q must have shape (3,), got {len(items)} entries")
            return [leg.dyad(as_exact(v, f"q[{i}]")) for i, (leg, v) in enumerate(zip(self.legs, items))]
        arr = self.check_q(q)
        return [leg.dyad(arr[..., i]) for i, leg in enumerate(self.legs)]

    def constraint_equations(self, q: Optional[JointValues] = None) -> list[sp.Expr]:
        """The three constraint quadrics as sympy expressions in ``x0..x3``.

        Parameters
        ----------
        q : None or (3,) numbers / sympy expressions
            ``None`` keeps the joint values as the symbols :attr:`joint_symbols`. Floats are
            taken as exact binary rationals.

        Returns
        -------
        list of three sympy expressions

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.stigger_husty()
        >>> m.constraint_equations(m.q_example)[0]
        -100*x0**2 - 100*x1**2 + 4*x2**2 + 4*x3**2
        """
        if q is not None and not is_symbolic(q):
            items = _three_joint_values(q)
            as_float_array([float(v) for v in items], "q", last=3)
            q = [as_exact(v, f"q[{i}]") for i, v in enumerate(items)]
        return [qd.expr() for qd in self.quadrics(q)]

    def kinematic_polynomial(self, q: Optional[JointValues] = None) -> sp.Poly:
        """The binary form in ``(x0, x1)`` whose real roots are the orientations of the assembly modes.

        Eliminates ``x2, x3`` as in :mod:`imagespace.core.elimination`: a form of degree <= 6 (degree
        4 before the removal of a factor ``x0**2 + x1**2`` when no leg has an RR dyad). Factors
        ``x0**2 + x1**2`` (no real roots) are divided out exactly. In case (a) of the elimination
        (the Cramer denominator vanishes identically, e.g. seed 003's collinear 3-RPR) the result
        is the binary quadratic that fixes the orientations, each carrying up to two modes.
        With a PP dyad the form also has the root ``phi_c + pi`` of the pair of planes, which
        :meth:`direct_kinematics` discards.

        Parameters
        ----------
        q : None or (3,) numbers / sympy expressions
            ``None``: general in :attr:`joint_symbols` (and in the design's symbols, if any).

        Returns
        -------
        sympy.Poly
            In the generators ``(x0, x1)``.

        Raises
        ------
        DegenerateDesignError
            If the polynomial vanishes identically (infinitely many assembly modes).

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.stigger_husty()
        >>> m.kinematic_polynomial(m.q_example).total_degree()
        6
        """
        return self.exact_forms(q)[0]

    def exact_forms(self, q: Optional[JointValues]) -> tuple[sp.Poly, Any, bool]:
        """``(P, elimination, case_a)`` for exact/symbolic ``q`` (None: general), cached by the
        exact value of ``q``: the kinematic polynomial, the sympy elimination it came from, and
        whether the Cramer denominator vanishes identically.

        Raises
        ------
        DegenerateDesignError
            the kinematic polynomial vanishes identically (an architecture singularity:
            infinitely many assembly modes).

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> P, el, case_a = m.exact_forms(m.q_example)
        >>> P.total_degree(), case_a
        (6, False)
        """
        key = _cache_key(q)
        if key in self._symbolic_cache:
            return self._symbolic_cache[key]
        eqs = self.quadrics(None if q is None else [as_exact(v, f"q[{i}]") for i, v in enumerate(q)]
                            if not is_symbolic(q) else q)
        x0, x1 = image_symbols()[:2]
        el = eliminate(eqs, self._plan)
        D = [sp.expand(v) for v in el.D]
        case_a = all(v == 0 for v in D)
        if case_a:
            form = orientation_form(el.rows)
        else:
            form = [sp.expand(v) for v in el.F]
            if all(v == 0 for v in form):
                raise DegenerateDesignError(
                    f"the kinematic polynomial of {self.name} vanishes identically"
                    + (" at q = " + str(list(q)) if q is not None else "")
                    + ": infinitely many assembly modes (architecture singularity)")
        expr = binary_form_poly(form).as_expr()
        N = x0**2 + x1**2
        while True:
            quo, rem = sp.div(expr, N, x0, x1)
            if sp.expand(rem) != 0 or sp.expand(quo) == 0:
                break
            expr = sp.expand(quo)
        poly = sp.Poly(expr, x0, x1)
        out = (poly, el, case_a)
        self._symbolic_cache[key] = out
        return out

    def compiled(self) -> Any:
        """The kinematic polynomial general in the joint values, derived once and compiled (cached).

        Returns
        -------
        CompiledPolynomial
            ``.coefficients(Q)`` evaluates the coefficients for a batch ``(n, 3)`` of joint
            vectors in one vectorised call.

        Raises
        ------
        InputError
            If the design has free symbols (substitute numbers first).

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.stigger_husty()
        >>> m.compiled().degree
        6
        """
        if "compiled" not in self._symbolic_cache:
            free = self.design_symbols
            if free:
                raise InputError(f"compiled() needs a numeric design; the design has the symbols "
                                 f"{sorted(map(str, free))}")
            from .codegen import CompiledPolynomial, compile_exprs

            P = self.kinematic_polynomial()
            d = P.total_degree()
            coeffs = form_coefficients(P)
            fn = compile_exprs(coeffs, self.joint_symbols)
            self._symbolic_cache["compiled"] = CompiledPolynomial(P, d, self.joint_symbols, fn)
        return self._symbolic_cache["compiled"]

    def singularity_polynomial(self, q: Optional[JointValues] = None) -> sp.Poly:
        """``det`` of the Jacobian of ``[Q1, Q2, Q3, x0**2 + x1**2 - 1]`` with respect to ``x0..x3``.

        A homogeneous quartic in the image coordinates; its zero set is the direct-kinematic
        singularity surface, and its sign at a normalised mode is :attr:`AssemblyMode.aspect`.
        Where every actuated joint only changes a radius or an offset (RPR, PPR and the like) the
        joint values drop out: they multiply ``x0**2 + x1**2`` in the quadric, whose gradient is
        a multiple of the normalisation row. Where an actuated joint moves a circle's centre or a
        line (an actuated RRR base revolute ...) the joint symbols stay in the result.

        Parameters
        ----------
        q : None or (3,) numbers / sympy expressions
            ``None``: general in :attr:`joint_symbols`.

        Returns
        -------
        sympy.Poly
            In ``(x0, x1, x2, x3)``; :attr:`joint_symbols` among its free symbols only where the
            surface depends on the joint values.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> S = m.singularity_polynomial()
        >>> S.total_degree(), S.free_symbols & set(m.joint_symbols)
        (4, set())
        """
        key = ("singularity", _cache_key(q))
        if key not in self._symbolic_cache:
            x = image_symbols()
            eqs = self.constraint_equations(q) + [x[0]**2 + x[1]**2 - 1]
            det = _jacobian_determinant(eqs, x)
            for s in self.joint_symbols:        # canonical in sin/cos of an actuated angle
                if det.has(sp.sin(s)):
                    det = sp.expand(det.subs(sp.sin(s)**2, 1 - sp.cos(s)**2))
            self._symbolic_cache[key] = sp.Poly(det, *x)
        return self._symbolic_cache[key]

    def inverse_kinematics(self, pose: npt.ArrayLike, working_modes: Optional[Sequence[int]] = None) -> FloatArray:
        """Actuated joint values at a pose.

        Parameters
        ----------
        pose : (3,) or (n, 3) float
            ``(x, y, phi)``.
        working_modes : sequence of three ints, optional
            The branch of each leg's inverse kinematics (see :mod:`imagespace.core.legs`); default 0.

        Returns
        -------
        (3,) or (n, 3) float
            For a batch, NaN where a leg cannot reach the pose.

        Raises
        ------
        InputError
            For a single pose that a leg cannot reach.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.stigger_husty()
        >>> m.inverse_kinematics([-7.7528, 6.3162, -1.6549]).round(2)
        array([10.  , 15.23, 13.25])
        """
        p = as_float_array(pose, "pose", last=3)
        wm = (0, 0, 0) if working_modes is None else self.check_working_modes(working_modes)
        cols = [leg.actuated_values(p, self.tolerances)[..., b] for leg, b in zip(self.legs, wm)]
        q = np.stack(cols, axis=-1)
        if p.ndim == 1 and np.any(np.isnan(q)):
            bad = [i for i in range(3) if np.isnan(q[i])]
            raise InputError(f"pose {p.tolist()} is out of reach of leg(s) {bad} "
                             f"(working_modes={wm})")
        return q

    def check_working_modes(self, working_modes: Sequence[int], name: str = "working_modes") -> tuple[int, int, int]:
        """Three branch indices, one per leg's inverse kinematics, checked by kind and range; the
        error names ``name``.

        Raises
        ------
        TypeError
            ``working_modes`` is not a sequence, or an entry is not a whole number.
        InputError
            it does not have three entries, or an entry is not a branch index of its leg.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.examples.general_3rpr().check_working_modes([1, 0, 1])
        (1, 0, 1)
        """
        if isinstance(working_modes, (str, bytes)) or not hasattr(working_modes, "__iter__"):
            raise InputTypeError(f"{name} must be a sequence of three whole numbers (branch indices), got "
                                 f"{type(working_modes).__name__} {working_modes!r:.80}")
        wm = tuple(working_modes)
        if len(wm) != 3:
            raise InputError(f"{name} must have three entries, got {working_modes!r:.80}")
        for i, (leg, b) in enumerate(zip(self.legs, wm)):
            if isinstance(b, (bool, np.bool_)) or not isinstance(b, (int, np.integer)):
                raise InputTypeError(f"{name}[{i}] must be a whole number (a branch index), got "
                                     f"{type(b).__name__} {b!r:.80}")
            if not 0 <= b < leg.n_branches:
                raise InputError(f"{name}[{i}] must be in 0..{leg.n_branches - 1} for {leg.joints}, got {b}")
        return (int(wm[0]), int(wm[1]), int(wm[2]))

    def joint_residual(self, pose: npt.ArrayLike, q: npt.ArrayLike, length: npt.ArrayLike = 1.0) -> Union[float, FloatArray]:
        """Largest deviation of the legs' inverse kinematics (best branch) from ``q``.

        Angles are compared modulo ``2 pi`` (radians); prismatic joints relatively,
        ``|dq| / max(|q|, length)``.

        Parameters
        ----------
        pose : (3,) or (n, 3) float
        q : (3,) or (n, 3) float
        length : float or (n,) float
            The length scale below which prismatic deviations count absolutely (default 1; the
            direct kinematics passes the design's length scale, so its checks do not depend on
            units).

        Returns
        -------
        float or (n,) float

        Raises
        ------
        InputError
            ``pose``, ``q`` or ``length`` has the wrong shape, or ``length`` is not
            positive.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.stigger_husty()
        >>> bool(m.joint_residual([1.8441, -9.8285, -1.3391], m.q_example_float) < 1e-3)
        True
        """
        p = as_float_array(pose, "pose", last=3)
        qa = as_float_array(q, "q", last=3)
        length = as_float_array(length, "length")
        if np.any(length <= 0):
            raise InputError(f"length must be positive (a length scale), got {length.tolist()}")
        if length.ndim > 1 or (length.ndim == 1 and (p.ndim < 2 and qa.ndim < 2
                                                      or length.shape[0] != max(len(p) if p.ndim == 2 else 1,
                                                                                len(qa) if qa.ndim == 2 else 1))):
            raise InputError(f"length must be a number or one per row (n,), got shape {length.shape}")
        if length.ndim:
            length = length[..., None]
        errs = []
        for i, leg in enumerate(self.legs):
            vals = leg.actuated_values(p, self.tolerances)  # (..., nb)
            qi = qa[..., i][..., None]
            d = leg.joint_distance(vals, qi)
            if not leg.actuated_is_angle:
                d = d / np.maximum(length, np.abs(qi))
            errs.append(np.nanmin(np.where(np.isnan(d), np.inf, d), axis=-1))
        return np.max(np.stack(errs, axis=-1), axis=-1)

    @property
    def q_example_float(self) -> Optional[FloatArray]:
        """``q_example`` as floats (``None`` if the mechanism has no example joint values)."""
        return None if self.q_example is None else np.array([float(v) for v in self.q_example])

    def enclosure(self) -> Any:
        """The kinematic polynomial general in q, expanded for rigorous batch evaluation (cached):
        a :class:`~imagespace.core.codegen.CoefficientEnclosure`.

        Raises
        ------
        InputError
            the design holds symbols (certified batches need a numeric design).

        Examples
        --------
        >>> import imagespace as isp
        >>> type(isp.examples.general_3rpr().enclosure()).__name__
        'CoefficientEnclosure'
        """
        if "enclosure" not in self._symbolic_cache:
            from .codegen import CoefficientEnclosure

            free = self.design_symbols
            if free:
                raise InputError(f"certified batches need a numeric design; the design has the "
                                 f"symbols {sorted(map(str, free))}")
            self._symbolic_cache["enclosure"] = CoefficientEnclosure(self.kinematic_polynomial(),
                                                                     self.joint_symbols)
        return self._symbolic_cache["enclosure"]

    def leg_points(self, pose: npt.ArrayLike, q: Optional[npt.ArrayLike] = None) -> list[FloatArray]:
        """Each leg as a polyline ``(k, 2)`` in the base frame at ``pose`` (for drawings).

        When ``q`` is given, the branch of each leg whose actuated value matches it is drawn.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.stigger_husty()
        >>> [p.shape for p in m.leg_points([1.8441, -9.8285, -1.3391])]
        [(2, 2), (2, 2), (3, 2)]
        """
        p = as_float_array(pose, "pose", last=3, allow_batch=False)
        qv = None
        if q is not None:
            qv = as_float_array(q, "q", last=3, allow_batch=False)
        out = []
        for i, leg in enumerate(self.legs):
            branch = 0
            if qv is not None:
                branch = max(int(leg.nearest_branch(p, qv[i], self.tolerances)), 0)
            out.append(leg.joint_points(p, branch, self.tolerances))
        return out


    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r}, legs={list(self.legs)!r})"

    @property
    def kinds(self) -> tuple[str, ...]:
        """The dyad kind of each leg with its actuated joint locked (``"RR"``, ``"PR"``, ``"RP"``, ``"PP"``)."""
        return self._kinds

    @property
    def elimination_plan(self) -> Any:
        """How ``x2, x3`` are eliminated for these dyad kinds (:func:`imagespace.core.elimination.plan_elimination`)."""
        return self._plan

    @property
    def design_symbols(self) -> set:
        """The free sympy symbols of the design (its geometry), not the joint symbols.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.examples.general_3rpr().design_symbols
        set()
        """
        return set().union(*(leg.free_symbols for leg in self.legs))

    @property
    def is_numeric(self) -> bool:
        """True when the design has no free symbols (only the joint values are variables)."""
        return not self.design_symbols
