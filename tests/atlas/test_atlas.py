"""The joint-space atlas: region labels, the surface and its evidence, cusp curves.

Every check compares with something the atlas did not compute: fresh certified counts at random
points (``certified_root_counts`` is the project's proven count, called here on points the atlas
never saw), the counts' changes along random segments, and cusp points re-solved with mpmath at
50 digits on the exact kinematic polynomial.
"""

import mpmath
import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.atlas import atlas_figure, joint_atlas, plot_atlas, plot_atlas_section
from imagespace.exceptions import InputError

BOX = [(8.0, 14.0), (2.0, 8.0), (7.0, 13.0)]


@pytest.fixture(scope="module")
def design():
    return isp.examples.general_3rpr()


@pytest.fixture(scope="module")
def atlas(design):
    return joint_atlas(design, BOX, 28)


@pytest.mark.slow
def test_region_labels_agree_with_certified_counts_at_10000_points(design, atlas, rng):
    """At 10,000 seeded points the certified count equals the atlas's label of the nearest node,
    except within a cell of the surface (the atlas's stated resolution)."""
    box = np.array(BOX)
    Q = box[:, 0] + rng.random((10_000, 3)) * (box[:, 1] - box[:, 0])
    counts, path = design.certified_root_counts(Q)
    assert (counts >= 0).all()
    label = atlas.count_at(Q)
    differ = np.flatnonzero(label != counts)
    assert len(differ) < 0.1 * len(Q)              # most points are well inside a region
    # every disagreement lies within one cell diagonal of a surface vertex
    from scipy.spatial import cKDTree

    d, _ = cKDTree(atlas.vertices).query(Q[differ])
    assert np.all(d <= np.linalg.norm(atlas.cell)), d.max()
    # and every region's own label is the certified count at its sample point
    samples = np.array([r.sample for r in atlas.regions])
    c, _ = design.certified_root_counts(samples)
    assert c.tolist() == [r.count for r in atlas.regions]


def test_counts_change_by_two_where_segments_cross_the_surface(design, atlas, rng):
    """Along 1,000 random segments the certified count changes only near the mesh, by +-2."""
    from scipy.spatial import cKDTree

    box = np.array(BOX)
    n, k = 1000, 24
    A = box[:, 0] + rng.random((n, 3)) * (box[:, 1] - box[:, 0])
    d = rng.normal(size=(n, 3))
    d *= (2.5 * atlas.cell.max() / np.linalg.norm(d, axis=1))[:, None]
    B = np.clip(A + d, box[:, 0], box[:, 1])
    s = np.linspace(0, 1, k)
    P = A[:, None, :] + s[None, :, None] * (B - A)[:, None, :]
    c, _ = design.certified_root_counts(P.reshape(-1, 3))
    c = c.reshape(n, k).astype(int)
    jumps = np.argwhere(c[:, 1:] != c[:, :-1])
    assert len(jumps) > 50                           # the test sees the surface at all
    steps = np.abs(c[:, 1:] - c[:, :-1])[c[:, 1:] != c[:, :-1]]
    assert set(steps.tolist()) <= {2}, np.unique(steps)
    mid = 0.5 * (P[jumps[:, 0], jumps[:, 1]] + P[jumps[:, 0], jumps[:, 1] + 1])
    dist, _ = cKDTree(atlas.vertices).query(mid)
    assert np.all(dist <= np.linalg.norm(atlas.cell)), dist.max()


def test_every_vertex_carries_evidence_recertified(design, atlas, rng):
    """The two ends of every sampled vertex's bracket, certified again, have different counts
    on either side of the vertex's level, and the bracket is short."""
    pick = rng.choice(len(atlas.vertices), 1500, replace=False)
    ends = atlas.evidence_points[pick]
    c0, _ = design.certified_root_counts(ends[:, 0])
    c1, _ = design.certified_root_counts(ends[:, 1])
    lev = atlas.vertex_level[pick]
    assert np.all((c0 < lev) & (c1 > lev))
    assert np.all(np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
                  <= design.tolerances.atlas_evidence_width * atlas.cell.min())
    assert np.allclose(ends.mean(axis=1), atlas.vertices[pick])


def _kinematic_functions(m):
    P = m.kinematic_polynomial()
    x0, x1 = P.gens
    t = sp.Symbol("t")
    p = sp.expand(P.as_expr().subs({x0: 1, x1: t}))
    q = m.joint_symbols
    exprs = [p, sp.diff(p, t), sp.diff(p, t, 2)]
    f = sp.lambdify((t,) + tuple(q), exprs, modules="mpmath")
    coeffs = sp.lambdify(tuple(q), sp.Poly(p, t).all_coeffs(), modules="mpmath")
    return f, coeffs


