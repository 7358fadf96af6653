"""The open-tree formalism of seed 000 for planar parallel mechanisms, derived symbolically.

Open the loops at passive joints: coordinates ``eta`` (``m`` of them), loop constraints
``phi(eta) = 0`` (``m - n``), task ``f(eta) = x`` (``n``). With ``Gamma = [Gamma_K; Gamma_G]``
(``d phi / d eta`` over ``d f / d eta``) velocities follow from ``Gamma etadot = [0; xdot]`` and
higher derivatives from its time derivatives. The equations of motion of the open tree come from
its Lagrangian (bodies with masses, centres and inertias; gravity), derived with sympy and
compiled: ``M(eta) etaddot = R(eta, etadot) + Gamma_K^T lambda + Z^T T`` with ``R`` the negated
Coriolis/centrifugal and gravity terms, i.e. ``A^T mu = M etaddot - R``, ``A^T = [Gamma_K^T Z^T]``,
``mu = [lambda; T]`` (seed 000 eq. 5; its printed ``R`` has the opposite sign, see the errata in docs/references.md).
"""

from __future__ import annotations

import copy
import numbers
from dataclasses import dataclass

import numpy as np
import sympy as sp

from .._validate import _short, as_count, as_sympy
from ..core.codegen import compile_exprs
from ..exceptions import InputError, InputTypeError
from . import checks

__all__ = ["Body", "OpenTreeModel"]


@dataclass(frozen=True)
class Body:
    """A rigid body of the open tree.

    Attributes
    ----------
    mass : number
    inertia : number
        About the centre of mass.
    centre : (x, y) sympy expressions in the coordinates
    angle : sympy expression
        The body's orientation (only its derivative enters the kinetic energy).
    name : str

    Raises
    ------
    TypeError
        For a string (never parsed) or a non-numeric, non-sympy mass, inertia, angle or centre,
        a centre that is not two entries, or a non-string name.
    InputError
        For a non-finite or non-positive mass, or a non-finite or negative inertia.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.dynamics.model import Body
    >>> t = sp.Symbol("t")
    >>> Body(1.0, 0.1, (sp.cos(t), sp.sin(t)), t, "link").name
    'link'
    """

    mass: object
    inertia: object
    centre: tuple
    angle: object
    name: str = ""

    def __post_init__(self):
        checks.not_text(self.mass, "mass")
        checks.not_text(self.inertia, "inertia")
        for name, v, strict in (("mass", self.mass, True), ("inertia", self.inertia, False)):
            if isinstance(v, (numbers.Real, sp.Number)) and not np.isfinite(float(v)):
                raise InputError(f"{name} must be finite, got {v!r}")
            if isinstance(v, (numbers.Real, sp.Number)) and not (v > 0 if strict else v >= 0):
                raise InputError(f"{name} must be {'positive' if strict else 'non-negative'}, got {v!r}")
        checks.not_text(self.angle, "angle")
        if isinstance(self.centre, (str, bytes)) or not hasattr(self.centre, "__iter__") or len(list(self.centre)) != 2:
            raise InputTypeError(f"centre must be (x, y), two numbers or sympy expressions, got {_short(self.centre)}")
        checks.not_text(list(self.centre), "centre")
        if not isinstance(self.name, str):
            raise InputTypeError(f"name must be a str, got {type(self.name).__name__} {_short(self.name)}")


