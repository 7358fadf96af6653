r"""One start system per family kind, carried to each design in milliseconds (issue [18], target 2).

A design's start system (:class:`~imagespace.spatial.homotopy.StartSystem`) is its regular finite
solutions at generic complex squared lengths ``p*``. Before, every design paid a total-degree
homotopy for it (:func:`~imagespace.spatial.homotopy.solve_start_system`, ``2^7`` paths per
attempt). Here the DESIGN moves too (coefficient-parameter homotopy, Morgan & Sommese 1989): a
leg's quadric :func:`~imagespace.spatial.quadrics.sphere_quadric` is an affine function of the
coefficients ``(a, b, W, c)`` -- base point, platform point, their products ``W = a b^T`` and
``c = |a|^2 + |b|^2 - L^2`` (:func:`~imagespace.spatial.quadrics.sphere_quadric_linear`). Letting
``W`` and ``c`` be arbitrary gives a linear family containing every Gough-Stewart design (6-6,
6-3, 3-6 and 3-3 alike). Its generic member is solved ONCE per process (and kept on disk next to
the compiled kernels, :func:`imagespace.core.codegen.kernel_cache_dir`), and each design's start
is the endpoint set of :func:`~imagespace.spatial.homotopy.move_start_system` from that member
(``LEG_FAMILY_COUNT`` paths instead of hundreds).

The count. The generic member of the linear family has ``LEG_FAMILY_COUNT = 40`` regular finite
solutions (measured with the total-degree solver: 40 on every random member tried, 768 paths each,
every other endpoint on the two-dimensional component ``x = 0, y . y = 0`` that every member
contains; ``tests/spatial/test_families.py`` repeats the count). So the generic member's 40
solutions reach every isolated solution (with ``x != 0``) of every design: 40 for a general one,
16 for a 6-3, 3-6 or 3-3 one (the other paths end on ``x = 0`` or diverge).

Never a short start system. A design's moved start is used only when it holds exactly the
family's theorem bound (:attr:`~imagespace.spatial.solver.QuadricFamily.bound`); otherwise (a
special design with fewer generic solutions, a lost path) the total-degree route is taken, as
before -- a missing start solution would be a missed assembly mode.

Which families. ``"legs6"``: six sphere quadrics (parameters ``p_0 .. p_5``) and Study's quadric,
i.e. every :class:`~imagespace.spatial.GoughStewart`. ``"rps3"``: three sphere quadrics
(parameters ``p_0 .. p_2``), three plane quadrics and Study's quadric, i.e. every
:class:`~imagespace.spatial.ThreeRPS`: a plane quadric
(:func:`~imagespace.spatial.quadrics.point_on_plane_quadric`) is linear in the normal ``n``, the
products ``V = n b^T`` and ``d = n . a`` (:func:`~imagespace.spatial.quadrics.point_on_plane_quadric_linear`),
and with ``V`` arbitrary the family's generic member has 40 regular finite solutions too
(measured as above), of which a 3-RPS design keeps 16: the sphere and the plane of one leg share
its points, and that sends 24 paths to ``x = 0``. So 40 carried paths replace the design's
``2^7`` total-degree paths.

References
----------
A. P. Morgan, A. J. Sommese, Coefficient-parameter polynomial continuation, Appl. Math. Comput.
29(2), 1989, doi:10.1016/0096-3003(89)90099-4.
A. J. Sommese, C. W. Wampler, The Numerical Solution of Systems of Polynomials Arising in
Engineering and Science, World Scientific, 2005, Theorem 7.1.1.
"""

from __future__ import annotations

import functools
import os
from typing import Any, Optional

import numpy as np

from ..exceptions import InputTypeError
from .homotopy import StartSystem, check_seed, move_start_system, solve_start_system
from .quadrics import point_on_plane_quadric_linear, sphere_quadric_linear, study_quadric_matrix

__all__ = ["FAMILY_KINDS", "FAMILY_COUNTS", "LEG_FAMILY_COUNT", "family_kind", "generic_member", "family_start_system",
           "design_start_system"]

