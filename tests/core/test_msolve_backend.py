"""imagespace.core.msolve against answers worked out by hand (rational intersections, double
roots, Bezout counts, exact binary values of floats) and its error paths."""

import math
import os
import stat
import sys
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from imagespace.core.msolve import (POSITIVE_DIMENSIONAL, MsolveError, MsolveResult,
                                    MsolveTimeoutError, msolve_available, msolve_binary,
                                    solve_real)
from imagespace.exceptions import (EliminationError, ImageSpaceError, InputError,
                                   MsolveUnavailableError)

pytestmark = pytest.mark.skipif(not msolve_available(), reason="msolve is not installed")

x, y, z = sp.symbols("x y z")


def contains(box, point):
    return all(lo <= p <= hi for (lo, hi), p in zip(box, point))


def test_circle_and_line_meet_in_two_rational_points():
    # x^2 + y^2 = 25 and y = x + 1: x^2 + x - 12 = 0, x = 3 or x = -4
    res = solve_real([x**2 + y**2 - 25, x - y + 1], [x, y])
    assert isinstance(res, MsolveResult)
    assert res.dimension == 0 and res.complex_count == 2 and res.distinct_count == 2
    assert res.variables == ("x", "y")
    assert sorted(map(tuple, res.midpoints().tolist())) == [(-4.0, -3.0), (3.0, 4.0)]
    for point in [(3, 4), (-4, -3)]:
        assert sum(contains(b, point) for b in res.boxes) == 1


def test_two_circles_with_rational_intersections():
    # x^2 + y^2 = 25 and (x - 6)^2 + y^2 = 25: subtracting, 12 x = 36, x = 3, y = +-4
    res = solve_real([x**2 + y**2 - 25, (x - 6)**2 + y**2 - 25], [x, y])
    assert res.count == 2 and res.complex_count == 2
    for point in [(3, 4), (3, -4)]:
        assert sum(contains(b, point) for b in res.boxes) == 1


def test_irrational_roots_are_enclosed_by_rational_boxes():
    res = solve_real([x - 3, y**2 - 5, z**2 - 7], [x, y, z])
    assert res.count == 4 and res.complex_count == 4
    signs = set()
    for (xl, xh), (yl, yh), (zl, zh) in res.boxes:
        assert xl <= 3 <= xh
        # y^2 = 5 inside [yl, yh] (which does not contain 0), likewise z^2 = 7
        assert yl * yh > 0 and zl * zh > 0
        assert min(yl * yl, yh * yh) <= 5 <= max(yl * yl, yh * yh)
        assert min(zl * zl, zh * zh) <= 7 <= max(zl * zl, zh * zh)
        assert yh - yl < Fraction(1, 2**100) and zh - zl < Fraction(1, 2**100)
        signs.add((yl > 0, zl > 0))
    assert len(signs) == 4
    mids = res.midpoints()
    assert np.allclose(np.sort(np.abs(mids[:, 1])), math.sqrt(5), rtol=0, atol=1e-15)


def test_box_order_follows_the_variables_when_msolve_reorders_them():
    # a double root in x makes msolve swap the variables internally: the boxes must not follow
    res = solve_real([x**2 - 4 * x + 4, y - 3], [x, y])
    assert res.count == 1
    assert contains(res.boxes[0], (2, 3))
    assert res.complex_count == 2 and res.distinct_count == 1     # x = 2 is a double root


def test_boxes_when_msolve_adds_a_separating_linear_form():
    # no coordinate separates the four points (+-1, +-1): msolve adds a linear form
    res = solve_real([x**2 - 1, y**2 - 1], [x, y])
    assert res.count == 4 and res.complex_count == 4
    found = {(float((bx[0] + bx[1]) / 2), float((by[0] + by[1]) / 2)) for bx, by in res.boxes}
    assert found == {(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)}


def test_multiplicity_counts():
    # (x - 1)^2 = 0, y^2 = 4: two real points, each of multiplicity 2
    res = solve_real([(x - 1)**2, y**2 - 4], [x, y])
    assert res.count == 2 and res.complex_count == 4 and res.distinct_count == 2
    # x^2 + 1 = 0, y = 0: two complex points, no real one
    res = solve_real([x**2 + 1, y], [x, y])
    assert res.dimension == 0 and res.count == 0 and res.complex_count == 2
    assert res.midpoints().shape == (0, 2)


