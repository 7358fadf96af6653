"""Bad input to the mesher gets a clear error naming the parameter (issue [14]).

Each case is a reproducer that, before the fix, was accepted silently (``max_memory=nan`` switched
the memory guard off, ``progress='yes'``, ``tol='1e-9'`` was parsed), ran a string through
``sympy.sympify``, or crashed with an internal exception (``AttributeError``, ``IndexError``,
``OverflowError``, scikit-image's ``No surface found``, numpy's ``RuntimeWarning``)."""

import warnings

import numpy as np
import pytest
import sympy as sp
import trimesh

import imagespace as isp
from imagespace.singular.meshing import FunctionImplicit, PolynomialImplicit, export_mesh, mesh_implicit, surface_implicit

u, v, w = sp.symbols("u v w")
BOX = [(-1.5, 1.5)] * 3


@pytest.fixture(scope="module")
def sphere():
    return PolynomialImplicit(u**2 + v**2 + w**2 - 1, (u, v, w))


@pytest.fixture(scope="module")
def surface():
    return isp.examples.stigger_husty().singularity_surface()


def test_polynomial_implicit_never_sympifies_a_string(monkeypatch):
    import builtins

    real_import = builtins.__import__

    def spy(name, *args, **kw):
        if name == "imagespace_issue14_canary":
            raise AssertionError("the string was evaluated")
        return real_import(name, *args, **kw)

    monkeypatch.setattr(builtins, "__import__", spy)
    with pytest.raises(TypeError, match="expr must be a number or sympy expression, got the string"):
        PolynomialImplicit("__import__('imagespace_issue14_canary')", (u, v, w))


@pytest.mark.parametrize("expr, symbols, exc, words", [
    ("x**2", (u, v, w), TypeError, "strings are never parsed"),
    (u, "uvw", TypeError, "symbols must be three sympy symbols, got str"),
    (u, None, TypeError, "symbols must be three sympy symbols"),
    (u, (u, "v", w), TypeError, r"symbols\[1\] must be a sympy Symbol"),
    (u, (u, u, w), isp.InputError, "three distinct"),
    (None, (u, v, w), TypeError, "expr must be a number or sympy expression"),
    (sp.Eq(u, 1), (u, v, w), TypeError, "sympy Equality"),
    (u + sp.nan, (u, v, w), isp.InputError, "expr must be finite"),
    (u + sp.I, (u, v, w), TypeError, "expr must be real"),
    (1 / u, (u, v, w), isp.InputError, "expr must be continuous"),
    (sp.tan(w) + u, (u, v, w), isp.InputError, "expr must be continuous"),
])
def test_polynomial_implicit_refuses_bad_input(expr, symbols, exc, words):
    with pytest.raises(exc, match=words):
        PolynomialImplicit(expr, symbols)


def test_implicit_methods_check_their_points(sphere):
    with pytest.raises(TypeError, match="P must be numeric"):
        sphere.value(None)
    with pytest.raises(isp.InputError, match=r"P must have shape \(3,\) or \(n, 3\)"):
        sphere.value([[1, 2]])                                   # was IndexError
    with pytest.raises(isp.InputError, match="P must have shape"):
        sphere.proven_sign([[1, 2]])
    with pytest.raises(TypeError, match="P must be real"):
        sphere.value_and_gradient(np.array([[1, 2, 3j]]))        # was a ComplexWarning
    with pytest.raises(TypeError, match="axes must be three 1-d float arrays"):
        sphere.grid(([0.0], [1.0]))
    with pytest.raises(TypeError, match=r"axes\[0\] must be numeric, got strings"):
        sphere.grid((["a"], [0.0], [0.0]))
    with pytest.raises(isp.InputError, match=r"axes\[0\] must be a 1-d array"):
        sphere.grid(([[0.0]], [0.0], [0.0]))
    assert np.isnan(sphere.value([[np.nan, 0, 0]])[0])       # NaN points have NaN values


def test_function_implicit_checks_the_callable_and_its_output():
    with pytest.raises(TypeError, match="value_and_gradient must be callable"):
        FunctionImplicit(None)
    with pytest.raises(TypeError, match="value must be callable or None"):
        FunctionImplicit(lambda P: P, value="x")
    bad = FunctionImplicit(lambda P: (np.zeros(3), np.zeros((3, 3))))
    with pytest.raises(isp.InputError, match=r"the function's F at 64 points must have shape \(64,\)"):
        mesh_implicit(bad, BOX, 8)                               # was numpy's "cannot reshape"


@pytest.mark.parametrize("kw, exc, words", [
    ({"max_memory": float("nan")}, isp.InputError, "max_memory must be a positive finite number"),
    ({"max_memory": float("inf")}, isp.InputError, "max_memory must be a positive finite number"),
    ({"max_memory": -1}, isp.InputError, "max_memory must be a positive finite number"),
    ({"max_memory": "1e9"}, TypeError, "max_memory must be a positive number of bytes"),
    ({"max_memory": None}, TypeError, "max_memory"),
    ({"resolution": 2.5}, TypeError, "resolution must be a whole number"),
    ({"resolution": "16"}, TypeError, "resolution must be an int or three ints"),
    ({"resolution": None}, TypeError, "resolution must be an int"),
    ({"resolution": True}, TypeError, "resolution must be a whole number"),
    ({"resolution": (8, 8, 8.0)}, TypeError, r"resolution\[2\] must be a whole number"),
    ({"resolution": (8, 8)}, isp.InputError, "got 2 entries"),
    ({"resolution": 2**1100}, isp.InputError, "above the limit max_memory"),     # was OverflowError
    ({"tol": "1e-9"}, TypeError, "tol must be a number"),                       # was parsed by float()
    ({"tol": None}, TypeError, "tol must be a number"),
    ({"tol": True}, TypeError, "tol must be a number"),
    ({"tol": float("nan")}, isp.InputError, r"tol must be in \(0, 0.01\)"),
    ({"tol": 2**1100}, isp.InputError, r"tol must be in \(0, 0.01\)"),          # was OverflowError
    ({"progress": "yes"}, TypeError, "progress must be True or False"),
    ({"progress": 1}, TypeError, "progress must be True or False"),
    ({"on_uncertified": None}, TypeError, "on_uncertified must be 'remove' or 'keep'"),
])
def test_mesh_implicit_options(sphere, kw, exc, words):
    with pytest.raises(exc, match=words):
        mesh_implicit(sphere, BOX, **{"resolution": 8, **kw})