#: the family kinds with one start system for all their designs
FAMILY_KINDS = ("legs6", "rps3")
#: regular finite solutions of the generic member of the linear leg family (measured, see above)
LEG_FAMILY_COUNT = 40
#: ... of each kind's linear family (measured the same way; the 3-RPS's: 40 as well)
FAMILY_COUNTS = {"legs6": LEG_FAMILY_COUNT, "rps3": 40}
#: seeds the generic member's coefficients (a fixed choice: every process uses the same member)
GENERIC_SEED = 20261203
#: the generic member: anchors of size ``GENERIC_ANCHOR`` (the families are written for designs
#: scaled to unit size), ``W = a b^T + GENERIC_SPREAD * G`` with ``G`` normal (not rank one) and
#: ``c = |a|^2 + |b|^2 - u``, ``u`` uniform in [0, 1): a random member near the real designs
#: (the paths to a design are then a little shorter; any random member is generic)
GENERIC_ANCHOR = 0.5
GENERIC_SPREAD = 0.3
#: total-degree attempts for the generic member (once per process)
GENERIC_ATTEMPTS = 12
#: a family's leg matrix is a member of the linear family when its least-squares residual on the
#: family's basis is at most this times its size (exact members: a few units in the last place)
MEMBER_TOL = 1e-12
#: bump when the generic member or its solver changes: older files on disk are then ignored
CACHE_VERSION = 1

_E = np.diag([1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0])
# per kind: the linear family of quadrics 0..5 ("leg": sphere, "plane": point on a plane), the
# number of parameters and which parameter each quadric carries (quadric 6: Study's)
_KINDS = {"legs6": (("leg",) * 6, 6, np.array([0, 1, 2, 3, 4, 5, -1])),
          "rps3": (("leg",) * 3 + ("plane",) * 3, 3, np.array([0, 1, 2, -1, -1, -1, -1]))}


def _check_kind(kind):
    if not isinstance(kind, str) or kind not in FAMILY_KINDS:
        from ..exceptions import InputError
        raise InputError(f"kind must be one of {', '.join(map(repr, FAMILY_KINDS))}, got {kind!r}")
    return kind


@functools.cache
def _basis(block):
    """A linear family's constant part and basis ``(8 x 8)`` matrices as columns (``"leg"``:
    :func:`~imagespace.spatial.quadrics.sphere_quadric_linear`, ``"plane"``:
    :func:`~imagespace.spatial.quadrics.point_on_plane_quadric_linear`)."""
    z, e, Z = np.zeros(3), np.eye(3), np.zeros((3, 3))
    units = [np.eye(9)[k].reshape(3, 3) for k in range(9)]
    if block == "leg":
        K0 = sphere_quadric_linear(z, z, Z, 0.0)
        cols = ([sphere_quadric_linear(e[i], z, Z, 0.0) for i in range(3)]
                + [sphere_quadric_linear(z, e[i], Z, 0.0) for i in range(3)]
                + [sphere_quadric_linear(z, z, W, 0.0) for W in units] + [sphere_quadric_linear(z, z, Z, 1.0)])
    else:
        K0 = point_on_plane_quadric_linear(z, Z, 0.0)
        cols = ([point_on_plane_quadric_linear(e[i], Z, 0.0) for i in range(3)]
                + [point_on_plane_quadric_linear(z, V, 0.0) for V in units]
                + [point_on_plane_quadric_linear(z, Z, 1.0)])
    return K0, np.array([(c - K0).ravel() for c in cols]).T


def _member_of(block, Q):
    """True when the matrix ``Q`` lies in the linear family ``block`` (relative residual at most
    ``MEMBER_TOL``)."""
    K0, B = _basis(block)
    r = (Q - K0).ravel()
    res = np.abs(B @ np.linalg.lstsq(B, r, rcond=None)[0] - r).max()
    return bool(res <= MEMBER_TOL * np.abs(Q).max())


