"""Cusps: triple roots checked on the exact kinematic polynomial with mpmath; loops around a cusp
change the assembly mode without meeting a singularity (certified); the count map is consistent."""

import mpmath as mp
import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.paths.cusp_loops import cusp_loop
from imagespace.singular.cusps import cusps, mode_count_map

CASES = [(isp.examples.general_3rpr, 2, 10.0, [(6, 16), (1, 9)]),
         (isp.examples.stigger_husty, 2, 13.25, [(6, 14), (11.2, 19.2)])]


@pytest.fixture(scope="module", params=range(len(CASES)))
def case(request):
    make, fixed, value, window = CASES[request.param]
    m = make()
    return m, fixed, value, window, cusps(m, fixed, value, window, 80)


@pytest.mark.slow
def test_every_cusp_is_a_triple_root_of_the_exact_polynomial(case):
    m, fixed, value, window, found = case
    assert len(found) >= 2
    x0, x1 = isp.image_symbols()[:2]
    P = m.kinematic_polynomial()                       # the sympy derivation, not the compiled one
    mp.mp.dps = 40
    for c in found:
        sub = dict(zip(m.joint_symbols, [sp.Float(v, 30) for v in c.q]))
        coeffs = [mp.mpf(str(sp.N(P.coeff_monomial((6 - k, k)).xreplace(sub), 35))) for k in range(7)]
        scale = sum(abs(v) for v in coeffs)
        th = mp.mpf(c.theta)

        def f(t):
            return sum(coeffs[k] * mp.cos(t) ** (6 - k) * mp.sin(t) ** k for k in range(7))
        for order in range(3):
            assert abs(mp.diff(f, th, order)) <= 1e-9 * scale
        # and three roots of the sextic in t = tan(theta) cluster at tan(theta)
        roots = mp.polyroots(coeffs[::-1], maxsteps=200, extraprec=200)
        close = [r for r in roots if abs(r - mp.tan(th)) < 1e-3]
        assert len(close) == 3


def test_mode_counts_are_even_and_change_across_the_discriminant():
    m = isp.examples.general_3rpr()
    cm = mode_count_map(m, 2, 10.0, [(6, 16), (1, 9)], 60)
    assert np.all(cm.counts % 2 == 0)
    assert len(cm.boundary()) > 20 and len(np.unique(cm.counts)) >= 3


@pytest.mark.slow
def test_a_loop_around_a_cusp_changes_the_mode_without_a_singularity(case):
    m, fixed, value, window, found = case
    loops = [cusp_loop(m, c, fixed, 0.05) for c in found]
    good = [lp for lp in loops if lp.changed and lp.continuous]
    assert good                                   # at least one cusp of the section
    loop = good[0]
    assert np.all(loop.aspects == loop.aspects[0])
    assert np.allclose(loop.q[0], loop.q[-1])
    path, chk = loop.certified_path(m)
    assert chk.singularity_free and chk.certified
    # independent: the two ends are different modes of the same joint values
    end = path.end / np.hypot(*path.end[:2])
    start = path.start / np.hypot(*path.start[:2])
    assert min(np.linalg.norm(end - start), np.linalg.norm(end + start)) > 1e-3
    assert m.joint_residual(isp.pose_of(end), loop.q[0]) < 1e-6


def test_bad_input():
    m = isp.examples.general_3rpr()
    with pytest.raises(isp.InputError, match="fixed"):
        mode_count_map(m, 3, 1.0, [(0, 1), (0, 1)])
    with pytest.raises(isp.InputError, match="window"):
        mode_count_map(m, 2, 10.0, [(1, 1), (0, 1)])
    with pytest.raises(isp.InputError, match="resolution"):
        mode_count_map(m, 2, 10.0, [(6, 16), (1, 9)], 4)
    with pytest.raises(isp.InputError, match="domain"):
        mode_count_map(m, 2, 10.0, [(-6, 16), (1, 9)], 10)


@pytest.mark.slow
def test_a_mode_changing_loop_links_the_cusp_edge_and_a_distant_one_does_not():
    from imagespace.singular.cusps import cusp_edges, linking_number
    m = isp.examples.general_3rpr()
    window = [(8, 14), (2, 8)]
    c = cusps(m, 2, 10.0, window, 60)[0]
    loop = cusp_loop(m, c, 2, 0.05)
    assert loop.changed and loop.continuous
    edges = cusp_edges(m, 2, np.linspace(9.8, 10.2, 9), window, 60)
    assert abs(linking_number(loop.q, edges)) == 1
    far = loop.q.copy()
    far[:, 0] += 1.5
    assert linking_number(far, edges) == 0
    # an independent check of linking_number: a circle about the z-axis and the z-axis
    t = np.linspace(0, 2 * np.pi, 101)
    circle = np.column_stack([np.cos(t), np.sin(t), np.zeros_like(t)])
    assert abs(linking_number(circle, [np.array([[0.0, 0.0, -2.0], [0.0, 0.0, 2.0]])])) == 1
    assert linking_number(circle, [np.array([[3.0, 0.0, -2.0], [3.0, 0.0, 2.0]])]) == 0
