"""The seeds' closed forms at their edges (issue 13, item 9): seed 003's collinear 3-RPR at
sin(theta) = 0 and seed 004's 3-PPR at |sin psi| = 1, against the leg geometry written here
(leg lengths and slider positions from the points, not from the package), the counts of the
notes' own constructions derived here, and the image-space direct kinematics."""

import warnings

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.examples import choi_3ppr_closed_form, collinear_3rpr_closed_form


# ---------------------------------------------------------------- seed 003: collinear 3-RPR

def collinear_legs(pose, R, r):
    """|P_i - A_i| for base A = (-R, 0), (0, 0), (R, 0), platform (-r, 0), (0, 0), (r, 0)."""
    x, y, th = pose
    A = np.array([[-R, 0.0], [0.0, 0.0], [R, 0.0]])
    p = np.array([-r, 0.0, r])
    P = np.column_stack([x + np.cos(th) * p, y + np.sin(th) * p])
    return np.linalg.norm(P - A, axis=1)


def line_and_circle_count(d, R, r):
    """The notes' construction, at an input whose cos(theta) formula gives cos(theta) = +-1 (the
    only orientation): legs 1 and 3 give the line x = (d1^2 - d3^2) / (4 (R - r cos theta)),
    leg 2 the circle x^2 + y^2 = d2^2; two real points when the line cuts the circle."""
    c = (2 * (d[1]**2 + R**2 + r**2) - d[0]**2 - d[2]**2) / (4 * r * R)
    assert abs(abs(c) - 1) < 1e-12                        # the input is at sin(theta) = 0
    x = (d[0]**2 - d[2]**2) / (4 * (R - r * np.sign(c)))
    return 2 if d[1]**2 - x**2 > 0 else 0


def same_poses(P, Q, tol):
    """Every pose of P is within tol of one of Q and vice versa (angles mod 2 pi)."""
    def dist(a, b):
        return max(abs(a[0] - b[0]), abs(a[1] - b[1]), abs(np.remainder(a[2] - b[2] + np.pi, 2 * np.pi) - np.pi))
    return all(min(dist(p, q) for q in Q) < tol for p in P) and all(min(dist(p, q) for p in P) < tol for q in Q)


def test_collinear_closed_form_at_sin_theta_zero():
    rng = np.random.default_rng(1303)
    checked = 0
    for _ in range(200):
        R = rng.uniform(0.5, 3.0)
        r = R * rng.choice([rng.uniform(0.1, 0.9), rng.uniform(1.1, 2.0)])
        th = rng.choice([0.0, np.pi])
        pose = np.array([rng.uniform(-1, 1) * R, rng.choice([-1, 1]) * rng.uniform(0.1, 2) * R, th])
        d = collinear_legs(pose, R, r)
        out = collinear_3rpr_closed_form(d, R, r)
        assert len(out) == line_and_circle_count(d, R, r) == 2
        for P in out:                                                     # the legs hold
            assert np.allclose(collinear_legs(P, R, r), d, rtol=1e-12, atol=1e-12 * R)
            assert np.sin(P[2]) == pytest.approx(0, abs=1e-12)
        assert abs(out[0, 1] + out[1, 1]) < 1e-12 * R and abs(out[0, 1]) > 0.05 * R   # (x, +-y)
        assert same_poses(out, [pose, pose * [1, -1, 1]], 1e-12 * R)
        checked += 1
    assert checked == 200
    # exact dyadic input, cos(theta) = 1 exactly: base (-2, 0), platform point (-1, 3/4), ...
    out = collinear_3rpr_closed_form([1.25, 0.75, 1.25], 2.0, 1.0)
    assert same_poses(out, [(0.0, 0.75, 0.0), (0.0, -0.75, 0.0)], 1e-15) and len(out) == 2


