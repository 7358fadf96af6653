"""The results of the direct kinematics: AssemblyMode, CertifiedModes and DKBatchResult."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional, Sequence, Union
import numpy as np

from .._html import html_table, modes_table, summary
from .._validate import as_row_index, as_row_indices
from ..exceptions import InputError, InputTypeError
from ..core.mechanism import index_rows
from ..core.kinematic_map import image_point as _image_point

__all__ = ["AssemblyMode", "AssemblyModes", "CertifiedModes", "DKBatchResult"]

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


class AssemblyModes(list):
    """The assembly modes of one joint vector from the floating-point direct kinematics: a list of
    :class:`AssemblyMode` that Jupyter shows as a table (one row a mode). The count is not proven
    here; ``direct_kinematics(q, certify=True)`` gives :class:`CertifiedModes`.

    Examples
    --------
    >>> import imagespace as isp
    >>> m = isp.examples.general_3rpr()
    >>> modes = m.direct_kinematics(m.q_example)
    >>> type(modes).__name__, len(modes), modes._repr_html_().count("<tr>")
    ('AssemblyModes', 6, 7)
    """

    def __repr__(self):
        return f"AssemblyModes({list.__repr__(self)})"

    def _repr_html_(self):
        real = sum(1 for mm in self if mm.is_real)
        title = (f"{real} real assembly mode{'' if real == 1 else 's'}"
                 + (f" and {len(self) - real} complex" if len(self) > real else "")
                 + " (floating point; certify=True proves the count)")
        return modes_table(list(self), title=title)


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
        Per certified real root (ascending ``t = x1/x0``, half-turn last), its modes.
    root_of_mode : tuple of int
        For each mode (in list order), the index of its root in the certificate.
    doubts : tuple of str
        What is not proven (the :class:`~imagespace.NearSingularWarning` messages; empty: proven).
    """

    def __init__(self, modes, certificate, modes_per_root, root_of_mode=(), doubts=()):
        super().__init__(modes)
        self.certificate = certificate
        self.modes_per_root = tuple(modes_per_root)
        self.root_of_mode = tuple(root_of_mode)
        self.doubts = tuple(doubts)

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


#: Names of the paths that answer a batch row, indexed by :attr:`DKBatchResult.solver_code`
#: (``"kernel"``: the compiled kernel, ``"numpy"``: the vectorised numpy path, ``"certified"``:
#: the per-row certified path, ``"invalid"``: a row that could not be solved).
SOLVER_NAMES = ("kernel", "numpy", "certified", "invalid")

#: Names of the certificate paths of a batch row (``certify=True``), indexed by
#: :attr:`DKBatchResult.certificate_path_code`: the values
#: :func:`~imagespace.core.certify.certify_real_roots_batch` reports (``"discs"``, ``"flint"``,
#: ``"zero"``, ``"uncertified"``, ``"invalid"``), those the certified batch adds (``"arb"``,
#: ``"continuum"``), ``"kernel"`` (a count certified inside the compiled kernel) and ``"reach"`` (no
#: real mode, proven by a reach bound, :mod:`imagespace.core.reach`).
CERTIFICATE_PATHS = ("discs", "flint", "arb", "uncertified", "invalid", "zero", "continuum", "kernel",
                     "reach")

#: Padded arrays built on access (:attr:`DKBatchResult.poses`, ...) are kept, read-only, while
#: the result is unchanged and all kept arrays together take at most this many bytes (so a loop
#: over the rows of a small result does not rebuild them per row); larger ones are built on every
#: access and not kept. Counted in :attr:`DKBatchResult.nbytes`.
PADDED_CACHE_BYTES = 8_000_000

#: Up to this many rows, a mutation copies the untouched runs of modes between the rows as blocks
#: (fast for the few rows a producer re-solves); more rows take one vectorised scatter. A speed
#: knob, not a decision: both give the same result.
SPLICE_BLOCK_ROWS = 512

_SOLVER_TABLE = np.array(SOLVER_NAMES)
_PATH_TABLE = np.array(CERTIFICATE_PATHS)
_INVALID = SOLVER_NAMES.index("invalid")


