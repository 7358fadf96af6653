"""Bad input to the legs gets a clear error naming the parameter (issue [14]).

Each case is a reproducer that, before the fix, was accepted silently (NaN joint values, bools,
``'yes'``), gave a misleading message (``must be >= 0, got nan``) or crashed with an internal
exception (``IndexError``, ``AttributeError``, a numpy ``RuntimeWarning``)."""

import numpy as np
import pytest
import sympy as sp

import imagespace as isp

a = sp.Symbol("a")

LEGS = {
    "RPR": lambda act=None: isp.RPR(base=(0, 0), platform=(1, 0), actuated=act),
    "RRR": lambda act=None: isp.RRR(base=(0, 0), platform=(0, 0), lengths=(1, 1), actuated=act),
    "PRR": lambda act=None: isp.PRR(base=(0, 0), axis=(1, 0), platform=(0, 0), length=1, actuated=act),
    "RRP": lambda act=None: isp.RRP(base=(0, 0), length=1, platform=(0, 0), direction=(1, 0), actuated=act),
    "RPP": lambda act=None: isp.RPP(base=(0, 0), platform=(0, 0), direction=(1, 0), angle=np.pi / 2, actuated=act),
    "PRP": lambda act=None: isp.PRP(base=(0, 0), axis=(1, 0), platform=(0, 0), direction=(0, 1), actuated=act),
    "PPR": lambda act=None: isp.PPR(base=(0, 0), axis=(1, 0), platform=(0, 0), angle=np.pi / 2, actuated=act),
}
ALL = [(k, act) for k in LEGS for act in (0, 1, 2)]


@pytest.mark.parametrize("kind, act", ALL)
def test_dyad_refuses_non_finite_joint_values(kind, act):
    leg = LEGS[kind](act)
    for q in (float("nan"), np.inf, np.array([1.0, np.nan])):
        with pytest.raises(isp.InputError, match=r"q .*must be finite"):
            leg.dyad(q)
    with pytest.raises(isp.InputError, match="must be finite"):
        leg.dyad(sp.nan)


@pytest.mark.parametrize("kind, act", ALL)
def test_dyad_refuses_joint_values_of_the_wrong_kind(kind, act):
    leg = LEGS[kind](act)
    for q, words in ((None, "q must be numeric"), ("1", "q must be numeric"), (1j, "q must be real"),
                     (np.array([1 + 1j]), "q must be real"), (True, "q must be numeric, got booleans"),
                     ([1, "a"], "strings are never parsed"), (sp.I, "q must be real"),
                     (sp.Eq(a, 1), "q must be a number or sympy expression"),
                     (sp.true, "q must be a number or sympy expression")):
        with pytest.raises(TypeError, match=words):
            leg.dyad(q)
    with pytest.raises(isp.InputError, match=r"q must be a number or a 1-d array .*shape \(2, 2\)"):
        leg.dyad(np.ones((2, 2)))


def test_dyad_of_the_rpr_reproducer():
    leg = isp.examples.general_3rpr().legs[0]
    with pytest.raises(isp.InputError, match=r"q \(the actuated joint rho of RPR\) must be finite, got nan"):
        leg.dyad(float("nan"))
    with pytest.raises(isp.InputError, match="must be >= 0"):
        leg.dyad(-1.0)


def test_joint_values_out_of_float_range():
    with pytest.raises(isp.InputError, match="q must be within the float range"):
        LEGS["RPR"](0).dyad(2**1100)                # an angle: its cosine is taken in float
    assert LEGS["RPR"](1).dyad(2**1100).k0 == -sp.Integer(2)**2200 + 1   # a length: exact, answered right
    with pytest.raises(isp.InputError, match="q = 1e\\+200 is too large for the float dyad"):
        LEGS["RPR"](1).dyad(1e200)


@pytest.mark.parametrize("kind", list(LEGS))
def test_methods_refuse_bad_options(kind):
    leg = LEGS[kind]()
    with pytest.raises(TypeError, match="branch must be a whole number"):
        leg.joint_points([0.5, 0.2, 0.1], branch="x")
    with pytest.raises(TypeError, match="branch must be a whole number"):
        leg.joint_points([0.5, 0.2, 0.1], branch=1.5)
    with pytest.raises(isp.InputError, match="branch must be"):
        leg.joint_points([0.5, 0.2, 0.1], branch=leg.n_branches)
    with pytest.raises(isp.InputError, match="branch must be at least 0"):
        leg.joint_points([0.5, 0.2, 0.1], branch=-1)
    with pytest.raises(TypeError, match="exact must be True or False"):
        leg.geometry(exact="yes")
    with pytest.raises(TypeError, match="q must be numeric"):
        leg.joint_values_ok("a")
    with pytest.raises(TypeError, match="q must be numeric"):
        leg.check_joint_value(None)
    with pytest.raises(isp.InputError, match="must be finite"):
        leg.check_joint_value(float("nan"))
    assert not leg.joint_values_ok(np.nan)
    with pytest.raises(TypeError, match="pose must be real"):
        leg.inverse_kinematics([1, 2, 3j])
    with pytest.raises(TypeError, match="pose must hold real numbers"):
        leg.actuated_values([True, 0, 0])


