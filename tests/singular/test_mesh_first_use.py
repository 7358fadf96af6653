"""The fast faces of the singularity surface held to independent references:

* ``singularity_polynomial`` (Laplace expansion in sparse polynomial arithmetic) against sympy's
  Berkowitz determinant of the symbolic Jacobian, expanded (the old derivation, written here), and
  against the exact determinant of the rational Jacobian at random rational points;
* the monomial table of :class:`PolynomialImplicit` (values, gradients, grids) against exact
  rational evaluation of the sympy expression, its rounding-error bound included;
* the per-design table general in the joint values (:class:`JointTable`) against the derivation at
  exact joint values (``singularity_polynomial(q=exact)``, charted by sympy), at seeded random q;
* a re-mesh and a section at a new q (the explorer's calls) do no symbolic work.
"""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
import imagespace.singular.charts as charts_mod
import imagespace.singular.implicit as implicit_mod
import imagespace.singular.pointwise as pointwise_mod
import imagespace.singular.proven_sign as proven_sign_mod
import imagespace.singular.surface as surface_mod
from imagespace.core.quadrics import image_symbols
from imagespace.singular.charts import JointTable
from imagespace.singular.implicit import PolynomialImplicit, surface_implicit
from imagespace.singular.meshing import mesh_surface

BOX = [(-12, 12), (-12, 12), (-3, 3)]


def rrr_design():
    return isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
                               isp.RPR(base=(6, 0), platform=(1, 0)), isp.RPR(base=(2, 5), platform=(0, 1))])


def berkowitz(m, q=None):
    """The derivation as it was: Berkowitz determinant of the symbolic Jacobian, expanded, with
    sin(q)**2 written as 1 - cos(q)**2."""
    x = image_symbols()
    eqs = m.constraint_equations(q) + [x[0]**2 + x[1]**2 - 1]
    det = sp.expand(sp.Matrix(eqs).jacobian(sp.Matrix(x)).det(method="berkowitz"))
    for s in m.joint_symbols:
        if det.has(sp.sin(s)):
            det = sp.expand(det.subs(sp.sin(s)**2, 1 - sp.cos(s)**2))
    return sp.Poly(det, *x)


@pytest.mark.slow
@pytest.mark.parametrize("make", [isp.examples.stigger_husty, isp.examples.general_3rpr, rrr_design,
                                  isp.examples.collinear_3rpr])
def test_singularity_polynomial_equals_the_berkowitz_derivation(make):
    m = make()
    P = m.singularity_polynomial()
    ref = berkowitz(m)
    assert P == ref                          # the same Poly: same expression, same domain
    assert P.as_expr() == ref.as_expr()


@pytest.mark.slow
def test_singularity_polynomial_equals_berkowitz_with_trig_constants():
    m = isp.examples.choi_3ppr()             # cos(7 pi/18), sin(7 pi/18), sqrt(3) in the entries
    assert m.singularity_polynomial() == berkowitz(m)


@pytest.mark.slow
def test_singularity_polynomial_at_exact_q_equals_berkowitz(rng):
    m = rrr_design()
    for _ in range(2):
        q = (sp.Rational(int(rng.integers(-40, 40)), 16), sp.Rational(int(rng.integers(60, 100)), 16), 5)
        assert m.singularity_polynomial(q) == berkowitz(m, q)


def test_singularity_polynomial_is_the_determinant_at_rational_points(rng):
    """An independent check: the exact determinant of the Jacobian, evaluated entry by entry at
    random rational image points and joint values, equals the polynomial there."""
    m = isp.PlanarParallel([isp.RPR(base=(0, 0), platform=(0, 0)),
                            isp.RRR(base=(7, 1), platform=(3, 1), lengths=(2, sp.Rational(5, 2)), actuated=1),
                            isp.PRR(base=(2, 6), axis=(1, 2), platform=(-1, 2), length=3)])
    x = image_symbols()
    qs = m.joint_symbols
    P = m.singularity_polynomial().as_expr()
    eqs = m.constraint_equations() + [x[0]**2 + x[1]**2 - 1]
    J = sp.Matrix(eqs).jacobian(sp.Matrix(x))
    for _ in range(4):
        sub = {v: sp.Rational(int(rng.integers(-50, 50)), int(rng.integers(1, 9))) for v in x + qs}
        exact = sp.Matrix(J.xreplace(sub)).det(method="bareiss")
        assert sp.nsimplify(P.xreplace(sub) - exact) == 0 or sp.expand(P.xreplace(sub) - exact) == 0


