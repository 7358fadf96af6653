"""Bad input to imagespace.spatial.screws gets a clear error naming the parameter (issue [14])."""

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.spatial.screws import (TranslationalFiveR, constraint_analysis, helical, planar_leg_wrenches, reciprocal_product,
                               reciprocal_system, revolute, singularity_fractions, transfer)

PLANAR_LEG = np.array([revolute([0, 0, 1], [0, 0, 0]), revolute([0, 0, 1], [1, 0, 0]), revolute([0, 0, 1], [1, 1, 0])])


@pytest.mark.parametrize("call, exc, words", [
    # strings never reach sympify
    (lambda: revolute([sp.Symbol("a"), "__import__('os')", 0], [0, 0, 0]), TypeError, r"axis\[1\]"),
    (lambda: helical([sp.Symbol("a"), 0, 1], [0, 0, 0], "__import__('os')"), TypeError, "pitch"),
    (lambda: helical([0, 0, 1], [0, 0, 0], "abc"), TypeError, "pitch must be numeric"),
    (lambda: helical([0, 0, 1], [0, 0, 0], 2**1100), isp.InputError, "pitch must be within"),
    (lambda: helical([0, 0, 1], [0, 0, 0], np.nan), isp.InputError, "pitch must be finite"),
    (lambda: transfer(revolute([0, 0, 1], [1, 0, 0]), [1, 2, 3], kind=np.array([1, 2])), isp.InputError, "kind"),
    (lambda: revolute([[0, 0, 1]] * 2, [[0, 0, 0]] * 3), isp.InputError, "axis and point must have the same number"),
    (lambda: transfer(revolute([0, 0, 1], [1, 0, 0]), [[1, 2, 3]] * 2), isp.InputError, "point must be one reference"),
    (lambda: reciprocal_product(PLANAR_LEG[:2], PLANAR_LEG), isp.InputError,
     "twist and wrench must have the same number"),
    (lambda: reciprocal_system(PLANAR_LEG, tol=None), TypeError, "tol must be numeric"),
    (lambda: reciprocal_system(PLANAR_LEG, tol=np.nan), isp.InputError, "tol must be finite"),
    (lambda: reciprocal_system(PLANAR_LEG, tol=2.5), isp.InputError, r"tol must be a relative tolerance in \(0, 1\)"),
    (lambda: constraint_analysis(None, 3), TypeError, "legs must be a sequence"),
    (lambda: constraint_analysis([], 3), isp.InputError, "legs must hold at least one leg"),
    (lambda: constraint_analysis([PLANAR_LEG] * 3, 2.5), TypeError, "dof must be a whole number"),
    (lambda: constraint_analysis([PLANAR_LEG] * 3, 3, actuated=[0.5, 0, 0]), TypeError, r"actuated\[0\]"),
    (lambda: constraint_analysis([PLANAR_LEG] * 3, 3, actuated=[-1, 0, 0]), isp.InputError, r"actuated\[0\]"),
    (lambda: constraint_analysis([PLANAR_LEG] * 3, 3, actuated=0), TypeError, "actuated must be a sequence"),
    (lambda: constraint_analysis([PLANAR_LEG] * 3, 3, intended=np.eye(6)), isp.InputError, r"intended must be \(3, 6\)"),
    (lambda: constraint_analysis([PLANAR_LEG] * 3, 3, tol="abc"), TypeError, "tol must be numeric"),
    (lambda: TranslationalFiveR(a="abc"), TypeError, "a must be numeric"),
    (lambda: TranslationalFiveR(l1=np.nan), isp.InputError, "l1 must be finite"),
    (lambda: TranslationalFiveR(l2=-1.0), isp.InputError, "l2 must be a positive"),
    (lambda: TranslationalFiveR().thetas([0.0, 0.1, 0.0], branch=0.5), TypeError, "branch must be 0 or 1"),
    (lambda: TranslationalFiveR().leg_twists([0.0, 0.1, 0.0], elbow=2), isp.InputError, "elbow must be 0 or 1"),
    (lambda: TranslationalFiveR().base(3), isp.InputError, "i must be the leg index"),
    (lambda: TranslationalFiveR.d(5, 0.1), isp.InputError, "i must be the leg index"),
    (lambda: TranslationalFiveR.couple_condition("abc"), TypeError, "theta must be numeric"),
    (lambda: singularity_fractions(None), TypeError, "mechanism must be a TranslationalFiveR"),
    (lambda: singularity_fractions(TranslationalFiveR(), n=2.5), TypeError, "n must be a whole number"),
    (lambda: singularity_fractions(TranslationalFiveR(), n=10**12), isp.InputError, "n must be at most"),
    (lambda: singularity_fractions(TranslationalFiveR(), box="abc"), TypeError, "box must be numeric"),
    (lambda: singularity_fractions(TranslationalFiveR(), eps=None), TypeError, "eps must be numeric"),
    (lambda: singularity_fractions(TranslationalFiveR(), seed=-1), isp.InputError, "seed must be at least 0"),
    (lambda: planar_leg_wrenches(None, [0.5, 1, 0.2]), TypeError, "manipulator must be a PlanarParallel"),
])
def test_bad_input(call, exc, words):
    with pytest.raises(exc, match=words):
        call()


def test_valid_input_still_works():
    a = sp.Symbol("a", real=True)
    tw = helical([0, 0, 1], [a, 0, 0], sp.Rational(1, 2))
    assert float(tw[5]) == 0.5 and sp.simplify(tw[4] + a) == 0
    assert helical(sp.Matrix([0, 0, 1]), [0, 0, 0], sp.Rational(1, 2))[5] == sp.Rational(1, 2)
    # three planar legs: nine constraint wrenches stacked, more than six rows (refused before)
    res = constraint_analysis([PLANAR_LEG] * 3, 3)
    assert res.constraint_rank == 3
    assert TranslationalFiveR(a=np.int64(1)).a == 1.0