def test_a_resolution_of_the_wrong_kind_is_still_an_input_error(sphere):
    """A TypeError by the convention, and still caught by ``except InputError`` as before."""
    with pytest.raises(isp.InputError, match="resolution must be an int"):
        mesh_implicit(sphere, BOX, 64.5)


@pytest.mark.parametrize("box, words", [
    ([(-1e308, 1e308)] * 3, "box sides must be within the float range"),     # was RuntimeWarning
    ([(-1e-310, 1e-310)] * 3, "too short for 8 grid points"),                # was an empty mesh, silently
    ([(1e10, 1e10 + 1e-5), (0, 1), (0, 1)], "too short for 8 grid points"),  # grid points would coincide
])
def test_boxes_the_grid_cannot_resolve(box, words):
    with pytest.raises(isp.InputError, match=words):
        mesh_implicit(PolynomialImplicit(u, (u, v, w)), box, 8)


def test_degenerate_fields_give_a_clear_error_or_an_empty_mesh_with_a_warning():
    # constant zero: the zero set is the whole box (was scikit-image's "No surface found")
    with pytest.raises(isp.InputError, match="func is 0 at every grid point"):
        mesh_implicit(PolynomialImplicit(sp.Integer(0), (u, v, w)), BOX, 8)
    # zero only on the box's boundary: no sign change (was "No surface found")
    with pytest.warns(UserWarning, match="touches 0 on the grid but changes sign nowhere"):
        mesh = mesh_implicit(PolynomialImplicit(u - 1, (u, v, w)), [(-1, 1)] * 3, 8)
    assert len(mesh.faces) == 0 and "does not change sign" in mesh.metadata["imagespace"]["note"]
    # not finite anywhere
    nan = FunctionImplicit(lambda P: (np.full(len(P), np.nan), np.zeros((len(P), 3))))
    with pytest.warns(UserWarning, match="NaN or infinite at every grid point"):
        assert len(mesh_implicit(nan, BOX, 8).faces) == 0
    # no zero in the box: an empty mesh, as before, without a warning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = mesh_implicit(PolynomialImplicit(u**2 + 1, (u, v, w)), BOX, 8)
    assert len(mesh.faces) == 0 and "does not meet" in mesh.metadata["imagespace"]["note"]


def test_large_function_values_are_meshed():
    """Gradients of 1e200 overflowed np.linalg.norm (RuntimeWarning); values above float32's range
    would be infinite in scikit-image's float32 grid."""
    F = PolynomialImplicit(1e200 * (u**2 + v**2 + w**2 - 1), (u, v, w))
    mesh = mesh_implicit(F, BOX, 12)
    assert len(mesh.faces) > 50 and mesh.metadata["imagespace"]["uncertified"] == 0
    assert np.allclose(np.linalg.norm(mesh.vertices, axis=1), 1.0, atol=1e-8)


def test_mesh_surface_and_surface_implicit_check_the_surface(surface):
    with pytest.raises(TypeError, match="surface must be a SingularitySurface"):
        isp.mesh_surface(None, [[-1, 1]] * 3)                    # was AttributeError '_cache'
    with pytest.raises(TypeError, match="surface must be a SingularitySurface"):
        surface_implicit("S")
    with pytest.raises(TypeError, match="chart must be 'image' or 'pose'"):
        surface_implicit(surface, None)
    with pytest.raises(isp.InputError, match="max_memory must be a positive finite number"):
        isp.mesh_surface(surface, [[-1, 1]] * 3, resolution=8, max_memory=float("nan"))


def test_export_mesh_checks_the_path(tmp_path):
    box = trimesh.creation.box()
    for bad in (None, 3, b"x.stl", ["x.stl"]):
        with pytest.raises(TypeError, match="path must be a str or pathlib.Path"):
            export_mesh(box, bad)
    (tmp_path / "folder.stl").mkdir()
    with pytest.raises(IsADirectoryError, match="is an existing folder"):
        export_mesh(box, tmp_path / "folder.stl")
    (tmp_path / "file").write_text("x")
    with pytest.raises(NotADirectoryError, match="which is a file"):
        export_mesh(box, tmp_path / "file" / "x.stl")
    assert export_mesh(box, str(tmp_path / "ok.ply")).exists()


def test_valid_options_still_work(sphere):
    mesh = mesh_implicit(sphere, BOX, np.array([8, 9, 10]), tol=np.float64(1e-9), progress=np.bool_(False),
                         max_memory=np.int64(10**9))
    assert len(mesh.faces) > 50
    assert mesh_implicit(sphere, BOX, [np.int64(8)], progress=False).metadata["imagespace"]["resolution"] == [8, 8, 8]
    assert len(PolynomialImplicit(3, (u, v, w)).grid(([0.0], [0.0], [0.0]))) == 1
