"""Exact forms over cos/sin of binary-rational angles (imagespace.core.transcendental).

Checked against identities that must hold (cos^2 + sin^2 = 1 recognised as exact zero; the
polynomial representation times its positive factor equals the direct arb value of the sympy
number), against forms built from known roots (counts and multiplicities by construction), and
against the case of issue [14] whose truth was found by msolve outside the project.
"""

from fractions import Fraction

import flint
import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.core.certify import flint_precision, to_arb
from imagespace.core.transcendental import (ExactConstants, ExactForm, certify_transcendental,
                                            transcendental_elimination)
from imagespace.exceptions import DegenerateDesignError

R = sp.Rational


def _form(coeffs):
    k = ExactConstants(coeffs)
    return ExactForm(k, k.polys(coeffs))


def test_constants_groups_angles_by_absolute_value():
    r = R(3, 7)
    k = ExactConstants([sp.cos(r) * sp.sin(-r), sp.cos(R(1, 2)), sp.sqrt(2) * sp.sin(r)])
    assert k.angles == (Fraction(3, 7), Fraction(1, 2))
    assert k.others == (sp.sqrt(2),)
    assert not k.decidable


@pytest.mark.parametrize("r", [R(1, 3), R(5, 2), R(-7, 4), R(3, 1), R(400, 1), sp.Rational(1e-7)])
def test_polys_times_their_factor_equal_the_numbers(r):
    """Each polynomial, evaluated at tau's ball, equals the sympy number times the common factor
    prod (1 + tau^2)^K (read off the polynomial of 1)."""
    c, s = sp.cos(r), sp.sin(r)
    exprs = [c, s, c**2 + 3 * s * c - R(1, 5), 1, s**3 - c]
    k = ExactConstants(exprs)
    polys = k.polys(exprs)
    with flint_precision(200):
        vb = k.variable_balls(200)
        from imagespace.core.transcendental import _eval_ball
        factor = _eval_ball(polys[3], vb)          # the number 1 carries exactly the factor
        for e, p in zip(exprs, polys):
            got = _eval_ball(p, vb) / factor
            want = to_arb(sp.sympify(e), 200)
            assert got.overlaps(want)
            assert abs(float((got - want).mid())) < 1e-40


def test_circle_identity_is_exact_zero():
    r = R(2, 3)
    f = _form([sp.cos(r)**2 + sp.sin(r)**2 - 1, 1])
    assert f.is_zero(0) is True
    f = _form([sp.cos(r)**2 - sp.sin(r)**2 - sp.cos(2 * r), 1])   # two groups: 2/3 and 4/3
    assert f.is_zero(0) is None or f.is_zero(0) is True            # never "non-zero"


def test_simple_roots_at_transcendental_points():
    r = R(1, 3)
    c = sp.cos(r)
    # (t - c)(t + c)(t - 2) : three real roots
    coeffs = sp.Poly(sp.expand((sp.Symbol("t") - c) * (sp.Symbol("t") + c) * (sp.Symbol("t") - 2)),
                     sp.Symbol("t")).all_coeffs()[::-1]
    cert = certify_transcendental(_form(coeffs))
    assert cert.certified and cert.count == 3 and cert.multiplicities == (1, 1, 1)
    roots = sorted([-float(sp.N(c, 30)), float(sp.N(c, 30)), 2.0])
    for (lo, hi), rt in zip(cert.intervals, roots):
        assert lo <= rt <= hi
        assert hi - lo < 1e-15


def test_roots_closer_than_double_precision_are_two():
    r = R(1, 3)
    c = sp.cos(r)
    t = sp.Symbol("t")
    eps = R(1, 10**30)
    coeffs = sp.Poly(sp.expand((t - c) * (t - c - eps) * (t**2 + 1)), t).all_coeffs()[::-1]
    cert = certify_transcendental(_form(coeffs))
    assert cert.certified and cert.count == 2


