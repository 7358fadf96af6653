"""Named numerical tolerances, in one frozen dataclass.

Scope of the promise (kept true by tests): every floating-point decision of the numpy
direct-kinematics path and of the floating-point steps of the certified per-call path
(:meth:`PlanarParallel.direct_kinematics` with or without ``certify``) reads its threshold from the
manipulator's :class:`Tolerances` (``PlanarParallel(..., tolerances=...)``), as do the singularity
classifications of :mod:`imagespace.singular.surface`. All of these thresholds are relative: the
quadrics are balanced to the design's length scale before any decision, so answers do not depend
on units. Certified answers (counts, multiplicities, root intervals) never read a tolerance.

The compiled batch kernel (:mod:`imagespace.solve.kernel`) reads its decision thresholds from the same
object (passed to it as an array, :func:`imagespace.solve.kernel.kernel_tolerances`). So do the
legs' inverse kinematics, the meshes, paths, mode changes, cusps, workspaces, fuzzy design choice,
the dynamics (through its model) and the figures: functions that receive a manipulator read
``manipulator.tolerances``; the others take a ``tolerances=None`` keyword (None: :data:`TOLERANCES`).
What stays a named module constant is a numerical-method knob, not a decision: how far a root is
polished, a bisection's stopping width, a finite-difference step, a minimiser's ``xatol``.
"""

import warnings
from dataclasses import dataclass

import numpy as np

__all__ = ["Tolerances", "TOLERANCES"]

