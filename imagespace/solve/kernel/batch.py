"""The design-bound batch kernel (:class:`BatchKernel`) and its factory (:func:`build_kernel`)."""

from __future__ import annotations

import numpy as np

from ...core._numba import HAVE_NUMBA
from ...core.elimination import ELIMINATION_ROW_SIZE, ELIMINATION_WORK_SIZE, ROW_F
from ...core.isolate import ISOLATE_WORK_SIZE, count_real_roots_row
from ...tolerances import TOLERANCES
from .loops import FORM_D, FORM_F, _SOURCE, _SERIAL_ROWS, _generic_loop
from .row import _MAX, eliminate_row, kernel_tolerances
from .tables import design_row, design_tables

class BatchKernel:
    """The generic compiled direct-kinematics kernel, bound to one design's tables (see the
    module docstring).

    Built by :func:`build_kernel`; called by :meth:`PlanarParallel.direct_kinematics_batch`. The
    compiled loop is the same for every design (compiled once per installation, then loaded
    from the cache); only the small :class:`DesignTables` differ.

    Attributes
    ----------
    source : str
        The generic loop's module (readable Python), the same for every design.
    layout : (3,) int
        Degrees of ``D``, ``X2``/``X3`` and ``F``.
    tables : DesignTables
    """

    def __init__(self, tables, tolerances=None):
        self.source = _SOURCE
        self.tables = tables
        self.layout = np.array([2, 3, tables.degree], dtype=np.int64)
        self.tolerances = kernel_tolerances(TOLERANCES if tolerances is None else tolerances)

    def __call__(self, Q, proof=True, lockstep=True):
        """Solve joint vectors ``Q`` (n, 3) (finite, in the joints' domains).

        Parameters
        ----------
        Q : (n, 3) float
        proof : bool
            Isolate the real roots with rigorous bounds on the coefficients of ``F`` (quadric
            coefficients with ``cos``/``sin`` enclosed, bounded elimination): the count of an
            unflagged row is then the proven number of distinct real roots of the exact
            kinematic form, and a row the bounds cannot decide is flagged 2. ``False`` takes
            the float coefficients as exact (an unflagged count may then be wrong near a
            double root; kept as the baseline of ``benchmarks/dk_throughput.py``).
        lockstep : bool
            Solve blocks of rows in lockstep (:mod:`.lockstep`, the default); ``False`` runs the
            row-at-a-time loop, which gives the same answers bit for bit (kept as the baseline of
            ``benchmarks/dk_throughput.py``).

        Returns
        -------
        X (n, 6, 4), poses (n, 6, 3), residual (n, 6), aspect (n, 6) int8, count (n,) int64,
        flag (n,) int8 (0 solved, 1 careful path needed, 2 certified path needed)

        Examples
        --------
        >>> import numpy as np
        >>> import imagespace as isp
        >>> from imagespace.solve.proof import batch_kernel
        >>> m = isp.examples.general_3rpr()
        >>> X, P, R, A, count, flag = batch_kernel(m)(np.array([m.q_example_float]))
        >>> count.tolist(), flag.tolist()
        ([6], [0])
        """
        Q = np.ascontiguousarray(Q, dtype=float)
        n = Q.shape[0]
        # every slot is written by the kernel (in parallel: the pages are first touched there)
        X = np.empty((n, _MAX, 4))
        P = np.empty((n, _MAX, 3))
        R = np.empty((n, _MAX))
        A = np.empty((n, _MAX), dtype=np.int8)
        cnt = np.empty(n, dtype=np.int64)
        flag = np.empty(n, dtype=np.int8)
        if n:
            _generic_loop("run" if lockstep else "run_rows")(Q, *self.tables.arrays(), self.tolerances, bool(proof),
                                                             X, P, R, A, cnt, flag)
        return X, P, R, A, cnt, flag

    def certified_counts(self, Q, lockstep=True):
        """Proven numbers of distinct real roots of the kinematic form for joint vectors ``Q`` (n, 3)
        (finite, in the joints' domains; floats taken as the exact binary rationals they are).

        Per row: the quadric coefficients with rigorous error bounds (``cos``/``sin`` enclosed),
        the elimination with a rigorous bound on every coefficient of ``F``, then
        :func:`imagespace.core.isolate.count_real_roots_row` (Descartes' rule in the Bernstein
        basis, every sign decided despite the bounds). No eigenvalues, no flint. Blocks of rows
        run in lockstep (:mod:`.lockstep`) unless ``lockstep`` is False (the row-at-a-time loop,
        the same answers; a benchmark baseline).

        Returns
        -------
        counts : (n,) int8
            The count, or -1 where the bounds could not decide it (a multiple or nearly multiple
            root, a root on a chart boundary): the caller decides those rows exactly.
        lo, hi : (n, 6) float
            Isolating interval of each root (NaN padded), in ``t = x1/x0`` where ``chart`` is 0
            and in ``s = x0/x1`` where it is 1.
        chart : (n, 6) int8
            -1 in unused slots.

        Examples
        --------
        >>> import numpy as np
        >>> import imagespace as isp
        >>> from imagespace.solve.proof import batch_kernel
        >>> m = isp.examples.general_3rpr()
        >>> counts, lo, hi, chart = batch_kernel(m).certified_counts(np.array([m.q_example_float]))
        >>> counts.tolist(), int((chart[0] >= 0).sum())
        ([6], 6)
        """
        Q = np.ascontiguousarray(Q, dtype=float)
        n = Q.shape[0]
        counts = np.empty(n, dtype=np.int8)
        lo = np.full((n, _MAX), np.nan)
        hi = np.full((n, _MAX), np.nan)
        chart = np.full((n, _MAX), -1, dtype=np.int8)
        if n > _SERIAL_ROWS:
            _generic_loop("run_counts" if lockstep else "run_counts_rows")(Q, *self.tables.arrays(), counts, lo, hi,
                                                                           chart)
        elif n:
            self._counts_serial(Q, counts, lo, hi, chart)
        return counts, lo, hi, chart

    def cramer_forms(self, Q):
        """The kinematic form ``F`` and the Cramer denominator ``D`` of each row of ``Q`` (n, 3),
        with rigorous bounds: the exact forms at the binary-rational input lie in ``F +- EF`` and
        ``D +- ED`` (the same compiled steps as :meth:`certified_counts`: quadric coefficients
        with ``cos``/``sin`` enclosed, the bounded elimination). For the proof that every root
        is a Cramer root (:func:`imagespace.core.form_bounds.no_common_real_root`).

        Returns
        -------
        F, EF : (n, 7) float
            Coefficients of ``x0**(6-k) x1**k`` (``F`` keeps its factors ``x0**2 + x1**2``).
        D, ED : (n, 3) float

        Examples
        --------
        >>> import numpy as np
        >>> import imagespace as isp
        >>> from imagespace.core.form_bounds import no_common_real_root
        >>> from imagespace.solve.proof import batch_kernel
        >>> m = isp.examples.general_3rpr()
        >>> no_common_real_root(*batch_kernel(m).cramer_forms(np.array([m.q_example_float]))).tolist()
        [True]
        """
        Q = np.ascontiguousarray(Q, dtype=float)
        n = Q.shape[0]
        F, EF = np.empty((n, FORM_F)), np.empty((n, FORM_F))
        D, ED = np.empty((n, FORM_D)), np.empty((n, FORM_D))
        if n:
            _generic_loop("run_forms")(Q, *self.tables.arrays(), F, EF, D, ED)
        return F, EF, D, ED

    def _counts_serial(self, Q, counts, lo, hi, chart):
        """The rows of ``run_counts`` one by one from Python, through the same compiled steps
        (``design_row``, ``eliminate_row``, ``count_real_roots_row``): a few rows (the per-call
        float path's proof) cost microseconds here, where starting the parallel loop's threads
        can cost milliseconds on a loaded machine."""
        expo, coef, cerr, nmono, trig, plan = self.tables.arrays()
        buf = np.empty(48 + ELIMINATION_ROW_SIZE)
        Ce = np.zeros(24)
        eout = np.zeros(ELIMINATION_ROW_SIZE)
        ework = np.empty(ELIMINATION_WORK_SIZE + 8)
        iwork = np.empty(ISOLATE_WORK_SIZE)
        for r in range(Q.shape[0]):
            design_row(Q[r], expo, coef, cerr, nmono, trig, True, buf, Ce, ework)
            d = eliminate_row(buf, Ce, plan, buf[48:], eout, ework, True)
            counts[r] = count_real_roots_row(buf[48 + ROW_F:], eout[ROW_F:], d, lo[r], hi[r], chart[r], iwork)


def build_kernel(manipulator):
    """The batch kernel of a numeric design, or None where the kernel does not apply (no numba,
    a PP dyad, a Cramer denominator vanishing identically): the generic compiled loop bound to
    the design's :func:`design_tables`. No per-design code is generated or compiled.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.kernel import build_kernel, HAVE_NUMBA
    >>> k = build_kernel(isp.examples.general_3rpr())
    >>> (k is not None) == HAVE_NUMBA
    True
    """
    if not HAVE_NUMBA:
        return None
    tables = design_tables(manipulator)
    if tables is None:
        return None
    return BatchKernel(tables, manipulator.tolerances)
