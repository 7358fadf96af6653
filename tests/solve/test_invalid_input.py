"""Bad input gets a clear error naming the parameter, never a silent wrong answer (issue [9],
the parts on the kinematic map, the validation module and the manipulator's DK options).

Each case is a reproducer that, before the fix, was accepted silently, crashed with an internal
exception, or returned a wrong answer."""

import warnings

import numpy as np
import pytest

import imagespace as isp


@pytest.fixture
def m():
    return isp.examples.general_3rpr()


@pytest.mark.parametrize("q, exc, words", [
    (np.array([11 + 1j, 5, 10]), TypeError, "q must be real"),
    ([True, 5, 10], TypeError, "q must hold real numbers"),
    (["11", "5", "10"], TypeError, "strings are never parsed"),
    ([2**1100, 5, 10], isp.InputError, "q must be within the float range"),
])
def test_joint_values_of_the_wrong_kind(m, q, exc, words):
    with warnings.catch_warnings():
        warnings.simplefilter("error")                # a ComplexWarning is not an answer
        with pytest.raises(exc, match=words):
            m.direct_kinematics(q)


@pytest.mark.parametrize("call, exc, words", [
    (lambda m: m.direct_kinematics([11, 5, 10], certify="yes"), TypeError, "certify must be True or False"),
    (lambda m: m.direct_kinematics([11, 5, 10], include_complex=1), TypeError, "include_complex"),
    (lambda m: m.direct_kinematics_batch(np.full((2, 3), 7.0), certify="yes"), TypeError, "certify"),
    (lambda m: m.direct_kinematics_batch(np.full((2, 3), 7.0), method=None), isp.InputError, "method"),
    (lambda m: list(m.direct_kinematics_chunks(np.full((3, 3), 7.0), chunk_size=2.5)), TypeError,
     "chunk_size must be a whole number"),
    (lambda m: list(m.direct_kinematics_chunks(np.full((3, 3), 7.0), chunk_size=0)), isp.InputError,
     "chunk_size must be at least 1"),
    (lambda m: m.inverse_kinematics([0.0, 0.0, 0.0], working_modes=(0.5, 0, 0)), TypeError,
     r"working_modes\[0\] must be a whole number"),
    (lambda m: m.inverse_kinematics([0.0, 0.0, 0.0], working_modes=3), TypeError, "working_modes"),
    (lambda m: isp.PlanarParallel(m.legs, tolerances=None), TypeError, "tolerances must be"),
    (lambda m: isp.PlanarParallel(None), TypeError, "legs must be a sequence of three Leg"),
    (lambda m: isp.PlanarParallel("RPR"), TypeError, "legs must be a sequence"),
])
def test_options_of_the_wrong_kind(m, call, exc, words):
    with pytest.raises(exc, match=words):
        call(m)


def test_options_that_are_right_still_work(m):
    assert len(m.direct_kinematics(np.array([11, 5, 10]))) == 6         # integer arrays are numbers
    assert len(m.direct_kinematics((11.0, 5.0, 10.0), certify=np.bool_(True))) == 6
    chunks = list(m.direct_kinematics_chunks(np.tile(m.q_example_float, (3, 1)), chunk_size=np.int64(2)))
    assert [s for s, _ in chunks] == [0, 2]


@pytest.mark.parametrize("bad", [np.nan, -1.0, 0.0, float("inf"), "a"])
def test_tolerances_are_validated_at_construction(bad):
    with pytest.raises((ValueError, TypeError), match="joint_residual"):
        isp.Tolerances(joint_residual=bad)
    with pytest.raises((ValueError, TypeError), match="newton_steps"):
        isp.Tolerances(newton_steps=2.5)


def test_extreme_homogeneous_representatives():
    """Any non-zero multiple is the same point: scale before squaring. The pose of (1, 0, 1, 1)
    is x = 2 (x0 x3 + x1 x2) = 2, y = 2 (-x0 x2 + x1 x3) = -2, phi = 0 (docs/conventions.md)."""
    for k in (1e-300, 1.0, 1e300):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            assert np.allclose(isp.pose_of([k, 0.0, k, k]), [2.0, -2.0, 0.0])
            assert np.allclose(isp.normalize([k] * 4), [np.sqrt(0.5)] * 4)
            assert np.allclose(isp.transform_matrix([k, 0.0, k, k])[1:, 0], [2.0, -2.0])
    # and the map and its inverse agree with image_point on an ordinary pose
    X = isp.image_point([2.0, -2.0, 0.0])
    assert np.allclose(X / X[0], [1.0, 0.0, 1.0, 1.0])