def test_bezout_count_of_three_general_quadrics():
    # three dense quadrics with random rational coefficients: 2 * 2 * 2 = 8 complex solutions
    rng = np.random.default_rng(18)
    monomials = [x**2, y**2, z**2, x * y, x * z, y * z, x, y, z, 1]
    polys = [sum(sp.Rational(int(rng.integers(-9, 10)), int(rng.integers(1, 5))) * m
                 for m in monomials) for _ in range(3)]
    res = solve_real(polys, [x, y, z])
    assert res.complex_count == 8 and res.distinct_count == 8
    for box in res.boxes:                   # each real solution: every residual near zero
        mid = {s: (lo + hi) / 2 for s, (lo, hi) in zip((x, y, z), box)}
        for p in polys:
            assert abs(float(p.subs(mid))) < 1e-20


def test_no_complex_solution_and_positive_dimension():
    res = solve_real([x - 1, x - 2], [x, y])
    assert res.dimension == -1 and res.complex_count == 0 and res.count == 0
    # (x - 1) y = 0 and (x - 1)(y - 2) = 0: the line x = 1 (y = 0 and y = 2 exclude each other)
    res = solve_real([(x - 1) * y, (x - 1) * (y - 2)], [x, y])
    assert res.dimension == POSITIVE_DIMENSIONAL and res.positive_dimensional
    assert res.boxes == [] and res.complex_count is None
    # one equation in two unknowns; no equation at all
    assert solve_real([x**2 + y**2 - 1], [x, y]).positive_dimensional
    assert solve_real([sp.Integer(0)], [x]).positive_dimensional
    # a non-zero constant: no solution
    assert solve_real([sp.Integer(3)], [x]).dimension == -1


def test_floats_enter_as_their_exact_binary_rationals():
    res = solve_real([x - 0.1], [x])
    (lo, hi), = res.boxes[0]
    assert lo <= Fraction(0.1) <= hi
    assert not lo <= Fraction(1, 10) <= hi          # 0.1 is not 1/10
    assert Fraction(0.1) == Fraction(3602879701896397, 2**55)
    # a sympy Float, a Poly over RR and a numpy float coefficient: the same exact value
    for p in [x - sp.Float(0.1), sp.Poly(x - 0.1, x), x - np.float64(0.1)]:
        (lo, hi), = solve_real([p], [x]).boxes[0]
        assert lo <= Fraction(0.1) <= hi and not lo <= Fraction(1, 10) <= hi
    # a float that is a dyadic number is that number
    res = solve_real([2 * x - 0.75], [x])
    assert contains(res.boxes[0], (Fraction(3, 8),))


def test_rational_coefficients_and_odd_names():
    a, b = sp.symbols("alpha_{1} b'")
    res = solve_real([sp.Rational(1, 3) * a - sp.Rational(2, 7), a + b], [a, b])
    assert res.variables == ("alpha_{1}", "b'")
    assert contains(res.boxes[0], (Fraction(6, 7), Fraction(-6, 7)))
    # names given as strings
    assert solve_real([x - 2], ["x"]).count == 1


def test_threads_option():
    res = solve_real([x**2 + y**2 - 25, x - y + 1], [x, y], threads=2)
    assert res.count == 2


def test_refuses_irrational_and_non_polynomial_input():
    with pytest.raises(InputError, match=r"polys\[0\].*rational"):
        solve_real([x - sp.sqrt(2)], [x])
    with pytest.raises(InputError, match="rational"):
        solve_real([x - sp.pi], [x])
    with pytest.raises(InputError, match=r"polys\[1\].*\['y'\]"):
        solve_real([x, x - y], [x])
    with pytest.raises(InputError, match="polynomial"):
        solve_real([1 / x], [x])
    with pytest.raises(InputError, match="non-finite"):
        solve_real([x - sp.Float("nan")], [x])
    with pytest.raises(InputError, match="distinct"):
        solve_real([x], [x, x])
    with pytest.raises(InputError, match="at least one"):
        solve_real([x], [])
    with pytest.raises(InputError, match="timeout"):
        solve_real([x], [x], timeout=0)
    with pytest.raises(TypeError, match="polys"):
        solve_real(x - 1, [x])
    with pytest.raises(TypeError, match="polys"):
        solve_real(["x - 1"], [x])
    with pytest.raises(TypeError, match="variables"):
        solve_real([x - 1], [x + 1])
    with pytest.raises(TypeError, match="threads"):
        solve_real([x - 1], [x], threads=1.5)