def _encode(values, table, name):
    """Codes (uint8) of an array of names from ``table`` (a tuple of str)."""
    arr = np.asarray(values)
    if arr.dtype.kind in "iu":
        if arr.size and (arr.min() < 0 or arr.max() >= len(table)):
            raise ValueError(f"{name} codes must lie in 0 .. {len(table) - 1}, got {arr.min()} .. {arr.max()}")
        return arr.astype(np.uint8)
    codes = np.full(arr.shape, 255, dtype=np.uint8)
    for k, v in enumerate(table):
        codes[arr == v] = k
    if np.any(codes == 255):
        bad = sorted({str(v) for v in arr[codes == 255].tolist()})
        raise ValueError(f"{name} must hold names from {table}, got {bad[:5]}")
    return codes


def _names_counts(codes, table):
    """``name: rows`` text of a code array (as :func:`imagespace._html.counts_text`, in O(n))."""
    hist = np.bincount(codes, minlength=len(table)) if codes.size else np.zeros(len(table), int)
    return ", ".join(f"{table[k]}: {int(hist[k])}" for k in sorted(np.flatnonzero(hist), key=lambda k: table[k]))


def _value_counts(values):
    """``value: rows`` text of a small non-negative integer array, in ascending order."""
    hist = np.bincount(values) if values.size else np.zeros(0, int)
    return ", ".join(f"{k}: {int(hist[k])}" for k in np.flatnonzero(hist))


def _offsets(count):
    """Cumulative mode offsets (n + 1,) int64 of the per-row counts."""
    off = np.zeros(count.shape[0] + 1, dtype=np.int64)
    np.cumsum(count, out=off[1:])
    return off


def _read_only(a):
    a = np.asarray(a)
    if a.flags.writeable:
        a = a.view()
        a.flags.writeable = False
    return a