def exact_value(expr, syms, p):
    return expr.xreplace({s: sp.Rational(Fraction(float(v))) for s, v in zip(syms, p)})


@pytest.mark.slow
@pytest.mark.parametrize("chart", ["image", "pose"])
def test_table_values_and_gradients_against_exact_evaluation(chart, rng):
    S = isp.examples.stigger_husty().singularity_surface()
    f = surface_implicit(S, chart)
    assert isinstance(f, PolynomialImplicit) and f.sign_test == "rounding-error bound, arb below it"
    expr, syms = S.chart_expression(chart)
    P = rng.uniform(-3, 3, (12, 3))
    F, G = f.value_and_gradient(P)
    Fb, bound, _ = f.value_bound(P)
    assert np.array_equal(F, Fb)             # the value is the sum the bound is about
    grads = [sp.diff(expr, s) for s in syms]
    for i, p in enumerate(P):
        if chart == "image":                 # polynomial: exact rational evaluation
            ev = float(exact_value(expr, syms, p))
            eg = [float(exact_value(g, syms, p)) for g in grads]
        else:                                # trigonometric in phi: 40 digits
            sub = {s: sp.Rational(Fraction(float(v))) for s, v in zip(syms, p)}
            ev = float(sp.N(expr.xreplace(sub), 40))
            eg = [float(sp.N(g.xreplace(sub), 40)) for g in grads]
        assert abs(F[i] - ev) <= bound[i]    # the rounding-error bound holds
        scale = max(abs(v) for v in eg) + 1.0
        assert np.allclose(G[i], eg, rtol=1e-11, atol=1e-11 * scale)


def test_grid_is_the_value_at_the_grid_points(rng):
    u, v, w = sp.symbols("u v w")
    f = PolynomialImplicit(u**3 * w - 2 * u * v**2 + v * w**2 - sp.Rational(1, 3), (u, v, w))
    axes = [np.sort(rng.uniform(-2, 2, n)) for n in (5, 4, 3)]
    G = f.grid(axes)
    U, V, W = np.meshgrid(*axes, indexing="ij")
    P = np.stack([U.ravel(), V.ravel(), W.ravel()], axis=-1)
    exact = np.array([float(exact_value(f.expr, (u, v, w), p)) for p in P])
    assert np.allclose(G.ravel(), exact, rtol=1e-13, atol=1e-13)


def q_values(rng, n):
    return [(float(rng.uniform(-2, 2)), float(rng.uniform(4, 6)), float(rng.uniform(4, 6))) for _ in range(n)]


def exact_ball_overlaps(ball, c):
    """Does the arb ``ball`` overlap the exact sympy constant ``c`` (enclosed to 1e-55)?"""
    import flint

    old = flint.ctx.prec
    flint.ctx.prec = 256
    try:
        r = sp.Rational(sp.N(c, 70))
        return ball.overlaps(flint.arb(flint.fmpq(int(r.p), int(r.q)), flint.arb("1e-55")))
    finally:
        flint.ctx.prec = old


def check_table_against(table, derived, q, chart, m):
    expr, syms = charts_mod.chart_substitution(derived.as_expr(), chart)
    plain, trig, monoms, coeffs = charts_mod.chart_terms(expr, syms)
    assert table.plain == plain and table.trig == trig
    tm, balls, _ = table.at(q)
    _, floats = table.float_coefficients(q)
    mine = {tuple(mm): (c, b) for mm, c, b in zip(tm.tolist(), floats, balls)}
    assert set(mine) == {tuple(mm) for mm in monoms.tolist()}
    for mm, c in zip(monoms.tolist(), coeffs):
        f, ball = mine[tuple(mm)]
        assert exact_ball_overlaps(ball, c)
        assert f == pytest.approx(float(sp.N(c, 40)), rel=4e-16)


