"""The results of the direct kinematics: AssemblyMode, CertifiedModes and DKBatchResult."""

from __future__ import annotations

import numpy as np
from dataclasses import dataclass, field
from typing import Optional

from .._html import counts_text, html_table, modes_table, summary

__all__ = ["AssemblyMode", "CertifiedModes", "DKBatchResult"]

#: Width of a :class:`DKBatchResult` row: a non-degenerate planar 3-leg design has at most six
#: assembly modes (the kinematic polynomial has degree <= 6). The numpy path, the kernel and the
#: certified path size their result arrays with it and refuse more modes as a degenerate design.
#: A shared structural constant of the solve stage, not public API (out of ``__all__``).
MAX_MODES = 6


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

    def _repr_html_(self):
        """A one-mode table for Jupyter.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> "aspect" in m.direct_kinematics(m.q_example)[0]._repr_html_()
        True
        """
        return modes_table([self], title="AssemblyMode")


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

    def _repr_html_(self):
        """The modes as a table (one row each) under the certificate's count and method.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> "6 real roots" in m.direct_kinematics(m.q_example, certify=True)._repr_html_()
        True
        """
        cert = self.certificate
        title = (f"CertifiedModes: {len(self)} modes, {cert.count} real roots "
                 f"(method {cert.method})")
        return modes_table(list(self), title=title, roots=self.root_of_mode)


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

    def _summary_rows(self):
        n = len(self.count)
        rows = [("rows", n), ("solved rows", int(np.count_nonzero(self.row_ok))),
                ("failed rows", len(self.errors))]
        if self.solver is not None:
            rows.append(("solver", counts_text(self.solver)))
        for name in ("special", "near_singular", "consistent"):
            flags = getattr(self, name)
            if flags is not None:
                rows.append((f"{name} rows", int(np.count_nonzero(flags))))
        if self.certificate_path is not None:
            rows.append(("certificate path", counts_text(self.certificate_path)))
        rows.append(("modes per row", counts_text(self.count)))
        return rows

    def __repr__(self):
        """A summary (rows, the histogram of the mode counts, solvers, flags), never the arrays.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> print(m.direct_kinematics_batch([m.q_example_float] * 3))  # doctest: +ELLIPSIS
        DKBatchResult(rows=3, solved_rows=3, failed_rows=0, solver={...: 3}, special_rows=0,
                      near_singular_rows=0, modes_per_row={6: 3})
        """
        return summary("DKBatchResult", [(k.replace(" ", "_"), "{" + v + "}" if isinstance(v, str) else str(v))
                                         for k, v in self._summary_rows()])

    def _repr_html_(self):
        """A summary table and the histogram of the number of real modes per row.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> "<table" in m.direct_kinematics_batch([m.q_example_float])._repr_html_()
        True
        """
        values, rows = np.unique(np.asarray(self.count), return_counts=True)
        return (html_table(self._summary_rows()[:-1], title=f"DKBatchResult: {len(self.count)} rows")
                + "\n" + html_table(zip(values.tolist(), rows.tolist()), title="real modes per row",
                                    header=("modes", "rows")))