@pytest.mark.slow
def test_cusp_curve_points_are_triple_roots_by_mpmath(design, atlas):
    """Points of the traced cusp curves, re-solved by mpmath (50 digits) on the exact kinematic
    polynomial in the section q3 = const through them, are triple roots."""
    assert atlas.cusp_curves
    f, coeffs = _kinematic_functions(design)
    mpmath.mp.dps = 50
    try:
        checked = 0
        for curve, theta in zip(atlas.cusp_curves, atlas.cusp_half_angles):
            for i in np.linspace(0, len(curve) - 1, 6).astype(int):
                q, th = curve[i], theta[i]
                if abs(np.cos(th)) < 0.2:
                    continue
                q3 = mpmath.mpf(q[2])
                sol = mpmath.findroot(lambda t, a, b: f(t, a, b, q3),
                                      (mpmath.tan(th), mpmath.mpf(q[0]), mpmath.mpf(q[1])))
                t_, a, b = (sol[k] for k in range(3))
                assert abs(a - q[0]) < 1e-6 and abs(b - q[1]) < 1e-6 and abs(t_ - np.tan(th)) < 1e-6
                roots = mpmath.polyroots(coeffs(a, b, q3), maxsteps=200, extraprec=200)
                near = [r for r in roots if abs(r - t_) < mpmath.mpf(10) ** -10]
                assert len(near) == 3, (q, near)
                checked += 1
        assert checked >= 6
    finally:
        mpmath.mp.dps = 15


def test_fractions_regions_and_exports(atlas, tmp_path):
    fr = atlas.fractions()
    assert abs(sum(fr.values()) - 1) < 1e-12 and set(fr) <= {0, 2, 4, 6}
    assert abs(sum(r.volume_fraction for r in atlas.regions) - 1) < 1e-12
    import trimesh

    back = trimesh.load(atlas.export_ply(tmp_path / "a.ply"), process=False)
    assert np.array_equal(back.vertices, atlas.vertices) and len(back.faces) == len(atlas.faces)
    text = atlas.write_table(tmp_path / "r.csv").read_text().splitlines()
    assert len(text) == len(atlas.regions) + 1


def test_figures(atlas, design):
    fig = plot_atlas(atlas, q=[11, 5, 10], manipulator=design)
    assert "6 modes (certified at q)" in [t.get_text() for t in fig.axes[0].get_legend().get_texts()][-1]
    assert len(plot_atlas_section(atlas, axis=0, q=[11, 5, 10]).axes) == 2
    f = atlas_figure(atlas, q=[11, 5, 10], manipulator=design)
    assert f.data[-1].name.startswith("q: 6 modes")
    with pytest.raises(TypeError, match="atlas must be a JointAtlas"):
        atlas_figure("atlas")
    with pytest.raises(InputError, match="q must be one joint vector"):
        atlas_figure(atlas, q=[[1, 2, 3], [4, 5, 6]])


def test_input_validation(design):
    with pytest.raises(InputError, match=r"joint_box\[0\].*leaves the domain"):
        joint_atlas(design, [(-1, 2), (2, 8), (7, 13)], 8)
    with pytest.raises(InputError, match="joint_box must be"):
        joint_atlas(design, [(1, 2), (2, 8)], 8)
    with pytest.raises(InputError, match="joint_box is empty"):
        joint_atlas(design, [(3, 2), (2, 8), (7, 13)], 8)
    with pytest.raises(TypeError, match="resolution must be a whole number"):
        joint_atlas(design, BOX, 8.5)
    with pytest.raises(InputError, match="resolution must be at least 4"):
        joint_atlas(design, BOX, 2)
    with pytest.raises(InputError, match="at most"):
        joint_atlas(design, BOX, 1000)
    with pytest.raises(TypeError, match="cusps must be"):
        joint_atlas(design, BOX, 8, cusps="yes")
    with pytest.raises(TypeError):
        joint_atlas("design", BOX, 8)


@pytest.mark.slow
def test_seed002_atlas_regions_and_cusps():
    """Seed 002 (Stigger-Husty): its six-mode joint vector lies in a six-mode region; the cusp
    curves satisfy the cusp system."""
    from imagespace.singular.cusps import cusp_system

    m = isp.examples.stigger_husty()
    a = joint_atlas(m, [(6, 14), (11, 19), (9, 17)], 24)
    assert a.count_at(m.q_example_float) == 6
    assert a.removed == 0 and a.cusp_curves
    for c, th in zip(a.cusp_curves, a.cusp_half_angles):
        G, _, s = cusp_system(m, np.column_stack([th, c]))
        assert np.all(np.max(np.abs(G), axis=1) <= 1e-8 * s)


def test_cusp_system_matches_the_section_system_and_finite_differences(design, rng):
    from imagespace.singular.cusps import cusp_system

    X = np.column_stack([rng.uniform(-2, 2, 40), rng.uniform(8, 14, 40), rng.uniform(2, 8, 40),
                         rng.uniform(7, 13, 40)])
    G, J, s = cusp_system(design, X)
    # f, f', f'' by differentiating f(theta) numerically (central differences of the value)
    h = 1e-4
    f = lambda th: cusp_system(design, np.column_stack([th, X[:, 1:]]))[0][:, 0]  # noqa: E731
    d1 = (f(X[:, 0] + h) - f(X[:, 0] - h)) / (2 * h)
    d2 = (f(X[:, 0] + h) - 2 * f(X[:, 0]) + f(X[:, 0] - h)) / h ** 2
    assert np.allclose(G[:, 1], d1, rtol=1e-5, atol=1e-6 * s.max())
    assert np.allclose(G[:, 2], d2, rtol=1e-3, atol=1e-4 * s.max())
    for k in range(4):
        E = np.zeros(4)
        E[k] = 1e-6
        fd = (cusp_system(design, X + E)[0] - cusp_system(design, X - E)[0]) / 2e-6
        assert np.allclose(J[:, :, k], fd, rtol=1e-4, atol=1e-6 * s.max())
