"""is_cuspidal: verified witnesses for cuspidal designs, proofs of absence for the others.

Independent checks: a witness is re-solved with mpmath (50 digits) on the exact kinematic
polynomial in its own section and must be a triple root inside the witness's enclosure; the
non-cuspidal designs are the literature's (3-RPR with similar base and platform triangles:
Wenger, Chablat & Zein, J. Mech. Des. 129, 2007: no cusp points).
"""

import mpmath
import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.atlas import default_joint_box, is_cuspidal, verify_cusp
from imagespace.core.legs import RPR
from imagespace.core.msolve import msolve_available
from imagespace.exceptions import InputError

needs_msolve = pytest.mark.skipif(not msolve_available(), reason="msolve is not installed")


def similar_3rpr(scale=sp.Rational(1, 2), base=((0, 0), (10, 0), (3, 8))):
    """Base and platform directly similar (the platform is the base scaled by ``scale``)."""
    legs = [RPR(base=b, platform=(scale * b[0], scale * b[1])) for b in base]
    return isp.PlanarParallel(legs, name="similar 3-RPR")


def triple_root_check(m, w):
    """mpmath: the witness's section system has a solution in the enclosure, a triple root."""
    P = m.kinematic_polynomial()
    x0, x1 = P.gens
    t = sp.Symbol("t")
    chart = {x0: 1, x1: t} if w.chart == "t" else {x0: t, x1: 1}
    p = sp.expand(P.as_expr().subs(chart))
    q = list(m.joint_symbols)
    fixed = q[w.fixed]
    free = [s for s in q if s != fixed]
    val = sp.Rational(w.value.numerator, w.value.denominator)
    exprs = [e.subs(fixed, val) for e in (p, sp.diff(p, t), sp.diff(p, t, 2))]
    f = sp.lambdify([t] + free, exprs, modules="mpmath")
    coeffs = sp.lambdify(free, sp.Poly(p.subs(fixed, val), t).all_coeffs(), modules="mpmath")
    a, b = [k for k in range(3) if k != w.fixed]
    mpmath.mp.dps = 50
    try:
        sol = mpmath.findroot(f, (mpmath.mpf(np.mean(w.t_enclosure)), mpmath.mpf(w.q[a]),
                                  mpmath.mpf(w.q[b])))
        assert w.t_enclosure[0] - 1e-12 <= float(sol[0]) <= w.t_enclosure[1] + 1e-12
        for j, k in ((1, a), (2, b)):
            assert w.enclosure[k, 0] - 1e-12 <= float(sol[j]) <= w.enclosure[k, 1] + 1e-12
        roots = mpmath.polyroots(coeffs(sol[1], sol[2]), maxsteps=300, extraprec=300)
        near = [r for r in roots if abs(r - sol[0]) < mpmath.mpf(10) ** -12]
        assert len(near) == 3
    finally:
        mpmath.mp.dps = 15


@pytest.mark.parametrize("name, box", [
    ("general_3rpr", [(8, 14), (2, 8), (7, 13)]),
    pytest.param("stigger_husty", [(6, 14), (11, 19), (9, 17)], marks=pytest.mark.slow),
])
def test_seed_designs_are_cuspidal_with_verified_witness(name, box):
    m = getattr(isp.examples, name)()
    r = is_cuspidal(m, box)
    assert r.cuspidal is True and r.witness is not None
    w = r.witness
    assert np.all(w.enclosure[:, 0] >= np.array(box)[:, 0]) and np.all(w.enclosure[:, 1] <= np.array(box)[:, 1])
    triple_root_check(m, w)


@pytest.mark.slow
@needs_msolve
@pytest.mark.parametrize("scale, base", [
    (sp.Rational(1, 2), ((0, 0), (10, 0), (3, 8))),
    (sp.Rational(2, 3), ((0, 0), (6, 0), (-2, 5))),
])
def test_similar_base_and_platform_are_not_cuspidal(scale, base):
    """Literature: similar base and platform triangles, no cusp (roots merge in pairs only)."""
    m = similar_3rpr(scale, base)
    r = is_cuspidal(m, [(1, 12), (1, 12), (1, 12)])
    assert r.cuspidal is False and r.witness is None
    assert "never three" in r.reason and r.method == "msolve"


@pytest.mark.slow
def test_verify_cusp_refuses_a_point_off_the_curve():
    m = isp.examples.general_3rpr()
    assert verify_cusp(m, [0.1, 11.0, 5.0, 10.0]) is None


def test_undecided_cases_say_why():
    m = isp.examples.collinear_3rpr()
    r = is_cuspidal(m, [(1, 5), (1, 5), (1, 5)])
    assert r.cuspidal is None and "degree 2" in r.reason


def test_default_box_and_validation():
    m = isp.examples.general_3rpr()
    box = default_joint_box(m)
    assert np.all(box[:, 0] > 0) and np.all(box[:, 1] > 14)
    with pytest.raises(InputError, match="timeout must be a positive"):
        is_cuspidal(m, [(8, 14), (2, 8), (7, 13)], timeout=0)
    with pytest.raises(TypeError, match="exact must be"):
        is_cuspidal(m, [(8, 14), (2, 8), (7, 13)], exact="no")
    with pytest.raises(InputError, match="joint_box"):
        is_cuspidal(m, [(8, 14), (2, 8)])
    with pytest.raises(InputError, match="x must be one point"):
        verify_cusp(m, [[0.1, 11.0, 5.0, 10.0]] * 2)


@needs_msolve
@pytest.mark.slow
def test_a_box_without_cusps_is_proven_empty():
    """A small box of the general 3-RPR away from its cusp curves: msolve proves no cusp (faces,
    x0 = 0 and the critical points of the curve); the traced curves of a larger atlas, an
    independent float computation, do not enter it either."""
    m = isp.examples.general_3rpr()
    box = np.array([(13.0, 14.0), (2.0, 3.0), (7.0, 8.0)])
    r = is_cuspidal(m, box)
    assert r.cuspidal is False and r.method == "msolve", r.reason
    from imagespace.atlas.curves import cusp_curves

    for c in cusp_curves(m, [(8, 14), (2, 8), (7, 13)], sections=2):
        inside = np.all((c[:, 1:] >= box[:, 0]) & (c[:, 1:] <= box[:, 1]), axis=1)
        assert not inside.any()