@pytest.mark.slow
def test_collinear_closed_form_agrees_with_the_image_space_dk_across_sin_theta_zero():
    """Rational designs, orientations approaching 0 and pi, and exactly 0 and pi: four modes, then
    two; the image-space DK gives the same set (its own multiplicity bookkeeping aside)."""
    rng = np.random.default_rng(1304)
    checked = 0
    designs = ((sp.Integer(2), sp.Integer(1)), (sp.Rational(5, 2), sp.Rational(3, 4)), (sp.Integer(1), sp.Integer(3)))
    for R, r in designs:
        m = isp.examples.collinear_3rpr(R, r)
        Rf, rf = float(R), float(r)
        for th in (0.3, 1e-3, 1e-6, 0.0, np.pi - 1e-3, np.pi):
            pose = np.array([rng.uniform(-0.5, 0.5) * Rf, rng.uniform(0.3, 1.5) * Rf, th])
            d = collinear_legs(pose, Rf, rf)
            out = collinear_3rpr_closed_form(d, Rf, rf)
            if np.sin(th) == pytest.approx(0, abs=1e-15):
                assert len(out) == line_and_circle_count(d, Rf, rf) == 2
            else:
                assert len(out) == 4
            for P in out:
                assert np.allclose(collinear_legs(P, Rf, rf), d, rtol=1e-12, atol=1e-12 * Rf)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)          # singular there, by construction
                dk = [mm.pose for mm in m.direct_kinematics(d)]
            # at a double orientation root the float DK is ~sqrt(eps) accurate (4e-8 seen); the
            # tolerance stays below half the 2e-6 gap of the pairs at theta = 1e-6
            assert len(dk) == len(out) and same_poses(out, dk, 2e-7 * Rf)
            checked += 1
    assert checked == 18


def test_collinear_closed_form_no_solution_and_bad_input():
    # d2 longer than at theta = 0 by 1e-6: cos(theta) = 1 + 1.6e-6, far beyond rounding, no pose;
    # shorter by as much: two orientations +-theta, four poses
    d = collinear_legs((0.5, 1.5, 0.0), 2.0, 1.0)
    assert collinear_3rpr_closed_form(d + [0.0, 1e-6, 0.0], 2.0, 1.0).shape == (0, 3)
    assert collinear_3rpr_closed_form(d - [0.0, 1e-6, 0.0], 2.0, 1.0).shape == (4, 3)
    with pytest.raises(isp.InputError, match="differ"):
        collinear_3rpr_closed_form([1.0, 1.0, 1.0], 1.0, 1.0)
    with pytest.raises(isp.InputError, match="shape"):
        collinear_3rpr_closed_form([1.0, 1.0], 2.0, 1.0)


# ---------------------------------------------------------------- seed 004: Choi's 3-PPR

def choi_sliders(pose, R, r, alpha):
    """Slider positions from the geometry: vertex B_i = (x, y) + r (sin(t_i + phi), -cos(t_i + phi))
    on the link through the slider A_i = O_i + rho_i u_i along w_i = cos(alpha) u_i + sin(alpha) v_i,
    i.e. cross(B_i - O_i - rho_i u_i, w_i) = 0, rho_i = cross(B_i - O_i, w_i) / cross(u_i, w_i)."""
    x, y, phi = pose
    rho = []
    for i in range(3):
        t = 2 * i * np.pi / 3
        u, v = np.array([np.cos(t), np.sin(t)]), np.array([-np.sin(t), np.cos(t)])
        O = -R * v
        w = np.cos(alpha) * u + np.sin(alpha) * v
        B = np.array([x, y]) + r * np.array([np.sin(t + phi), -np.cos(t + phi)])
        cross = lambda a, b: a[0] * b[1] - a[1] * b[0]
        rho.append(cross(B - O, w) / cross(u, w))
    return np.array(rho)