def test_timeout_stops_msolve():
    rng = np.random.default_rng(7)
    v = sp.symbols("v0:5")
    polys = [sum(int(rng.integers(-9, 10)) * a * b for a in v for b in v) + 1 for _ in range(5)]
    with pytest.raises(MsolveTimeoutError, match="timeout"):
        solve_real(polys, v, timeout=1e-6)


def test_binary_lookup_and_environment(monkeypatch, tmp_path):
    path = msolve_binary()
    assert os.path.isabs(path) and os.access(path, os.X_OK)
    monkeypatch.setenv("MSOLVE", path)
    assert msolve_binary() == path and solve_real([x - 1], [x]).count == 1
    not_executable = tmp_path / "msolve"
    not_executable.write_text("")
    not_executable.chmod(stat.S_IRUSR)
    monkeypatch.setenv("MSOLVE", str(not_executable))
    with pytest.raises(MsolveUnavailableError, match=r"MSOLVE.*pip install imagespace\[exact\]"):
        msolve_binary()
    with pytest.raises(MsolveUnavailableError):
        solve_real([x - 1], [x])
    assert msolve_available() is False


def test_exception_family():
    assert issubclass(MsolveUnavailableError, ImageSpaceError)
    assert issubclass(MsolveUnavailableError, RuntimeError)
    assert issubclass(MsolveTimeoutError, MsolveError)
    assert issubclass(MsolveError, EliminationError) and issubclass(MsolveError, RuntimeError)


# --------------------------------------------------------------------------- no orphans, no files

_LONG_RUN = """
import sys
sys.path.insert(0, {root!r})
import sympy as sp
from imagespace.core.msolve import solve_real
v = sp.symbols("v0:6")
# six dense quadrics in six unknowns with 300-digit coefficients: msolve needs minutes
big = 10**300
polys = [sum(((i * 7 + j * 3 + k) % 11 - 5) * big * v[j] * v[k] for j in range(6)
             for k in range(j, 6)) + (i + 1) for i in range(6)]
print("start", flush=True)
try:
    solve_real(polys, v, timeout=300)
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
"""


def _children(pid):
    out = []
    for p in os.listdir("/proc"):
        if p.isdigit():
            try:
                with open(f"/proc/{p}/stat") as fh:
                    fields = fh.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if fields[1] == str(pid):
                out.append(int(p))
    return out


def _cmdline(pid):
    try:
        with open(f"/proc/{pid}/cmdline") as fh:
            return fh.read()
    except OSError:
        return ""


def _alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def _start_long_run(tmp_path, request):
    import subprocess
    import sys
    import time

    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    env = dict(os.environ, TMPDIR=str(tmp_path))
    proc = subprocess.Popen([sys.executable, "-c", _LONG_RUN.format(root=root)],
                            stdout=subprocess.PIPE, text=True, env=env)
    request.addfinalizer(lambda: (proc.poll() is None and proc.kill(), proc.wait(),
                                  proc.stdout.close()))
    assert proc.stdout.readline().strip() == "start"
    deadline = time.monotonic() + 60
    kids = []
    while time.monotonic() < deadline and not kids:
        kids = [k for k in _children(proc.pid) if "msolve" in _cmdline(k)]
        time.sleep(0.05)
    assert kids, "msolve did not start"
    time.sleep(0.5)
    return proc, kids[0]


@pytest.mark.slow
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc and prctl: Linux only")
def test_msolve_dies_with_its_killed_caller_and_leaves_no_files(tmp_path, request):
    import signal
    import time

    proc, child = _start_long_run(tmp_path, request)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    deadline = time.monotonic() + 5
    while _alive(child) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not _alive(child), "msolve outlived its killed caller"
    assert os.listdir(tmp_path) == []                   # no temporary folder, no input file


@pytest.mark.slow
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc: Linux only")
def test_ctrl_c_stops_msolve(tmp_path, request):
    import signal
    import time

    proc, child = _start_long_run(tmp_path, request)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate(timeout=10)
    assert out.strip() == "interrupted" and time.monotonic() - sent < 10
    assert not _alive(child) and os.listdir(tmp_path) == []
