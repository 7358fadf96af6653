r"""The compiled batch direct-kinematics kernel: ONE generic kernel for every design, one pass per
joint vector, real roots only.

:meth:`PlanarParallel.direct_kinematics_batch` sends large batches here when numba is present.
Nothing is generated or compiled per design. A design enters as small tables
(:func:`design_tables`, derived once in a few milliseconds): each leg's eight quadric coefficients
and their derivatives in the joint value, as polynomials in the features ``q, cos q, sin q``
(``cos``/``sin`` for an actuated revolute), and the elimination plan. Per joint vector the
kernel then

1. evaluates the three dyad quadrics ``Q_i(x; q_i)`` (8 coefficients each) and their derivatives
   ``dQ_i/dq_i`` (the diagonal of ``Jq``, used for the joint-space residual) from the tables
   (:func:`design_row`),
2. eliminates ``x2, x3`` numerically, as binary-form arithmetic on these coefficients: the Cramer
   forms ``D, X2, X3`` and the form ``F`` of :mod:`imagespace.core.elimination`
   (:func:`imagespace.core.elimination.eliminate_row`, the compiled twin of ``eliminate``; ``F``
   keeps its factors ``x0**2 + x1**2``, which have no real roots),
3. finds the real roots of ``F`` on the projective line in two charts, ``t = x1/x0`` in
   ``[-1, 1]`` and ``s = x0/x1`` in ``(-1, 1)``, so half-turns are ordinary roots and no chart
   sees a root beyond 1. The roots are isolated by Descartes' rule in the Bernstein basis
   (:func:`imagespace.core.isolate.count_real_roots_row`) on the rigorous enclosure of ``F``
   that steps 1 and 2 compute alongside the values (``cos``/``sin`` enclosed, every rounding of
   the elimination bounded), so the number of isolated roots is the proven number of distinct
   real roots of the exact kinematic form at the binary-rational input, and a row whose bounds
   cannot separate its roots is flagged (``suspect``) rather than guessed; each root is then
   refined by Newton kept inside its isolating interval. No eigenvalues, no complex arithmetic,
4. back-substitutes ``x2 = X2/D, x3 = X3/D``, polishes ``(x0..x3)`` by Newton on
   ``[Q1, Q2, Q3, x0**2 + x1**2 - 1]`` (4x4 Gaussian elimination with partial pivoting) unless the
   residual is at rounding level already, and checks every mode: relative constraint residual
   below ``1e-9``, joint residual ``max_i |Q_i| / |dQ_i/dq_i|`` reported,
5. writes normalised image points, poses, aspects (sign of the 4x4 determinant) sorted by ``phi``.

The rows go through these steps in blocks of :data:`.lockstep.LOCKSTEP_ROWS`, side by side
(:mod:`.lockstep`: structure-of-arrays loops over the rows of a block, the split grid of the
isolation computed and classified for the block at once), with exactly the operations of the
row-at-a-time functions (:mod:`.row`, :func:`design_row`, ``eliminate_row``,
``count_real_roots_row``), so both loops give the same answers bit for bit; the row-at-a-time
loop stays as the benchmarks' baseline (``kernel(Q, lockstep=False)``).

Package layout: :mod:`.tables` (design tables, :func:`design_row`), :mod:`.newton` (the
bracketed Newton iteration that refines each isolated root), :mod:`.row` (the per-row stages),
:mod:`.lockstep`, :mod:`.block_layout` and :mod:`.block_isolate` (the block stages), :mod:`.loops`
(the generated generic loops and their on-disk cache), :mod:`.batch` (:class:`BatchKernel`,
:func:`build_kernel`).

A row is flagged instead of guessed when a float computation cannot decide it: roots the
isolation cannot separate (a double root, or a complex pair within rounding of the axis:
``suspect``), or the Cramer denominator vanishing at a root, a vanishing polynomial, a Newton
step that does not converge (``special``). The caller re-solves flagged rows with the numpy
path, which marks the rows whose count it cannot separate ``near_singular``.

The same tables drive the certified counts (:meth:`BatchKernel.certified_counts`): steps 1 and 2
with a rigorous error bound on every value (``cos``/``sin`` enclosed by
:func:`imagespace.core.bounded_trig.cos_sin_bounded`), then Descartes' rule in the Bernstein
basis (:func:`imagespace.core.isolate.count_real_roots_row`) with every sign decided despite the
bounds.

Designs the kernel does not take (the caller uses the numpy path): a PP dyad (its pair of planes
carries a spurious root that only the leg's inverse kinematics can discard) and designs whose
Cramer denominator vanishes identically (case (a), e.g. seed 003).

The compiled loops are cached on disk (``$IMAGESPACE_CACHE/kernels`` or
``~/.cache/imagespace/kernels``) only in a directory private to the user (created 0700; refused,
with a :class:`KernelCacheWarning`, when owned by someone else, writable by group or others, or a
symbolic link): one entry per installation, shared by every design. The cached ``k_<key>.py`` is
never executed: the source is compared with it (rewritten when it differs) and executed from
memory. A corrupted numba cache entry is deleted and rebuilt when the kernel is loaded; with no
writable place the loops are compiled in memory.
"""

from __future__ import annotations

from ...core._numba import HAVE_NUMBA
from ...core.codegen import KernelCacheWarning
from ...core.elimination import ELIMINATION_ROW_SIZE, ELIMINATION_WORK_SIZE, ROW_D, ROW_F  # noqa: F401
from ...core.isolate import ISOLATE_WORK_SIZE, count_real_roots_row  # noqa: F401
from .batch import BatchKernel, build_kernel
from .loops import _compile, _generic_loop, _SOURCE  # noqa: F401
from .newton import _horner, _monotone_root  # noqa: F401
from .row import (_MAX, _WORK_SIZE, _bf, _det4, _solve4, _solve_row, _system,  # noqa: F401
                  eliminate_row, kernel_tolerances)
from .tables import MAX_MONOMIALS, DesignTables, design_row, design_tables

__all__ = ["BatchKernel", "DesignTables", "KernelCacheWarning", "build_kernel", "design_tables", "design_row",
           "HAVE_NUMBA", "MAX_MONOMIALS"]
