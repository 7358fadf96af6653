"""Walk every public callable with hostile arguments (issue 36: "make the suite find these").

Every callable named in the ``__all__`` of ``imagespace`` or of a subpackage a user imports by name
(``walker_support.PUBLIC_MODULES``), every public class as a constructor and the public methods of the
main result/design classes (``walker_support.METHOD_CLASSES``) get, one parameter at a time, the
hostile values of ``walker_support.hostile_values`` while the other parameters keep valid values:
the documented ones (the first call the callable's own doctest makes, recorded) or an entry of
``walker_support.VALID_CALLS``. Parameters not given in that call are walked from their default.

Each call must return, or raise an :class:`~imagespace.exceptions.ImageSpaceError` whose message
names the parameter (``InputError`` derives from ``ValueError`` and ``InputTypeError`` also from
``TypeError``, so a raw ``ValueError`` is told apart by not being an ``ImageSpaceError``). A raw
exception from numpy/sympy/python, a hang (a ~10 s ``setitimer`` alarm per call), a string
accepted for a numeric parameter, the hostile string's marker file appearing, or a file left in
the working directory (each call runs in an empty temporary directory) is a failure.

Widgets: ``imagespace.widgets`` builds its explorers headless (ipywidgets without a front end),
so they are walked; only ``PanelView``/``TraceView``, which need live panels, are skipped (see
``walker_support.NOT_WALKED``).

The failures found on today's code are listed in ``KNOWN_FAILURES``; each is an
``xfail(strict=True)`` case, so the suite is green now and a fix turns its entry into an XPASS
(the entry must then be removed). The fast lane walks a few telling kinds per parameter
(``walker_support.FAST_KINDS``), the slow lane every kind. The walk is deterministic: fixed hostile tables, the doctests' own values.
"""

from __future__ import annotations

import inspect
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import walker_support as W  # noqa: E402

import imagespace as isp  # noqa: E402

from known_failures import KNOWN_FAILURES, SLOW_WALKS  # noqa: E402


def _signature_params(name):
    kind, owner, attr, obj = W.public_callables()[name]
    if kind == "method":
        fn = getattr(owner, attr)
        raw = obj
        sig = inspect.signature(fn)
        params = list(sig.parameters.values())
        if not isinstance(raw, (classmethod, staticmethod)) and params:
            params = params[1:]       # self
    else:
        try:
            params = list(inspect.signature(obj).parameters.values())
        except (TypeError, ValueError):
            return []
    return [p.name for p in params if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD) and not p.name.startswith("_")]


def walk_cases():
    return [(name, param) for name in W.walked_names() for param in _signature_params(name)]


def case_marks(name):
    return [pytest.mark.slow] if name in SLOW_WALKS else []


_KNOWN_BY_CASE = {case: set(kinds) for case, (kinds, _what) in KNOWN_FAILURES.items()}


def _lane_kinds(name, param, lane):
    """The hostile kinds a lane walks for one parameter: the fast lane a few telling ones
    (:data:`walker_support.FAST_KINDS`), the slow lane all."""
    pl = W.plan(name)
    assert pl is not None, f"{name}: no valid call"
    valid, has_valid = {p: (v, h) for p, v, h in pl[4]}[param]
    kinds = {k for k, _ in W.hostile_values(valid, has_valid)}
    return kinds & W.FAST_KINDS if lane == "fast" else kinds


def _walk_params():
    out = []
    for n, p in walk_cases():
        for lane in ("fast", "slow"):
            marks = case_marks(n) + ([pytest.mark.slow] if lane == "slow" else [])
            out.append(pytest.param(n, p, lane, marks=marks, id=f"{lane}::{n}::{p}"))
    return out


@pytest.mark.parametrize("name, param, lane", _walk_params())
def test_hostile_values_are_refused_cleanly(name, param, lane):
    kinds = _lane_kinds(name, param, lane) - _KNOWN_BY_CASE.get((name, param), set())
    problems = W.walk_parameter(name, param, kinds) if kinds else {}
    assert not problems, f"{name}({param}=...):\n" + "\n".join(f"  {k}: {v}" for k, v in problems.items())


def _known_params():
    out = []
    for (n, p), kinds in sorted(_KNOWN_BY_CASE.items()):
        for lane in ("fast", "slow") if kinds & W.FAST_KINDS else ("slow",):
            marks = case_marks(n) + ([pytest.mark.slow] if lane == "slow" else [])
            marks.append(pytest.mark.xfail(strict=True, reason=f"{len(kinds)} hostile kinds fail"))
            out.append(pytest.param(n, p, sorted(kinds), lane, marks=marks, id=f"{lane}::{n}::{p}"))
    return out


@pytest.mark.parametrize("name, param, kinds, lane", _known_params())
def test_known_failures(name, param, kinds, lane):
    """The failures of ``KNOWN_FAILURES`` for one parameter, as one strict xfail: when a fix makes
    every listed kind of this parameter (of the lane's kinds) behave, the case XPASSes and its
    lines must go."""
    walk = set(kinds) & _lane_kinds(name, param, lane)
    if not walk:
        pytest.skip("the listed kinds are not walked for this parameter in this lane")
    problems = W.walk_parameter(name, param, walk)
    assert not problems, "\n".join(f"{k}: {v}" for k, v in problems.items())


@pytest.mark.parametrize("name", [pytest.param(n, marks=case_marks(n)) for n in W.walked_names()])
def test_valid_call_works(name):
    """The valid values the walk starts from really work (else the walk proves nothing)."""
    pl = W.plan(name)
    assert pl is not None, f"{name}: no valid call (add one to walker_support.VALID_CALLS or NOT_WALKED)"
    fn, args, kwargs, _, _ = pl
    problem = W.probe(fn, [W._fresh(a) for a in args], dict(kwargs))
    assert problem is None, f"{name}: its valid call fails: {problem}"


def test_the_walk_is_complete():
    names = W.public_callables()
    stale = [n for n in W.NOT_WALKED if n not in names]
    assert not stale, f"NOT_WALKED names no public callable (remove): {stale}"
    stale = sorted({n for n, _ in KNOWN_FAILURES if n not in names or n in W.NOT_WALKED})
    assert not stale, f"KNOWN_FAILURES names a callable that is not walked: {stale}"
    assert len(walk_cases()) > 500
    assert "imagespace.is_cuspidal" in names and "imagespace.spatial.krawczyk_certify" in names
    assert "imagespace.manipulator.PlanarParallel.direct_kinematics" in names


def test_no_marker_file():
    assert not os.path.exists(W.MARKER)


# --------------------------------------------------------------------------------------------
# behaviours the walk cannot judge from the exception type alone


def test_pose_from_matrix_reads_the_rotation_tolerance():
    """``pose_from_matrix(T, tolerances=...)`` must use ``tolerances.rotation_matrix``: a loose
    tolerance accepts a slightly skew rotation, a tight one refuses a nearly exact one."""
    from imagespace.spatial import pose_from_matrix

    T = np.eye(4)
    T[0, 1] = 1e-4
    pose_from_matrix(T, tolerances=isp.Tolerances(rotation_matrix=1e-3))
    T[0, 1] = 1e-11
    with pytest.raises(isp.InputError):
        pose_from_matrix(T, tolerances=isp.Tolerances(rotation_matrix=1e-13))
