import pytest
import numpy as np
import sympy as sp

import imagespace as isp

x0, x1, x2, x3 = isp.image_symbols()
s181 = sp.sqrt(181)
H1 = -100 * x1**2 + 4 * x2**2 + 4 * x3**2 - 100
H2 = -88 * x1**2 - 48 * x1 * x2 + 4 * x2**2 + 4 * x3**2 - 8 * x3 - 228
H3 = (1364 * x1**2 * s181 - 80 * x1 * x2 * s181 - 72 * x1 * x3 * s181 + 296 * x1 * s181
      + 72 * x2 * s181 - 80 * x3 * s181 - 9593 * x1**2 + 84 * s181 - 9593) * s181 / 362


def _proportional(expr, printed):
    """expr (homogeneous, dehomogenised at x0 = 1) is a constant multiple of the printed one."""
    a = sp.Poly(sp.expand(expr.subs(x0, 1)), x1, x2, x3)
    b = sp.Poly(sp.expand(printed), x1, x2, x3)
    if set(a.monoms()) != set(b.monoms()):
        return False
    ma = a.monoms()[0]
    ra, rb = a.coeff_monomial(ma), b.coeff_monomial(ma)
    return all(sp.expand(a.coeff_monomial(mm) * rb - b.coeff_monomial(mm) * ra) == 0 for mm in a.monoms())


def test_seed_002_equations_5_to_7():
    m = isp.examples.stigger_husty()
    eqs = m.constraint_equations(m.q_example)
    for e, printed in zip(eqs, (H1, H2, H3)):
        assert _proportional(e, printed)
        # homogeneous of degree 2
        assert sp.Poly(e, x0, x1, x2, x3).is_homogeneous


def _pose_image(rng):
    pose = np.array([rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-np.pi, np.pi)])
    return pose, isp.image_point(pose)


def test_quadrics_against_euclidean_geometry(rng):
    """Each quadric equals |z|^2 times the Euclidean condition (circle, line, line through point, angle)."""
    for _ in range(50):
        pose, X = _pose_image(rng)
        R = np.array([[np.cos(pose[2]), -np.sin(pose[2])], [np.sin(pose[2]), np.cos(pose[2])]])
        t = pose[:2]
        p, M, d = rng.normal(size=2), rng.normal(size=2), rng.normal(size=2)
        rho2 = rng.uniform(0.5, 4)
        # RR: |R p + t - M|^2 - rho^2
        rr = isp.rr_quadric(M, rho2, p).evaluate(X)
        assert np.isclose(rr, np.sum((R @ p + t - M) ** 2) - rho2)
        # PR: n . (R p + t) - n . M with n = d turned by +90 deg
        n = np.array([-d[1], d[0]])
        pr = isp.pr_quadric(p, M, d).evaluate(X)
        assert np.isclose(pr, n @ (R @ p + t) - n @ M)
        # RP: platform line (p, d) through base point M: m . (R^T (M - t)) - m . p
        mvec = np.array([-d[1], d[0]])
        rp = isp.rp_quadric(p, d, M).evaluate(X)
        assert np.isclose(rp, mvec @ (R.T @ (M - t)) - mvec @ p)
        # PP: sin(phi - phi_c) up to the factor |z|^2 = 1
        phic = rng.uniform(-np.pi, np.pi)
        pp = isp.pp_quadric(np.cos(phic), np.sin(phic)).evaluate(X)
        assert np.isclose(pp, np.sin(pose[2] - phic))


@pytest.mark.slow
def test_symbolic_and_numeric_quadric_agree(rng):
    for _ in range(10):
        p, M = rng.normal(size=2), rng.normal(size=2)
        qd = isp.rr_quadric(M, 2.0, p)
        X = rng.normal(size=4)
        e = qd.expr()
        assert np.isclose(float(e.subs(dict(zip((x0, x1, x2, x3), X)))), qd.evaluate(X))
        g = [float(sp.diff(e, v).subs(dict(zip((x0, x1, x2, x3), X)))) for v in (x0, x1, x2, x3)]
        assert np.allclose(g, qd.gradient(X))


@pytest.mark.slow
def test_one_dyad_system_evaluator_and_its_numba_twin_agree_on_random_input():
    """dk_system (numpy, used by the numpy DK path and Quadric.evaluate/gradient) and
    dk_system_row (the source the compiled kernel is built from) are one formula: equal on random
    coefficients and points; and the values are the sympy expression of the quadric, the
    Jacobian its symbolic derivatives (an independent derivation by sympy.diff)."""
    import sympy as sp
    from imagespace.core.quadrics import Quadric, dk_system, dk_system_row, image_symbols

    rng = np.random.default_rng(20261201)
    C = rng.normal(size=(5, 3, 8))
    X = rng.normal(size=(5, 2, 4))
    Fv, J = dk_system(C, X)
    val, Jr = np.empty(4), np.empty((4, 4))
    for n in range(5):
        for k in range(2):
            dk_system_row(C[n].ravel(), X[n, k], val, Jr)
            assert np.allclose(val, Fv[n, k], rtol=1e-14, atol=1e-13)
            assert np.allclose(Jr, J[n, k], rtol=1e-14, atol=1e-13)
    x = image_symbols()
    for i in range(3):
        q = Quadric("RR", *[sp.Rational(v) for v in C[0, i]])
        e = q.expr()
        for k in range(2):
            sub = dict(zip(x, [sp.Rational(v) for v in X[0, k]]))
            assert abs(float(e.subs(sub)) - Fv[0, k, i]) < 1e-12 * (1 + abs(Fv[0, k, i]))
            grad = [float(sp.diff(e, xj).subs(sub)) for xj in x]
            assert np.allclose(grad, J[0, k, i], rtol=1e-12, atol=1e-12)
            assert np.isclose(float(q.evaluate(X[0, k])), Fv[0, k, i], rtol=1e-14, atol=1e-13)
            assert np.allclose(q.gradient(X[0, k]), J[0, k, i], rtol=1e-14, atol=1e-13)
    from imagespace.solve.kernel import HAVE_NUMBA
    if HAVE_NUMBA:                                          # the compiled twin itself
        from imagespace.solve.kernel import _system
        _system(C[1].ravel(), X[1, 0], val, Jr)
        assert np.allclose(val, Fv[1, 0], rtol=1e-14, atol=1e-13) and np.allclose(Jr, J[1, 0], rtol=1e-14, atol=1e-13)
