"""Aspects and uniqueness domains of a planar parallel manipulator (Chablat & Wenger).

In the workspace ``W`` (the poses whose inverse kinematics lies in a joint box) of a design with
one working mode:

* the **aspects** are the connected components of ``W`` minus the singularity surface, i.e. the
  largest connected regions of constant sign of ``det J``;
* the **characteristic surfaces** of an aspect ``A`` are ``f^-1(f(dA)) cap A``: the other
  preimages, inside ``A``, of the joint vectors of its boundary (``f`` the inverse kinematics);
* the **basic regions** are the connected components of ``A`` minus its characteristic surfaces;
  each is mapped one-to-one onto its image, a **basic component** of joint space; basic regions
  with the same image are *equivalent*;
* the **uniqueness domains** are the largest unions of adjacent basic regions of one aspect
  holding at most one basic region of each basic component: the direct kinematics restricted to
  a uniqueness domain has exactly one solution. Uniqueness domains may overlap (a basic region
  whose component has a single preimage belongs to every domain next to it). A design is
  non-cuspidal exactly when its uniqueness domains are its aspects.

Here the construction runs on a regular grid of the pose box ``(x, y, phi)`` (``phi`` periodic):
the aspects are grid components of one sign of ``det J`` (the quartic, at the normalised image
point); on every node ``X`` the direct kinematics at ``q = f(X)`` (float batch) gives the number
``n_A(X)`` of assembly modes that fall in ``X``'s own aspect; the characteristic surfaces are where
``n_A`` jumps, the basic regions the components of constant ``n_A``; equivalent basic regions are
found by following the other modes of sampled nodes; the uniqueness domains grow from each basic
region of the most-covered basic component by adding adjacent regions of components not yet
present. Everything is at grid resolution and in floating point: a drawing and a decomposition
to plan with, not a proof (regions thinner than a cell are missed; ``slivers`` counts the
basic regions too small to take part).

References
----------
D. Chablat, P. Wenger, *Working modes and aspects in fully parallel manipulators*, IEEE ICRA
1998, arXiv:0707.2006 (working modes, aspects; illustrated on an RR-RRR); D. Chablat, P. Wenger,
arXiv:0705.1148 (working modes, aspects, characteristic surfaces and uniqueness domains of fully
parallel manipulators); P. Wenger, D. Chablat, *Uniqueness domains in the workspace of parallel
manipulators*, arXiv:0705.0960 (parallel manipulators with one inverse kinematic solution: the
aspects are not uniqueness domains, the characteristic surfaces cut the workspace into basic
regions that yield the uniqueness domains; illustrated on a 3-RPR with an octree model);
D. Chablat, G. Moroz, P. Wenger, *Uniqueness domains and non singular assembly mode changing
trajectories*, arXiv:1104.0840 (non-singular assembly-mode changes explained by uniqueness
domains); P. Wenger, *Cuspidal and noncuspidal robot manipulators*, Robotica 25(6), 2007,
hal-00454562 (characteristic surfaces, uniqueness domains, the non-cuspidal criterion).

No published example's number of uniqueness domains is reproduced here. The examples to
reproduce are arXiv:0705.0960's 3-RPR and arXiv:1104.0840's, but the stored copies reachable
when this was written (issue [17]) hold only each paper's title, abstract and the start of its
introduction: not the example's anchors, joint limits or counts. No count is claimed without
them. The construction follows the definitions above; the tests check it against the direct
kinematics and against the non-cuspidal criterion, and check on a general 3-RPR what
arXiv:0705.0960's abstract states of its own: the aspects are not uniqueness domains (more
domains than aspects).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .._html import dataclass_html, dataclass_repr
from .._validate import _short, as_box, as_count, as_float_array
from ..core.mechanism import check_mechanism
from ..exceptions import InputError, InputTypeError
from .boxes import check_joint_box
from ..solve import front

__all__ = ["UniquenessDomains", "uniqueness_domains", "workspace_box", "plot_uniqueness_domains"]

_MARGIN = 0.05                 # the pose box reaches this share of its sides beyond the modes
_WORKSPACE_SAMPLES = 6000      # random joint vectors whose modes bound the pose box (a knob)
_CLASS_SAMPLES = 60            # nodes per basic region followed to find its equivalent regions
_CLASS_VOTE = 0.3              # share of those samples that must agree before two regions are equivalent
_MIN_ASPECT = 0.005            # sign components below this share of the workspace nodes are grid noise
_MIN_REGION = 0.02             # basic regions below this share of their aspect are slivers


def workspace_box(manipulator, joint_box, seed=0):
    """A pose box ``((x_min, x_max), (y_min, y_max), (-pi, pi))`` around the modes reachable from
    ``joint_box`` (bounding box of the modes of random joint vectors, 5 % margin; float).

    Parameters
    ----------
    manipulator : PlanarParallel
    joint_box : (3, 2) float
    seed : int

    Returns
    -------
    (3, 2) float

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import workspace_box
    >>> workspace_box(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)])[2].tolist()
    [-3.141592653589793, 3.141592653589793]
    """
    box = check_joint_box(manipulator, joint_box)
    rng = np.random.default_rng(as_count(seed, "seed", 0))
    Q = box[:, 0] + rng.random((_WORKSPACE_SAMPLES, 3)) * (box[:, 1] - box[:, 0])
    res = front.direct_kinematics_batch(manipulator, Q)
    P = res.poses[res.valid]
    if not len(P):
        raise InputError(f"no assembly mode found for joint vectors of joint_box {box.tolist()}: the "
                         "workspace is empty")
    lo, hi = P[:, :2].min(axis=0), P[:, :2].max(axis=0)
    pad = _MARGIN * (hi - lo) + _MARGIN
    return np.array([[lo[0] - pad[0], hi[0] + pad[0]], [lo[1] - pad[1], hi[1] + pad[1]], [-np.pi, np.pi]])


@dataclass(frozen=True, repr=False)
class UniquenessDomains:
    """Aspects, basic regions and uniqueness domains on a pose grid (see :func:`uniqueness_domains`).

    Attributes
    ----------
    name : str
    joint_box : (3, 2) float
    pose_box : (3, 2) float
        ``phi`` spans ``[-pi, pi)`` (periodic).
    axes : tuple of three (n_i,) float
    aspect : (nx, ny, nphi) int32
        Aspect index per node, ``-1`` outside the workspace or on the singularity surface.
    aspect_sign : (k,) int
        Sign of ``det J`` on each aspect.
    region : (nx, ny, nphi) int32
        Basic region per node (``-1`` outside the aspects).
    region_aspect : (r,) int
    region_preimages : (r,) int
        ``n_A``: modes of the region's joint vectors in its aspect (the size of its class).
    region_class : (r,) int
        Basic component (equivalence class) of each region.
    domains : tuple of tuple of int
        Each uniqueness domain as the basic regions it unites.
    domain_aspect : tuple of int
    slivers : int
        Basic regions too small to take part.
    seconds : float
    """

    name: str
    joint_box: np.ndarray
    pose_box: np.ndarray
    axes: tuple
    aspect: np.ndarray
    aspect_sign: np.ndarray
    region: np.ndarray
    region_aspect: np.ndarray
    region_preimages: np.ndarray
    region_class: np.ndarray
    domains: tuple
    domain_aspect: tuple
    slivers: int
    seconds: float = 0.0
    q: Optional[np.ndarray] = field(default=None)

    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html

    @property
    def n_aspects(self):
        """Number of aspects."""
        return len(self.aspect_sign)

    @property
    def n_domains(self):
        """Number of uniqueness domains."""
        return len(self.domains)

    def domain_mask(self, k):
        """Boolean mask of the pose grid: the nodes of uniqueness domain ``k``.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.atlas import uniqueness_domains
        >>> ud = uniqueness_domains(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 20)
        >>> ud.domain_mask(0).dtype
        dtype('bool')
        """
        from .._validate import as_index

        k = as_index(k, "k", self.n_domains)
        return np.isin(self.region, np.array(self.domains[k]))

    def poses(self, mask):
        """Poses ``(n, 3)`` of the grid nodes where ``mask`` is True.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.atlas import uniqueness_domains
        >>> ud = uniqueness_domains(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 20)
        >>> ud.poses(ud.aspect >= 0).shape[1]
        3
        """
        shape = tuple(len(a) for a in self.axes)
        raw = np.asarray(mask) if isinstance(mask, np.ndarray) else None
        if raw is None or raw.dtype != bool:
            raise InputTypeError(f"mask must be a boolean array of the grid's shape {shape} (such as "
                                 f"ud.aspect >= 0), got {type(mask).__name__} {_short(mask)}")
        if raw.shape != shape:
            raise InputError(f"mask must have the grid's shape {shape}, got shape {raw.shape}")
        idx = np.argwhere(raw)
        return np.column_stack([self.axes[k][idx[:, k]] for k in range(3)])

    def locate(self, P):
        """Grid node indices ``(n, 3)`` nearest to poses ``P`` (``phi`` wrapped), and whether each
        pose lies inside the pose box.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.atlas import uniqueness_domains
        >>> ud = uniqueness_domains(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 20)
        >>> ud.locate([[0.0, 0.0, 0.1]])[0].shape
        (1, 3)
        """
        P = np.atleast_2d(as_float_array(P, "P", last=3, finite=False))
        return _locate(self.axes, self.pose_box, P)

    def figure(self, **kwargs):
        """Matplotlib figure of the domains; see :func:`plot_uniqueness_domains`.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.atlas import uniqueness_domains
        >>> ud = uniqueness_domains(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 20)
        >>> len(ud.figure().axes) == 2 * ud.n_domains
        True
        """
        return plot_uniqueness_domains(self, **kwargs)


def _locate(axes, pose_box, P):
    idx = np.empty((len(P), 3), dtype=int)
    inside = np.ones(len(P), dtype=bool)
    for k in range(2):
        h = axes[k][1] - axes[k][0]
        i = np.rint((P[:, k] - axes[k][0]) / h)
        inside &= (i >= 0) & (i <= len(axes[k]) - 1)
        idx[:, k] = np.clip(np.nan_to_num(i, nan=0), 0, len(axes[k]) - 1).astype(int)
    n = len(axes[2])
    h = axes[2][1] - axes[2][0]
    with np.errstate(invalid="ignore"):
        i2 = np.remainder(np.rint((P[:, 2] - axes[2][0]) / h), n)
    idx[:, 2] = np.nan_to_num(i2, nan=0).astype(int)
    inside &= np.all(np.isfinite(P), axis=1)
    return idx, inside


def _label_periodic(mask):
    """Connected components of a 3D mask (6-neighbourhood), periodic along the last axis."""
    from scipy import ndimage

    lab, n = ndimage.label(mask)
    if n == 0:
        return lab, 0
    parent = np.arange(n + 1)

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    a, b = lab[:, :, 0], lab[:, :, -1]
    both = (a > 0) & (b > 0)
    for u, v in set(zip(a[both].tolist(), b[both].tolist())):
        ru, rv = find(u), find(v)
        if ru != rv:
            parent[max(ru, rv)] = min(ru, rv)
    roots = np.array([find(i) for i in range(n + 1)])
    uniq, new = np.unique(roots[1:], return_inverse=True)
    mapping = np.concatenate([[0], new + 1])
    return mapping[lab], len(uniq)


def uniqueness_domains(manipulator, joint_box, resolution=40, pose_box=None, working_modes=None):
    """Aspects, basic regions and uniqueness domains of a design in a joint box (module notes).

    Parameters
    ----------
    manipulator : PlanarParallel
    joint_box : (3, 2) float
        The joint limits.
    resolution : int or (3,) int
        Grid nodes per pose axis ``(x, y, phi)``, 8..200.
    pose_box : (3, 2) float, optional
        Default :func:`workspace_box` (``phi`` always spans ``[-pi, pi)``).
    working_modes : sequence of three int, optional
        The legs' inverse-kinematic branches (designs whose legs have two).

    Returns
    -------
    UniquenessDomains

    Raises
    ------
    TypeError
        ``manipulator`` not a design; non-numeric boxes or resolution.
    InputError
        A bad box; a resolution outside 8..200; an empty workspace.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import uniqueness_domains
    >>> ud = uniqueness_domains(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 24)
    >>> ud.n_aspects >= 2 and ud.n_domains >= ud.n_aspects
    True
    """
    t0 = time.perf_counter()
    check_mechanism(manipulator)
    jbox = check_joint_box(manipulator, joint_box)
    if isinstance(resolution, (list, tuple, np.ndarray)):
        if len(resolution) != 3:
            raise InputError(f"resolution must be one whole number or three, got {_short(resolution)}")
        res = tuple(as_count(r, f"resolution[{i}]", 8) for i, r in enumerate(resolution))
    else:
        res = (as_count(resolution, "resolution", 8),) * 3
    if max(res) > 200:
        raise InputError(f"resolution must be at most 200 per axis, got {res}")
    if pose_box is None:
        pbox = workspace_box(manipulator, jbox)
    else:
        pbox = as_box(as_float_array(pose_box, "pose_box"), "pose_box", dim=3)
        pbox = pbox.copy()
        pbox[2] = (-np.pi, np.pi)
    tol = manipulator.tolerances
    axes = (np.linspace(pbox[0, 0], pbox[0, 1], res[0]), np.linspace(pbox[1, 0], pbox[1, 1], res[1]),
            np.linspace(-np.pi, np.pi, res[2], endpoint=False))
    P = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    Q = manipulator.inverse_kinematics(P, working_modes=working_modes) if working_modes is not None \
        else manipulator.inverse_kinematics(P)
    Q = np.asarray(Q, dtype=float).reshape(-1, 3)
    inW = np.all(np.isfinite(Q), axis=1) & np.all((Q >= jbox[:, 0]) & (Q <= jbox[:, 1]), axis=1)
    S = manipulator.singularity_surface(working_modes=working_modes)
    det = np.asarray(S.at_poses(P), dtype=float)
    scale = np.nanmax(np.abs(det[inW])) if inW.any() else 1.0
    sign = np.where(np.abs(det) > tol.aspect_singular * scale, np.sign(det), 0).astype(int)
    shape = res
    # aspects
    aspect = np.full(shape, -1, dtype=np.int32)
    signs = []
    n_w = max(int(inW.sum()), 1)
    for sg in (1, -1):
        lab, n = _label_periodic((inW & (sign == sg)).reshape(shape))
        sizes = np.bincount(lab.ravel(), minlength=n + 1)
        for k in range(1, n + 1):
            if sizes[k] < _MIN_ASPECT * n_w:
                continue                  # a few nodes cut off by the grid at the surface: no aspect
            aspect[lab == k] = len(signs)
            signs.append(sg)
    # n_A at every workspace node: modes of f(X) that fall in X's aspect
    flat_aspect = aspect.ravel()
    nodes = np.flatnonzero(flat_aspect >= 0)
    dk = front.direct_kinematics_batch(manipulator, Q[nodes])
    poses = dk.poses                                          # (n, 6, 3)
    valid = dk.valid
    idx, inside = _locate(axes, pbox, poses.reshape(-1, 3))
    lin = np.ravel_multi_index(idx.T, shape)
    mode_aspect = np.where(inside & valid.ravel(), flat_aspect[lin], -1).reshape(valid.shape)
    own = flat_aspect[nodes][:, None]
    nA = np.sum(mode_aspect == own, axis=1)
    nA = np.maximum(nA, 1)                                    # the node's own pose, if the float DK missed it
    nA_grid = np.zeros(np.prod(shape), dtype=int)
    nA_grid[nodes] = nA
    nA_grid = nA_grid.reshape(shape)
    # basic regions: components of constant n_A in an aspect
    region = np.full(shape, -1, dtype=np.int32)
    r_aspect, r_pre, r_size = [], [], []
    for a in range(len(signs)):
        in_a = aspect == a
        for k in np.unique(nA_grid[in_a]):
            lab, n = _label_periodic(in_a & (nA_grid == k))
            for j in range(1, n + 1):
                m = lab == j
                region[m] = len(r_aspect)
                r_aspect.append(a)
                r_pre.append(int(k))
                r_size.append(int(m.sum()))
    r_aspect, r_pre, r_size = np.array(r_aspect), np.array(r_pre), np.array(r_size)
    aspect_size = np.bincount(flat_aspect[flat_aspect >= 0], minlength=len(signs))
    big = r_size >= _MIN_REGION * aspect_size[r_aspect] if len(r_size) else np.array([], dtype=bool)
    # equivalent regions: the other modes of a region's nodes, in the same aspect, land in which regions?
    flat_region = region.ravel()
    node_pos = {int(n): i for i, n in enumerate(nodes)}
    parent = np.arange(len(r_aspect))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    rng = np.random.default_rng(0)
    mode_region = np.where(mode_aspect >= 0, flat_region[lin].reshape(valid.shape), -1)
    for r in np.flatnonzero(big):
        members = np.flatnonzero(flat_region == r)
        pick = members if len(members) <= _CLASS_SAMPLES else rng.choice(members, _CLASS_SAMPLES, replace=False)
        votes = {}
        for node in pick:
            i = node_pos[int(node)]
            for other in set(mode_region[i][(mode_aspect[i] == r_aspect[r])].tolist()) - {r, -1}:
                votes[other] = votes.get(other, 0) + 1
        for other, v in votes.items():
            # equivalent regions lie over one basic component: same aspect, same number of preimages
            if (big[other] and v >= _CLASS_VOTE * len(pick) and r_aspect[other] == r_aspect[r]
                    and r_pre[other] == r_pre[r]):
                ra, rb = find(r), find(other)
                if ra != rb:
                    parent[max(ra, rb)] = min(ra, rb)
    roots = np.array([find(i) for i in range(len(r_aspect))])
    _, r_class = np.unique(roots, return_inverse=True)
    # adjacency of basic regions (6-neighbourhood, phi periodic)
    adj = {}
    for axis in range(3):
        a = region
        b = np.roll(region, -1, axis=axis)
        if axis < 2:
            sl = [slice(None)] * 3
            sl[axis] = slice(0, -1)
            a, b = a[tuple(sl)], b[tuple(sl)]
        pair = (a >= 0) & (b >= 0) & (a != b)
        for u, v in set(zip(a[pair].tolist(), b[pair].tolist())):
            adj.setdefault(u, set()).add(v)
            adj.setdefault(v, set()).add(u)
    # uniqueness domains: grow from each region of the most-covered class of every aspect
    domains, dom_aspect = [], []
    for a in range(len(signs)):
        regs = [r for r in np.flatnonzero((r_aspect == a) & big)]
        if not regs:
            continue
        classes = {}
        for r in regs:
            classes.setdefault(int(r_class[r]), []).append(int(r))
        top = max(len(v) for v in classes.values())
        starts = [r for v in classes.values() if len(v) == top for r in v]
        seen = set()
        for s in starts:
            dom, used = {s}, {int(r_class[s])}
            frontier = [s]
            while frontier:
                nxt = []
                for u in sorted(frontier, key=lambda r: -r_size[r]):
                    for v in sorted(adj.get(u, ()), key=lambda r: -r_size[r]):
                        if v in dom or not big[v] or r_aspect[v] != a or int(r_class[v]) in used:
                            continue
                        dom.add(v)
                        used.add(int(r_class[v]))
                        nxt.append(v)
                frontier = nxt
            key = frozenset(dom)
            if key not in seen:
                seen.add(key)
                domains.append(tuple(sorted(dom)))
                dom_aspect.append(a)
    return UniquenessDomains(manipulator.name, jbox, pbox, axes, aspect, np.array(signs), region,
                             r_aspect, r_pre, r_class, tuple(domains), tuple(dom_aspect),
                             int((~big).sum()), time.perf_counter() - t0, Q.reshape(shape + (3,)))


def plot_uniqueness_domains(ud, max_points=3000):
    """Matplotlib figure: one column per uniqueness domain; top, the domain (colour) inside its
    aspect (grey) in the pose box ``(x, y, phi)``; bottom, its image in joint space.

    Parameters
    ----------
    ud : UniquenessDomains
    max_points : int
        Points drawn per panel at most (layout only).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    TypeError
        ``ud`` not a UniquenessDomains; ``max_points`` not a whole number.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import uniqueness_domains, plot_uniqueness_domains
    >>> ud = uniqueness_domains(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 20)
    >>> len(plot_uniqueness_domains(ud).axes) == 2 * ud.n_domains
    True
    """
    import matplotlib.pyplot as plt

    if not isinstance(ud, UniquenessDomains):
        raise InputTypeError(f"ud must be a UniquenessDomains, got {type(ud).__name__} {_short(ud)}")
    max_points = as_count(max_points, "max_points")
    n = max(ud.n_domains, 1)
    fig = plt.figure(figsize=(3.2 * n, 6.4))
    cmap = plt.get_cmap("tab10")
    rng = np.random.default_rng(0)

    def sub(A):
        return A if len(A) <= max_points else A[rng.choice(len(A), max_points, replace=False)]

    for k in range(ud.n_domains):
        m = ud.domain_mask(k)
        a = ud.domain_aspect[k]
        rest = (ud.aspect == a) & ~m
        top = fig.add_subplot(2, n, k + 1, projection="3d")
        bot = fig.add_subplot(2, n, n + k + 1, projection="3d")
        G = sub(ud.poses(rest))
        P = sub(ud.poses(m))
        c = cmap(k % 10)
        top.scatter(G[:, 0], G[:, 1], np.degrees(G[:, 2]), s=1, color="0.8", alpha=0.25)
        top.scatter(P[:, 0], P[:, 1], np.degrees(P[:, 2]), s=2, color=c, alpha=0.5)
        sg = "+" if ud.aspect_sign[a] > 0 else "-"
        top.set_title(f"domain {k}: aspect {a} (det J {sg})", fontsize=9)
        top.set_xlabel("x", fontsize=8)
        top.set_ylabel("y", fontsize=8)
        top.set_zlabel("phi (deg)", fontsize=8)
        Qk = sub(ud.q[m])
        bot.scatter(Qk[:, 0], Qk[:, 1], Qk[:, 2], s=2, color=c, alpha=0.4)
        bot.set_xlim(*ud.joint_box[0])
        bot.set_ylim(*ud.joint_box[1])
        bot.set_zlim(*ud.joint_box[2])
        bot.set_xlabel("q1", fontsize=8)
        bot.set_ylabel("q2", fontsize=8)
        bot.set_zlabel("q3", fontsize=8)
        bot.set_title("its image in joint space", fontsize=9)
        for axx in (top, bot):
            axx.tick_params(labelsize=6)
    fig.suptitle(f"{ud.name}: {ud.n_aspects} aspects, {ud.n_domains} uniqueness domains "
                 f"(pose grid {'x'.join(str(len(a)) for a in ud.axes)})", fontsize=11)
    return fig
