"""Hostile input to every public spatial function that takes user vectors (issue [15]).

As for the planar side (``tests/*/test_invalid_*.py``): a clear error naming the parameter, never a
silent wrong answer, and above all no string ever evaluated. Each target is one argument of one
public function; every hostile kind is tried in it:

* a string that would create a file (beside a sympy number, which used to send the whole vector
  to ``sympy.sympify``; alone; in a numpy object array): refused, and the file does not exist;
* complex, bool, ``None``, a ragged nested list, wrong lengths, 0-d and 3-d arrays, NaN and
  infinity: a TypeError or InputError whose message names the parameter;
* ``1e300`` (and ``1e-300``): a finite answer or an InputError naming the parameter, never a
  NaN, an infinity or a RuntimeWarning.

Before the fix, 14 of these functions ran the planted string (``study_point([sp.Integer(1), 0, 0,
0], ["__import__('os').system('touch X')", 0, 0])``) and the Study-map functions returned zeros,
NaN or -inf at ``1e200 .. 1e300`` with only a RuntimeWarning.
"""

import warnings

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.spatial import poses, quadrics, screws, singularities, study
from imagespace.spatial.gough_stewart import GoughStewart
from imagespace.spatial.three_rps import ThreeRPS

ONE = sp.Integer(1)
RNG = np.random.default_rng(15)
BASE = RNG.normal(size=(6, 3))
PLAT = RNG.normal(size=(6, 3))
GS = GoughStewart(BASE, PLAT)
RPS = ThreeRPS([[1, 0, 0], [-0.5, 0.8, 0], [-0.5, -0.8, 0]], [[0.5, 0, 0], [-0.25, 0.4, 0], [-0.25, -0.4, 0]])
LOCUS = singularities.constant_orientation_singularity(GS, np.eye(3))
S_OK = study.study_point([1.0, 0.0, 0.0, 0.0], [0.1, 0.2, 1.0])
I3 = np.eye(3)
TWIST = np.array([0.0, 0, 1, 0, -1, 0])
LEGS = screws.TranslationalFiveR().leg_twists([0.0, 0.1, 0.0])
RPR3 = isp.examples.general_3rpr()


def _good(n):
    """A harmless valid vector of length ``n`` (a Study point for 8, a unit-ish vector otherwise)."""
    return {8: list(S_OK), 4: [1.0, 0.0, 0.0, 0.0], 3: [1.0, 0.0, 0.0], 6: list(TWIST)}[n]


