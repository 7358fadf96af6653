"""Named numerical tolerances, in one frozen dataclass.

Scope of the promise (kept true by tests): every floating-point decision of the numpy
direct-kinematics path and of the floating-point steps of the certified per-call path
(:meth:`PlanarParallel.direct_kinematics` with or without ``certify``) reads its threshold from the
manipulator's :class:`Tolerances` (``PlanarParallel(..., tolerances=...)``), as do the singularity
classifications of :mod:`imagespace.singular.surface`. All of these thresholds are relative: the
quadrics are balanced to the design's length scale before any decision, so answers do not depend
on units. Certified answers (counts, multiplicities, root intervals) never read a tolerance.

The compiled batch kernel (:mod:`imagespace.solve.kernel`) reads its decision thresholds from the same
object (passed to it as an array); its root finder's numerical constants (how far a critical point
is polished) are named module constants there, as are the thresholds of meshing, paths, cusps,
backlash, workspaces and dynamics, which this object does not cover.
"""

from dataclasses import dataclass

__all__ = ["Tolerances", "TOLERANCES"]


@dataclass(frozen=True)
class Tolerances:
    """Thresholds used by the numeric paths.

    Attributes
    ----------
    joint_residual : float
        A candidate assembly mode is reported only if the inverse kinematics of every leg
        reproduces the given joint value to within this, relative to the joint's scale
        (``max(1, |q|, design length scale)`` for prismatic joints, ``1`` for angles).
    real_root_imag : float
        A numeric root ``t`` of the kinematic polynomial is a real candidate when
        ``|Im t| <= real_root_imag * (1 + |t|)``; candidates are then polished and checked, so
        a loose value only costs time.
    duplicate : float
        Two polished modes closer than this (in the normalised image point) are one mode.
    degenerate : float
        A binary form whose coefficients are all below ``degenerate`` times the scale of its
        inputs is treated as identically zero (exact arithmetic then confirms).
    newton_steps : int
        Maximum Newton iterations when polishing a mode on the full constraint system.
    singular : float
        A Jacobian is singular when ``|det| / prod(row norms) <= singular`` (dimensionless);
        a float conic invariant is zero when below ``singular`` times the coefficient scale to
        the invariant's degree.
    cramer_identically_zero : float
        The Cramer denominator ``D`` of a row is taken as identically zero (case (a)) when its
        coefficients are below this, relative to the balanced quadrics (max coefficient 1).
    cramer_small : float
        ``D`` is small at a root (case (b), the orientation is solved on its own) when
        ``|D(root)| <= cramer_small * max|D|``.
    rank : float
        Relative singular-value threshold for the rank of the linear part of a fixed-orientation
        system, and for a continuum of positions.
    newton_stop : float
        Newton on the full system stops when a step is below this times the point's size;
        a Jacobian with ``|det| <= newton_stop * prod(row norms)`` takes no step.
    near_singular_gap : float
        The compiled kernel's rows: two real roots of the kinematic polynomial closer than this
        (in the half-angle) make the row ``near_singular``; on the numpy path, a root this close
        to the spurious orientation of a PP dyad is that root.
    near_singular_condition : float
        Rows solved orientation by orientation (Cramer cases): a mode whose
        ``|det J| / prod(row norms)`` is below this, or a line-circle intersection whose
        discriminant is below this relative to its terms, makes the row ``near_singular``.
    ik_parallel : float
        Leg inverse kinematics: two lines (unit directions) with ``|u x v|`` below this are
        parallel, and the branch they would give does not exist (NaN).
    ik_tangent : float
        Leg inverse kinematics: a circle-line (or elbow) intersection whose discriminant is
        negative by less than this, relative to the squared link length (``1 + r^2`` for a
        circle of radius ``r`` and a line), is a tangency (the two branches meet) rather than no
        solution.
    kernel_chart_overlap : float
        The compiled kernel: a root ``t`` of one chart's polynomial is kept when
        ``|t| <= 1 + kernel_chart_overlap``; the roots both charts keep are deduplicated
        (``kernel_chart_duplicate``).
    kernel_chart_duplicate : float
        The compiled kernel: two orientation candidates from the two charts with
        ``|x0 x1' - x1 x0'|`` below this are one root.
    kernel_newton_stop : float
        The compiled kernel: Newton on the full system stops once a step is below this times the
        point's size.
    kernel_residual : float
        The compiled kernel: a polished mode whose largest constraint value, relative to
        ``1 + x2^2 + x3^2``, exceeds this sends the row to the numpy path.
    kernel_duplicate : float
        The compiled kernel: two modes closer than this (relative to the position's size) send
        the row to the numpy path (two roots polished onto one mode).

    The compiled kernel also reads ``cramer_small`` (a root with ``|D| <= cramer_small max|D|``
    sends the row to the numpy path) and ``newton_stop`` (its 4x4 solve's pivot threshold); it
    receives all six as one array (:func:`imagespace.solve.kernel.kernel_tolerances`).
    """

    joint_residual: float = 1e-7
    real_root_imag: float = 1e-5
    duplicate: float = 1e-7
    degenerate: float = 1e-11
    newton_steps: int = 30
    singular: float = 1e-9
    cramer_identically_zero: float = 1e-9
    cramer_small: float = 1e-7
    rank: float = 1e-9
    newton_stop: float = 1e-14
    near_singular_gap: float = 1e-6
    near_singular_condition: float = 1e-8
    ik_parallel: float = 1e-14
    ik_tangent: float = 1e-12
    kernel_chart_overlap: float = 1e-12
    kernel_chart_duplicate: float = 1e-10
    kernel_newton_stop: float = 1e-9
    kernel_residual: float = 1e-9
    kernel_duplicate: float = 1e-9

    def __post_init__(self):
        for name, value in self.__dict__.items():
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0 \
                    or value != value or value == float("inf"):
                raise ValueError(f"Tolerances.{name} must be a positive finite number, got {value!r}")
        if int(self.newton_steps) != self.newton_steps:
            raise ValueError(f"Tolerances.newton_steps must be a whole number, got {self.newton_steps!r}")


TOLERANCES = Tolerances()
