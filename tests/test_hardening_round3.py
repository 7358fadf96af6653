"""Issue 36's reproductions: each fails on the main of 2026-12-06 (code from strings, raw errors,
a guard defeated by int64 wrap-around) and passes now."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import imagespace as isp

EVIL = "__import__('os').system('touch {marker}')"


@pytest.fixture
def marker(tmp_path):
    path = tmp_path / "pwned"
    yield path
    assert not path.exists(), "a string was evaluated as code"


@pytest.mark.parametrize("bad, kind", [
    (EVIL, isp.InputTypeError), (None, isp.InputTypeError), (True, isp.InputTypeError),
    (1 + 2j, isp.InputTypeError), (float("nan"), isp.InputError), (float("inf"), isp.InputError),
])
def test_continuum_at_never_sympifies_and_names_q(marker, bad, kind):
    from imagespace.solve.continuum import continuum_at

    m = isp.examples.general_3rpr()
    value = bad.format(marker=marker) if isinstance(bad, str) else bad
    with pytest.raises(kind, match=r"q\[0\]"):
        continuum_at(m, [value, 5, 10])


def test_continuum_at_shapes():
    from imagespace.solve.continuum import continuum_at

    m = isp.examples.general_3rpr()
    with pytest.raises(isp.InputError, match="3 joint values"):
        continuum_at(m, [1, 2])
    with pytest.raises(isp.InputTypeError, match="sequence"):
        continuum_at(m, 5)
    assert continuum_at(m, [sp.Float(11), 5, 10]) == continuum_at(m, [11, 5, 10])


def test_quadratic_field_forms_never_sympify(marker):
    from imagespace.core.quadratic_field import QuadraticFieldForms

    q = sp.symbols("q1:4")
    with pytest.raises(isp.InputTypeError, match=r"forms\[0\]\[0\].*never parsed"):
        QuadraticFieldForms([[EVIL.format(marker=marker)]], q)
    with pytest.raises(isp.InputTypeError, match="forms must be"):
        QuadraticFieldForms("x", q)


@pytest.mark.parametrize("d, kind", [(4, isp.InputError), (0, isp.InputError), (-1, isp.InputError),
                                     (2.5, isp.InputTypeError), ("2", isp.InputTypeError),
                                     (True, isp.InputTypeError)])
def test_radicand_is_checked(d, kind):
    import flint

    from imagespace.core.quadratic_field import poly_gcd

    z, one = flint.fmpq(0), flint.fmpq(1)
    with pytest.raises(kind, match="d must be an integer > 1"):
        poly_gcd([(z, one), (one, z)], [(z, -one), (one, z)], d)


def test_batch_row_index_errors_name_the_index():
    m = isp.examples.general_3rpr()
    res = m.direct_kinematics_batch([m.q_example_float])
    with pytest.raises(isp.RowIndexError, match=r"i = 5 is out of range .* 1 rows"):
        res.modes(5)
    with pytest.raises(IndexError):                  # still an IndexError, as for a list
        res.modes(-2)
    with pytest.raises(isp.InputTypeError, match="row index"):
        res.modes(True)
    assert len(res.modes(-1)) == len(res.modes(0)) == 6


@pytest.mark.parametrize("resolution", [10**9, (2**21,) * 3, (2**31, 2**31, 4)])
def test_atlas_node_guard_survives_int64_wraparound(resolution):
    # (2**21)**3 = 2**63 wraps to a negative int64 in np.prod: the guard used to let it through
    m = isp.examples.general_3rpr()
    with pytest.raises(isp.InputError, match="grid nodes; at most"):
        isp.joint_atlas(m, [(9, 13), (3, 7), (8, 12)], resolution=resolution)


def test_exceptions_keep_their_builtin_meaning():
    assert issubclass(isp.InputTypeError, TypeError) and issubclass(isp.InputTypeError, isp.ImageSpaceError)
    assert not issubclass(isp.InputTypeError, ValueError)
    assert issubclass(isp.RowIndexError, IndexError) and issubclass(isp.RowIndexError, isp.InputError)


def test_pose_from_matrix_honours_the_rotation_tolerance_and_prints_the_entry():
    from imagespace.spatial import pose_from_matrix

    T = np.eye(4)
    T[0, 0] = 1.000001
    with pytest.raises(isp.InputError, match=r"T\[:3, :3\] must .*1\.000001"):
        pose_from_matrix(T)
    loose = pose_from_matrix(T, tolerances=isp.Tolerances(rotation_matrix=1e-5))
    assert np.allclose(loose, [1, 0, 0, 0, 0, 0, 0, 0], atol=1e-6)


def test_sweep_records_a_design_that_calls_sys_exit_and_keeps_finished_ones_on_ctrl_c():
    import sys

    def f(a):
        if a == 2.0:
            sys.exit(3)
        return {"v": a * 2}

    t = isp.sweep(f, {"a": [1.0, 2.0, 3.0]}, on_error="record", progress=False)
    assert "SystemExit" in str(t.errors[1]) and t.values["v"][0] == 2.0 and t.values["v"][2] == 6.0

    def g(a):
        if a == 3.0:
            raise KeyboardInterrupt
        return {"v": a}

    with pytest.raises(KeyboardInterrupt) as info:
        isp.sweep(g, {"a": [1.0, 2.0, 3.0]}, on_error="record", progress=False)
    partial = info.value.partial_table
    assert partial.values["v"][:2].tolist() == [1.0, 2.0] and "interrupted" in str(partial.errors[2])


def test_reduced_angle_never_parses_a_string_and_reduces_1e300_exactly(marker):
    import mpmath

    from imagespace.core.certify import reduced_angle

    with pytest.raises(isp.InputTypeError, match="angle .*never parsed"):
        reduced_angle(EVIL.format(marker=marker))
    with pytest.raises(isp.InputError, match="angle must be finite"):
        reduced_angle(float("nan"))
    with mpmath.workdps(400):                         # 1e300 is a binary rational; pi to 400 digits
        x = mpmath.mpf(1e300)
        want = float(x - 2 * mpmath.pi * mpmath.floor(x / (2 * mpmath.pi) + mpmath.mpf(1) / 2))
    assert reduced_angle(1e300) == pytest.approx(want, abs=4e-16)