# (id, the parameter's name in messages, a callable taking the argument, the argument's shape)
TARGETS = [
    ("quaternion_multiply.p", "p", lambda v: study.quaternion_multiply(v, [1, 0, 0, 0]), (4,)),
    ("quaternion_multiply.q", "q", lambda v: study.quaternion_multiply([1, 0, 0, 0], v), (4,)),
    ("quaternion_conjugate", "q", study.quaternion_conjugate, (4,)),
    ("matrix_from_quaternion", "q", study.matrix_from_quaternion, (4,)),
    ("quaternion_from_matrix", "R", study.quaternion_from_matrix, (3, 3), I3),
    ("study_point.rotation", "rotation", lambda v: study.study_point(v, [0, 0, 0]), (4,)),
    ("study_point.translation", "translation", lambda v: study.study_point([1, 0, 0, 0], v), (3,)),
    ("rotation_matrix", "s", study.rotation_matrix, (8,)),
    ("translation", "s", study.translation, (8,)),
    ("transform_matrix", "s", study.transform_matrix, (8,)),
    ("transform_points.s", "s", lambda v: study.transform_points(v, [1, 0, 0]), (8,)),
    ("transform_points.points", "points", lambda v: study.transform_points(S_OK, v), (3,)),
    ("study_condition", "s", study.study_condition, (8,)),
    ("normalize_study", "s", study.normalize_study, (8,)),
    ("compose_study.a", "a", lambda v: study.compose_study(v, S_OK), (8,)),
    ("compose_study.b", "b", lambda v: study.compose_study(S_OK, v), (8,)),
    ("inverse_study", "s", study.inverse_study, (8,)),
    ("planar_to_study", "image_point", study.planar_to_study, (4,)),
    ("study_to_planar", "s", study.study_to_planar, (8,), study.planar_to_study([1.0, 0.2, 0.3, 0.4])),
    ("quadric_value.Q", "Q", lambda v: quadrics.quadric_value(v, S_OK), (8, 8)),
    ("quadric_value.s", "s", lambda v: quadrics.quadric_value(quadrics.study_quadric_matrix(), v), (8,)),
    ("sphere_quadric.base_point", "base_point", lambda v: quadrics.sphere_quadric(v, [0, 0, 0], 1.0), (3,)),
    ("sphere_quadric.platform_point", "platform_point", lambda v: quadrics.sphere_quadric([0, 0, 0], v, 1.0), (3,)),
    ("sphere_quadric_exact.base_point", "base_point",
     lambda v: quadrics.sphere_quadric_exact(v, [0, 0, 0], 1.0), (3,)),
    ("point_on_plane_quadric.platform_point", "platform_point",
     lambda v: quadrics.point_on_plane_quadric(v, [0, 0, 0], [0, 0, 1]), (3,)),
    ("point_on_plane_quadric.plane_normal", "plane_normal",
     lambda v: quadrics.point_on_plane_quadric([0, 0, 0], [0, 0, 0], v), (3,)),
    ("point_on_line_quadrics.line_point", "line_point",
     lambda v: quadrics.point_on_line_quadrics([0, 0, 0], v, [0, 0, 1]), (3,)),
    ("point_on_line_quadrics.line_direction", "line_direction",
     lambda v: quadrics.point_on_line_quadrics([0, 0, 0], [0, 0, 0], v), (3,)),
    ("landed_point_times_n", "point", quadrics.landed_point_times_n, (3,)),
    ("pose_from_rotation.R", "R", lambda v: poses.pose_from_rotation(v, [0, 0, 0]), (3, 3), I3),
    ("pose_from_rotation.t", "t", lambda v: poses.pose_from_rotation(I3, v), (3,)),
    ("pose_from_quaternion.q", "q", lambda v: poses.pose_from_quaternion(v, [0, 0, 0]), (4,)),
    ("pose_from_rpy.rpy", "rpy", lambda v: poses.pose_from_rpy(v, [0, 0, 0]), (3,)),
    ("pose_from_matrix", "T", poses.pose_from_matrix, (4, 4)),
    ("GoughStewart.base_points", "base_points", lambda v: GoughStewart(v, PLAT), (6, 3)),
    ("GoughStewart.inverse_kinematics", "s", GS.inverse_kinematics, (8,)),
    ("GoughStewart.leg_vectors", "s", GS.leg_vectors, (8,)),
    ("GoughStewart.constraint_quadrics", "lengths", GS.constraint_quadrics, (6,)),
    ("GoughStewart.jacobian", "s", GS.jacobian, (8,)),
    ("GoughStewart.aspects", "s", GS.aspects, (8,)),
    ("ThreeRPS.platform_points", "platform_points", lambda v: ThreeRPS(np.eye(3), v), (3, 3)),
    ("ThreeRPS.base_axes", "base_axes", lambda v: ThreeRPS(np.eye(3), 0.5 * np.eye(3), base_axes=v), (3, 3)),
    ("ThreeRPS.inverse_kinematics", "s", RPS.inverse_kinematics, (8,), [1.0, 0, 0, 0, 0, 0, 0, 1.0]),
    ("ThreeRPS.constraint_quadrics", "lengths", RPS.constraint_quadrics, (3,)),
    ("jacobian_matrix", "s", lambda v: singularities.jacobian_matrix(GS, v), (8,)),
    ("jacobian_determinant", "s", lambda v: singularities.jacobian_determinant(GS, v), (8,)),
    ("aspect", "s", lambda v: singularities.aspect(GS, v), (8,)),
    ("constant_orientation_singularity", "rotation",
     lambda v: singularities.constant_orientation_singularity(GS, v), (4,)),
    ("ConstantOrientationSingularity.value", "points", LOCUS.value, (3,)),
    ("revolute.axis", "axis", lambda v: screws.revolute(v, [0, 0, 0]), (3,)),
    ("revolute.point", "point", lambda v: screws.revolute([0, 0, 1], v), (3,)),
    ("prismatic", "axis", screws.prismatic, (3,)),
    ("helical.axis", "axis", lambda v: screws.helical(v, [0, 0, 0], 0.5), (3,)),
    ("transfer.screw", "screw", lambda v: screws.transfer(v, [1, 0, 0]), (6,)),
    ("transfer.point", "point", lambda v: screws.transfer(TWIST, v), (3,)),
    ("reciprocal_product.twist", "twist", lambda v: screws.reciprocal_product(v, TWIST), (6,)),
    ("reciprocal_product.wrench", "wrench", lambda v: screws.reciprocal_product(TWIST, v), (6,)),
    ("TranslationalFiveR.leg_twists", "P", lambda v: screws.TranslationalFiveR().leg_twists(v), (3,)),
    ("TranslationalFiveR.thetas", "P", lambda v: screws.TranslationalFiveR().thetas(v), (3,)),
    ("TranslationalFiveR.couple_condition", "theta", screws.TranslationalFiveR.couple_condition, (3,)),
    ("GoughStewart.platform_points", "platform_points", lambda v: GoughStewart(BASE, v), (6, 3)),
    ("ThreeRPS.base_points", "base_points", lambda v: ThreeRPS(v, 0.5 * np.eye(3)), (3, 3), np.eye(3)),
    ("helical.point", "point", lambda v: screws.helical([0, 0, 1], v, 0.5), (3,)),
    ("reciprocal_system", "twists", screws.reciprocal_system, (2, 6), [TWIST, [0, 0, 0, 1.0, 0, 0]]),
    ("constraint_analysis.legs[1]", "legs[1]",
     lambda v: screws.constraint_analysis([LEGS[0], v, LEGS[2]], 3), (5, 6), None),
    ("constraint_analysis.intended", "intended",
     lambda v: screws.constraint_analysis(LEGS, 3, intended=v), (3, 6), np.eye(6)[3:]),
    ("planar_leg_wrenches", "pose", lambda v: screws.planar_leg_wrenches(RPR3, v), (3,), [0.5, 1.0, 0.2]),
    ("mesh_constant_orientation_singularity", "rotation",
     lambda v: isp.spatial_surfaces.mesh_constant_orientation_singularity(GS, v, [(-2, 2)] * 3, resolution=8),
     (4,)),
]
TARGETS = [t if len(t) == 5 else t + (None,) for t in TARGETS]
IDS = [t[0] for t in TARGETS]
OPTIONAL = {"base_axes", "intended"}    # None means "the default" for these
NAN_ROWS = {"theta"}                     # documented: a non-finite row gives NaN, the batch goes on


