"""Sweeps keep what they computed and work where users are (issue 14, "Data loss").

A failing design names its parameters (``on_error="raise"``) or is recorded in the table
(``on_error="record"``) serially, in local processes and on Dask; the default is serial and the
opt-in pools take functions defined inside a test (closures, which plain pickle cannot ship) and
scripts without a ``__main__`` guard. Expected rows are computed here, independently of ``sweep``.
"""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

import imagespace as isp
from imagespace.design.sweep import DesignEvaluationError, sweep


def _grid_and_bad(seed):
    rng = np.random.default_rng(seed)
    a = np.round(rng.uniform(-2, 2, 3), 3)
    b = np.round(rng.uniform(-2, 2, 4), 3)
    bad = (float(a[rng.integers(3)]), float(b[rng.integers(4)]))
    return {"a": a, "b": b}, bad


def _expected(grid, bad, ok_rows=None):
    """Row-major rows, values and errors computed without sweep."""
    rows = [(float(x), float(y)) for x in grid["a"] for y in grid["b"]]
    s = np.array([np.nan if r == bad else r[0] + r[1] for r in rows])
    p = np.array([np.nan if r == bad else r[0] * r[1] for r in rows])
    return rows, s, p, rows.index(bad)


def _failing(bad, kind="raise"):
    scale = 1.0                                               # a closure cell: not plain-picklable

    def f(a, b):
        if (float(a), float(b)) == bad:
            if kind == "raise":
                raise ZeroDivisionError(f"no design at {a}, {b}")
            if kind == "missing":
                return {"sum": a + b}
            if kind == "extra":
                return {"sum": a + b, "product": a * b, "other": 1.0}
            if kind == "string":
                return {"sum": "oops", "product": a * b}
            if kind == "none":
                return None
            if kind == "complex":
                return {"sum": complex(a, b), "product": a * b}
        return {"sum": scale * (a + b), "product": scale * a * b}
    return f


def _check_recorded(t, grid, bad, message):
    rows, s, p, k = _expected(grid, bad)
    np.testing.assert_array_equal(t.values["sum"], s)
    np.testing.assert_array_equal(t.values["product"], p)
    assert t.failed == [k]
    assert message in t.errors[k]
    assert all(e == "" for i, e in enumerate(t.errors) if i != k)
    assert [(float(x), float(y)) for x, y in zip(t.params["a"], t.params["b"])] == rows


@pytest.mark.slow
@pytest.mark.parametrize("processes", [None, 2])
def test_record_keeps_every_finished_row(processes):
    grid, bad = _grid_and_bad(1)
    t = sweep(_failing(bad), grid, processes=processes, progress=False, on_error="record")
    _check_recorded(t, grid, bad, "ZeroDivisionError: no design at")
    assert t.how == ("serial" if processes is None else "processes (2)")


@pytest.mark.slow
@pytest.mark.parametrize("processes", [None, 2])
def test_raise_names_the_failing_design_and_chains_the_cause(processes):
    grid, bad = _grid_and_bad(2)
    rows, s, p, k = _expected(grid, bad)
    with pytest.raises(DesignEvaluationError) as info:
        sweep(_failing(bad), grid, processes=processes, progress=False)
    err = info.value
    assert isinstance(err, isp.ImageSpaceError)
    assert f"'a': {bad[0]}" in str(err) and f"'b': {bad[1]}" in str(err)
    assert err.params == {"a": bad[0], "b": bad[1]} and err.index == k
    assert isinstance(err.__cause__, ZeroDivisionError) and "no design at" in str(err.__cause__)
    # the finished rows are kept on the error
    t = err.table
    assert t.errors[k].startswith("ZeroDivisionError")
    good = [i for i in range(len(rows)) if t.errors[i] == ""]
    assert set(range(k)) <= set(good) if processes is None else True
    np.testing.assert_array_equal(t.values["sum"][good], s[good])
    assert all(np.isnan(t.values["sum"][i]) for i in range(len(rows)) if i not in good)


@pytest.mark.parametrize("kind, message", [("missing", "no value for ['product']"),
                                           ("extra", "unexpected ['other']"),
                                           ("string", "non-number for 'sum'"),
                                           ("complex", "non-number for 'sum'"),
                                           ("none", "not a dict of numbers")])
def test_bad_returns_are_reported_like_errors(kind, message):
    grid, bad = _grid_and_bad(3)
    t = sweep(_failing(bad, kind), grid, progress=False, on_error="record")
    _check_recorded(t, grid, bad, message)
    with pytest.raises(DesignEvaluationError, match=f"'a': {bad[0]}, 'b': {bad[1]}"):
        sweep(_failing(bad, kind), grid, progress=False)


@pytest.mark.slow
def test_bad_return_in_worker_processes():
    grid, bad = _grid_and_bad(4)
    t = sweep(_failing(bad, "missing"), grid, processes=2, chunksize=2, progress=False, on_error="record")
    _check_recorded(t, grid, bad, "no value for ['product']")


@pytest.mark.slow
def test_default_is_serial_and_a_local_function_runs_in_processes():
    grid, _ = _grid_and_bad(5)
    offset = 0.25

    def local(a, b):                                          # defined here: plain pickle fails
        return {"s": a + b + offset, "d": a - b}

    serial = sweep(local, grid, progress=False)
    assert serial.how == "serial"
    pooled = sweep(local, grid, processes=2, progress=False)
    assert pooled.how == "processes (2)" and serial.equals(pooled)
    rows = [(float(x), float(y)) for x in grid["a"] for y in grid["b"]]
    np.testing.assert_array_equal(pooled.values["s"], [x + y + offset for x, y in rows])
    np.testing.assert_array_equal(pooled.values["d"], [x - y for x, y in rows])


@pytest.mark.slow
def test_unguarded_script_runs_in_processes(tmp_path):
    script = tmp_path / "unguarded.py"
    script.write_text(textwrap.dedent("""
        from imagespace.design.sweep import sweep

        def f(a, b):
            return {"s": a * 10 + b}

        t = sweep(f, {"a": [1, 2], "b": [3, 4, 5]}, processes=2, progress=False)
        print(t.how, t.values["s"].tolist())
    """))
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120,
                         cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "processes (2) [13.0, 14.0, 15.0, 23.0, 24.0, 25.0]"


@pytest.mark.slow
def test_dask_records_and_raises():
    distributed = pytest.importorskip("distributed")
    grid, bad = _grid_and_bad(6)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
        t = sweep(_failing(bad), grid, client=client, progress=False, on_error="record")
        m = sweep(_failing(bad, "missing"), grid, client=client, progress=False, on_error="record")
        with pytest.raises(DesignEvaluationError, match=f"'a': {bad[0]}, 'b': {bad[1]}") as info:
            sweep(_failing(bad), grid, client=client, progress=False)
    assert t.how.startswith("dask")
    _check_recorded(t, grid, bad, "ZeroDivisionError: no design at")
    _check_recorded(m, grid, bad, "no value for ['product']")
    assert isinstance(info.value.__cause__, ZeroDivisionError)


def test_bad_arguments():
    grid, _ = _grid_and_bad(7)
    with pytest.raises(isp.InputError, match="on_error"):
        sweep(_failing(None), grid, on_error="ignore")
    with pytest.raises(isp.InputError, match="processes"):
        sweep(_failing(None), grid, processes=-1)
    with pytest.raises(isp.InputError, match="chunksize"):
        sweep(_failing(None), grid, chunksize=0)