def family_kind(family: Any) -> Optional[str]:
    """The family kind a design's quadric family belongs to, or None (then no shared start).

    ``"legs6"`` when the family is six quadrics of the linear leg family (checked on the matrices:
    least-squares residual on the basis of :func:`~imagespace.spatial.quadrics.sphere_quadric_linear`
    at most ``MEMBER_TOL``), parameters ``0..5`` times ``x . x``, and Study's quadric; ``"rps3"``
    for three of them (parameters ``0..2``), three of the linear plane family
    (:func:`~imagespace.spatial.quadrics.point_on_plane_quadric_linear`) and Study's quadric.

    Parameters
    ----------
    family : QuadricFamily
        (:class:`imagespace.spatial.solver.QuadricFamily`, read through its public fields ``A``,
        ``E``, ``pidx``, ``nparams``; not imported here: the solver imports this module.)

    Returns
    -------
    str or None

    Raises
    ------
    TypeError
        If ``family`` lacks a QuadricFamily's fields.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> rng = np.random.default_rng(0)
    >>> family_kind(isp.GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3))).family())
    'legs6'
    >>> family_kind(isp.ThreeRPS(np.eye(3), 0.5 * np.eye(3)).family())
    'rps3'
    """
    missing = [f for f in ("A", "E", "pidx", "nparams") if not hasattr(family, f)]
    if missing:
        raise InputTypeError(f"family must be a QuadricFamily (fields A, E, pidx, nparams), got "
                             f"{type(family).__name__} without {', '.join(missing)}")
    A, E, pidx = (np.asarray(getattr(family, f)) for f in ("A", "E", "pidx"))
    if (A.shape != (7, 8, 8) or not np.array_equal(E, _E) or not np.array_equal(A[6], study_quadric_matrix())
            or not np.all(np.isfinite(A))):
        return None
    for kind, (blocks, nparams, kpidx) in _KINDS.items():
        if getattr(family, "nparams", None) == nparams and np.array_equal(pidx, kpidx) and all(
                _member_of(block, A[k]) for k, block in enumerate(blocks)):
            return kind
    return None


def generic_member(kind: str) -> np.ndarray:
    """The generic member of a family kind: its parameter-free matrices ``A``.

    Parameters
    ----------
    kind : str
        One of :data:`FAMILY_KINDS`.

    Returns
    -------
    (7, 8, 8) float

    Raises
    ------
    InputError
        On an unknown kind.

    Examples
    --------
    >>> A = generic_member("legs6")
    >>> A.shape, bool(np.linalg.matrix_rank(A[0][np.ix_([0, 1, 2, 3], [0, 1, 2, 3])]) == 4)
    ((7, 8, 8), True)
    """
    blocks = _KINDS[_check_kind(kind)][0]
    legs = blocks.count("leg")
    rng = np.random.default_rng(GENERIC_SEED)
    a = GENERIC_ANCHOR * rng.normal(size=(legs, 3))
    b = GENERIC_ANCHOR * rng.normal(size=(legs, 3))
    W = np.einsum("ni,nj->nij", a, b) + GENERIC_SPREAD * rng.normal(size=(legs, 3, 3))
    c = (a * a).sum(axis=1) + (b * b).sum(axis=1) - rng.random(legs)
    parts = [sphere_quadric_linear(a, b, W, c)]
    planes = len(blocks) - legs
    if planes:
        # the planes through the legs' base points, normal n, carrying their platform points
        n = rng.normal(size=(planes, 3))
        V = np.einsum("ni,nj->nij", n, b[:planes]) + GENERIC_SPREAD * rng.normal(size=(planes, 3, 3))
        parts.append(point_on_plane_quadric_linear(n, V, (n * a[:planes]).sum(axis=1) + GENERIC_SPREAD
                                                   * rng.normal(size=planes)))
    return np.concatenate(parts + [study_quadric_matrix()[None]])


def _cache_file(kind, seed):
    from ..core.codegen import kernel_cache_dir

    root = kernel_cache_dir()
    if root is None:
        return None
    return os.path.join(root, f"start_{kind}_{int(seed)}_v{CACHE_VERSION}.npz")