def _valid(shape, override=None):
    """A valid value of ``shape`` for the target (rows of a design, a rotation, a vector)."""
    if override is not None:
        return np.array(override, dtype=float)
    if shape == (6, 3):
        return BASE.copy()
    if shape == (3, 3):
        return 0.5 * np.eye(3)
    if shape == (8, 8):
        return quadrics.study_quadric_matrix()
    if shape == (4, 4):
        return np.eye(4)
    if shape == (5, 6):
        return LEGS[1].copy()
    return np.array(_good(shape[0]), dtype=float)


def _with(shape, entry, index=1, override=None):
    """The valid value as python objects, a sympy number in it (the old path to ``sympify``) and
    entry ``index`` (flat) replaced by ``entry``."""
    v = np.array(_valid(shape, override), dtype=object)
    flat = v.reshape(-1)
    other = 1 if index == 0 else 0
    flat[other] = sp.Float(float(flat[other])) if float(flat[other]) != 1.0 else ONE
    flat[index] = entry
    return v.tolist()


def _plant(tmp_path, tag):
    target = tmp_path / f"evaluated_{tag}"
    return target, f"__import__('pathlib').Path({str(target)!r}).touch()"


def _named(excinfo, name):
    text = str(excinfo.value)
    assert name in text, f"the message does not name {name!r}: {text}"


