"""Every direct-kinematics path of imagespace, judged against msolve's verdict (:mod:`truth`).

Paths (``PATHS``) and what each promises:

``dk.certify``            ``m.direct_kinematics(q, certify=True)`` on the row as given (exact
                          rationals and angles as sympy numbers, doubles as floats). Without a
                          ``NearSingularWarning`` it claims a proof: its modes must be msolve's
                          distinct real assembly modes, one for one, each pose within ``1e-9`` of
                          the design's size (phi modulo 2 pi). A ``DegenerateDesignError`` must
                          match a real continuum.
``batch.certify[auto]``,  ``m.direct_kinematics_batch(Q, certify=True, method=...)`` on the rows as
``batch.certify[numpy]``  doubles, all rows of a case in one batch, a NaN row appended: a row with
                          ``row_ok`` and ``consistent`` must have the right ``count`` and poses; a
                          masked row must carry a message in ``errors`` (the NaN row must be
                          masked); the batch must not raise.
``root_counts``           ``m.certified_root_counts(Q)``: a count ``>= 0`` is a proof of the number
                          of real assembly modes (-1 declines).
``dk.float``              ``m.direct_kinematics(q)`` on the doubles: right (the count exactly, the
                          poses within ``FLOAT_POSE_TOL``), or flagged by a ``NearSingularWarning``.
``batch.float[auto]``,    ``m.direct_kinematics_batch(Q)``: right, or ``near_singular``, or masked
``batch.float[numpy]``    with a message.

Verdicts: ``ok``; ``wrong`` (a failure); ``flagged`` (the path declined: a warning, a row not
``consistent`` or ``near_singular``, a count of -1, a masked row); ``refused`` (an ``InputError`` on
a valid row that is not *moderate*: a slider value beyond 100 times the design's size or below
``2^-60`` of it, an angle beyond 7 radians or below ``2^-60``: the path may honestly say its
double-precision stage cannot hold it; on a moderate row an ``InputError`` is ``wrong``: the
input is valid, so its stated reason is false); ``undecided`` (msolve's verdict was not robust:
not judged).
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass
from typing import Optional

import numpy as np

from .spec import build_design, design_size, dumps, float_row, frac, leg_is_angle, q_exact, q_float, row_is_float
from .truth import Truth, truth

POSE_TOL = 1e-9
#: the float paths promise the count where not flagged, and poses as accurate as double precision
#: allows at the row's conditioning: next to a fold (two modes ~1e-6 apart, 1e-12 from the double
#: root) Newton's method lands ~1e-9 off. Judged at this tolerance (still far below the distance
#: of two modes a double can tell apart at such rows), the certified paths at ``POSE_TOL``.
FLOAT_POSE_TOL = 1e-7
PATHS = ("dk.certify", "batch.certify[auto]", "batch.certify[numpy]", "root_counts", "dk.float",
         "batch.float[auto]", "batch.float[numpy]")
CERTIFIED_PATHS = PATHS[:4]
FLOAT_PATHS = PATHS[4:]
STATUSES = ("ok", "wrong", "flagged", "refused", "undecided")


@dataclass
class Verdict:
    path: str
    row: int
    status: str
    detail: str = ""
    seconds: float = 0.0             # the path's time on the whole case (all rows)

    def __str__(self):
        return f"{self.path} row {self.row}: {self.status}" + (f" -- {self.detail}" if self.detail else "")


# --------------------------------------------------------------------------- the truth of a case

def decide(case):
    """``[(truth of the row as given, truth of its doubles)] * rows`` (one msolve verdict when the row
    is all doubles)."""
    legs, witness = case["legs"], case.get("witness")
    out = []
    for r in case["rows"]:
        t = truth(legs, r["q"], witness if r.get("witness", True) else None)
        if row_is_float(r["q"]):
            out.append((t, t))
        else:
            out.append((t, truth(legs, float_row(legs, r["q"]), witness)))
    return out


# --------------------------------------------------------------------------- comparisons

def match_poses(got, want, size, tol=POSE_TOL):
    """``(ok, why)``: ``got`` and ``want`` ``(k, 3)`` are the same modes (one for one, positions
    within ``tol`` of the design's size, phi modulo 2 pi)."""
    got = np.asarray(got, dtype=float).reshape(-1, 3)
    want = np.asarray(want, dtype=float).reshape(-1, 3)
    if len(got) != len(want):
        return False, f"{len(got)} modes, msolve {len(want)}"
    if not len(got):
        return True, ""
    if not np.all(np.isfinite(got)):
        return False, f"non-finite pose {got.tolist()}"
    D = np.empty((len(got), len(want)))
    for i, p in enumerate(got):
        for j, r in enumerate(want):
            sc = max(size, abs(r[0]), abs(r[1]))
            D[i, j] = max(abs(p[0] - r[0]) / sc, abs(p[1] - r[1]) / sc, abs(math.remainder(p[2] - r[2], 2 * math.pi)))
    used_i, used_j, worst = set(), set(), 0.0
    for flat in np.argsort(D, axis=None):
        i, j = divmod(int(flat), len(want))
        if i in used_i or j in used_j:
            continue
        used_i.add(i)
        used_j.add(j)
        worst = max(worst, D[i, j])
    if worst > tol:
        return False, f"a pose off by {worst:.2e} (relative): got {np.round(got, 10).tolist()}, msolve {np.round(want, 10).tolist()}"
    return True, ""


def moderate(legs, qf):
    """Every joint value of the row within the float stage's plain range (see the module docstring)."""
    size = design_size(legs)
    if not 2.0 ** -30 <= size <= 2.0 ** 30:
        return False
    for s, v in zip(legs, qf):
        v = abs(float(v))
        if leg_is_angle(s):
            if v > 7 or 0 < v < 2.0 ** -60:
                return False
        elif v > 100 * size or 0 < v < 2.0 ** -60 * size:
            return False
    return True


def _modes_verdict(path, i, t, poses, size, flagged=False, note=""):
    if flagged:
        return Verdict(path, i, "flagged", note)
    if t.status == "continuum":
        return Verdict(path, i, "wrong", f"{len(poses)} modes claimed, msolve: a real continuum")
    ok, why = match_poses(poses, t.poses, size, POSE_TOL if path in CERTIFIED_PATHS else FLOAT_POSE_TOL)
    return Verdict(path, i, "ok" if ok else "wrong", "" if ok else why)


def _input_error(path, i, exc, legs, qf, t):
    msg = str(exc).splitlines()[0][:300]
    if moderate(legs, qf):
        return Verdict(path, i, "wrong", f"InputError on a valid moderate row ({t.describe()}): {msg}")
    return Verdict(path, i, "refused", f"InputError ({t.describe()}): {msg}")


def _call(fn, *args, **kw):
    """``(result, exception, near)``: ``fn`` with every warning recorded (near: a NearSingularWarning)."""
    import imagespace as isp

    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        try:
            res, exc = fn(*args, **kw), None
        except Exception as e:          # judged by the caller
            res, exc = None, e
    near = [w for w in rec if issubclass(w.category, isp.NearSingularWarning)]
    return res, exc, (str(near[0].message)[:200] if near else "")


def _per_call(m, path, i, q, t, legs, qf, certify):
    import imagespace as isp

    size = design_size(legs)
    res, exc, near = _call(m.direct_kinematics, q, certify=certify)
    if exc is not None:
        if isinstance(exc, isp.DegenerateDesignError):
            if t.status == "continuum":
                return Verdict(path, i, "ok")
            return Verdict(path, i, "wrong", f"DegenerateDesignError (a continuum) but msolve: {t.describe()}: "
                                             f"{str(exc)[:200]}")
        if isinstance(exc, isp.InputError):
            return _input_error(path, i, exc, legs, qf, t)
        return Verdict(path, i, "wrong", f"raised {type(exc).__name__}: {str(exc)[:300]}")
    poses = [list(mm.pose) for mm in res]
    return _modes_verdict(path, i, t, poses, size, flagged=bool(near), note=near)


def _batch_rows(res, n):
    return [res.poses[i][:int(res.count[i])] for i in range(n)]


def _batch(m, path, Q, truths, legs, certify, method):
    """Verdicts of one batch call (``Q`` the case's rows and a NaN row)."""
    size = design_size(legs)
    n = len(truths)
    res, exc, _ = _call(m.direct_kinematics_batch, Q, certify=certify, method=method)
    if exc is not None:
        return [Verdict(path, i, "wrong", f"the batch raised {type(exc).__name__}: {str(exc)[:300]}") for i in range(n)]
    out = []
    if bool(res.row_ok[n]) or not str(res.errors.get(n, "")).strip():
        out.append(Verdict(path, n, "wrong", "the NaN row is not masked with a message"))
    for i, t in enumerate(truths):
        if t.status == "undecided":
            out.append(Verdict(path, i, "undecided", t.why))
            continue
        if not bool(res.row_ok[i]):
            msg = str(res.errors.get(i, "")).strip()
            if not msg:
                out.append(Verdict(path, i, "wrong", "row masked without a message in errors"))
            elif t.status == "continuum":
                out.append(Verdict(path, i, "ok", f"masked: {msg[:120]}"))
            elif any(w in msg.lower() for w in ("continuum", "degenerate", "infinitely")):
                out.append(Verdict(path, i, "wrong", f"masked as a continuum but msolve: {t.describe()}: {msg[:200]}"))
            else:
                out.append(Verdict(path, i, "flagged", f"masked: {msg[:200]}"))
            continue
        if certify:
            flagged = not bool(res.consistent[i])
            note = "not consistent"
        else:
            flagged = bool(res.near_singular[i])
            note = "near_singular"
        poses = res.poses[i][:int(res.count[i])]
        out.append(_modes_verdict(path, i, t, poses, size, flagged=flagged, note=note))
    return out


def _root_counts(m, path, Q, truths):
    n = len(truths)
    res, exc, _ = _call(m.certified_root_counts, Q)
    if exc is not None:
        return [Verdict(path, i, "wrong", f"raised {type(exc).__name__}: {str(exc)[:300]}") for i in range(n)]
    counts, where = res
    out = []
    if int(counts[n]) != -1:
        out.append(Verdict(path, n, "wrong", f"the NaN row got the count {int(counts[n])}"))
    for i, t in enumerate(truths):
        c = int(counts[i])
        if t.status == "undecided":
            out.append(Verdict(path, i, "undecided", t.why))
        elif c < 0:
            out.append(Verdict(path, i, "ok" if t.status == "continuum" else "flagged", f"-1 ({where[i]})"))
        elif t.status == "continuum":
            out.append(Verdict(path, i, "wrong", f"count {c} ({where[i]}) proven, msolve: a real continuum"))
        elif c != t.count:
            out.append(Verdict(path, i, "wrong", f"count {c} ({where[i]}) proven, msolve: {t.count} real modes"))
        else:
            out.append(Verdict(path, i, "ok", str(where[i])))
    return out


def judge_case(case, truths=None, paths=PATHS, m=None):
    """Every path in ``paths`` on every row of ``case``: a list of :class:`Verdict`."""
    legs = case["legs"]
    truths = decide(case) if truths is None else truths
    if m is None:
        m = build_design(legs)
    out = []
    rows = case["rows"]
    qfs = [q_float(legs, r["q"]) for r in rows]
    for path in paths:
        t0 = time.perf_counter()
        n0 = len(out)
        _judge_path(m, path, legs, rows, qfs, truths, out)
        dt = time.perf_counter() - t0
        for v in out[n0:]:
            v.seconds = dt
    return out


def _judge_path(m, path, legs, rows, qfs, truths, out):
    """Append the verdicts of one path on every row of a case to ``out``."""
    if path in ("dk.certify", "dk.float"):
        for i, r in enumerate(rows):
            t = truths[i][0] if path == "dk.certify" else truths[i][1]
            if t.status == "undecided":
                out.append(Verdict(path, i, "undecided", t.why))
                continue
            q = q_exact(legs, r["q"]) if path == "dk.certify" else qfs[i]
            out.append(_per_call(m, path, i, q, t, legs, qfs[i], path == "dk.certify"))
        return
    Q = np.vstack(qfs + [np.full(3, np.nan)])
    ft = [t[1] for t in truths]
    if path == "root_counts":
        out += _root_counts(m, path, Q, ft)
    else:
        certify = path.startswith("batch.certify")
        method = path.split("[")[1].rstrip("]")
        out += _batch(m, path, Q, ft, legs, certify, method)


def failures(verdicts):
    return [v for v in verdicts if v.status == "wrong"]


def replay_command(case):
    """One shell command that replays ``case`` (from the repository root)."""
    return "python -m tests.referee --case '" + dumps(case).replace("'", "'\\''") + "'"


def report_failure(case, verdicts):
    """The failing verdicts of a case, its JSON and the command that replays it."""
    bad = failures(verdicts)
    lines = [f"REFEREE FAILURE {case.get('label')} [{case.get('class')}] {case.get('note', '')}"]
    for v in bad:
        r = case["rows"][v.row] if v.row < len(case["rows"]) else {"note": "the appended NaN row", "q": []}
        lines.append(f"  {v}  [row: {r.get('note', '')}; q = {r['q']}]")
    lines.append("  replay: " + replay_command(case))
    return "\n".join(lines)
