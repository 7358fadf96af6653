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
    mode_membership : float
        :func:`imagespace.paths.modechange.plan_mode_change` and ``joint_trajectory``: a mode (or
        a path's start pose) belongs to the joint values ``q`` when the legs' joint residual
        (:meth:`PlanarParallel.joint_residual`, relative to the joint's scale) is below this.
    same_mode : float
        ``plan_mode_change``: two normalised image points that agree to within this (absolute,
        entrywise, on points with ``x0**2 + x1**2 = 1``) are the same assembly mode.
    cusp_leading_coefficient : float
        :func:`imagespace.singular.cusps.cusps`: a seed cell whose kinematic form has a leading
        coefficient below this times the sum of its coefficients' absolute values is skipped
        (a root at infinity of the chart).
    cusp_merge : float
        ``cusps``: converged points closer than this times the window's largest side (in the free
        joints) and than this in the half-angle (radians) are one cusp.
    cusp_chain_reach : float
        :func:`imagespace.singular.cusps.cusp_edges`: cusps of consecutive sections are joined
        only when closer than this times the window's largest side.
    linking_parallel : float
        :func:`imagespace.singular.cusps.linking_number`: a curve segment whose triple product with
        a cone triangle is below this (absolute, in joint units cubed) is parallel to it and
        does not cross.
    loop_jump_ratio : float
        :func:`imagespace.paths.cusp_loops.cusp_loop`: a walk is continuous when no step exceeds
        this times the median step (or ``loop_jump_floor``, whichever is larger).
    loop_jump_floor : float
        ``cusp_loop``: steps up to this (in the normalised image point) never count as a jump.
    implicit_coefficient : float
        :class:`imagespace.singular.implicit.PolynomialImplicit`: signs are proven with the float
        rounding-error bound only if every coefficient rounds to float with a relative error
        below this (otherwise the signs are float signs, not proven).
    mesh_on_grid : float
        :func:`imagespace.singular.meshing.mesh_implicit`: a marching-cubes coordinate within this
        (in grid cells) of an integer lies on a grid plane.
    mesh_node_merge : float
        ``mesh_implicit``: vertices within this (in grid cells, on every axis) of the same grid
        node are merged.
    mesh_min_altitude : float
        ``mesh_implicit``: faces whose altitude is below this times ``tol * size`` are dropped as
        degenerate.
    plot_orientation : float
        :func:`imagespace.plotting.plot_conic_section`: an assembly mode is marked when its
        orientation is within this (radians, modulo ``2 pi``) of the section's ``phi``.
    chart_x0 : float
        The command line's ``demo``: an image point is printed in the chart ``x0 = 1`` when
        ``|x0|`` exceeds this (the point is normalised, ``x0**2 + x1**2 = 1``), otherwise as is.

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
    kernel_chart_duplicate: float = 1e-10
    kernel_newton_stop: float = 1e-9
    kernel_residual: float = 1e-9
    kernel_duplicate: float = 1e-9
    # singular/, paths/, plotting
    mode_membership: float = 1e-6
    same_mode: float = 1e-12
    cusp_leading_coefficient: float = 1e-14
    cusp_merge: float = 1e-3
    cusp_chain_reach: float = 0.1
    linking_parallel: float = 1e-15
    loop_jump_ratio: float = 20.0
    loop_jump_floor: float = 1e-9
    implicit_coefficient: float = 1e-6
    mesh_on_grid: float = 1e-12
    mesh_node_merge: float = 1e-9
    mesh_min_altitude: float = 1e-3
    plot_orientation: float = 1e-6
    chart_x0: float = 1e-12

    def __post_init__(self):
        for name, value in self.__dict__.items():
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0 \
                    or value != value or value == float("inf"):
                raise ValueError(f"Tolerances.{name} must be a positive finite number, got {value!r}")
        if int(self.newton_steps) != self.newton_steps:
            raise ValueError(f"Tolerances.newton_steps must be a whole number, got {self.newton_steps!r}")


TOLERANCES = Tolerances()