@pytest.mark.parametrize("target", TARGETS, ids=IDS)
def test_a_planted_string_is_never_evaluated(target, tmp_path):
    """The string would create a file if anything evaluated it: beside a sympy number (the old
    path to ``sympify``), beside a sympy symbol, alone, and in a numpy object array."""
    _, name, call, shape, ok = target
    cases = []
    for k, make in enumerate([
            lambda code: _with(shape, code, override=ok),
            lambda code: _with(shape, code, index=0, override=ok),
            lambda code: [code] * shape[0] if len(shape) == 1 else [[code] * shape[1]] * shape[0],
            lambda code: np.array(_with(shape, code, override=ok), dtype=object),
            lambda code: ([sp.Symbol("a")] + [code] * (shape[0] - 1) if len(shape) == 1
                          else [[sp.Symbol("a")] + [code] * (shape[1] - 1)] * shape[0]),
            lambda code: code]):
        path, code = _plant(tmp_path, k)
        cases.append((path, make(code)))
    for path, value in cases:
        with pytest.raises((TypeError, isp.InputError)) as excinfo:
            call(value)
        assert not path.exists(), f"{name}: the planted string was evaluated"
        _named(excinfo, name)


@pytest.mark.parametrize("target", TARGETS, ids=IDS)
@pytest.mark.parametrize("kind", ["complex", "sympy I", "bool", "None entry", "None", "nested", "bytes"])
def test_wrong_kinds_are_type_errors_naming_the_parameter(target, kind):
    _, name, call, shape, ok = target
    value = {"complex": lambda: _with(shape, 0.5 + 1j, override=ok),
             "sympy I": lambda: _with(shape, sp.I, override=ok),
             "bool": lambda: _with(shape, True, override=ok),
             "None entry": lambda: _with(shape, None, override=ok),
             "None": lambda: None,
             "nested": lambda: _with(shape, [1.0, [2.0]], override=ok),
             "bytes": lambda: _with(shape, b"1", override=ok)}[kind]()
    if value is None and name in OPTIONAL:
        return                                               # None is the documented default
    with pytest.raises((TypeError, isp.InputError)) as excinfo:
        call(value)
    _named(excinfo, name)


@pytest.mark.parametrize("target", TARGETS, ids=IDS)
def test_complex_and_bool_arrays_are_refused(target):
    _, name, call, shape, ok = target
    for value in (np.asarray(_valid(shape, ok)) + 0.5j, np.ones(shape, dtype=bool)):
        with pytest.raises(TypeError) as excinfo:
            call(value)
        _named(excinfo, name)


@pytest.mark.parametrize("target", TARGETS, ids=IDS)
@pytest.mark.parametrize("kind", ["short", "long", "0-d", "3-d"])
def test_wrong_shapes_are_input_errors_naming_the_parameter(target, kind):
    _, name, call, shape, ok = target
    good = _valid(shape, ok)
    value = {"short": lambda: good[..., :-1],
             "long": lambda: np.concatenate([good, good[..., :1]], axis=-1),
             "0-d": lambda: np.float64(1.0),
             "3-d": lambda: np.broadcast_to(good, (2, 2) + good.shape)}[kind]()
    with pytest.raises((isp.InputError, TypeError)) as excinfo:
        call(value)
    _named(excinfo, name)


@pytest.mark.parametrize("target", TARGETS, ids=IDS)
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_entries_are_input_errors_naming_the_parameter(target, bad):
    _, name, call, shape, ok = target
    value = _valid(shape, ok).copy()
    value.reshape(-1)[1] = bad
    if name in NAN_ROWS:
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)
            assert np.all(np.isnan(call(value)))
        return
    with pytest.raises(isp.InputError) as excinfo:
        call(value)
    _named(excinfo, name)


