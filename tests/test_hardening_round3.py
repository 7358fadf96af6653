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


def test_tolerances_raise_the_library_errors():
    with pytest.raises(isp.InputTypeError, match="Tolerances.rank .*never parsed"):
        isp.Tolerances(rank="1e-9")
    with pytest.raises(isp.InputTypeError, match="Tolerances.rank"):
        isp.Tolerances(rank=True)
    with pytest.raises(isp.InputError, match="Tolerances.rank must be a positive finite number"):
        isp.Tolerances(rank=float("nan"))
    with pytest.raises(isp.InputError, match="newton_steps must be a whole number"):
        isp.Tolerances(newton_steps=2.5)


@pytest.mark.parametrize("bad", [True, np.True_, "11", 1j])
def test_a_bool_or_string_in_a_long_python_list_is_refused(bad):
    # the entry check once stopped at 4,096 entries: a True past it became 1.0
    m = isp.examples.general_3rpr()
    rows = [[11.0, 5.0, 10.0]] * 5000 + [[bad, 5.0, 10.0]]
    with pytest.raises(isp.InputTypeError, match="^Q must"):
        m.direct_kinematics_batch(rows)


def test_an_all_zero_quadric_is_degenerate():
    with pytest.raises(isp.DegenerateDesignError, match="every coefficient zero"):
        isp.Quadric("RR", *[0] * 8)
    with pytest.raises(isp.DegenerateDesignError, match="every coefficient zero"):
        isp.Quadric("PP", *[sp.Integer(0)] * 8)
    isp.Quadric("RR", *[sp.Symbol("a")] + [0] * 7)    # an expression that may vanish is not refused


def test_a_leg_given_twice_is_reported():
    R = isp.RRR(base=(0, 0), platform=(1, 0), lengths=(2, 2))
    with pytest.warns(isp.RepeatedLegWarning, match=r"legs\[0\] and legs\[1\] are the same RRR"):
        m = isp.PlanarParallel([R, R, isp.RPR(base=(5, 0), platform=(0, 1))])
    # where the two angles differ the design assembles: the two circles about the elbows pin the
    # platform point (the same leg at q = 0.3 and 1.1); the third leg's length from a chosen phi
    c1, c2 = 2 * np.array([np.cos(0.3), np.sin(0.3)]), 2 * np.array([np.cos(1.1), np.sin(1.1)])
    mid, d = (c1 + c2) / 2, np.linalg.norm(c2 - c1)
    h = np.sqrt(4 - (d / 2) ** 2)
    p = mid - h * np.array([-(c2 - c1)[1], (c2 - c1)[0]]) / d    # on both circles, not the base pivot
    phi = 0.4
    rot = np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])
    origin = p - rot @ [1.0, 0.0]                                   # the platform point (1, 0)
    length = np.linalg.norm(origin + rot @ [0.0, 1.0] - [5.0, 0.0])
    with pytest.warns(isp.NearSingularWarning, match="leg singularity"):
        # two of its modes put the platform point on the base pivot, where the RRR's angle is free
        modes = m.direct_kinematics([0.3, 1.1, length], certify=True)
    assert any(np.allclose(mode.pose, [*origin, phi], atol=1e-8) for mode in modes)
    Rm = isp.RRR(base=(0, 0), platform=(1, 0), lengths=(2, 2), actuated=1)
    with pytest.raises(isp.DegenerateDesignError, match="concentric circles"):
        isp.PlanarParallel([Rm, Rm, isp.RPR(base=(5, 0), platform=(0, 1))])


def test_points_off_studys_quadric_are_not_displacements():
    from imagespace import spatial as S

    off = [1, 0, 0, 0, 1, 0, 0, 0]                  # x . y = 1
    for f in (S.translation, S.transform_matrix):
        with pytest.raises(isp.InputError, match="^s must lie on Study's quadric"):
            f(off)
    with pytest.raises(isp.InputError, match="^s must lie on Study's quadric"):
        S.transform_points(off, [[0.0, 0.0, 0.0]])
    # the rotation of x and the dual-quaternion algebra are defined for any point with x != 0
    assert np.allclose(S.rotation_matrix(off), np.eye(3))
    assert np.allclose(S.compose_study(off, [1, 0, 0, 0, 0, 0, 0, 0]), S.normalize_study(off))
    # a displacement rounded to floats is on it: a half-turn and a far translation
    s = S.study_point([0.0, 0.3, 0.4, 0.5], [1e6, -2e5, 3.0])
    assert np.allclose(S.translation(s), [1e6, -2e5, 3.0])


def test_a_zero_sympy_quaternion_is_refused():
    from imagespace import spatial as S

    with pytest.raises(isp.InputError, match="non-zero quaternion"):
        S.matrix_from_quaternion([sp.Integer(0)] * 4)


