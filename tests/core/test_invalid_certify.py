"""certify_real_roots and certify_real_roots_batch refuse what is not a binary form (issue [9])."""

import numpy as np
import pytest
import sympy as sp

import imagespace as isp


@pytest.mark.parametrize("form, exc, words", [
    ([True, False, True], TypeError, r"form\[0\] must be a number or a sympy expression, got the boolean"),
    ([1, np.bool_(False), -1], TypeError, r"form\[1\] .* boolean"),
    ([1, sp.true, -1], TypeError, r"form\[1\] .* boolean"),
    ([[1, 0, -1], [1, 0, -1]], TypeError, r"form\[0\] must be a number"),
    (np.ones((2, 3)), isp.InputError, "certify_real_roots_batch"),
    (5, TypeError, "form must be a sympy Poly or a sequence of numbers, got int 5"),
    (None, TypeError, "form must be a sympy Poly"),
])
def test_form_of_the_wrong_kind(form, exc, words):
    with pytest.raises(exc, match=words):
        isp.certify_real_roots(form)


def test_the_right_forms_still_count():
    # x0^2 - x1^2 has the two real roots t = x1/x0 = +-1, whatever the container
    for form in ([1, 0, -1], np.array([1.0, 0.0, -1.0]), (sp.Integer(1), 0, sp.Integer(-1))):
        assert isp.certify_real_roots(form).count == 2


@pytest.mark.parametrize("F, err, exc, words", [
    (np.array([[True, False, True]]), None, TypeError, "F must be numeric, got booleans"),
    ([["1", "0", "-1"]], None, TypeError, "strings are never parsed"),
    (np.array([[1 + 0j, 0, -1]]), None, TypeError, "F must be real"),
    ([[1.0, 0.0, -1.0]], [["a", 0, 0]], TypeError, "err"),
    ([[1.0, 0.0, -1.0]], [[-1.0, 0.0, 0.0]], isp.InputError, "err must hold non-negative"),
])
def test_batch_input_of_the_wrong_kind(F, err, exc, words):
    with pytest.raises(exc, match=words):
        isp.certify_real_roots_batch(F, err=err, exact=lambda i: [1, 0, -1])


def test_non_finite_batch_rows_are_masked_not_raised():
    counts, path = isp.certify_real_roots_batch(np.array([[1.0, 0.0, -1.0], [np.nan, 0.0, 1.0]]))
    assert counts.tolist() == [2, -1] and path.tolist()[1] == "invalid"