@pytest.mark.slow
@pytest.mark.parametrize("target", TARGETS, ids=IDS)
@pytest.mark.parametrize("scale", [1e200, 1e300, 1e-300])
def test_absurd_magnitudes_are_answered_or_refused(target, scale):
    """Every entry scaled: a finite answer or an InputError naming the parameter; no NaN, no
    infinity and no RuntimeWarning on the way."""
    _, name, call, shape, ok = target
    value = _valid(shape, ok) * scale
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        try:
            out = call(value)
        except isp.InputError as exc:
            assert name in str(exc), str(exc)
            return
        except isp.DegenerateDesignError:
            return
    arrays = out if isinstance(out, (tuple, list)) else [out]
    for a in arrays:
        if isinstance(a, np.ndarray) and a.dtype == object:
            continue                                         # exact Fractions: any size is an answer
        if isinstance(a, (np.ndarray, float, int, np.floating)):
            assert np.all(np.isfinite(np.asarray(a, dtype=float))), f"{name}: non-finite answer {a!r}"


# -- magnitudes answered correctly: independent values, not the code's own output -------------------

def _pose(seed):
    """A rotation matrix (Rodrigues, written here) and a translation, with its quaternion."""
    rng = np.random.default_rng(seed)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    angle = rng.uniform(0.1, 3.0)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    R = np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K
    q = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])
    t = rng.normal(size=3)
    y = 0.5 * np.array([-t @ q[1:], *(q[0] * t + np.cross(t, q[1:]))])   # y = t x / 2, written out
    return R, t, q, np.concatenate([q, y])


@pytest.mark.parametrize("scale", [1e200, 1e300, 1e-200, 1e-300, 2.0 ** -1000])
def test_study_points_of_any_scale_give_the_same_displacement(scale):
    """A Study point is projective: ``lambda s`` is the same displacement for every ``lambda != 0``
    (as long as ``lambda s`` keeps its digits: not subnormal)."""
    R, t, q, s = _pose(1)
    z = s * scale
    assert np.allclose(study.rotation_matrix(z), R, atol=1e-12)
    assert np.allclose(study.translation(z), t, atol=1e-12)
    assert np.allclose(study.transform_matrix(z)[:3, 3], t, atol=1e-12)
    assert np.allclose(study.normalize_study(z), s * np.sign(s[0]), atol=1e-12)
    assert np.allclose(study.transform_points(z, [1.0, 2.0, 3.0]), R @ [1.0, 2.0, 3.0] + t, atol=1e-12)
    assert np.allclose(study.matrix_from_quaternion(q * scale), R, atol=1e-12)
    inv = study.inverse_study(z)
    assert np.allclose(study.rotation_matrix(inv), R.T, atol=1e-12)
    assert np.allclose(study.translation(inv), -R.T @ t, atol=1e-12)
    both = study.compose_study(z, z)
    assert np.allclose(study.rotation_matrix(both), R @ R, atol=1e-12)
    assert np.allclose(study.translation(both), R @ t + t, atol=1e-12)
    assert np.allclose(study.study_point(q * scale, t), s * np.sign(s[0]), atol=1e-12)