def test_batch_result_editing_refuses_junk_with_the_library_errors():
    m = isp.examples.general_3rpr()
    b = m.direct_kinematics_batch([m.q_example_float] * 2)
    with pytest.raises(isp.InputTypeError, match=r"parts\[1\] must be a DKBatchResult"):
        isp.DKBatchResult.concatenate([b, 5])
    with pytest.raises(isp.InputError, match="at least one"):
        isp.DKBatchResult.concatenate([])
    with pytest.raises(isp.RowIndexError, match="rows must lie in -2 .. 1"):
        b.set_modes(7, [])
    with pytest.raises(isp.InputTypeError, match=r"modes\[0\] must hold AssemblyMode"):
        b.set_modes(0, [5])
    with pytest.raises(isp.InputError, match="distinct"):
        b.set_modes([0, 0], [[], []])
    with pytest.raises(isp.RowIndexError):
        b[5]
    assert len(isp.DKBatchResult.concatenate([b, b])) == 4


def test_uniqueness_domain_poses_want_a_mask_of_the_grid():
    from imagespace.atlas import uniqueness_domains

    ud = uniqueness_domains(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 8)
    mask = ud.aspect >= 0
    assert ud.poses(mask).shape == (int(mask.sum()), 3)
    with pytest.raises(isp.InputTypeError, match="^mask must be a boolean array"):
        ud.poses(5)
    with pytest.raises(isp.InputError, match=r"^mask must have the grid's shape \(8, 8, 8\)"):
        ud.poses(np.ones(3, bool))


def test_certified_root_counts_guards_its_memory():
    m = isp.examples.general_3rpr()
    Q = np.broadcast_to(np.array([11.0, 5.0, 10.0]), (10 ** 9, 3))    # a view: nothing allocated
    with pytest.raises(isp.InputError, match="certified_root_counts of 1,000,000,000 rows needs about"):
        m.certified_root_counts(Q)


@pytest.mark.parametrize("scale", [1e100, 1e200])
def test_a_three_rps_in_huge_units_answers_like_the_unit_design(scale):
    a = np.array([[1, 0, 0], [-0.5, 0.8, 0], [-0.5, -0.8, 0]])
    b = np.array([[0.5, 0, 0], [-0.25, 0.4, 0], [-0.25, -0.4, 0]])
    L = np.array([1.2, 1.1, 1.3])
    unit = isp.ThreeRPS(a, b).direct_kinematics(L, certify=True)
    big = isp.ThreeRPS(a * scale, b * scale)
    r = big.direct_kinematics(L * scale, certify=True)
    assert r.certified and r.count == unit.count > 0
    # the same poses, the translations scaled (Study points up to sign; the leg lengths back)
    assert np.allclose(np.linalg.norm(big.leg_vectors(r.study_points) / scale, axis=-1), L, rtol=1e-9)


def test_msolve_numbers_of_any_length_convert():
    from imagespace.core import msolve

    n = 7 ** 12000                                      # ~10,000 digits: past python's 4,300 limit
    assert msolve._int(msolve._digits(n)) == n
    assert msolve._int(msolve._digits(-n)) == -n


@pytest.mark.slow
def test_is_cuspidal_in_1e100_units_decides_as_in_unit_units():
    # the float witness search overflows at this size; the exact decision is unit-free
    g = isp.examples.general_3rpr()
    s = sp.Integer(10) ** 100
    legs = [isp.RPR(base=tuple(sp.nsimplify(v) * s for v in L.geometry()["base"]),
                    platform=tuple(sp.nsimplify(v) * s for v in L.geometry()["platform"])) for L in g.legs]
    box = [(8, 14), (2, 8), (7, 13)]
    unit = isp.is_cuspidal(g, box)
    big = isp.is_cuspidal(isp.PlanarParallel(legs), [(lo * 1e100, hi * 1e100) for lo, hi in box], timeout=120)
    assert unit.cuspidal is True and big.cuspidal is True and "float search was skipped" in big.reason


def test_explorer_waits_take_seconds_only():
    from imagespace._validate import as_seconds

    for bad, err in (("5", isp.InputTypeError), (float("nan"), isp.InputError), (-1.0, isp.InputError),
                     (None, isp.InputTypeError), ([1, 2], isp.InputError)):
        with pytest.raises(err, match="^timeout"):
            as_seconds(bad)
    pytest.importorskip("ipywidgets")
    gs, L = isp.examples.dietmaier_1998()
    explorer = isp.widgets.explore(gs, L)
    with pytest.raises(isp.InputTypeError, match="^timeout"):
        explorer.wait("5")
    with pytest.raises(isp.InputError, match="^timeout"):
        explorer.wait(float("nan"))
    assert explorer.wait(60.0)