class OpenTreeModel:
    """A planar parallel mechanism opened into a tree, with its equations of motion.

    Parameters
    ----------
    eta : sequence of sympy symbols
        The tree's joint coordinates (``m``).
    constraints : sequence of sympy expressions
        ``phi(eta) = 0`` (``m - n``).
    task : sequence of sympy expressions
        ``f(eta)`` (``n``).
    actuated : sequence of int
        Indices (into ``eta``) of the actuated coordinates (``n``).
    bodies : sequence of Body
    gravity : (2,) float
        Acceleration of gravity (e.g. ``(0, -9.81)``).
    tolerances : Tolerances, optional
        The thresholds of the numeric decisions made with this model (the ``dynamics_*`` and
        ``timelaw_*`` fields: Newton acceptance, rank and consistency tests); ``None``: the
        defaults. Kept as ``model.tolerances``; :meth:`with_tolerances` gives a copy with others.

    Raises
    ------
    TypeError
        For a non-sequence ``eta``/``constraints``/``task``/``actuated``/``bodies``, a non-symbol in
        ``eta``, a string anywhere in the symbolic input, a body that is not a :class:`Body`, or a
        ``tolerances`` that is not a :class:`~imagespace.tolerances.Tolerances`.
    InputError
        For repeated symbols, a count of constraints other than ``m - n``, actuated indices that
        are not ``n`` distinct coordinates, or a malformed ``gravity``.

    Examples
    --------
    >>> from imagespace.dynamics.seed000 import seed000_model
    >>> model = seed000_model()
    >>> model.m, model.n
    (5, 3)
    """

    def __init__(self, eta, constraints, task, actuated, bodies, gravity=(0.0, -9.81), tolerances=None):
        self.tolerances = checks.tolerances(tolerances)
        for name, seq in (("eta", eta), ("constraints", constraints), ("task", task), ("actuated", actuated),
                          ("bodies", bodies)):
            if isinstance(seq, (str, bytes)) or not hasattr(seq, "__iter__"):
                raise InputTypeError(f"{name} must be a sequence, got {type(seq).__name__} {_short(seq)}")
        self.eta = tuple(eta)
        for i, e in enumerate(self.eta):
            if not isinstance(e, sp.Symbol):
                raise InputTypeError(f"eta[{i}] must be a sympy Symbol, got {type(e).__name__} {_short(e)}")
        if len(set(self.eta)) != len(self.eta):
            raise InputError(f"eta must be distinct symbols, got {_short(self.eta)}")
        self.m = len(self.eta)
        constraints, task = list(constraints), list(task)
        checks.not_text(constraints, "constraints")
        checks.not_text(task, "task")
        self.phi = sp.Matrix(constraints)
        self.f = sp.Matrix(task)
        self.n = len(self.f)
        if len(self.phi) + self.n != self.m:
            raise InputError(f"need m - n = {self.m - self.n} loop constraints for m = {self.m} coordinates "
                             f"and n = {self.n} task equations, got {len(self.phi)}")
        act = [as_count(a, f"actuated[{i}]", 0) for i, a in enumerate(actuated)]
        if len(act) != self.n or len(set(act)) != self.n or not all(0 <= a < self.m for a in act):
            raise InputError(f"actuated must be {self.n} distinct coordinate indices in 0..{self.m - 1}, got {actuated}")
        self.actuated = tuple(act)
        self.Z = np.zeros((self.n, self.m))
        for k, a in enumerate(act):
            self.Z[k, a] = 1.0
        self.bodies = tuple(bodies)
        for i, b in enumerate(self.bodies):
            checks.instance(b, Body, f"bodies[{i}]")
        self.gravity = checks.vector(gravity, "gravity", 2)
        self._derive()

    def with_tolerances(self, tolerances):
        """The same model (sharing its compiled functions) with other decision thresholds.

        Raises
        ------
        TypeError
            If ``tolerances`` is neither None nor a :class:`~imagespace.tolerances.Tolerances`.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.dynamics.seed000 import seed000_model
        >>> seed000_model().with_tolerances(isp.Tolerances(dynamics_residual=1e-6)).tolerances.dynamics_residual
        1e-06
        """
        out = copy.copy(self)
        out.tolerances = checks.tolerances(tolerances)
        return out

    # -- symbolic derivation ------------------------------------------------------------------
    def _derive(self):
        eta = sp.Matrix(self.eta)
        m = self.m
        d1 = sp.Matrix(sp.symbols(f"d1_0:{m}", real=True))        # etadot
        d2 = sp.Matrix(sp.symbols(f"d2_0:{m}", real=True))        # etaddot
        self._d1, self._d2 = d1, d2
        GK = self.phi.jacobian(eta)
        GG = self.f.jacobian(eta)
        G = sp.Matrix.vstack(GK, GG)

        def ddt(expr, order_syms):
            # time derivative of an expression in eta (and etadot if order_syms has two levels)
            out = sum((sp.diff(expr, e) * v for e, v in zip(eta, d1)), sp.S(0))
            if order_syms > 1:
                out += sum((sp.diff(expr, v) * w for v, w in zip(d1, d2)), sp.S(0))
            return out

        Gdot = G.applyfunc(lambda e: ddt(e, 1))
        Gddot = Gdot.applyfunc(lambda e: ddt(e, 2))
        # mass matrix, potential, R = -(coriolis) - grad V
        M = sp.zeros(m, m)
        V = sp.S(0)
        for b in self.bodies:
            c = sp.Matrix(list(b.centre))
            Jc = c.jacobian(eta)
            Ja = sp.Matrix([b.angle]).jacobian(eta)
            M += as_sympy(b.mass) * Jc.T * Jc + as_sympy(b.inertia) * Ja.T * Ja
            V += -as_sympy(b.mass) * (self.gravity[0] * c[0] + self.gravity[1] * c[1])
        M = M.applyfunc(sp.simplify)
        Ke = (d1.T * M * d1)[0] / 2
        Mdot = M.applyfunc(lambda e: ddt(e, 1))
        cor = Mdot * d1 - sp.Matrix([sp.diff(Ke, e) for e in eta])
        R = (-cor - sp.Matrix([sp.diff(V, e) for e in eta])).applyfunc(sp.expand)
        Rdot = R.applyfunc(lambda e: ddt(e, 2))
        self.M_sym, self.R_sym, self.V_sym, self.Gamma_sym = M, R, V, G
        args1 = list(eta)
        args2 = list(eta) + list(d1)
        args3 = list(eta) + list(d1) + list(d2)
        self._G = compile_exprs(list(G), args1)
        self._Gdot = compile_exprs(list(Gdot), args2)
        self._Gddot = compile_exprs(list(Gddot), args3)
        self._M = compile_exprs(list(M), args1)
        self._Mdot = compile_exprs(list(Mdot), args2)
        self._R = compile_exprs(list(R), args2)
        self._Rdot = compile_exprs(list(Rdot), args3)
        self._V = compile_exprs([V], args1)
        self._phi = compile_exprs(list(self.phi), args1)
        self._f = compile_exprs(list(self.f), args1)

    # -- numeric faces ---------------------------------------------------------------------------
    def _mat(self, fn, *args, shape):
        flat = np.concatenate([checks.vector(a, name, self.m)
                               for a, name in zip(args, ("eta", "etad", "etadd"))])
        return np.asarray(fn(*flat)).reshape(shape)

    def Gamma(self, eta):
        """``Gamma = [Gamma_K; Gamma_G]`` at ``eta`` (``(m, m)``).

        Raises
        ------
        TypeError
            For non-numeric coordinates.
        InputError
            For coordinates of a length other than ``m`` or non-finite ones.

        Examples
        --------
        >>> from imagespace.dynamics import seed000_model
        >>> model = seed000_model(); eta = [0.7, 2.2, 2.5, 0.4, 0.0]; d = [0.1, 0.2, -0.1, 0.3, 0.0]
        >>> model.Gamma(eta).shape
        (5, 5)
        """
        return self._mat(self._G, eta, shape=(self.m, self.m))

    def Gamma_dot(self, eta, etad):
        """Time derivative of ``Gamma`` for the rates ``etad``.

        Raises
        ------
        TypeError
            For non-numeric coordinates.
        InputError
            For coordinates of a length other than ``m`` or non-finite ones.

        Examples
        --------
        >>> from imagespace.dynamics import seed000_model
        >>> model = seed000_model(); eta = [0.7, 2.2, 2.5, 0.4, 0.0]; d = [0.1, 0.2, -0.1, 0.3, 0.0]
        >>> model.Gamma_dot(eta, d).shape
        (5, 5)
        """
        return self._mat(self._Gdot, eta, etad, shape=(self.m, self.m))

    def Gamma_ddot(self, eta, etad, etadd):
        """Second time derivative of ``Gamma`` (rates ``etad``, accelerations ``etadd``).

        Raises
        ------
        TypeError
            For non-numeric coordinates.
        InputError
            For coordinates of a length other than ``m`` or non-finite ones.

        Examples
        --------
        >>> from imagespace.dynamics import seed000_model
        >>> model = seed000_model(); eta = [0.7, 2.2, 2.5, 0.4, 0.0]; d = [0.1, 0.2, -0.1, 0.3, 0.0]
        >>> model.Gamma_ddot(eta, d, d).shape
        (5, 5)
        """
        return self._mat(self._Gddot, eta, etad, etadd, shape=(self.m, self.m))

    def M(self, eta):
        """Mass matrix of the open tree (``(m, m)``).

        Raises
        ------
        TypeError
            For non-numeric coordinates.
        InputError
            For coordinates of a length other than ``m`` or non-finite ones.

        Examples
        --------
        >>> from imagespace.dynamics import seed000_model
        >>> model = seed000_model(); eta = [0.7, 2.2, 2.5, 0.4, 0.0]; d = [0.1, 0.2, -0.1, 0.3, 0.0]
        >>> model.M(eta).shape
        (5, 5)
        """
        return self._mat(self._M, eta, shape=(self.m, self.m))

    def M_dot(self, eta, etad):
        """Time derivative of the mass matrix.

        Raises
        ------
        TypeError
            For non-numeric coordinates.
        InputError
            For coordinates of a length other than ``m`` or non-finite ones.

        Examples
        --------
        >>> from imagespace.dynamics import seed000_model
        >>> model = seed000_model(); eta = [0.7, 2.2, 2.5, 0.4, 0.0]; d = [0.1, 0.2, -0.1, 0.3, 0.0]
        >>> model.M_dot(eta, d).shape
        (5, 5)
        """
        return self._mat(self._Mdot, eta, etad, shape=(self.m, self.m))

    def R(self, eta, etad):
        """``R = -(Coriolis/centrifugal) - grad V`` (``(m,)``).

        Raises
        ------
        TypeError
            For non-numeric coordinates.
        InputError
            For coordinates of a length other than ``m`` or non-finite ones.

        Examples
        --------
        >>> from imagespace.dynamics import seed000_model
        >>> model = seed000_model(); eta = [0.7, 2.2, 2.5, 0.4, 0.0]; d = [0.1, 0.2, -0.1, 0.3, 0.0]
        >>> model.R(eta, d).shape
        (5,)
        """
        return self._mat(self._R, eta, etad, shape=(self.m,))

    def R_dot(self, eta, etad, etadd):
        """Time derivative of ``R`` (rates and accelerations).

        Raises
        ------
        TypeError
            For non-numeric coordinates.
        InputError
            For coordinates of a length other than ``m`` or non-finite ones.

        Examples
        --------
        >>> from imagespace.dynamics import seed000_model
        >>> model = seed000_model(); eta = [0.7, 2.2, 2.5, 0.4, 0.0]; d = [0.1, 0.2, -0.1, 0.3, 0.0]
        >>> model.R_dot(eta, d, d).shape
        (5,)
        """
        return self._mat(self._Rdot, eta, etad, etadd, shape=(self.m,))

    def potential(self, eta):
        """Potential energy ``V(eta)`` (gravity).

        Raises
        ------
        TypeError
            For non-numeric coordinates.
        InputError
            For coordinates of a length other than ``m`` or non-finite ones.

        Examples
        --------
        >>> from imagespace.dynamics import seed000_model
        >>> isinstance(seed000_model().potential([0.7, 2.2, 2.5, 0.4, 0.0]), float)
        True
        """
        return float(self._mat(self._V, eta, shape=(1,))[0])

    def A_T(self, eta):
        """``A^T = [Gamma_K^T  Z^T]`` (``(m, m)``): rows are coordinates, columns the unknowns ``mu``.

        Raises
        ------
        TypeError
            For non-numeric coordinates.
        InputError
            For coordinates of a length other than ``m`` or non-finite ones.

        Examples
        --------
        >>> from imagespace.dynamics import seed000_model
        >>> model = seed000_model(); eta = [0.7, 2.2, 2.5, 0.4, 0.0]; d = [0.1, 0.2, -0.1, 0.3, 0.0]
        >>> model.A_T(eta).shape
        (5, 5)
        """
        GK = self.Gamma(eta)[: self.m - self.n]
        return np.hstack([GK.T, self.Z.T])

    def A_T_dot(self, eta, etad):
        """Time derivative of ``A^T``.

        Raises
        ------
        TypeError
            For non-numeric coordinates.
        InputError
            For coordinates of a length other than ``m`` or non-finite ones.

        Examples
        --------
        >>> from imagespace.dynamics import seed000_model
        >>> model = seed000_model(); eta = [0.7, 2.2, 2.5, 0.4, 0.0]; d = [0.1, 0.2, -0.1, 0.3, 0.0]
        >>> model.A_T_dot(eta, d).shape
        (5, 5)
        """
        GKd = self.Gamma_dot(eta, etad)[: self.m - self.n]
        return np.hstack([GKd.T, np.zeros((self.m, self.n))])

    def loop(self, eta):
        """The loop constraints ``phi(eta)``.

        Raises
        ------
        TypeError
            For non-numeric coordinates.
        InputError
            For coordinates of a length other than ``m`` or non-finite ones.

        Examples
        --------
        >>> from imagespace.dynamics import seed000_model
        >>> model = seed000_model(); eta = [0.7, 2.2, 2.5, 0.4, 0.0]; d = [0.1, 0.2, -0.1, 0.3, 0.0]
        >>> model.loop(eta).shape
        (2,)
        """
        return self._mat(self._phi, eta, shape=(self.m - self.n,))

    def task(self, eta):
        """The task coordinates ``f(eta)``.

        Raises
        ------
        TypeError
            For non-numeric coordinates.
        InputError
            For coordinates of a length other than ``m`` or non-finite ones.

        Examples
        --------
        >>> from imagespace.dynamics import seed000_model
        >>> model = seed000_model(); eta = [0.7, 2.2, 2.5, 0.4, 0.0]; d = [0.1, 0.2, -0.1, 0.3, 0.0]
        >>> model.task(eta).shape
        (3,)
        """
        return self._mat(self._f, eta, shape=(self.n,))