def test_far_translations_are_answered_exactly_where_a_float_holds_them():
    """A translation of 1e300 (the dual part 1e300 times the rotation part) is a representable
    displacement: the map answers it; one whose ``|y| / |x|`` overflows is refused by name."""
    R, t, q, _ = _pose(2)
    far = t * 1e300
    s = study.study_point(q, far)
    assert np.allclose(study.translation(s) / 1e300, t, rtol=1e-12)
    assert np.allclose(study.rotation_matrix(s), R, atol=1e-12)
    lens = GS.inverse_kinematics(s)
    assert np.all(np.isfinite(lens)) and np.allclose(lens / 1e300, np.linalg.norm(t), rtol=1e-9)
    edge = study.study_point([1.0, 0, 0, 0], [1.7e308, -1.7e308, 1e308])
    assert study.translation(edge).tolist() == [1.7e308, -1.7e308, 1e308]
    with pytest.raises(isp.InputError, match="s is too large"):
        study.translation([1e-300, 0, 0, 0, 0, 1e300, 0, 0])      # |t| = 2e600
    twice = study.compose_study(edge, edge)                     # a float Study point ...
    assert twice.tolist() == [1.0, 0, 0, 0, 0, 1.7e308, -1.7e308, 1e308]
    with pytest.raises(isp.InputError, match="s is too large"):
        study.translation(twice)                                   # ... of the translation 3.4e308
    far_y = [1.0, 0, 0, 0, 0, 1.5e308, 0, 0]
    with pytest.raises(isp.InputError, match="a or b is too large"):
        study.compose_study(far_y, far_y)                          # its dual part 3e308


def test_forms_outside_the_float_range_are_refused_not_rounded_to_inf_or_zero():
    """``x . y``, ``z^T Q z``, the reciprocal product and the quaternion product at scales where
    their true value (written here) leaves the float range: an InputError, not inf, NaN or 0."""
    _, _, _, s = _pose(3)
    off = s + np.array([0, 0, 0, 0, 1.0, 0, 0, 0])            # x . y = s[0] != 0: off the quadric
    with pytest.raises(isp.InputError, match="s is too large"):
        study.study_condition(off * 1e200)                       # s[0] * 1e400
    with pytest.raises(isp.InputError, match="s is too small"):
        study.study_condition(off * 1e-200)                      # s[0] * 1e-400, not 0
    assert study.study_condition(off * 1e100) == pytest.approx(s[0] * 1e200, rel=1e-12)
    with pytest.raises(isp.InputError, match="too large"):
        quadrics.quadric_value(quadrics.study_quadric_matrix(), off * 1e200)
    with pytest.raises(isp.InputError, match="p or q is too large"):
        study.quaternion_multiply([1e200, 0, 0, 0], [1e200, 0, 0, 0])
    with pytest.raises(isp.InputError, match="p or q is too small"):
        study.quaternion_multiply([1e-200, 0, 0, 0], [1e-200, 0, 0, 0])
    assert np.allclose(study.quaternion_multiply([0, 1e150, 0, 0], [0, 0, 1e150, 0]), [0, 0, 0, 1e300])
    with pytest.raises(isp.InputError, match="reciprocal product"):
        screws.reciprocal_product([1e200, 0, 0, 0, 0, 0], [0, 0, 0, 1e200, 0, 0])
    with pytest.raises(isp.InputError, match="reciprocal product"):
        screws.reciprocal_product([1e-200, 0, 0, 0, 0, 0], [0, 0, 0, 1e-200, 0, 0])


def test_lengths_whose_squares_leave_the_float_range_are_refused_by_name():
    """The quadrics hold ``L^2``: at 1e200 it was -inf, at 1e-200 it vanished without a trace."""
    for L in (1e200, 1e-200):
        with pytest.raises(isp.InputError, match="lengths must have squares within the float range"):
            GS.constraint_quadrics(np.full(6, L))
        with pytest.raises(isp.InputError, match="lengths must have squares within the float range"):
            RPS.constraint_quadrics(np.full(3, L))
        with pytest.raises(isp.InputError, match="length must have squares"):
            quadrics.sphere_quadric([0, 0, 0], [1, 0, 0], L)
    Q = GS.constraint_quadrics(np.full(6, 1e150))               # L^2 = 1e300: still a float
    assert np.all(np.isfinite(Q)) and Q[0, 0, 0] == pytest.approx(np.sum(BASE[0] ** 2 + PLAT[0] ** 2) - 1e300)