def test_structural_double_root_has_multiplicity_two():
    """(t - cos r)^2 (t^2 + 1): the direct isolation cannot separate the double root; the
    square-free factors over Q(tan(r/2)) certify one real root of multiplicity 2."""
    r = R(7, 5)                                    # cos r > 0
    t = sp.Symbol("t")
    for rr in (r, R(5, 2)):                        # and cos r < 0 (the cot variable)
        c = sp.cos(rr)
        coeffs = sp.Poly(sp.expand((t - c)**2 * (t**2 + 1) * (t + 3)), t).all_coeffs()[::-1]
        cert = certify_transcendental(_form(coeffs))
        assert cert.certified, cert.method
        assert cert.count == 2 and sorted(cert.multiplicities) == [1, 2]
        assert "square-free" in cert.method


def test_two_groups_double_root_verified():
    t = sp.Symbol("t")
    c1, s2 = sp.cos(R(1, 3)), sp.sin(R(9, 7))
    coeffs = sp.Poly(sp.expand((t - c1)**2 * (t - s2)), t).all_coeffs()[::-1]
    cert = certify_transcendental(_form(coeffs))
    assert cert.certified and cert.count == 2 and sorted(cert.multiplicities) == [1, 2]


def test_root_at_infinity_and_continuum():
    r = R(1, 4)
    c, s = sp.cos(r), sp.sin(r)
    # x0 * (x0 - c x1): coefficients of x0^2, x0 x1, x1^2 -> top coefficient exactly zero
    cert = certify_transcendental(_form([1, -c, c**2 + s**2 - 1]))
    assert cert.certified and cert.count == 2 and cert.at_infinity == 1
    with pytest.raises(DegenerateDesignError):
        certify_transcendental(_form([c**2 + s**2 - 1, 0]))


def test_related_angles_are_never_a_wrong_count():
    """cos(1) - (2 cos(1/2)^2 - 1) is zero, but not as a polynomial in two free groups: the
    leading coefficient cannot be decided, so the answer is 'not certified', never a count."""
    c1, ch = sp.cos(R(1)), sp.cos(R(1, 2))
    f = _form([-1, 0, c1 - 2 * ch**2 + 1])
    from imagespace.core import transcendental as tr
    old = tr.MAX_BITS
    tr.MAX_BITS = 512                       # keep the test quick: the question is undecidable
    try:
        cert = certify_transcendental(f)
    finally:
        tr.MAX_BITS = old
    assert not cert.certified and cert.count is None


def test_elimination_returns_none_for_rational_input():
    m = isp.examples.general_3rpr()
    assert transcendental_elimination(m.quadrics(m.q_example), m.elimination_plan) is None


def test_issue_14_case_three_rrr_type():
    """Issue [14]: an RRR (actuated base revolute) + RRP + PRR design at float joint values. The
    issue's exact external solver found 4 real modes, two of them 5.5e-8 apart near
    phi = -3.1414; rounded cos/sin gave 2."""
    m = isp.PlanarParallel([
        isp.RRR(base=(R(58169, 7450), R(310161, 59600)), platform=(R(-23, 8), R(3, 4)), lengths=(R(19, 8), R(47, 8))),
        isp.RRP(base=(R(441627, 106760), R(68531, 106760)), length=R(25, 4), platform=(R(-9, 4), R(25, 8)),
                direction=(R(-85, 157), R(132, 157))),
        isp.PRR(base=(R(43131, 7400), R(35541, 14800)), axis=(R(-3, 5), R(-4, 5)), platform=(R(-21, 8), R(17, 8)),
                length=R(19, 4))])
    q = [-1.920140724811376, -1.4172525442553405, 0.24711037622577975]
    modes = m.direct_kinematics(q, certify=True)
    assert len(modes) == 4 and modes.certificate.certified
    phis = sorted(mm.pose[2] for mm in modes)
    assert abs(phis[0] - phis[1]) < 1e-6 and abs(phis[0] + 3.1414) < 1e-3
    # every mode satisfies the legs' inverse kinematics at the given joint values
    for mm in modes:
        assert mm.residual < 1e-9
    counts, path = m.certified_root_counts(np.array([q]))
    assert counts.tolist() == [4] and path.tolist() == ["arb"]
    res = m.direct_kinematics_batch(np.array([q, q]), certify=True)
    assert res.certified_roots.tolist() == [4, 4] and res.count.tolist() == [4, 4]