@pytest.mark.parametrize("call", [
    lambda: isp.compose([0.0, 0.0, 1.0, 1.0], [1.0, 0.0, 0.0, 0.0]),
    lambda: isp.compose([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 1.0]),
    lambda: isp.inverse([0.0, 0.0, 1.0, 1.0]),
    lambda: isp.pose_of([0.0, 0.0, 1.0, 1.0]),
    lambda: isp.normalize([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 2.0, 0.0]]),
])
def test_points_of_the_absolute_line_are_refused_everywhere(call):
    with pytest.raises(isp.InputError, match="absolute line"):
        call()


@pytest.mark.parametrize("call", [
    lambda: isp.image_point(np.array([1 + 1j, 0.0, 0.0])),
    lambda: isp.pose_of(np.array([1 + 0j, 0, 0, 0])),
    lambda: isp.normalize(np.array([1 + 0j, 0, 0, 0])),
    lambda: isp.transform_matrix(np.array([1 + 0j, 0, 0, 0])),
    lambda: isp.inverse(np.array([1 + 0j, 0, 0, 0])),
])
def test_complex_arrays_are_refused_by_the_kinematic_map(call):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(TypeError, match="real"):
            call()


def test_strings_never_reach_an_evaluator(tmp_path):
    target = tmp_path / "planted"
    payload = f"__import__('pathlib').Path({str(target)!r}).write_text('x') and 0"
    for call in (lambda: isp.image_point([payload, 0, 0]),
                 lambda: isp.pose_of([payload, 0, 0, 0]),
                 lambda: isp.normalize([1.0, payload, 0, 0]),
                 lambda: isp.certify_real_roots([payload, 0, -1])):
        with pytest.raises(TypeError):
            call()
    assert not target.exists()


def test_symbolic_joint_value_is_refused_by_name(m):
    import sympy as sp
    with pytest.raises(TypeError, match="q must be numeric, got the symbolic value"):
        m.direct_kinematics([sp.Symbol("a"), 5, 10])
    # exact sympy numbers are numbers: the same six modes as the floats
    assert len(m.direct_kinematics([sp.sqrt(121), sp.Integer(5), sp.Rational(10)], certify=True)) == 6


def test_a_batch_too_large_for_memory_points_to_the_chunks(m, monkeypatch):
    """2e7 rows with 1 GB available: refused before allocating, naming the way out."""
    from imagespace import _memory
    monkeypatch.setattr(_memory, "available_memory", lambda: 1e9)
    Q = np.broadcast_to(m.q_example_float, (20_000_000, 3))
    with pytest.raises(isp.InputError, match=r"20,000,000 rows needs about .* GB .*direct_kinematics_chunks"):
        m.direct_kinematics_batch(Q, method="numpy")
    (start, r), = list(m.direct_kinematics_chunks(Q[:5], chunk_size=8, method="numpy"))
    assert start == 0 and r.count.tolist() == [6] * 5


@pytest.mark.parametrize("call, exc, words", [
    (lambda m: m.direct_kinematics_chunks(None), TypeError, "Q must be numeric"),         # raised at the call,
    (lambda m: m.direct_kinematics_chunks(np.zeros((2, 3)), chunk_size="a"), TypeError, "chunk_size"),  # not at
    (lambda m: m.direct_kinematics_chunks(np.zeros((2, 3)), method="x"), isp.InputError, "method"),     # the first
    (lambda m: m.direct_kinematics_chunks(np.zeros((2, 3), dtype=complex)), TypeError, "Q must be a real"),  # chunk
    (lambda m: m.joint_residual([0.1, 0.2, 0.3], m.q_example_float, length=-1), isp.InputError, "length must be positive"),
    (lambda m: m.joint_residual([0.1, 0.2, 0.3], m.q_example_float, length=np.nan), isp.InputError, "length must be finite"),
    (lambda m: m.joint_residual([0.1, 0.2, 0.3], m.q_example_float, length=[1, 2]), isp.InputError, "one per row"),
    (lambda m: m.joint_residual([0.1, 0.2, 0.3], m.q_example_float, length=2**1100), isp.InputError, "float range"),
    (lambda m: m.leg_points([0.1, 0.2, 0.3], q=2.5), isp.InputError, r"q must have shape \(3,\)"),
    (lambda m: m.leg_points([0.1, 0.2, 0.3], q=[1, 2]), isp.InputError, r"q must have shape \(3,\)"),
    (lambda m: m.constraint_equations([[1, 2, 3]]), isp.InputError, r"q must have shape \(3,\)"),
    (lambda m: m.kinematic_polynomial([[11, 5, 10]]), isp.InputError, r"q must have shape \(3,\)"),
    (lambda m: m.kinematic_polynomial("abc"), TypeError, "q must be three joint values"),
])
def test_more_manipulator_options_of_the_wrong_kind(m, call, exc, words):
    with pytest.raises(exc, match=words):
        call(m)