def test_designs_of_any_size_are_judged_the_same():
    """Collinearity and the leg-plane test are relative to the design's size: the same design in
    units 1e-200 or 1e200 apart is accepted (it was "collinear" when tiny, an OverflowError in the
    3-RPS when huge), and the aspect of a pose scales with it."""
    s = study.study_point([1.0, 0.0, 0.0, 0.0], [0.1, 0.2, 1.0])
    ref = GS.aspects(s)
    for k in (1e-200, 1e200):
        g = GoughStewart(BASE * k, PLAT * k)
        assert g.aspects(study.study_point([1.0, 0.0, 0.0, 0.0], np.array([0.1, 0.2, 1.0]) * k)) == ref
        m = ThreeRPS(RPS.base_points * k, RPS.platform_points * k)
        assert np.allclose(m.base_axes / k, RPS.base_axes)
    with pytest.raises(isp.DegenerateDesignError, match="collinear"):
        ThreeRPS([[0, 0, 0], [1e-200, 0, 0], [2e-200, 0, 0]], 0.5 * np.eye(3))


def test_the_degree_12_jacobian_form_scales_as_it_must():
    """``jacobian_determinant`` is a form of degree 12: ``lambda^12`` times its value at ``s``
    while that is a float, refused where it is not."""
    d = singularities.jacobian_determinant(GS, S_OK)
    assert singularities.jacobian_determinant(GS, S_OK * 1e20) == pytest.approx(d * 1e240, rel=1e-9)
    assert singularities.jacobian_determinant(GS, S_OK * 1e-20) == pytest.approx(d * 1e-240, rel=1e-9)
    with pytest.raises(isp.InputError, match="s is out of range"):
        singularities.jacobian_determinant(GS, S_OK * 1e30)
    assert singularities.aspect(GS, S_OK * 1e300) == singularities.aspect(GS, S_OK)
    with pytest.raises(isp.InputError, match="points is too large"):
        LOCUS.value([1e200, 0, 0])


def test_unit_axes_of_any_size():
    """A screw axis of 1e300 or 1e-300 is a direction: unit twist, not zeros or a zero-axis error."""
    for k in (1e300, 1e-300):
        assert np.allclose(screws.revolute([0, 0, k], [1, 0, 0]), [0, 0, 1, 0, -1, 0])
        assert np.allclose(screws.prismatic([0, k, 0]), [0, 0, 0, 0, 1, 0])
    with pytest.raises(isp.InputError, match="point is too large"):
        screws.revolute([1, 1, 0], [1.7e308, -1.7e308, 0])


# -- the symbolic faces still work ------------------------------------------------------------------

def test_symbolic_faces_still_accept_sympy_and_numbers():
    a = sp.Symbol("a", real=True)
    s = study.study_point([ONE, 0, 0, 0], [a, 0, 0])
    assert list(s) == [1, 0, 0, 0, 0, a / 2, 0, 0]
    assert study.translation(list(s))[0] == a
    Q = quadrics.sphere_quadric([a, 0, 0], [0, 0, 0], sp.Integer(2))
    assert sp.expand(Q[0, 0]) == a ** 2 - 4
    assert quadrics.point_on_plane_quadric([0, 0, 0], [0, 0, a], [0, 0, 1]).shape == (8, 8)
    assert quadrics.form_matrix(study.study_symbols()[0] ** 2)[0, 0] == 1
    with pytest.raises(isp.InputError, match="plane_normal must be non-zero"):
        quadrics.point_on_plane_quadric([0, 0, 0], [0, 0, a], [0, 0, 0])
    with pytest.raises(isp.InputError, match="length must be >= 0"):
        quadrics.sphere_quadric([a, 0, 0], [0, 0, 0], sp.Integer(-2))


