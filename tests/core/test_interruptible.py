"""Long exact work stops on Ctrl-C: call_interruptibly (a child process), the exact root
isolation on long integers that uses it, and Sturm's count that skips factors without real roots
(checked against sympy's independent count)."""

import os
import signal
import subprocess
import sys
import textwrap
import time

import flint
import pytest
import sympy as sp

from imagespace.core.certify import _sturm_real_root_count, certify_real_roots
from imagespace.core.interruptible import ComputationTimeoutError, call_interruptibly, can_fork
from imagespace.exceptions import InputError

linux = pytest.mark.skipif(not can_fork(), reason="children are forked on Linux only")
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _raise_value_error(text):
    raise ValueError(text)


def _spin(seconds):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        pass
    return "done"


@pytest.mark.slow
@linux
def test_results_and_errors_cross_the_process_boundary():
    assert call_interruptibly(pow, (2, 100)) == 2**100
    with pytest.raises(ValueError, match="from the child"):
        call_interruptibly(_raise_value_error, ("from the child",))
    with pytest.raises(ComputationTimeoutError, match="timeout=0.2"):
        call_interruptibly(_spin, (30,), timeout=0.2)
    with pytest.raises(InputError, match="timeout"):
        call_interruptibly(pow, (2, 3), timeout=-1)
    assert call_interruptibly(_spin, (0,), in_child=False) == "done"


def test_sturm_count_agrees_with_sympy():
    t = sp.Symbol("t")
    for expr in [(t - 1) * (t + 2) * (t**2 + 1), t**6 + 1, (t**2 - 2) * (t**4 - 3) * t,
                 (t - 1) * ((t**2 + 1)**2 * 2**300 + 1), (3 * t - 1)**2 * (t + 5)]:
        poly = sp.Poly(expr, t)
        coeffs = [int(c) for c in reversed(poly.all_coeffs())]
        assert _sturm_real_root_count(flint.fmpz_poly(coeffs)) == poly.count_roots()


def test_long_coefficients_without_real_roots_are_decided_by_sturm():
    t = sp.Symbol("t")
    poly = sp.Poly((t**2 + 1)**2 * 2**8000 + 1, t)          # no real root, clustered at +-i
    start = time.monotonic()
    cert = certify_real_roots([int(c) for c in reversed(poly.all_coeffs())])
    assert cert.certified and cert.count == 0
    assert time.monotonic() - start < 60        # a guard against a hang, not a speed claim


@pytest.mark.slow
@linux
def test_ctrl_c_stops_a_long_certified_call():
    """A subprocess certifies a form whose isolation takes minutes; SIGINT must reach it as a
    KeyboardInterrupt within a few seconds, and its computing child must be gone."""
    script = textwrap.dedent(f"""
        import os, sys, time
        sys.path.insert(0, {ROOT!r})
        from imagespace.core.certify import certify_real_roots
        import sympy as sp
        t = sp.Symbol("t")
        poly = sp.Poly((t - 1) * ((t**2 + 1)**2 * 2**4000 + 1), t)
        form = [int(c) for c in reversed(poly.all_coeffs())]
        print("ready", flush=True)
        try:
            certify_real_roots(form)
            print("finished", flush=True)
        except KeyboardInterrupt:
            kids = [p for p in os.listdir("/proc") if p.isdigit() and
                    open(f"/proc/{{p}}/stat").read().split(")")[-1].split()[1] == str(os.getpid())]
            print("interrupted", len(kids), flush=True)
    """)
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "ready"
        time.sleep(1.0)                         # the isolation is under way in the child
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=10)
        assert time.monotonic() - sent < 10
        assert out.split() == ["interrupted", "0"], out
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
