"""Krawczyk in arb on ill-conditioned solutions: two rows of Dietmaier's design with its lengths moved
about 4e-4 relative (from the seeded 4,000-row sample of ``benchmarks/spatial_dk.py``) have real
solutions where the Jacobian's condition number is ~1e7. Float centres miss every box the float
Jacobian contracts (or hit one by the luck of their last bits, which depend on the start system),
so the compiled test and arb's float-centred boxes fail there; arb's Newton refinement at
CERT_PRECISION bits (``certify._refine``) proves every one of them. The count is checked
against msolve on the exact system (slow) and the float classification of the endpoints (fast)."""

from fractions import Fraction

import numpy as np
import pytest

import imagespace as isp
from imagespace.spatial import certify
from imagespace.spatial.homotopy import PATH_OK, classify_batch, track_parameters

# the two rows' leg lengths, exactly (hex floats: inputs, not results)
ROWS = [[float.fromhex(h) for h in row] for row in (
    ["0x1.0000f7576ca51p+0", "0x1.4a60c7103a4e4p-1", "0x1.161661311916cp+0", "0x1.80e085e808dddp+0",
     "0x1.482d56c619f71p+0", "0x1.8ac945a123dc1p-1"],
    ["0x1.ffff369a3d8c9p-1", "0x1.4a6297004c60fp-1", "0x1.1616906613712p+0", "0x1.80e22641e99f7p+0",
     "0x1.482c4b01908c8p+0", "0x1.8aca5e0037439p-1"])]


def _setup(L):
    gs, _ = isp.examples.dietmaier_1998()
    fam = gs.family()
    L = np.asarray(L)
    Z, st, _ = track_parameters(gs.start_system, ((L / fam.scale) ** 2)[None])
    Qx = fam.exact([(Fraction(v) / Fraction(fam.scale)) ** 2 for v in L])
    return gs, Z[0][st[0] == PATH_OK], Qx, (Z, st)


@pytest.mark.parametrize("k", [0, 1])
def test_refinement_proves_the_ill_conditioned_solutions(k, monkeypatch):
    gs, Z, Qx, (Zb, st) = _setup(ROWS[k])
    cert = certify.krawczyk_certify(Qx, Z)
    assert cert.complete(40)
    _, real, distinct, _ = classify_batch(Zb, st, gs.tolerances)
    assert int(distinct[0]) == 40 and cert.real_count == int(real[0].sum())
    # the refined boxes alone (float-centred boxes switched off) prove every solution, the same
    # real ones: whether a float centre happens to be close enough depends on the start system's
    # last bits (a freshly solved start and a cached one differ there), the refinement does not
    monkeypatch.setattr(certify, "_RADII", ())
    refined = certify.krawczyk_certify(Qx, Z)
    assert refined.complete(40) and refined.real_count == cert.real_count
    # each refined box holds the solution the default run proved (boxes are disjoint, so the same)
    d = np.abs(refined.points[:, None, :] - cert.points[None]).max(axis=2)
    assert np.all(d.min(axis=1) <= refined.radii + cert.radii[d.argmin(axis=1)])
    # and with neither kind of box nothing is claimed
    monkeypatch.setattr(certify, "_REFINED_RADII", ())
    assert not certify.krawczyk_certify(Qx, Z).certified.any()


msolve = pytest.importorskip("imagespace.core.msolve")


@pytest.mark.slow
@pytest.mark.skipif(not msolve.msolve_available(), reason="msolve is not installed")
def test_certified_without_msolve_agrees_with_msolve():
    gs, _ = isp.examples.dietmaier_1998()
    L = np.asarray(ROWS[0])
    r = gs.direct_kinematics(L, certify=True)
    assert r.certified and r.method == "homotopy+krawczyk"
    exact = gs.direct_kinematics(L, method="exact")
    assert exact.count == r.count
    # the same modes (Study points up to sign)
    P, Q = np.asarray(r.study_points), np.asarray(exact.study_points)
    d = np.minimum(np.abs(P[:, None, :] - Q[None]).max(axis=2), np.abs(P[:, None, :] + Q[None]).max(axis=2))
    assert np.all(d.min(axis=1) < 1e-8)
