"""Rows whose tracked endpoints the compiled certificate cannot prove (a path lost, two paths merged)
are tracked again from other generic starts before arb and msolve (``solver.RETRY_STARTS``).

The first tracking pass of each batch is spoiled on purpose (a path marked lost in one row, two
endpoints made equal in another); the batch must still certify every row, without the exact
solver, with the real count that arb's Krawczyk test (python-flint balls, an independent
implementation of the proof) proves on endpoints tracked row by row from the design's start."""

from fractions import Fraction

import numpy as np
import pytest

import imagespace as isp
from imagespace.spatial import solver
from imagespace.spatial.certify import krawczyk_certify
from imagespace.spatial.homotopy import PATH_FAILED, track_parameters
from imagespace.spatial.study import study_point


def _design_and_rows(seed, n):
    rng = np.random.default_rng(seed)
    gs = isp.GoughStewart(rng.integers(-8, 9, (6, 3)) / 8.0, rng.integers(-8, 9, (6, 3)) / 16.0)
    poses = study_point(rng.normal(size=(n, 4)), rng.uniform(-0.4, 0.4, (n, 3)) + [0, 0, 1.5])
    return gs, gs.inverse_kinematics(poses)


def _arb_count(gs, L):
    fam = gs.family()
    Z, st, _ = track_parameters(gs.start_system, ((L / fam.scale) ** 2)[None])
    Qx = fam.exact([(Fraction(float(v)) / Fraction(fam.scale)) ** 2 for v in L])
    cert = krawczyk_certify(Qx, Z[0][st[0] == 0])
    assert cert.complete(fam.bound)
    return int(np.sum(cert.certified & (cert.real == 1)))


def _spoil_first_pass(monkeypatch):
    """The solver's first tracking call loses a path of row 0 and merges two paths of row 1."""
    calls = []
    original = solver.track_parameters

    def spoiled(start, P, *args, **kwargs):
        Z, status, steps = original(start, P, *args, **kwargs)
        calls.append(P.shape[0])
        if len(calls) == 1:
            Z, status = Z.copy(), status.copy()
            status[0, 3] = PATH_FAILED
            Z[1, 7] = Z[1, 8]
        return Z, status, steps

    monkeypatch.setattr(solver, "track_parameters", spoiled)
    return calls


def _no_exact_solver(Q):
    raise AssertionError("the exact solver was called")


@pytest.mark.parametrize("n", [4, solver.RECENTRE_MIN_ROWS + 2])
def test_spoiled_rows_are_certified_by_a_second_start(monkeypatch, n):
    gs, L = _design_and_rows(11, n)
    truth = [_arb_count(gs, L[i]) for i in (0, 1)]
    fam = gs.family()
    calls = _spoil_first_pass(monkeypatch)
    fast = solver.solve_rows(fam, gs.start_system, L ** 2, gs.tolerances, lengths=L)
    assert len(calls) >= 2                               # the spoiled rows were tracked again
    assert fast.reliable.all() and fast.certified.all()
    assert fast.counts[:2].tolist() == truth
    calls.clear()
    cert = solver.certify_rows(fam, gs.start_system, L, gs.tolerances, exact_solver=_no_exact_solver)
    assert cert.certified.all()
    assert cert.counts[:2].tolist() == truth


def test_without_second_chances_the_spoiled_rows_are_flagged(monkeypatch):
    """The spoiling is real: with no retry the compiled certificate refuses those rows."""
    gs, L = _design_and_rows(11, 4)
    _spoil_first_pass(monkeypatch)
    monkeypatch.setattr(solver, "RETRY_STARTS", 0)
    fast = solver.solve_rows(gs.family(), gs.start_system, L ** 2, gs.tolerances, lengths=L)
    assert fast.reliable.tolist() == [False, False, True, True]