def _load(path, A, kind):
    """The start system stored at ``path`` for the member ``A``, or None (missing, unreadable,
    another member, wrong shapes, or points that are not the member's regular solutions: each is
    carried from the member to itself, which polishes it and checks it as the solver's own
    endpoints are; the checked points are returned)."""
    from ..core.codegen import read_regular_file

    raw = read_regular_file(path)
    if raw is None:
        return None
    import io

    _, nparams, pidx = _KINDS[kind]
    try:
        with np.load(io.BytesIO(raw), allow_pickle=False) as f:
            data = {k: f[k] for k in ("A", "p_star", "patch", "solutions", "paths")}
        sol = np.ascontiguousarray(data["solutions"], dtype=complex)
        p_star = np.ascontiguousarray(data["p_star"], dtype=complex)
        patch = np.ascontiguousarray(data["patch"], dtype=complex)
        paths = int(data["paths"])
    except Exception:      # any unreadable file (bad zip, CRC, dtype, missing key): solve again
        return None
    if (not np.array_equal(data["A"], A) or p_star.shape != (nparams,) or patch.shape != (8,)
            or sol.ndim != 2 or sol.shape[1] != 8 or not np.all(np.isfinite(sol))
            or not np.all(np.isfinite(p_star)) or not np.all(np.isfinite(patch))):
        return None
    checked = move_start_system(StartSystem(A, _E, pidx, p_star, patch, sol, paths), A)
    if len(checked.solutions) != len(sol):
        return None
    return StartSystem(A, _E, pidx, p_star, patch, checked.solutions, paths)


def _store(path, st):
    """Store a start system in the kernel cache (atomically, mode 0o600 like the folder); a
    failure to write only costs the next process a solve."""
    from .._files import atomic_write
    from ..exceptions import InputError

    try:
        atomic_write(path, lambda fh: np.savez(fh, A=st.A, p_star=st.p_star, patch=st.patch,
                                               solutions=st.solutions, paths=np.int64(st.paths)), mode=0o600)
    except (OSError, InputError):
        pass


@functools.cache
def family_start_system(kind: str, seed: int = 0) -> StartSystem:
    """The generic member's start system (total-degree homotopy), once per process and kind.

    Read from the kernel cache directory when an earlier process stored it there (same member,
    same ``seed``); computed and stored otherwise.

    Parameters
    ----------
    kind : str
        One of :data:`FAMILY_KINDS`.
    seed : int
        As :func:`~imagespace.spatial.homotopy.solve_start_system`'s: the same ``p*`` and patch
        as a design's own total-degree start with this seed.

    Returns
    -------
    StartSystem
        :data:`FAMILY_COUNTS` ``[kind]`` solutions unless the total-degree runs missed some (then no
        design uses it: :func:`design_start_system` falls back).

    Raises
    ------
    InputError
        On an unknown kind or a seed that is not an integer.

    Examples
    --------
    >>> len(family_start_system("legs6").solutions)
    40
    """
    _check_kind(kind)
    seed = check_seed(seed)
    A = generic_member(kind)
    path = _cache_file(kind, seed)
    _, nparams, pidx = _KINDS[kind]
    count = FAMILY_COUNTS[kind]
    st = _load(path, A, kind) if path else None
    if st is None or len(st.solutions) < count:
        st = solve_start_system(A, _E, pidx, nparams, seed=int(seed), attempts=GENERIC_ATTEMPTS,
                                expected=count)
        if path and len(st.solutions) >= count:
            _store(path, st)
    return st


def design_start_system(family: Any, seed: int = 0) -> Optional[StartSystem]:
    """A design's start system carried from its family kind's generic member, or None.

    None when the family has no kind (:func:`family_kind`) or no theorem bound, when the generic
    member's start is short, or when the moved start does not hold exactly the family's bound
    (special design, lost path): the caller then takes the total-degree route
    (:func:`imagespace.spatial.solver.start_system` does).

    Parameters
    ----------
    family : QuadricFamily
    seed : int
        Seeds ``p*`` and the patch (as :func:`family_start_system`) and ``gamma``.

    Returns
    -------
    StartSystem or None
        The design's regular solutions at the same ``p*`` and patch as its total-degree start with
        this seed.

    Raises
    ------
    TypeError
        If ``family`` is not a QuadricFamily (:func:`family_kind`).

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> rng = np.random.default_rng(0)
    >>> gs = isp.GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
    >>> st = design_start_system(gs.family())
    >>> len(st.solutions), st.paths
    (40, 40)
    """
    kind = family_kind(family)
    bound = getattr(family, "bound", None)
    if kind is None or bound is None:
        return None
    generic = family_start_system(kind, seed)
    if len(generic.solutions) < FAMILY_COUNTS[kind]:
        return None
    moved = move_start_system(generic, family.A, seed=seed)
    return moved if len(moved.solutions) == bound else None
