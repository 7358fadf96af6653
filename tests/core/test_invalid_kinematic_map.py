"""Bad input to the kinematic map gets a clear error naming the parameter (issue [14]).

Above all, a string in a symbolic face is refused, never handed to ``sympy.sympify`` (which
evaluates it as Python code). Each case is a reproducer that was accepted, evaluated or crashed
before the fix."""

import numpy as np
import pytest
import sympy as sp

import imagespace as isp

a = sp.Symbol("a")


class _Evaluated(Exception):
    pass


def test_a_string_in_the_symbolic_face_is_never_evaluated(monkeypatch):
    import builtins

    real_import = builtins.__import__

    def spy(name, *args, **kw):
        if name == "imagespace_issue14_canary":
            raise _Evaluated(name)
        return real_import(name, *args, **kw)

    monkeypatch.setattr(builtins, "__import__", spy)
    with pytest.raises(TypeError, match=r"pose\[1\] must be a number or sympy expression, got the string"):
        isp.image_point([a, "__import__('imagespace_issue14_canary')", 0])


@pytest.mark.parametrize("call, words", [
    (lambda: isp.image_point([a, "__import__('os')", 0]), r"pose\[1\] .*strings are never parsed"),
    (lambda: isp.pose_of([a, "1", 0, 0]), r"image_point\[1\] .*got the string '1'"),
    (lambda: isp.inverse([a, "1", 0, 0]), r"image_point\[1\] .*string"),
    (lambda: isp.normalize([a, "1", 0, 0]), r"image_point\[1\] .*string"),
    (lambda: isp.transform_matrix([a, "1", 0, 0]), r"image_point\[1\] .*string"),
    (lambda: isp.compose([a, "1", 0, 0], [1, 0, 0, 0]), r"a\[1\] .*string"),
    (lambda: isp.compose([1, 0, 0, 0], [a, b"1", 0, 0]), r"b\[1\] .*string"),
    (lambda: isp.transform_points([a, 1, 0, 0], ["1", 0]), r"points\[0\] .*string"),
])
def test_strings_in_symbolic_faces_are_refused(call, words):
    with pytest.raises(TypeError, match=words):
        call()


@pytest.mark.parametrize("entry, exc, words", [
    (None, TypeError, "got NoneType"),
    (True, TypeError, "got bool"),
    (1j, TypeError, "must be real"),
    (sp.I, TypeError, "must be real"),
    ([1, 2], TypeError, "got list"),
    (sp.true, TypeError, "sympy BooleanTrue"),
    (sp.Eq(a, 1), TypeError, "sympy Equality"),
    (np.nan, isp.InputError, "must be finite"),
    (sp.nan, isp.InputError, "must be finite"),
    (sp.oo, isp.InputError, "must be finite"),
])
def test_other_wrong_entries_in_symbolic_faces(entry, exc, words):
    with pytest.raises(exc, match=r"pose\[1\] .*" + words):
        isp.image_point([a, entry, 0])


def test_symbolic_faces_refuse_the_absolute_line_when_decidable():
    for call, name in [(isp.pose_of, "image_point"), (isp.normalize, "image_point"),
                       (isp.inverse, "image_point"), (isp.transform_matrix, "image_point")]:
        with pytest.raises(isp.InputError, match=name + r" must have \(x0, x1\) != \(0, 0\)"):
            call([0, 0, a, 1])
    with pytest.raises(isp.InputError, match="absolute line"):
        isp.pose_of([sp.Integer(0), sp.Float(0.0), a, 1])        # Float(0) == 0 is False in sympy
    with pytest.raises(isp.InputError, match=r"^a must have"):
        isp.compose([0, 0, a, 1], [1, 0, 0, 0])
    with pytest.raises(isp.InputError, match=r"^b must have"):
        isp.compose([1, 0, 0, 0], [0, 0, a, 1])


def test_symbolic_faces_of_the_wrong_shape():
    with pytest.raises(TypeError, match="pose must be a sequence of 3"):
        isp.image_point(a)
    with pytest.raises(isp.InputError, match="image_point must have 4 entries, got 3"):
        isp.pose_of([a, 1, 0])
    with pytest.raises(isp.InputError, match="shape"):
        isp.inverse(np.array([[a, 1, 0, 0]], dtype=object))


def test_transform_points_has_a_symbolic_face():
    # was: AttributeError 'MutableDenseMatrix' object has no attribute 'ndim'
    out = isp.transform_points([1, 0, a, 1], [1, 0])
    assert out == sp.Matrix([3, -2 * a])
    X = isp.image_point([1.0, 2.0, 0.5])
    num = isp.transform_points(X, [1.0, 2.0])
    assert np.allclose(np.array(isp.transform_points(X, [sp.Integer(1), 2]), dtype=float).ravel(), num)


def test_batches_of_different_lengths_are_refused_by_name():
    # was: numpy's "operands could not be broadcast together"
    with pytest.raises(isp.InputError, match="a and b must be single points or batches of the same length"):
        isp.compose(np.ones((2, 4)), np.ones((3, 4)))
    assert isp.compose(np.ones((2, 4)), np.ones((1, 4))).shape == (2, 4)


def test_valid_symbolic_input_still_works():
    assert isp.image_point([a, 0.5, 0]) == sp.Matrix([1, 0, -sp.Float(0.25), a / 2])
    assert isp.image_point([a, np.int64(1), 0])[2] == sp.Rational(-1, 2)
    assert isp.inverse(sp.Matrix([1, a, 0, 0])) == sp.Matrix([1, -a, 0, 0])
    assert isp.compose([1, 0, a, 0], [1, 0, 0, 0]) == sp.Matrix([1, 0, a, 0])


@pytest.mark.parametrize("call", [isp.pose_of, isp.normalize, isp.transform_matrix,
                                  lambda X: isp.transform_points(X, [1.0, 0.0])])
def test_displacements_beyond_the_float_range_are_refused(call):
    """(x0, x1) = (1e-320, 0) next to x2 = x3 = 1: a translation of about 1e320. Was a numpy
    'divide by zero' RuntimeWarning and inf or NaN entries (the rotation block of transform_matrix
    came out 0/0)."""
    with pytest.raises(isp.InputError, match="image_point describes a displacement beyond the float range"):
        call([1e-320, 0.0, 1.0, 1.0])
    with pytest.raises(isp.InputError, match=r"at row\(s\) \[1\]"):
        call(np.array([[1.0, 0, 0, 0], [1e-320, 0.0, 1.0, 1.0]]))
