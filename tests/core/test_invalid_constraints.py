"""Bad input to the dyad quadrics gets a clear error naming the parameter (issue [14]).

Each case is a reproducer that, before the fix, gave a NaN or zero quadric silently, a kind
nobody knows, or an internal ``unsupported operand`` error."""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import imagespace as isp

a = sp.Symbol("a")


@pytest.mark.parametrize("call, exc, words", [
    (lambda: isp.rr_quadric((np.nan, 0), 1, (0, 0)), isp.InputError, r"centre\[0\] must be finite, got nan"),
    (lambda: isp.rr_quadric((0, 0), np.inf, (0, 0)), isp.InputError, "radius_squared must be finite"),
    (lambda: isp.rr_quadric((0, 0), 1, (0, sp.nan)), isp.InputError, r"point\[1\] must be finite"),
    (lambda: isp.rr_quadric(("a", 0), 1, (0, 0)), TypeError, r"centre\[0\] .*string 'a'; strings are never parsed"),
    (lambda: isp.rr_quadric((0, 0), "1", (0, 0)), TypeError, "radius_squared .*string"),
    (lambda: isp.rr_quadric((0, 0), None, (0, 0)), TypeError, "radius_squared .*NoneType"),
    (lambda: isp.rr_quadric((0, 0), True, (0, 0)), TypeError, "radius_squared .*bool"),
    (lambda: isp.rr_quadric((0, 0), 1j, (0, 0)), TypeError, "radius_squared must be real"),
    (lambda: isp.rr_quadric(None, 1, (0, 0)), TypeError, "centre must be a 2-vector"),
    (lambda: isp.rr_quadric((0, 0, 0), 1, (0, 0)), isp.InputError, "centre must have two entries"),
    (lambda: isp.rr_quadric(((1, 2), 0), 1, (0, 0)), TypeError, r"centre\[0\] .*tuple"),
    (lambda: isp.rr_quadric((2**1100, 0), 1, (0, 0)), isp.InputError, r"centre\[0\] must be within the float range"),
    (lambda: isp.rr_quadric((1e300, 0), 1.0, (1e300, 0)), isp.InputError, "coefficient k2 must be finite"),
    (lambda: isp.pr_quadric((0, 0), (0, 0), (0, 0)), isp.InputError, "line_direction must be non-zero"),
    (lambda: isp.pr_quadric((0, 0), (0, 0), (sp.Integer(0), 0.0)), isp.InputError, "line_direction must be non-zero"),
    (lambda: isp.rp_quadric((0, 0), (0, 0), (0, 0)), isp.InputError, "line_direction must be non-zero"),
    (lambda: isp.rp_quadric((0, 0), (1, 0), (0, "x")), TypeError, r"base_point\[1\] .*string"),
    (lambda: isp.pp_quadric(0, 0), isp.InputError, r"\(cos_phi, sin_phi\) must be non-zero"),
    (lambda: isp.pp_quadric(np.array([1.0, 0.0]), np.array([0.0, 0.0])), isp.InputError, r"row\(s\) \[1\]"),
    (lambda: isp.pp_quadric("1", 0), TypeError, "cos_phi .*string"),
    (lambda: isp.pp_quadric(np.array([1 + 0j]), np.array([0.0])), TypeError, "cos_phi must be real"),
])
def test_constructors_refuse_bad_input(call, exc, words):
    with pytest.raises(exc, match=words):
        call()


@pytest.mark.parametrize("kind, coeffs, exc, words", [
    ("XX", [sp.Integer(1)] * 8, isp.InputError, "kind must be one of RR, PR, RP, PP, got 'XX'"),
    (None, [1] * 8, TypeError, "kind must be one of"),
    ("RR", [1] * 7 + ["x"], TypeError, "coefficient k2 .*strings are never parsed"),
    ("RR", [1] * 7 + [np.nan], isp.InputError, "coefficient k2 must be finite"),
    ("RR", [1] * 7 + [True], TypeError, "coefficient k2 .*bool"),
    ("RR", [1] * 7 + [1j], TypeError, "coefficient k2 must be real"),
    ("RR", [1] * 7 + [np.array(["1"])], TypeError, "coefficient k2 must be numeric, got strings"),
    ("RR", [1] * 6 + [np.ones(3), np.ones(2)], isp.InputError, "one common shape"),
])
def test_quadric_validates_at_construction(kind, coeffs, exc, words):
    with pytest.raises(exc, match=words):
        isp.Quadric(kind, *coeffs)


def test_methods_refuse_bad_input():
    q = isp.rr_quadric((0, 0), 1, (0, 0))
    with pytest.raises(TypeError, match="points must be numeric"):
        q.evaluate(None)
    with pytest.raises(isp.InputError, match=r"points must have shape \(..., 4\)"):
        q.evaluate([1, 0, 0])
    with pytest.raises(TypeError, match="points must be real"):
        q.gradient(np.array([1, 0, 0, 1j]))
    with pytest.raises(TypeError, match="evaluate needs numeric coefficients.*substitute numbers"):
        isp.rr_quadric((a, 0), 1, (0, 0)).evaluate([1, 0, 0, 0])
    batch = isp.rr_quadric((np.array([1.0, 2.0]), 0), 1.0, (0, 0))
    with pytest.raises(isp.InputError, match="do not match this batch"):
        batch.evaluate(np.ones((3, 4)))
    with pytest.raises(isp.InputError, match="expr needs one quadric"):
        batch.expr()
    with pytest.raises(TypeError, match="x must be four sympy symbols"):
        q.expr(x="abcd")


def test_valid_input_still_works():
    q = isp.rr_quadric((a, 0), Fraction(1, 2), (0, 0))          # symbols and fractions
    assert q.expr() == sp.expand(isp.rr_quadric((a, 0), sp.Rational(1, 2), (0, 0)).expr())
    assert isp.pr_quadric((0, 0), (0, 0), (a, 0)).kind == "PR"     # a may be 0: not decidable
    x = sp.symbols("y0:4")
    assert isp.pp_quadric(0, 1).expr(x) == -x[0]**2 + x[1]**2
    batch = isp.rr_quadric((np.array([1.0, 2.0]), 0), np.array([1.0, 4.0]), (0, 0))
    assert batch.evaluate(np.array([[1.0, 0, 0, 0.5], [1.0, 0, 0, 1.0]])).shape == (2,)
    assert float(isp.rr_quadric((np.int64(1), 0), np.float32(1), (0, 0)).evaluate([1.0, 0, 0, 0])) == 0.0


def test_complex_sympy_coefficients_are_refused():
    with pytest.raises(TypeError, match="radius_squared must be real"):
        isp.rr_quadric((0, 0), 1 + a * sp.I, (0, 0))
    with pytest.raises(TypeError, match="coefficient c must be real"):
        isp.Quadric("RR", sp.I * a, *[0] * 7)