def test_platform_methods_are_numeric_faces():
    """Sympy numbers are numbers there (the same answer as floats); a symbol is refused by name
    (it used to crash inside with "too many values to unpack")."""
    exact = [ONE, 0, 0, 0, 0, sp.Rational(1, 20), sp.Rational(1, 10), sp.Rational(1, 2)]
    floats = np.array([float(v) for v in exact])
    assert np.allclose(GS.inverse_kinematics(exact), np.linalg.norm(PLAT + [0.1, 0.2, 1.0] - BASE, axis=1))
    assert np.array_equal(GS.jacobian(exact), GS.jacobian(floats))
    assert GS.aspects(exact) == GS.aspects(floats)
    for call in (GS.inverse_kinematics, GS.jacobian, GS.aspects, RPS.inverse_kinematics):
        with pytest.raises(TypeError, match="s must be numeric, got the symbolic value"):
            call([sp.Symbol("a"), 0, 0, 0, 0, 0, 0, 0])


def test_exact_study_points_refuse_a_planted_string(tmp_path):
    """Refused before msolve runs: the string is never sympified."""
    from imagespace.spatial.exact import exact_real_study_points

    path, code = _plant(tmp_path, "polys")
    for polys in ([study.study_symbols()[0], code], code, [code]):
        with pytest.raises(TypeError, match="polys"):
            exact_real_study_points(polys)
        assert not path.exists()


def test_form_matrix_and_exact_sphere_refuse_strings(tmp_path):
    for call in (lambda code: quadrics.form_matrix(code),
                 lambda code: quadrics.sphere_quadric_exact([0, 0, 0], [1, 0, 0], code),
                 lambda code: quadrics.sphere_quadric([0, 0, 0], [1, 0, 0], [ONE, code][1]),
                 lambda code: quadrics.sphere_quadric([ONE, 0, 0], [1, 0, 0], code)):
        path, code = _plant(tmp_path, "x")
        with pytest.raises(TypeError, match="str"):
            call(code)
        assert not path.exists()
    with pytest.raises(TypeError, match="string"):
        quadrics.sphere_quadric_exact([0, 0, 0], [1, 0, 0], "1/3")     # Fraction("1/3") would parse it


# -- the planar sections ------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def surface():
    return isp.examples.stigger_husty().singularity_surface()


@pytest.mark.parametrize("make", [
    lambda code: [ONE, code], lambda code: [code], lambda code: code, lambda code: (sp.pi, code),
    lambda code: np.array([ONE, code], dtype=object), lambda code: {ONE: code}])
def test_section_never_evaluates_a_planted_string(surface, make, tmp_path):
    path, code = _plant(tmp_path, "phi")
    with pytest.raises((TypeError, isp.InputError)) as excinfo:
        surface.section(make(code))
    assert not path.exists(), "the planted string was evaluated"
    assert "phi" in str(excinfo.value)


@pytest.mark.parametrize("phi, exc", [
    (0.5 + 1j, TypeError), (sp.I, TypeError), (sp.Integer(1) + sp.I, TypeError), (True, TypeError),
    (None, TypeError), ([0.5, [1.0]], TypeError), ([sp.pi, sp.pi], TypeError), (np.nan, isp.InputError),
    (np.inf, isp.InputError), (sp.oo, isp.InputError), (sp.nan, isp.InputError),
    (sp.Symbol("t"), isp.InputError), (np.zeros(2), isp.InputError), (np.zeros((1, 1, 1)), isp.InputError)])
def test_section_wrong_kinds_name_phi(surface, phi, exc):
    with pytest.raises(exc, match="phi"):
        surface.section(phi)


def test_section_at_absurd_angles_is_answered(surface):
    """``phi`` is an angle: the double 1e300 is one orientation. Its conic equals the one at the
    same angle reduced mod ``4 pi`` in 1200-bit arithmetic (mpmath, written here)."""
    import mpmath

    with mpmath.workprec(1200):
        reduced = float(mpmath.fmod(mpmath.mpf(1e300), 4 * mpmath.pi))
    big, same = surface.section(1e300), surface.section(reduced)
    assert big.type == same.type
    scale = max(abs(c) for c in same.coefficients)
    assert np.allclose(big.coefficients, same.coefficients, rtol=0, atol=1e-9 * scale)
    assert surface.section(sp.pi / 3).exact
