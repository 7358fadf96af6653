"""Backlash: the thresholds of the image-space analysis against an independent four-bar sweep in
Cartesian coordinates (seed 002: release the PPR leg, point c runs on the coupler curve)."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.paths.backlash import backlash, released_curve

SQ181 = np.sqrt(181.0)
N_DIR = np.array([10.0, 9.0]) / SQ181


def fourbar_graph(n=60000):
    """Poses of the 2-RPR four-bar of seed 002 (A=(0,0)-a=(0,0), 10; B=(7,0)-b=(5,0), sqrt(232)),
    by the crank angle of leg A, both assembly branches, and the PPR joint value of each pose
    (q3 = sqrt(181) - n . c, c = platform point (7, 10)); edges along the motion."""
    al = np.linspace(0, 2 * np.pi, n, endpoint=False)
    P = 10 * np.column_stack([np.cos(al), np.sin(al)])              # platform origin = point a
    B = np.array([7.0, 0.0])
    d = np.linalg.norm(B - P, axis=1)
    r1, r2 = 5.0, np.sqrt(232.0)
    a = (r1**2 - r2**2 + d**2) / (2 * d)
    h2 = r1**2 - a**2
    ok = h2 >= 0
    h = np.sqrt(np.where(ok, h2, 0))
    e = (B - P) / d[:, None]
    perp = np.column_stack([-e[:, 1], e[:, 0]])
    nodes, q3 = [], []
    for sgn in (1, -1):
        bw = P + a[:, None] * e + sgn * h[:, None] * perp             # world position of b
        phi = np.arctan2(bw[:, 1] - P[:, 1], bw[:, 0] - P[:, 0])
        c = P + np.column_stack([np.cos(phi) * 7 - np.sin(phi) * 10, np.sin(phi) * 7 + np.cos(phi) * 10])
        nodes.append(np.column_stack([P, phi]))
        q3.append(np.where(ok, SQ181 - c @ N_DIR, np.nan))
    poses = np.stack(nodes, 1)                                        # (n, 2, 3)
    q3 = np.stack(q3, 1)
    edges = []
    for k in range(n):
        k2 = (k + 1) % n
        for s in (0, 1):
            if ok[k] and ok[k2]:
                edges.append(((k, s), (k2, s)))
        if ok[k] != ok[k2]:                                           # the branches meet
            kk = k if ok[k] else k2
            edges.append(((kk, 0), (kk, 1)))
    return poses, q3, edges


def connected(poses, q3, edges, start, goal, q0, delta):
    inside = np.abs(q3 - q0) <= delta
    nbr = {}
    for a, b in edges:
        if inside[a] and inside[b]:
            nbr.setdefault(a, []).append(b)
            nbr.setdefault(b, []).append(a)
    seen, stack = {start}, [start]
    while stack:
        a = stack.pop()
        for b in nbr.get(a, []):
            if b not in seen:
                seen.add(b)
                stack.append(b)
    return goal in seen


def nearest(poses, pose):
    d = np.linalg.norm(poses[:, :, :2] - pose[:2], axis=2) + \
        np.abs(np.remainder(poses[:, :, 2] - pose[2] + np.pi, 2 * np.pi) - np.pi)
    d = np.where(np.isfinite(d), d, np.inf)
    k, s = np.unravel_index(np.argmin(d), d.shape)
    return (int(k), int(s))


@pytest.fixture(scope="module")
def analysis():
    m = isp.examples.stigger_husty()
    return m, backlash(m, m.q_example_float, 2, delta=0.3)


@pytest.fixture(scope="module")
def sweep():
    return fourbar_graph()


@pytest.mark.slow
def test_thresholds_match_an_independent_four_bar_sweep(analysis, sweep):
    m, res = analysis
    poses, q3, edges = sweep
    q0 = m.q_example_float[2]
    nodes = [nearest(poses, mm.pose) for mm in res.modes]
    checked = 0
    k = len(res.modes)
    for a in range(k):
        for b in range(a + 1, k):
            t = res.thresholds[a, b]
            if np.isfinite(t) and t > 1e-3:
                assert not connected(poses, q3, edges, nodes[a], nodes[b], q0, 0.98 * t)
                assert connected(poses, q3, edges, nodes[a], nodes[b], q0, 1.02 * t)
                checked += 1
            elif not np.isfinite(t):
                assert not connected(poses, q3, edges, nodes[a], nodes[b], q0, 1e3)
    assert checked >= 5


@pytest.mark.slow
def test_released_curve_satisfies_the_locked_legs(analysis):
    m, res = analysis
    X = res.points.reshape(-1, 4)
    X = X[np.all(np.isfinite(X), axis=1)]
    P = isp.pose_of(X)
    for j in (0, 1):
        q = m.legs[j].actuated_values(P)[:, 0]
        assert np.allclose(q, m.q_example_float[j], rtol=1e-9)


@pytest.mark.slow
def test_connections_follow_the_play(analysis, sweep):
    """Which pairs of modes a play connects, against the independent four-bar sweep: for every pair
    of distinct modes, ``connected`` must say what a flood fill of the band ``|q3 - q0| <= delta``
    over the Cartesian sweep says (the plays 0.3, 0.8 and 1.0 lie between the thresholds, 0.247,
    0.718, 0.915 and 5.05, far beyond the sweep's resolution)."""
    m, res = analysis
    poses, q3, edges = sweep
    q0 = m.q_example_float[2]
    middle = backlash(m, m.q_example_float, 2, delta=0.8)
    bigger = backlash(m, m.q_example_float, 2, delta=1.0)
    checked = 0
    for r in (res, middle, bigger):
        k = len(r.modes)
        assert k == 6 and r.connected.shape == (k, k)
        nodes = [nearest(poses, mm.pose) for mm in r.modes]
        expected = np.array([[connected(poses, q3, edges, nodes[a], nodes[b], q0, r.delta) for b in range(k)]
                             for a in range(k)])
        off = ~np.eye(k, dtype=bool)
        assert np.array_equal(r.connected[off], expected[off])
        # both answers occur: the check distinguishes connected from separated pairs
        assert expected[off].any() and not expected[off].all()
        checked += int(off.sum())
    assert checked == 3 * 30
    assert np.all(middle.connected >= res.connected) and np.all(bigger.connected >= middle.connected)
    assert np.all(bigger.mobility >= res.mobility - 1e-12)


def test_bad_input():
    m = isp.examples.stigger_husty()
    with pytest.raises(isp.InputError, match="delta"):
        backlash(m, m.q_example_float, 2, delta=-1)
    with pytest.raises(isp.InputError, match="leg"):
        released_curve(m, m.q_example_float, 3)
    with pytest.raises(isp.InputError, match="samples"):
        released_curve(m, m.q_example_float, 2, samples=5)