class DKBatchResult:
    """Direct kinematics of a batch of joint vectors.

    The modes are held ragged (only the real modes, row after row: ``nbytes`` is about 120 bytes
    per row for four modes); the padded ``(n, 6, ...)`` attributes below are built on access and
    read-only. The producers change a result through :meth:`set_modes`, :meth:`replace_rows`
    and :meth:`set_solver`.

    Attributes
    ----------
    image_points : (n, 6, 4) float, read-only
        Normalised image points of the real modes, NaN in unused slots (derived from ``poses``
        by :func:`~imagespace.core.kinematic_map.image_point`, not stored).
    poses : (n, 6, 3) float, read-only
    valid : (n, 6) bool, read-only
        Which slots hold a mode (valid slots come first, sorted by ``phi``).
    count : (n,) uint8, read-only
        Number of real assembly modes per row.
    aspect : (n, 6) int8, read-only
        0 in unused slots.
    row_ok : (n,) bool
        False for rows that could not be solved (non-finite input, a joint value outside its
        domain, a degenerate design at those joint values); see ``errors``.
    errors : dict
        Row index -> message for every row with ``row_ok`` False.
    special : (n,) bool
        Rows that needed the careful per-row path (Cramer denominator vanishing identically or
        at a root, polynomial identically zero; with the kernel also a root touching the axis).
    residual : (n, 6) float, read-only
        Joint-space residual of each mode: from the legs' inverse kinematics on the numpy path,
        to first order ``max_i |Q_i| / |dQ_i/dq_i|`` on the kernel path. NaN in unused slots.
    solver : (n,) str, read-only
        Which path answered each row: ``"kernel"`` (compiled one-pass kernel), ``"numpy"``
        (vectorised numpy path), ``"certified"`` (per-row certified path), ``"invalid"``.
        Stored as ``solver_code`` (uint8) indexing :data:`SOLVER_NAMES`.
    solver_code : (n,) uint8, read-only
        ``SOLVER_NAMES[solver_code[i]] == solver[i]``.
    certified_roots : (n,) int8, only with ``certify=True``
        Proven number of distinct real roots of the kinematic polynomial per row (-1 where the
        row is not valid).
    certificate_path : (n,) str, read-only, only with ``certify=True``
        ``"kernel"`` (proven inside the compiled kernel: bounded elimination and Bernstein
        isolation), ``"discs"`` (vectorised inclusion discs, designs the kernel does not take),
        ``"flint"`` (exact isolation), ``"arb"``, ``"uncertified"``, ``"zero"``, ``"continuum"``
        or ``"invalid"``; stored as
        ``certificate_path_code``.
    certificate_path_code : (n,) uint8, read-only, only with ``certify=True``
        ``CERTIFICATE_PATHS[certificate_path_code[i]] == certificate_path[i]``.
    consistent : (n,) bool, only with ``certify=True``
        The row's modes are accounted for by its certificate: either every certified real root
        (all simple, inclusion discs) holds exactly one float mode and no mode lies outside
        them, or the row was solved again root by root by ``direct_kinematics(q, certify=True)``
        (``solver == "certified"``). False only where no certificate could be had (masked rows,
        irrational coefficients with a multiple root).
    near_singular : (n,) bool
        The floating-point answer of this row may have the wrong count: the real roots of its
        exact kinematic polynomial could not be proven simple and isolated
        (:func:`imagespace.solve.proof.proven_roots`), or the modes found do not sit one per
        proven root (:func:`imagespace.solve.proof.modes_match_roots`). A row without the flag
        has the proven count. Rows the compiled kernel answers itself (their roots isolated
        on a rigorous enclosure), rows answered by the certified path and, with
        ``certify=True``, every ``consistent`` row are never near-singular.
    multiplicity : (n, 6) int8, read-only
        Multiplicity of each mode's root (1 except on rows solved by the certified path; 1 in
        unused slots as well). Not stored while every mode has multiplicity 1.

    nbytes : int
        Bytes of the arrays held (see the property).

    Certified semantics (``certify=True``): as for :class:`CertifiedModes`, on every row.

    The constructor takes the padded arrays (as :meth:`from_padded`) and keeps only the real
    modes; ``image_points`` is accepted for the old signature and not stored.
    """

    def __init__(self, image_points: Optional[np.ndarray], poses: np.ndarray, valid: np.ndarray,
                 count: Optional[np.ndarray], residual: np.ndarray, aspect: np.ndarray, row_ok: np.ndarray,
                 errors: Optional[dict] = None, special: Optional[np.ndarray] = None,
                 solver: Optional[np.ndarray] = None, certified_roots: Optional[np.ndarray] = None,
                 certificate_path: Optional[np.ndarray] = None, consistent: Optional[np.ndarray] = None,
                 near_singular: Optional[np.ndarray] = None, multiplicity: Optional[np.ndarray] = None):
        valid = np.asarray(valid, dtype=bool)
        n = valid.shape[0]
        if valid.shape != (n, MAX_MODES):
            raise ValueError(f"valid must have shape (n, {MAX_MODES}), got {valid.shape}")
        # with a count whose first slots are exactly the valid ones both checks below hold at once
        given = None if count is None else np.asarray(count)
        if given is not None and given.shape == (n,) and np.array_equal(valid, np.arange(MAX_MODES) < given[:, None]):
            cnt = given.astype(np.uint8)
        else:
            cnt = np.count_nonzero(valid, axis=1).astype(np.uint8)
            if given is not None and not np.array_equal(given, cnt):
                i = int(np.flatnonzero(given != cnt)[0])
                raise ValueError(f"count must equal the number of valid slots per row, got count[{i}] = "
                                 f"{given[i]} with {cnt[i]} valid slots")
            if not np.array_equal(valid, np.arange(MAX_MODES) < cnt[:, None]):
                i = int(np.flatnonzero(np.any(valid != (np.arange(MAX_MODES) < cnt[:, None]), axis=1))[0])
                raise ValueError(f"valid slots must come first in each row, got valid[{i}] = {valid[i].tolist()}")
        for name, arr, shape in (("poses", poses, (n, MAX_MODES, 3)), ("residual", residual, (n, MAX_MODES)),
                                 ("aspect", aspect, (n, MAX_MODES))):
            if np.shape(arr) != shape:
                raise ValueError(f"{name} must have shape {shape}, got {np.shape(arr)}")
        # the valid slots' flat indices, gathered with take (several times faster than a mask)
        slots = np.flatnonzero(valid.reshape(-1))
        mult = None
        if multiplicity is not None:
            mc = np.asarray(multiplicity).reshape(-1).take(slots)
            if np.any(mc != 1):
                mult = mc.astype(np.int8)
        self._set_modes(cnt, np.asarray(poses, dtype=float).reshape(-1, 3).take(slots, axis=0),
                        np.asarray(residual, dtype=float).reshape(-1).take(slots),
                        np.asarray(aspect).reshape(-1).take(slots).astype(np.int8), mult)
        self.row_ok = np.asarray(row_ok, dtype=bool)
        self.errors = {} if errors is None else errors
        self.special = None if special is None else np.asarray(special, dtype=bool)
        self.near_singular = None if near_singular is None else np.asarray(near_singular, dtype=bool)
        self.consistent = None if consistent is None else np.asarray(consistent, dtype=bool)
        self._solver: Optional[np.ndarray] = None
        self._certified_roots: Optional[np.ndarray] = None
        self._certificate_path: Optional[np.ndarray] = None
        self.solver = solver
        self.certified_roots = certified_roots
        self.certificate_path = certificate_path

    @classmethod
    def from_padded(cls, poses: np.ndarray, valid: np.ndarray, residual: np.ndarray, aspect: np.ndarray,
                    row_ok: np.ndarray, **fields: Any) -> "DKBatchResult":
        """A result from padded ``(n, 6, ...)`` arrays (what the kernel and the numpy path build),
        keeping only the valid slots.

        Parameters
        ----------
        poses : (n, 6, 3) float
        valid : (n, 6) bool
            Valid slots first in each row.
        residual : (n, 6) float
        aspect : (n, 6) int
        row_ok : (n,) bool
        **fields
            ``errors``, ``special``, ``solver`` (names or codes), ``certified_roots``,
            ``certificate_path``, ``consistent``, ``near_singular``, ``multiplicity``, ``count``
            (checked against ``valid``), ``image_points`` (ignored: derived from ``poses``).

        Raises
        ------
        ValueError
            ``valid`` is not of shape ``(n, 6)``, has a valid slot after an unused one, or
            disagrees with ``count``; a solver or certificate path name is not in the table.

        Examples
        --------
        >>> import numpy as np
        >>> from imagespace.solve.results import DKBatchResult
        >>> P = np.full((2, 6, 3), np.nan); P[0, 0] = [1.0, 2.0, 0.5]
        >>> r = DKBatchResult.from_padded(P, ~np.isnan(P[..., 0]), np.zeros((2, 6)),
        ...                               np.ones((2, 6), int), np.array([True, True]), solver="numpy")
        >>> r.count.tolist(), r.poses[0, 0].tolist(), r.solver.tolist()
        ([1, 0], [1.0, 2.0, 0.5], ['numpy', 'numpy'])
        """
        image_points = fields.pop("image_points", None)
        count = fields.pop("count", None)
        return cls(image_points, poses, valid, count, residual, aspect, row_ok, **fields)

    @classmethod
    def concatenate(cls, parts: Sequence["DKBatchResult"]) -> "DKBatchResult":
        """The rows of ``parts`` one after the other, in one result (errors renumbered; a field
        present in some parts only is filled with its empty value: False, ``"invalid"``, -1).

        Raises
        ------
        InputError
            ``parts`` is empty.
        InputTypeError
            ``parts`` is not a sequence of :class:`DKBatchResult`.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> a = m.direct_kinematics_batch([m.q_example_float])
        >>> b = m.direct_kinematics_batch([[float("nan"), 1.0, 1.0]])
        >>> r = DKBatchResult.concatenate([a, b])
        >>> r.count.tolist(), r.solver.tolist(), list(r.errors)
        ([6, 0], ['numpy', 'invalid'], [1])
        """
        parts = list(parts) if not isinstance(parts, (str, bytes, DKBatchResult)) and hasattr(parts, "__iter__") \
            else [parts]  # type: ignore[list-item]  # a lone result (or junk, refused just below)
        if not parts:
            raise InputError("parts must hold at least one DKBatchResult, got none")
        for i, p in enumerate(parts):
            if not isinstance(p, DKBatchResult):
                raise InputTypeError(f"parts[{i}] must be a DKBatchResult, got {type(p).__name__} {p!r:.60}")
        if len(parts) == 1:
            p = parts[0]
            out = cls.__new__(cls)
            out.__dict__.update({k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in vars(p).items()})
            out.errors = dict(p.errors)
            out.release_padded()
            return out
        sizes = [len(p) for p in parts]
        start = np.concatenate([[0], np.cumsum(sizes)]).astype(int)

        def cat(attr, fill, dtype, per_mode=False):
            vals = [getattr(p, attr) for p in parts]
            if all(v is None for v in vals):
                return None
            return np.concatenate([v if v is not None else
                                   np.full(len(p._poses) if per_mode else len(p), fill, dtype=dtype)
                                   for v, p in zip(vals, parts)])

        out = cls.__new__(cls)
        out._set_modes(np.concatenate([p._count for p in parts]), np.concatenate([p._poses for p in parts]),
                       np.concatenate([p._residual for p in parts]), np.concatenate([p._aspect for p in parts]),
                       cat("_multiplicity", 1, np.int8, per_mode=True))
        out.row_ok = np.concatenate([p.row_ok for p in parts])
        out.errors = {int(k) + int(s0): msg for p, s0 in zip(parts, start) for k, msg in p.errors.items()}
        out.special = cat("special", False, bool)
        out.near_singular = cat("near_singular", False, bool)
        out.consistent = cat("consistent", False, bool)
        out._solver = cat("_solver", _INVALID, np.uint8)
        out._certified_roots = cat("_certified_roots", -1, np.int8)
        out._certificate_path = cat("_certificate_path", CERTIFICATE_PATHS.index("invalid"), np.uint8)
        return out

    # -- the ragged storage ------------------------------------------------------------------------
    def _set_modes(self, count, poses, residual, aspect, multiplicity):
        """Install the ragged modes (count uint8 (n,), per-mode arrays (M, ...)); drop kept arrays."""
        self._count = count
        self._offsets = _offsets(count)
        self._poses = poses
        self._residual = residual
        self._aspect = aspect
        self._multiplicity = multiplicity
        self._cache = {}

    def __len__(self):
        return int(self._count.shape[0])

    @property
    def nbytes(self) -> int:
        """Bytes of every array the result holds (ragged modes, per-row arrays, offsets and the
        padded arrays kept from an access, see :data:`PADDED_CACHE_BYTES`); ``errors`` not counted.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> r = m.direct_kinematics_batch([m.q_example_float] * 10)
        >>> r.nbytes    # 60 modes * 33 B (pose, residual, aspect) + 10 rows * 5 B + 11 offsets * 8 B
        2118
        """
        total = sum(v.nbytes for v in vars(self).values() if isinstance(v, np.ndarray))
        return int(total + sum(v.nbytes for v in self._cache.values()))

    _cache: dict

    def release_padded(self) -> None:
        """Drop the padded arrays kept from earlier accesses (see :data:`PADDED_CACHE_BYTES`).

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> r = m.direct_kinematics_batch([m.q_example_float] * 10)
        >>> before = r.nbytes
        >>> _ = r.poses
        >>> r.nbytes - before, r.release_padded(), r.nbytes - before     # poses 60 * 24 B, valid 60 B
        (1500, None, 0)
        """
        self._cache = {}

    @property
    def count(self) -> np.ndarray:
        """(n,) uint8, read-only: the number of real modes per row."""
        return _read_only(self._count)

    def _row_slice(self, i):
        i = as_row_index(i, len(self))         # numpy-like: negative indices wrap
        return slice(int(self._offsets[i]), int(self._offsets[i + 1]))

    def _padded(self, name, build):
        arr = self._cache.get(name)
        if arr is None:
            arr = build()
            arr.flags.writeable = False
            if arr.nbytes + sum(v.nbytes for v in self._cache.values()) <= PADDED_CACHE_BYTES:
                self._cache[name] = arr
        return arr

    def _scatter(self, values, fill, dtype, trailing=()):
        out = np.full((len(self), MAX_MODES) + trailing, fill, dtype=dtype)
        out[self.valid] = values
        return out

    @property
    def valid(self) -> np.ndarray:
        return self._padded("valid", lambda: np.arange(MAX_MODES) < self._count[:, None])

    @property
    def poses(self) -> np.ndarray:
        return self._padded("poses", lambda: self._scatter(self._poses, np.nan, float, (3,)))

    @property
    def image_points(self) -> np.ndarray:
        return self._padded("image_points", lambda: self._scatter(
            _image_point(self._poses) if len(self._poses) else np.zeros((0, 4)), np.nan, float, (4,)))

    @property
    def residual(self) -> np.ndarray:
        return self._padded("residual", lambda: self._scatter(self._residual, np.nan, float))

    @property
    def aspect(self) -> np.ndarray:
        return self._padded("aspect", lambda: self._scatter(self._aspect, 0, np.int8))

    @property
    def multiplicity(self) -> np.ndarray:
        def build():
            if self._multiplicity is None:
                return np.ones((len(self), MAX_MODES), dtype=np.int8)
            return self._scatter(self._multiplicity, 1, np.int8)
        return self._padded("multiplicity", build)

    def _per_row(self, a, name):
        """``a`` as a fresh (n,) array (a scalar is broadcast to every row)."""
        if a.ndim == 0:
            return np.full(len(self), a, dtype=a.dtype)
        if a.shape != (len(self),):
            raise ValueError(f"{name} must have shape ({len(self)},), got {a.shape}")
        return a

    @property
    def solver(self) -> Optional[np.ndarray]:
        if self._solver is None:
            return None
        return self._padded("solver", lambda: _SOLVER_TABLE[self._solver])

    @solver.setter
    def solver(self, names: Any) -> None:
        self._cache.pop("solver", None)
        self._solver = None if names is None else self._per_row(_encode(names, SOLVER_NAMES, "solver"), "solver")

    @property
    def solver_code(self) -> Optional[np.ndarray]:
        return None if self._solver is None else _read_only(self._solver)

    @property
    def certificate_path(self) -> Optional[np.ndarray]:
        if self._certificate_path is None:
            return None
        return self._padded("certificate_path", lambda: _PATH_TABLE[self._certificate_path])

    @certificate_path.setter
    def certificate_path(self, names: Any) -> None:
        self._cache.pop("certificate_path", None)
        self._certificate_path = None if names is None else self._per_row(
            _encode(names, CERTIFICATE_PATHS, "certificate_path"), "certificate_path")

    @property
    def certificate_path_code(self) -> Optional[np.ndarray]:
        return None if self._certificate_path is None else _read_only(self._certificate_path)

    @property
    def certified_roots(self) -> Optional[np.ndarray]:
        return self._certified_roots

    @certified_roots.setter
    def certified_roots(self, counts: Any) -> None:
        if counts is None:
            self._certified_roots = None
            return
        c = np.asarray(counts)
        if c.size and (c.min() < -1 or c.max() > 127):
            raise ValueError(f"certified_roots must lie in -1 .. 127, got {c.min()} .. {c.max()}")
        self._certified_roots = self._per_row(c.astype(np.int8), "certified_roots")

    # -- mutation ------------------------------------------------------------------------------------
    def _splice(self, rows, count, poses, residual, aspect, multiplicity):
        """Replace the modes of the distinct ``rows`` (int array) by ragged ones (``count`` per row,
        per-mode arrays in the order of ``rows``): one O(n + M) rebuild, one field at a time (the
        peak is the result plus its largest field)."""
        n = len(self)
        old_off = self._offsets
        new_count = self._count.copy()
        new_count[rows] = count
        off = _offsets(new_count)
        sub_off = _offsets(count)
        total = int(off[-1])
        if rows.size <= SPLICE_BLOCK_ROWS:
            # few rows: copy the untouched runs of modes between them as blocks
            order = np.argsort(rows, kind="stable")
            segments = []                      # (destination start, source, source start, length)
            prev = 0
            for k in order.tolist():
                r = int(rows[k])
                a, b = int(old_off[prev]), int(old_off[r])
                segments.append((int(off[prev]), "old", a, b - a))
                segments.append((int(off[r]), "new", int(sub_off[k]), int(count[k])))
                prev = r + 1
            segments.append((int(off[prev]), "old", int(old_off[prev]), int(old_off[n]) - int(old_off[prev])))

            def merge(old, new, fill, dtype):
                out = np.empty((total,) + old.shape[1:], dtype=dtype)
                for d, src, a, length in segments:
                    if length:
                        out[d:d + length] = (old if src == "old" else new)[a:a + length]
                return out
        else:
            keep = np.ones(n, dtype=bool)
            keep[rows] = False
            keep_modes = np.repeat(keep, self._count)             # old modes kept, in order
            kc = self._count[keep]
            dest_keep = np.repeat(off[:-1][keep] - old_off[:-1][keep], kc) + np.flatnonzero(keep_modes)
            del keep_modes
            dest_sub = np.repeat(off[rows] - sub_off[:-1], count) + np.arange(int(sub_off[-1]))

            def merge(old, new, fill, dtype):
                out = np.empty((total,) + old.shape[1:], dtype=dtype)
                out[dest_keep] = old[np.repeat(keep, self._count)]
                out[dest_sub] = new
                return out

        if self._multiplicity is not None or multiplicity is not None:
            old_m = self._multiplicity if self._multiplicity is not None else np.ones(len(self._poses), np.int8)
            new_m = multiplicity if multiplicity is not None else np.ones(len(poses), np.int8)
            mult = merge(old_m, new_m, 1, np.int8)
            self._multiplicity = None if np.all(mult == 1) else mult
        self._poses = merge(self._poses, poses, np.nan, float)
        self._residual = merge(self._residual, residual, np.nan, float)
        self._aspect = merge(self._aspect, aspect, 0, np.int8)
        self._count, self._offsets = new_count, off
        self.release_padded()

    def set_modes(self, rows: Union[int, Sequence[int], np.ndarray], modes: Sequence) -> None:
        """Overwrite the modes of rows with lists of :class:`AssemblyMode` (at most six per row,
        extra modes are dropped), in one rebuild.

        Parameters
        ----------
        rows : int or sequence of int
        modes : list of AssemblyMode (``rows`` an int) or one such list per row

        Raises
        ------
        InputError
            Repeated rows, or not one list of modes per row.
        InputTypeError
            ``modes`` does not hold lists of :class:`AssemblyMode`.
        RowIndexError
            A row outside the result.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> r = m.direct_kinematics_batch([m.q_example_float] * 2)
        >>> r.set_modes(1, r.modes(0)[:2])
        >>> r.count.tolist()
        [6, 2]
        """
        if np.ndim(rows) == 0:
            r = as_row_indices(np.array([rows]), len(self))
            modes = [modes]
        else:
            r = as_row_indices(rows, len(self))
        if isinstance(modes, (str, bytes)) or not hasattr(modes, "__len__"):
            raise InputTypeError(f"modes must be lists of AssemblyMode (one per row), got {type(modes).__name__}")
        if len(modes) != r.size:
            raise InputError(f"modes must hold one list per row ({r.size}), got {len(modes)}")
        lists = [list(ms)[:MAX_MODES] if not isinstance(ms, (str, bytes)) and hasattr(ms, "__iter__") else ms
                 for ms in modes]
        for k, ms in enumerate(lists):
            bad = [ms] if not isinstance(ms, list) else [mm for mm in ms if not isinstance(mm, AssemblyMode)]
            if bad:
                raise InputTypeError(f"modes[{k}] must hold AssemblyMode objects, got {type(bad[0]).__name__} "
                                     f"{bad[0]!r:.60}")
        flat = [mm for ms in lists for mm in ms]
        count = np.array([len(ms) for ms in lists], dtype=np.uint8)
        poses = np.array([mm.pose for mm in flat], dtype=float).reshape(-1, 3)
        self._splice(r, count, poses, np.array([mm.residual for mm in flat], dtype=float),
                     np.array([mm.aspect for mm in flat], dtype=np.int8),
                     np.array([mm.multiplicity for mm in flat], dtype=np.int8))

    def replace_rows(self, rows: Union[Sequence[int], np.ndarray], sub: "DKBatchResult") -> None:
        """Copy every per-row field and the modes of ``sub`` (a result of ``len(rows)`` rows) into
        ``rows``, in one rebuild; ``sub``'s errors are renumbered to ``rows``.

        Raises
        ------
        ValueError
            Repeated rows, or ``sub`` has not ``len(rows)`` rows.
        IndexError
            A row outside the result.

        Examples
        --------
        >>> import imagespace as isp
        >>> import numpy as np
        >>> m = isp.examples.general_3rpr()
        >>> r = m.direct_kinematics_batch([m.q_example_float] * 3, method="numpy")
        >>> r.replace_rows([2], m.direct_kinematics_batch([[np.nan, 1, 1]]))
        >>> r.count.tolist(), r.solver.tolist(), list(r.errors)
        ([6, 6, 0], ['numpy', 'numpy', 'invalid'], [2])
        """
        r = as_row_indices(rows, len(self))
        if len(sub) != r.size:
            raise ValueError(f"sub must have {r.size} rows (one per row), got {len(sub)}")
        self._splice(r, sub._count, sub._poses, sub._residual, sub._aspect, sub._multiplicity)
        self.row_ok[r] = sub.row_ok
        for k in r.tolist():
            self.errors.pop(k, None)
        for k, msg in sub.errors.items():
            self.errors[int(r[k])] = msg
        n = len(self)
        for name in ("special", "near_singular", "consistent"):
            mine, theirs = getattr(self, name), getattr(sub, name)
            if theirs is not None:
                if mine is None:
                    mine = np.zeros(n, dtype=bool)
                    setattr(self, name, mine)
                mine[r] = theirs
        for attr, fill in (("_solver", _INVALID), ("_certificate_path", CERTIFICATE_PATHS.index("invalid")),
                           ("_certified_roots", -1)):
            theirs = getattr(sub, attr)
            if theirs is not None:
                mine = getattr(self, attr)
                if mine is None:
                    mine = np.full(n, fill, dtype=theirs.dtype)
                    setattr(self, attr, mine)
                mine[r] = theirs
        self._cache.pop("solver", None)
        self._cache.pop("certificate_path", None)

    def set_solver(self, rows: Union[int, Sequence[int], np.ndarray], name: str) -> None:
        """Record that ``name`` (one of :data:`SOLVER_NAMES`) answered ``rows`` (indices or a
        boolean mask).

        Raises
        ------
        ValueError
            ``name`` is not in :data:`SOLVER_NAMES`.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> r = m.direct_kinematics_batch([m.q_example_float] * 2)
        >>> r.set_solver([1], "certified")
        >>> r.solver.tolist(), r.solver_code.tolist()
        (['numpy', 'certified'], [1, 2])
        """
        if name not in SOLVER_NAMES:
            raise ValueError(f"name must be one of {SOLVER_NAMES}, got {name!r}")
        if self._solver is None:
            self._solver = np.full(len(self), _INVALID, dtype=np.uint8)
        self._solver[as_row_indices(rows, len(self))] = SOLVER_NAMES.index(name)
        self._cache.pop("solver", None)

    # -- reading ---------------------------------------------------------------------------------------
    def modes(self, i):
        """The modes of row ``i`` as a list of :class:`AssemblyMode`.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> len(m.direct_kinematics_batch([m.q_example_float]).modes(0))
        6
        """
        s = self._row_slice(i)
        P = self._poses[s]
        if not len(P):
            return []
        X = _image_point(P)
        mult = self._multiplicity
        return [AssemblyMode(X[j], P[j].copy(), float(self._residual[s][j]), int(self._aspect[s][j]), True,
                             1 if mult is None else int(mult[s][j]))
                for j in range(len(P))]

    def __getitem__(self, i):
        """Row ``i``'s modes as the per-call answer (an :class:`AssemblyModes`); negative ``i``
        counts from the end, a slice gives a list of them.

        Raises
        ------
        RowIndexError
            ``i`` is out of range (an ``IndexError``); InputTypeError: not an integer or a slice.

        Examples
        --------
        >>> import numpy as np, imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> r = m.direct_kinematics_batch(np.array([m.q_example_float, [np.nan, 1, 1]]))
        >>> len(r[0]), len(r[-1]), [len(x) for x in r[::-1]]
        (6, 0, [0, 6])
        """
        return index_rows(self, i, lambda k: AssemblyModes(self.modes(k)))

    @property
    def certified(self) -> np.ndarray:
        """(n,) bool: rows whose modes are proven (``certify=True``: the certified count accounts
        for them); all False without a certificate.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> m.direct_kinematics_batch([m.q_example_float], certify=True).certified.tolist()
        [True]
        """
        if self.consistent is None:
            return np.zeros(len(self), dtype=bool)
        return np.asarray(self.consistent, dtype=bool) & np.asarray(self.row_ok, dtype=bool)

    def _summary_rows(self):
        n = len(self)
        rows = [("rows", n), ("solved rows", int(np.count_nonzero(self.row_ok))),
                ("failed rows", len(self.errors))]
        if self._solver is not None:
            rows.append(("solver", _names_counts(self._solver, SOLVER_NAMES)))
        for name in ("special", "near_singular", "consistent"):
            flags = getattr(self, name)
            if flags is not None:
                rows.append((f"{name} rows", int(np.count_nonzero(flags))))
        if self._certificate_path is not None:
            rows.append(("certificate path", _names_counts(self._certificate_path, CERTIFICATE_PATHS)))
        rows.append(("modes per row", _value_counts(self._count)))
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
        hist = np.bincount(self._count) if len(self) else np.zeros(0, int)
        values = np.flatnonzero(hist)
        return (html_table(self._summary_rows()[:-1], title=f"DKBatchResult: {len(self)} rows")
                + "\n" + html_table(zip(values.tolist(), hist[values].tolist()), title="real modes per row",
                                    header=("modes", "rows")))