def test_choi_closed_form_at_the_fold_returns_the_one_pose_and_decides_either_side():
    """At phi = alpha and phi = alpha - pi the rotations phi and 2 alpha - phi coincide: one pose.
    The sliders come from the geometry, so sin(psi) evaluates to 1 within rounding either side."""
    rng = np.random.default_rng(404)
    checked = 0
    for _ in range(200):
        R = rng.uniform(0.5, 2.0)
        r = rng.uniform(0.1, 1.0) * R
        alpha = rng.uniform(np.pi / 6, 5 * np.pi / 6)
        phi = rng.choice([alpha, alpha - np.pi])
        pose = np.array([rng.uniform(-0.3, 0.3) * R, rng.uniform(-0.3, 0.3) * R, phi])
        rho = choi_sliders(pose, R, r, alpha)
        out = choi_3ppr_closed_form(rho, R, r, alpha)
        assert out.shape == (1, 3)                                # phi = 2 alpha - phi (mod 2 pi)
        assert np.allclose(choi_sliders(out[0], R, r, alpha), rho, atol=1e-12 * R)
        assert same_poses(out, [pose], 1e-6)
        checked += 1
    assert checked == 200
    # the rounding allowance is tight: sin(psi) = sin(alpha) (sum rho / 3 + R cot alpha) / r beyond 1
    # by 3e-9 has no solution, below 1 by as much has two
    R, r, alpha = 1.0, 0.5, 7 * np.pi / 18
    rho = choi_sliders((0.1, -0.05, alpha), R, r, alpha)
    assert choi_3ppr_closed_form(rho + 3e-9 * r / np.sin(alpha), R, r, alpha).shape == (0, 3)
    assert choi_3ppr_closed_form(rho - 3e-9 * r / np.sin(alpha), R, r, alpha).shape == (2, 3)


@pytest.mark.slow
def test_choi_closed_form_agrees_with_the_image_space_dk_at_and_off_the_fold():
    rng = np.random.default_rng(405)
    checked = 0
    for R, r, alpha in ((1.0, 0.5, 7 * np.pi / 18), (1.3, 0.4, 1.1), (0.8, 0.7, 2.0)):
        m = isp.examples.choi_3ppr(R, r, alpha)
        for dphi in (0.0, -np.pi, 0.4, 1e-3):
            pose = np.array([rng.uniform(-0.2, 0.2) * R, rng.uniform(-0.2, 0.2) * R, alpha + dphi])
            rho = choi_sliders(pose, R, r, alpha)
            out = choi_3ppr_closed_form(rho, R, r, alpha)
            expected = [pose] if dphi in (0.0, -np.pi) else [pose, pose * [1, 1, 0] + [0, 0, alpha - dphi]]
            assert len(out) == len(expected)
            assert same_poses(out, expected, 1e-6)
            for P in out:
                assert np.allclose(choi_sliders(P, R, r, alpha), rho, atol=1e-12 * R)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)          # singular at the fold
                dk = [mm.pose for mm in m.direct_kinematics(rho)]
            assert len(dk) == len(out) and same_poses(out, dk, 1e-6)
            checked += 1
    assert checked == 12


def test_closed_form_ulps_decides_the_boundary_of_the_closed_forms():
    # theta = 0 exactly at d = (1.25, 0.75, 1.25); 1e-9 longer d1 is a pair +-theta, unless the
    # rounding allowance is widened past 1 - cos(theta) ~ 1e-10 of the terms
    d = [1.25 + 1e-9, 0.75, 1.25]
    assert len(isp.examples.collinear_3rpr_closed_form(d)) == 4
    wide = isp.Tolerances(closed_form_ulps=1e8)
    poses = isp.examples.collinear_3rpr_closed_form(d, tolerances=wide)
    assert len(poses) == 2 and np.all(poses[:, 2] == 0)
    # Choi's 3-PPR: just inside the boundary |sin psi| = 1 there are two rotations, one when widened
    m = isp.examples.choi_3ppr()
    q = m.inverse_kinematics(np.array([0.1, -0.05, 7 * np.pi / 18 - 1e-6]))
    assert len(isp.examples.choi_3ppr_closed_form(q)) == 2
    assert len(isp.examples.choi_3ppr_closed_form(q, tolerances=wide)) == 1