DEPRECATED = {
    "kernel_chart_overlap": "the compiled kernel's charts are isolated by Descartes' rule and do not overlap",
    "kernel_chart_duplicate": "the compiled kernel's charts are isolated by Descartes' rule and share no root",
}
"""Fields of :class:`Tolerances` that no computation reads any more; setting one to anything but
its default warns (``FutureWarning``)."""


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
        Numpy path: a root this close (in the half-angle) to the spurious orientation of a PP
        dyad is that root (only where no proof of the roots is available), and a mode this
        close to a cluster of roots the discs cannot separate belongs to it (Cramer cases).
        No longer a criterion of the compiled kernel: its counts are proven.
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
        Deprecated, has no effect (issue [15]): the compiled kernel isolates the roots of each
        chart by Descartes' rule in the Bernstein basis, so its charts (``t`` in ``[-1, 1]``,
        ``s`` in ``(-1, 1)``) neither overlap nor share a root. Setting it warns
        (``FutureWarning``); the field will be removed.
    kernel_chart_duplicate : float
        Deprecated, has no effect (issue [15]), for the same reason; setting it warns.
    kernel_newton_stop : float
        The compiled kernel: Newton on the full system stops once a step is below this times the
        point's size.
    kernel_residual : float
        The compiled kernel: a polished mode whose largest constraint value, relative to
        ``1 + x2^2 + x3^2``, exceeds this sends the row to the numpy path. The numpy path asks
        the same of a polished candidate whose legs' inverse kinematics is undefined (a leg
        singularity) before keeping it as a flagged mode.
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
    atlas_evidence_width : float
        :func:`imagespace.atlas.joint_atlas`: a surface vertex is kept when the two points of
        different certified counts that bracket it are at most this many grid cells apart;
        vertices with a wider (or no) bracket are removed and counted.
    atlas_cusp_residual : float
        ``joint_atlas`` (cusp curves): a corrected point is on a cusp curve when
        ``max(|f|, |f'|, |f''|)`` is below this times the sum of the form's coefficients'
        absolute values (a float decision for the drawing; cusps are proven by
        :func:`imagespace.atlas.is_cuspidal`).
    atlas_cusp_seed_reach : float
        ``joint_atlas`` (cusp curves): a seed closer than this (in the scaled unknowns, box
        sides scaled to pi) to a traced curve lies on it and starts no new curve.
    aspect_singular : float
        :func:`imagespace.atlas.uniqueness_domains`: a pose-grid node whose
        ``|det J| / prod(row norms)`` is below this is on the singularity surface and belongs to
        no aspect.
    plot_orientation : float
        :func:`imagespace.plotting.plot_conic_section`: an assembly mode is marked when its
        orientation is within this (radians, modulo ``2 pi``) of the section's ``phi``.
    chart_x0 : float
        The command line's ``demo``: an image point is printed in the chart ``x0 = 1`` when
        ``|x0|`` exceeds this (the point is normalised, ``x0**2 + x1**2 = 1``), otherwise as is.
    workspace_inside : float
        :meth:`imagespace.design.workspace.Workspace.contains`: a point is inside an exact
        (polygon) workspace when its signed edge cross products are all ``>= -workspace_inside``
        (absolute, in squared length units of the design).
    workspace_affine : float
        The workspaces: the legs' inverse kinematics is affine in ``(x, y)`` at fixed ``phi`` when
        it reproduces probe points to within ``workspace_affine`` (relative, and absolute times
        ``1 + max|q|``).
    workspace_affine_constant : float
        The workspaces: the affine coefficients ``a_i`` are independent of ``phi`` when those of
        three orientations agree to within this (absolute; plus numpy's default relative part).
    workspace_common_offset : float
        :func:`imagespace.design.workspace.reachable_workspace`: the offsets ``c_i(phi)`` differ by
        constants (exact polytope projection) when ``c_i - c_0`` varies by at most this times
        ``1 + max|c|`` (plus numpy's default relative part).
    workspace_vertex_det : float
        The reachable polytope: three facet planes meet in a vertex when ``|det|`` of their
        normals is at least this (absolute; the normals are the legs' unscaled gradients).
    workspace_vertex_feasible : float
        The reachable polytope: a vertex is kept when it violates no facet by more than this
        times ``1 + |h|`` (``h`` the facet's offset).
    fuzzy_tie : float
        :func:`imagespace.design.sweep.fuzzy_minmax`: rows whose weighted score ``W_c`` (in
        ``[0, 1]``) is within this of the best are all listed as best (absolute).
    dynamics_residual : float
        :mod:`imagespace.dynamics`: the loop and task equations are solved when their largest
        residual after Newton is at most this (absolute, in the model's units); otherwise the
        kinematics did not converge.
    dynamics_rank : float
        :func:`imagespace.dynamics.drive_singularity`: the rank of ``A`` drops by more than one
        when its second-smallest singular value is below this times the largest.
    dynamics_alpha_zero : float
        :func:`imagespace.dynamics.drive_singularity`: a row-dependence coefficient
        ``alpha_p = -nu_p / nu_s`` below this (absolute; ``|alpha_p| <= 1`` by the choice of
        ``s``) is zero, i.e. row ``p`` is not involved.
    dynamics_consistency_slope : float
        :func:`imagespace.dynamics.consistent_acceleration`: the consistency condition does not
        involve the path acceleration when its slope is below this times ``max(1, |base|)``.
    dynamics_mu_dot : float
        :func:`imagespace.dynamics.inverse_dynamics`: inside the band, the ``mudot`` term is put
        back only where ``|g| >`` this (``g`` the dimensionless singularity measure); closer, the
        term is below the rounding of eq. 5 itself.
    dynamics_consistency : float
        :func:`imagespace.dynamics.inverse_dynamics`: a crossing of the drive singularity is
        consistent when ``|nu . (M etaddot - R)| <= dynamics_consistency * |M etaddot - R|``
        (dimensionless; ``imagespace.dynamics.solve.CONSISTENCY_RTOL`` is its default).
    timelaw_root : float
        :meth:`imagespace.dynamics.TimeLaw.is_monotone`: a root of ``s'`` is real when
        ``|Im| <`` this, and strictly inside ``(0, T)`` when farther than this from both ends
        (absolute, in time units).
    timelaw_monotone : float
        :meth:`imagespace.dynamics.TimeLaw.is_monotone`: ``s'`` is non-negative when no sample is
        below ``-timelaw_monotone * max(1, max|s'|)``.
    closed_form_ulps : float
        The closed forms of :mod:`imagespace.examples` (``collinear_3rpr_closed_form``,
        ``choi_3ppr_closed_form``): a quantity within ``closed_form_ulps * eps * scale`` of zero
        (``eps`` the float64 machine epsilon, ``scale`` the size of its terms) is zero, so a
        boundary case reached through rounding is the boundary case.
    rotation_matrix : float
        :func:`imagespace.spatial.study.quaternion_from_matrix`: a matrix is accepted as a rotation
        when ``|R^T R - I|`` and ``|det R - 1|`` are at most this (absolute).
    planar_subspace : float
        :func:`imagespace.spatial.study.study_to_planar`: a Study point is planar when
        ``x1, x2, y0, y3`` are at most this times ``max |s|``.
    spatial_real_imag : float
        Spatial fast path, rows its compiled certificate did not prove (never ``reliable``; the
        proven rows' real modes are decided by the certificate): an endpoint (scaled so its
        largest ``|x_i|`` is 1) is counted as a real mode when its imaginary parts are at most
        this times its largest entry.
    spatial_nonreal_imag : float
        ... and clearly not real above this (an unproven row's float diagnosis).
    spatial_distinct : float
        Two endpoints closer than this (unit-normalised, Euclidean) are one solution reached twice
        (path jumping): ``complex_count`` of an unproven row counts them once.
    study_quadric : float
        A Study point given where the answer is Euclidean (``translation``, and so
        ``transform_matrix`` and ``transform_points``) is on Study's quadric when ``|x . y|`` is
        at most this times ``|x|^2 + |y|^2``; a point further off is refused.
    spatial_plane : float
        ``ThreeRPS.inverse_kinematics``: a leg is in its revolute joint's plane when
        ``|u . leg|`` is at most this times ``|u| |leg|``.
    spatial_aspect : float
        ``GoughStewart.aspects``: the sign of ``det J`` is 0 when ``|det J|`` is at most this times
        Hadamard's bound (the product of the row norms).
    spatial_collinear : float
        :class:`imagespace.spatial.GoughStewart` and :class:`imagespace.spatial.ThreeRPS`: the
        base (or platform) anchors lie on one line, a degenerate design, when the second singular
        value of the centred anchors (for the 3-RPS: the norm of the cross product of two sides,
        over the squared size) is at most this times ``max |coordinate|``: relative to the design's
        size, so the same design in any unit gets the same answer.

    far_reach_ratio : float
        A row whose prismatic joint values exceed this times the design's size (its largest
        coordinate or link length) is beyond what the float paths resolve (the design shrinks
        below their relative resolution next to the legs; measured on random 3-RPR designs: wrong
        float counts from about 1e5): it is answered by a reach bound
        (:mod:`imagespace.core.reach`) or by the certified per-row path instead. The spatial
        platforms measure against their largest anchor coordinate and decide such rows with msolve.
    exact_reach_ratio : float
        Spatial platforms: legs longer than this times the design's size that no reach bound
        decides are refused (masked in a batch): msolve on coefficients of hundreds of digits
        takes minutes (a Gough-Stewart row: 10-20 s up to 1e40 times, beyond 600 s at 1e300).

    The compiled kernel also reads ``cramer_small`` (a root with ``|D| <= cramer_small max|D|``
    sends the row to the numpy path) and ``newton_stop`` (its 4x4 solve's pivot threshold); it
    receives its thresholds as one array (:func:`imagespace.solve.kernel.kernel_tolerances`).

    Examples
    --------
    >>> from imagespace.tolerances import Tolerances, TOLERANCES
    >>> loose = Tolerances(joint_residual=1e-5)
    >>> loose.joint_residual, TOLERANCES.joint_residual
    (1e-05, 1e-07)
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
    kernel_chart_overlap: float = 1e-12       # deprecated: no effect (see DEPRECATED)
    kernel_chart_duplicate: float = 1e-10     # deprecated: no effect (see DEPRECATED)
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
    atlas_evidence_width: float = 1 / 64
    atlas_cusp_residual: float = 1e-10
    atlas_cusp_seed_reach: float = 0.05
    aspect_singular: float = 1e-9
    chart_x0: float = 1e-12
    # design/, dynamics/, spatial/
    workspace_inside: float = 1e-12
    workspace_affine: float = 1e-10
    workspace_affine_constant: float = 1e-12
    workspace_common_offset: float = 1e-10
    workspace_vertex_det: float = 1e-12
    workspace_vertex_feasible: float = 1e-9
    fuzzy_tie: float = 1e-12
    dynamics_residual: float = 1e-9
    dynamics_rank: float = 1e-8
    dynamics_alpha_zero: float = 1e-12
    dynamics_consistency_slope: float = 1e-14
    dynamics_mu_dot: float = 1e-7
    dynamics_consistency: float = 1e-6
    timelaw_root: float = 1e-12
    timelaw_monotone: float = 1e-12
    closed_form_ulps: float = 16
    rotation_matrix: float = 1e-9
    planar_subspace: float = 1e-12
    spatial_collinear: float = 1e-12
    spatial_real_imag: float = 1e-8
    spatial_nonreal_imag: float = 1e-5
    spatial_distinct: float = 1e-6
    spatial_aspect: float = 1e-12
    spatial_plane: float = 1e-9
    study_quadric: float = 1e-8
    # absurd input (solve/, spatial/)
    far_reach_ratio: float = 1e3
    exact_reach_ratio: float = 1e20

    def __post_init__(self):
        from .exceptions import InputError, InputTypeError

        for name, value in self.__dict__.items():
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
                raise InputTypeError(f"Tolerances.{name} must be a positive finite number, got "
                                     f"{type(value).__name__} {value!r}; strings are never parsed")
            if not value > 0 or value != value or value == float("inf"):
                raise InputError(f"Tolerances.{name} must be a positive finite number, got {value!r}")
        if int(self.newton_steps) != self.newton_steps:
            raise InputError(f"Tolerances.newton_steps must be a whole number, got {self.newton_steps!r}")
        for name, why in DEPRECATED.items():
            if getattr(self, name) != _DEFAULTS[name]:
                warnings.warn(f"Tolerances.{name} is deprecated and has no effect ({why}); it will be "
                              f"removed", FutureWarning, stacklevel=3)


_DEFAULTS = {name: field.default for name, field in Tolerances.__dataclass_fields__.items()}

TOLERANCES = Tolerances()