@pytest.mark.parametrize("actuated, exc", [("1", TypeError), (1.0, TypeError), (True, TypeError),
                                           (None, None), (3, isp.InputError), (-1, isp.InputError),
                                           (2**1100, isp.InputError)])
def test_actuated_index(actuated, exc):
    if exc is None:
        assert LEGS["RPR"](actuated).actuated == isp.RPR.default_actuated
        return
    with pytest.raises(exc, match="actuated must be 0, 1 or 2"):
        LEGS["RPR"](actuated)


@pytest.mark.parametrize("call, exc, words", [
    (lambda: isp.RPR(base=(np.nan, 0), platform=(0, 0)), isp.InputError, r"base\[0\] must be finite"),
    (lambda: isp.RPR(base=("a", 0), platform=(0, 0)), TypeError, r"base\[0\] must be a real number"),
    (lambda: isp.RPR(base=None, platform=(0, 0)), TypeError, "base must be a 2-vector"),
    (lambda: isp.RPR(base=(2**1100, 0), platform=(0, 0)), isp.InputError, r"base\[0\] must be within the float range"),
    (lambda: isp.RRR(base=(0, 0), platform=(0, 0), lengths=(1, 2**1100)), isp.InputError,
     r"lengths\[1\] must be within the float range"),
    (lambda: isp.PRR(base=(0, 0), axis=(0, 0), platform=(0, 0), length=1), isp.InputError,
     "axis must be a non-zero direction"),
    (lambda: isp.PRR(base=(0, 0), axis=(1, 0), platform=(0, 0), length=2**1100), isp.InputError,
     "length must be within the float range"),
    (lambda: isp.RRP(base=(0, 0), length=1, platform=(0, 0), direction=(0.0, 0.0)), isp.InputError,
     "direction must be a non-zero direction"),
    (lambda: isp.PRP(base=(0, 0), axis=(1, 0), platform=(0, 0), direction=(2**1100, 0)), isp.InputError,
     r"direction\[0\] must be within the float range"),
    (lambda: isp.RPP(base=(0, 0), platform=(0, 0), direction=(1, 0), angle=2**1100), isp.InputError,
     "angle must be within the float range"),
    (lambda: isp.PPR(base=(0, 0), axis=(1, 0), platform=(0, 0), angle=2**1100), isp.InputError,
     "angle must be within the float range"),
    (lambda: isp.PPR(base=(0, 0), axis=(1, 0), platform=(0, 0), angle=np.nan), isp.InputError,
     "angle must be finite"),
    (lambda: isp.PPR(base=(0, 0), axis=(1, 0), platform=(0, 0), angle=0), isp.DegenerateDesignError,
     "must not be 0 or pi"),
])
def test_constructors_refuse_bad_geometry(call, exc, words):
    with pytest.raises(exc, match=words):
        call()


def test_valid_input_still_works():
    leg = LEGS["RPR"]()
    assert leg.dyad(np.array([1.0, 2.0])).k0.shape == (2,)
    assert leg.dyad(np.array([], dtype=float)).k0.shape == (0,)
    assert leg.dyad(a).expr().has(a)
    assert leg.joint_values_ok([-1.0, 2.0, np.inf]).tolist() == [False, True, False]
    assert leg.joint_points([0.5, 0.2, 0.1], branch=np.int64(1)).shape == (2, 2)
    assert leg.geometry(exact=np.bool_(False)) == {"base": (0.0, 0.0), "platform": (1.0, 0.0)}
    big = isp.RPR(base=(1e308, 0), platform=(0, 0))          # large but finite: allowed
    assert big.geometry(exact=False)["base"] == (1e308, 0.0)


@pytest.mark.parametrize("call, words", [
    (lambda: isp.RPR(base=(sp.I, 0), platform=(0, 0)), r"base\[0\] must be real"),
    (lambda: isp.RPR(base=(a + sp.I, 0), platform=(0, 0)), r"base\[0\] must be real"),
    (lambda: isp.RPR(base=(sp.true, 0), platform=(0, 0)), r"base\[0\] .*sympy BooleanTrue"),
    (lambda: isp.RPR(base=(sp.Eq(a, 1), 0), platform=(0, 0)), r"base\[0\] .*sympy Equality"),
    (lambda: isp.PRR(base=(0, 0), axis=(1, sp.I), platform=(0, 0), length=1), r"axis\[1\] must be real"),
    (lambda: isp.PRR(base=(0, 0), axis=(1, 0), platform=(0, 0), length=sp.I), "length must be real"),
    (lambda: isp.RPP(base=(0, 0), platform=(0, 0), direction=(1, 0), angle=sp.I), "angle must be real"),
])
def test_sympy_geometry_of_the_wrong_kind(call, words):
    """Was 'Cannot convert complex to float' (or a leg holding Eq(a, 1) as a coordinate)."""
    with pytest.raises(TypeError, match=words):
        call()


def test_symbolic_geometry_still_works():
    leg = isp.RPR(base=sp.Matrix([a, 1]), platform=(sp.sqrt(2), sp.pi))
    assert leg.free_symbols == {a}
    assert leg.dyad(sp.Symbol("q")).expr().has(a)