@pytest.mark.slow
@pytest.mark.parametrize("chart", ["image", "pose"])
def test_joint_table_equals_the_derivation_at_q(chart, rng):
    """An actuated base revolute (q enters through cos q, sin q): the table at q equals the general
    derivation with the exact q substituted (what singularity_surface(q=) meant before the table)."""
    m = rrr_design()
    table = JointTable(m, chart)
    general = m.singularity_polynomial().as_expr()
    for q in q_values(rng, 3):
        qe = [sp.Rational(Fraction(v)) for v in q]
        derived = sp.Poly(general.xreplace(dict(zip(m.joint_symbols, qe))), *image_symbols())
        check_table_against(table, derived, q, chart, m)
        # singularity_polynomial(q=exact) takes cos q, sin q as the binary rationals of their floats
        # (exact_cos_sin): the same surface to rounding
        at_q = m.singularity_polynomial(qe)
        d = sp.Poly(derived.as_expr() - at_q.as_expr(), *image_symbols())
        assert max(abs(float(c)) for c in d.coeffs()) <= 1e-13 * max(abs(float(c)) for c in at_q.coeffs())


def test_joint_table_equals_singularity_polynomial_at_exact_q(rng):
    """An actuated slider that moves a circle's centre (q enters polynomially): the table at q equals
    singularity_polynomial(q=exact) coefficient by coefficient."""
    m = isp.PlanarParallel([isp.PRR(base=(0, 0), axis=(1, 0), platform=(0, 0), length=3, actuated=0),
                            isp.RPR(base=(6, 0), platform=(1, 0)), isp.RPR(base=(2, 5), platform=(0, 1))])
    assert m.joint_symbols[0] in m.singularity_polynomial().free_symbols
    for chart in ("image", "pose"):
        table = JointTable(m, chart)
        for q in q_values(rng, 2):
            qe = [sp.Rational(Fraction(v)) for v in q]
            check_table_against(table, m.singularity_polynomial(qe), q, chart, m)


def test_given_joint_mesh_equals_the_derived_one(rng):
    m = rrr_design()
    q = q_values(rng, 1)[0]
    S = m.singularity_surface(q=q)
    mesh = mesh_surface(S, BOX, resolution=24)
    expr, syms = S.chart_expression("image")
    ref = mesh_surface.__globals__["mesh_implicit"](PolynomialImplicit(expr, syms), BOX, resolution=24)
    md = mesh.metadata["imagespace"]
    assert md["uncertified"] == md["removed"] == 0 and md["sign_test"] == "rounding-error bound, arb below it"
    assert len(mesh.faces) == len(ref.faces) and len(mesh.vertices) == len(ref.vertices)
    size = 24.0
    assert np.max(np.abs(np.sort(mesh.vertices, axis=0) - np.sort(ref.vertices, axis=0))) <= 2e-9 * size


def test_section_at_q_equals_the_exact_conic(rng):
    m = rrr_design()
    q = q_values(rng, 1)[0]
    S = m.singularity_surface(q=q)
    for phi in (0.3, -1.2):
        fast = S.section_coefficients([phi])[0]
        exact = np.array([float(c) for c in isp.ConicSection.of(S, phi).coefficients])
        assert np.allclose(fast, exact, rtol=1e-12, atol=1e-12 * np.abs(exact).max())


def test_new_q_does_no_symbolic_work(rng, monkeypatch):
    """The explorer's calls at a new q (singularity_surface(q=), mesh_surface, section_coefficients)
    run on the design's table: no chart substitution, no parsing, no lambdify."""
    m = rrr_design()
    q1, q2 = q_values(rng, 2)
    S1 = m.singularity_surface(q=q1)
    mesh_surface(S1, BOX, resolution=16)
    S1.section_coefficients([0.2])

    def refuse(*args, **kwargs):
        raise AssertionError("symbolic work at a new q")

    for mod, name in ((surface_mod, "chart_substitution"), (charts_mod, "chart_substitution"),
                      (surface_mod, "compile_exprs"), (implicit_mod, "compile_exprs"),
                      (pointwise_mod, "compile_exprs"),
                      (charts_mod, "chart_terms"), (proven_sign_mod, "chart_terms")):
        monkeypatch.setattr(mod, name, refuse)
    S2 = m.singularity_surface(q=q2)
    mesh = mesh_surface(S2, BOX, resolution=16)
    assert len(mesh.faces) > 0 and mesh.metadata["imagespace"]["uncertified"] == 0
    assert S2.section_coefficients([0.2]).shape == (1, 6)
    monkeypatch.undo()
    # the polynomial itself is still there when read: the general one at the exact q
    qe = dict(zip(m.joint_symbols, [sp.Rational(Fraction(v)) for v in q2]))
    assert S2.polynomial == sp.Poly(m.singularity_polynomial().as_expr().xreplace(qe), *image_symbols())
