"""The only bridge from a sympy derivation to a numpy evaluator: lambdify with common
subexpression elimination, cached.

A derivation is paid for once per design: :meth:`PlanarParallel.compiled` derives the kinematic
polynomial general in the joint values and compiles its coefficients here, so evaluating them for
a batch of joint vectors is one vectorised numpy call.
"""

from __future__ import annotations

import os
import stat
import sys
import types
import warnings
from dataclasses import dataclass
from typing import Callable

import numpy as np
import sympy as sp

from .._files import atomic_write
from .._validate import as_float_array, as_sympy

__all__ = ["compile_exprs", "CompiledPolynomial", "CoefficientEnclosure", "KernelCacheWarning", "kernel_cache_dir",
           "load_cached_module", "read_regular_file", "warn_once"]


def compile_exprs(exprs, symbols):
    """Compile sympy expressions into one numpy function of the given symbols.

    Parameters
    ----------
    exprs : sequence of sympy expressions
    symbols : sequence of sympy symbols
        The arguments, in order.

    Returns
    -------
    callable
        ``f(*arrays) -> (n, len(exprs))`` float array (arrays broadcast together; constants are
        broadcast to the common shape).

    Examples
    --------
    >>> import numpy as np, sympy as sp
    >>> from imagespace.core.codegen import compile_exprs
    >>> a, b = sp.symbols("a b")
    >>> compile_exprs([a * b, a + 1, sp.Integer(2)], [a, b])(np.array([1.0, 2.0]), np.array([3.0, 4.0]))
    array([[3., 2., 2.],
           [8., 3., 2.]])
    """
    exprs = [as_sympy(e) for e in exprs]
    fn = sp.lambdify(list(symbols), exprs, modules="numpy", cse=True)

    def evaluate(*args):
        arrays = np.broadcast_arrays(*[np.asarray(a, dtype=float) for a in args])
        shape = arrays[0].shape if arrays else ()
        out = fn(*arrays)
        return np.stack([np.broadcast_to(np.asarray(v, dtype=float), shape) for v in out], axis=-1)

    return evaluate


@dataclass(frozen=True)
class CompiledPolynomial:
    """The kinematic polynomial of one design, general in the joint values, compiled.

    Attributes
    ----------
    polynomial : sympy.Poly
        The symbolic binary form (generators ``x0, x1``; coefficients in ``q1, q2, q3``).
    degree : int
    symbols : tuple
        The joint symbols, in argument order.
    """

    polynomial: sp.Poly
    degree: int
    symbols: tuple
    _fn: Callable

    def coefficients(self, Q):
        """Coefficients ``(n, degree + 1)`` for joint vectors ``Q`` ``(n, 3)``; column ``k``
        multiplies ``x0**(degree - k) x1**k``.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> m.compiled().coefficients([[11.0, 5.0, 10.0]]).shape
        (1, 7)
        """
        Q = as_float_array(Q, "Q", last=3, finite=False)
        single = Q.ndim == 1
        Q2 = np.atleast_2d(Q)
        out = self._fn(Q2[:, 0], Q2[:, 1], Q2[:, 2])
        return out[0] if single else out


_U = 2.0**-53


class CoefficientEnclosure:
    """Coefficients of a binary form that depend polynomially on the joint values, with a
    rigorous bound on their floating-point error, and their exact values where they are rational.

    The kinematic polynomial general in ``q`` has coefficients that are polynomials in the
    *features* ``q_i``, ``cos q_i``, ``sin q_i`` (revolute actuators) with exact constant
    coefficients. Expanded on those monomials (a few dozen for a 3-RPR), a batch is one matrix
    product, and its error is bounded the classical way (Higham, *Accuracy and Stability of
    Numerical Algorithms*, 2nd ed., eq. 3.5 for inner products; products of features with their
    absolute errors propagated first order plus the second-order term): ``cos``/``sin`` come
    with rigorous bounds from :func:`~imagespace.core.bounded_trig.cos_sin_enclosure` (compiled;
    arb beyond its range), the constants are rounded once (their error is bounded), the joint values are exact
    binary rationals. So the exact coefficients lie in ``F +- E`` for every row.

    Parameters
    ----------
    poly : sympy.Poly or list of sympy expressions
        A Poly in ``(x0, x1)`` whose coefficients are polynomial in the features of ``symbols``,
        or directly a list of such coefficients (any number of them).
    symbols : sequence of three sympy symbols

    Raises
    ------
    ValueError
        A coefficient is not polynomial in the features of ``symbols``.

    Examples
    --------
    >>> import numpy as np
    >>> import imagespace as isp
    >>> from imagespace.core.codegen import CoefficientEnclosure
    >>> m = isp.examples.general_3rpr()
    >>> enc = CoefficientEnclosure(m.kinematic_polynomial(), m.joint_symbols)
    >>> F, E = enc.evaluate(np.array([[11.0, 5.0, 10.0]]))
    >>> F.shape, bool(np.all(E < 1e-9 * np.abs(F).max()))
    ((1, 7), True)
    """

    def __init__(self, poly, symbols):
        if isinstance(poly, sp.Poly):
            d = poly.total_degree()
            coeffs = [sp.expand(poly.coeff_monomial(poly.gens[0] ** (d - k) * poly.gens[1] ** k))
                      for k in range(d + 1)]
        else:                                   # a plain list of coefficient expressions
            coeffs = [sp.expand(as_sympy(c)) for c in poly]
            d = len(coeffs) - 1
        self.degree = d
        self.symbols = tuple(symbols)
        gens = list(self.symbols)
        trig = []
        for i, s in enumerate(self.symbols):
            for f in (sp.cos, sp.sin):
                if any(c.has(f(s)) for c in coeffs):
                    gens.append(f(s))
                    trig.append((len(gens) - 1, i, f is sp.cos))
        self._trig = trig
        terms = {}
        for k, c in enumerate(coeffs):
            pc = sp.Poly(c, *gens)
            for mono, val in pc.terms():
                if val.free_symbols:
                    raise ValueError(f"coefficient {k} is not polynomial in the joint features: {c}")
                terms.setdefault(mono, [sp.Integer(0)] * (d + 1))[k] = val
        monos = sorted(terms)
        self._expo = np.array(monos, dtype=int).reshape(len(monos), len(gens))
        exact = [[terms[m][k] for k in range(d + 1)] for m in monos]
        self._exact = exact
        self.rational = all(v.is_Rational for row in exact for v in row) and not trig
        Cf = np.zeros((len(monos), d + 1))
        Ce = np.zeros((len(monos), d + 1))
        for a, row in enumerate(exact):
            for k, v in enumerate(row):
                if v == 0:
                    continue
                if v.is_Rational:
                    Cf[a, k] = float(v)                   # correctly rounded
                    Ce[a, k] = abs(Cf[a, k]) * _U + 2.0**-1074
                else:
                    Cf[a, k] = float(sp.N(v, 40))
                    Ce[a, k] = abs(Cf[a, k]) * 2 * _U + 2.0**-1000
        self._Cf, self._Ce = Cf, Ce
        if self.rational:
            import flint

            self._Cq = [[flint.fmpq(int(v.p), int(v.q)) for v in row] for row in exact]

    def _features(self, Q):
        """Feature values ``(n, G)`` and absolute error bounds ``(n, G)``."""
        n = Q.shape[0]
        G = self._expo.shape[1]
        val = np.zeros((n, G))
        err = np.zeros((n, G))
        val[:, :3] = Q
        if self._trig:
            from .bounded_trig import cos_sin_enclosure   # numba: imported on first use

            cols = sorted({i for _, i, _ in self._trig})
            c, s, ec, es = cos_sin_enclosure(Q[:, cols])
            for g, i, is_cos in self._trig:
                j = cols.index(i)
                val[:, g] = c[:, j] if is_cos else s[:, j]
                err[:, g] = ec[:, j] if is_cos else es[:, j]
        return val, err

    def evaluate(self, Q):
        """Coefficients ``F`` (n, d+1) and rigorous error bounds ``E`` (n, d+1) for joint
        vectors ``Q`` (n, 3) (finite floats, taken as exact binary rationals).

        Examples
        --------
        >>> import numpy as np
        >>> import imagespace as isp
        >>> from imagespace.core.codegen import CoefficientEnclosure
        >>> m = isp.examples.general_3rpr()
        >>> enc = CoefficientEnclosure(m.kinematic_polynomial(), m.joint_symbols)
        >>> enc.evaluate(np.array([[11.0, 5.0, 10.0]]))[0].shape
        (1, 7)
        """
        Q = np.asarray(Q, dtype=float)
        fv, fe = self._features(Q)
        n, M = Q.shape[0], self._expo.shape[0]
        phi = np.ones((n, M))
        perr = np.zeros((n, M))
        nmul = np.zeros(M)
        with np.errstate(over="ignore", invalid="ignore"):
            for g in range(self._expo.shape[1]):
                for a in np.flatnonzero(self._expo[:, g]):
                    for _ in range(self._expo[a, g]):
                        v, e = fv[:, g], fe[:, g]
                        # (phi +- perr)(v +- e): first order, second order, and the rounding
                        newp = phi[:, a] * v
                        perr[:, a] = (np.abs(phi[:, a]) * e + np.abs(v) * perr[:, a] + perr[:, a] * e
                                      + np.abs(newp) * _U)
                        phi[:, a] = newp
                        nmul[a] += 1
            Cf, Ce = self._Cf, self._Ce
            F = phi @ Cf
            gamma = (M + 2) * _U / (1 - (M + 2) * _U)
            E = (gamma * (np.abs(phi) @ np.abs(Cf)) + perr @ (np.abs(Cf) + Ce) + np.abs(phi) @ Ce)
            E = E * (1 + 8 * _U) + M * 2.0**-1070
        bad = ~np.isfinite(E) | ~np.isfinite(F)
        E[bad] = np.inf
        return F, E

    def exact_sympy(self, q):
        """Exact coefficients (sympy numbers) at exact rational joint values ``q``, for constants
        that are not rational (e.g. in ``Q(sqrt(181))``); ``None`` with trigonometric features.

        Examples
        --------
        >>> import sympy as sp
        >>> import imagespace as isp
        >>> from imagespace.core.codegen import CoefficientEnclosure
        >>> m = isp.examples.stigger_husty()
        >>> enc = CoefficientEnclosure(m.kinematic_polynomial(), m.joint_symbols)
        >>> len(enc.exact_sympy([sp.Integer(10), sp.Integer(15), sp.Rational(53, 4)]))
        7
        """
        if self._trig:
            return None
        out = self._combine(self._exact, [sp.Rational(v) for v in q], sp.Integer(1), sp.Integer(0))
        return [sp.expand(v) for v in out]

    def _combine(self, rows, qq, one, zero):
        """``sum_m c_m q^m`` per coefficient, in whatever exact number type ``rows``/``qq`` hold."""
        out = [zero] * (self.degree + 1)
        for a, row in enumerate(rows):
            mono = one
            for g, e in enumerate(self._expo[a]):
                if e:
                    mono = mono * qq[g] ** int(e)
            for k, c in enumerate(row):
                if c != 0:
                    out[k] = out[k] + c * mono
        return out

    def exact(self, q):
        """Exact coefficients (Fractions) at exact joint values ``q`` (Fractions, fmpq or floats), or
        ``None`` when the constants or features are not rational (use the sympy derivation).

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.core.codegen import CoefficientEnclosure
        >>> m = isp.examples.general_3rpr()
        >>> enc = CoefficientEnclosure(m.kinematic_polynomial(), m.joint_symbols)
        >>> len(enc.exact([11.0, 5.0, 10.0]))
        7
        """
        if not self.rational:
            return None
        import flint
        from fractions import Fraction

        qq = []
        for v in q:
            f = v if isinstance(v, flint.fmpq) else Fraction(v)
            qq.append(f if isinstance(f, flint.fmpq) else flint.fmpq(f.numerator, f.denominator))
        out = self._combine(self._Cq, qq, flint.fmpq(1), flint.fmpq(0))
        return [Fraction(int(v.p), int(v.q)) for v in out]


# -- the on-disk cache of generated kernels ----------------------------------------------------------
#
# A generated module is never read back: the source just generated is compared with the file
# and executed from memory (the file only anchors numba's cache, which keys on its path, mtime
# and size). numba's cache files are pickles, so the directory must be private: created 0700,
# refused when owned by another user, writable by group or others, or a symbolic link.

_DIR_MODE = 0o700          # mode of the cache directories the kernel cache creates
_FOREIGN_WRITE = 0o022     # group/other write bits: such a directory is refused
_warned: set[tuple[str, str]] = set()  # (reason, path) already warned about in this process


class KernelCacheWarning(UserWarning):
    """The on-disk kernel cache was refused or repaired; the kernel itself still works.

    Examples
    --------
    >>> from imagespace.solve.kernel import KernelCacheWarning
    >>> issubclass(KernelCacheWarning, UserWarning)
    True
    """


def warn_once(reason, path, message):
    """Issue one :class:`KernelCacheWarning` per ``(reason, path)`` and process.

    Examples
    --------
    >>> import warnings
    >>> from imagespace.core.codegen import warn_once
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     warn_once("example", "/nowhere", "said once"); warn_once("example", "/nowhere", "said once")
    >>> len(w)
    1
    """
    if (reason, path) in _warned:
        return
    _warned.add((reason, path))
    warnings.warn(message, KernelCacheWarning, stacklevel=4)


def _cache_root():
    """``$IMAGESPACE_CACHE/kernels`` or ``~/.cache/imagespace/kernels`` (honouring XDG_CACHE_HOME)."""
    root = os.environ.get("IMAGESPACE_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "imagespace")
    return os.path.join(os.path.abspath(root), "kernels")


def _make_private_dirs(path):
    """Create the missing components of ``path``, each 0700 whatever the umask (existing ones,
    including a symbolic link at the end, are left alone: :func:`_refusal` judges the leaf)."""
    missing = []
    p = path
    while not os.path.lexists(p):
        missing.append(p)
        parent = os.path.dirname(p)
        if parent == p:
            break
        p = parent
    for p in reversed(missing):
        try:
            os.mkdir(p, _DIR_MODE)
        except FileExistsError:
            continue          # created concurrently: judged like any existing directory
        os.chmod(p, _DIR_MODE)   # the umask may have removed bits, never adds any


def _refusal(path):
    """Why the cache directory ``path`` must not be used (None when it is private to us)."""
    st = os.lstat(path)
    if stat.S_ISLNK(st.st_mode):
        return "is a symbolic link"
    if not stat.S_ISDIR(st.st_mode):
        return "is not a directory"
    euid = os.geteuid() if hasattr(os, "geteuid") else None
    if euid is not None and st.st_uid != euid:
        return f"is owned by uid {st.st_uid}, not by this user (uid {euid})"
    if st.st_mode & _FOREIGN_WRITE:
        return f"is writable by group or others (mode {stat.S_IMODE(st.st_mode):o})"
    return None


def _ancestor_refusal(path):
    """Why a directory above ``path`` makes the cache unsafe (None when none does): every
    ancestor (symbolic links resolved) must be owned by this user or root, and writable by group
    or others only with the sticky bit (as ``/tmp``), else someone else could swap the cache for
    a directory of their own."""
    euid = os.geteuid() if hasattr(os, "geteuid") else None
    p = os.path.dirname(os.path.realpath(path))
    while True:
        st = os.stat(p)
        if euid is not None and st.st_uid not in (euid, 0):
            return f"lies under {p}, owned by uid {st.st_uid} (neither this user nor root)"
        if st.st_mode & _FOREIGN_WRITE and not st.st_mode & stat.S_ISVTX:
            return f"lies under {p}, writable by group or others (mode {stat.S_IMODE(st.st_mode):o})"
        parent = os.path.dirname(p)
        if parent == p:
            return None
        p = parent


def kernel_cache_dir():
    """Where generated kernels live, so numba's on-disk cache can keep them between sessions;
    None when it cannot be created (then kernels are compiled in memory) or is refused (with one
    :class:`KernelCacheWarning` naming the reason and the path).

    Examples
    --------
    >>> import os
    >>> from imagespace.core.codegen import kernel_cache_dir
    >>> d = kernel_cache_dir()
    >>> d is None or (os.stat(d).st_mode & 0o022) == 0      # nobody else may write there
    True
    """
    path = _cache_root()
    try:
        _make_private_dirs(path)
        reason = _refusal(path) or _ancestor_refusal(path)
    except OSError:
        return None
    if reason is None:
        # numba caches a file's machine code in __pycache__ next to it (unless NUMBA_CACHE_DIR
        # names another directory: then that one, the user's choice): private too, and held to
        # the same checks (a link, a foreign owner or a group/world-writable mode refuses the
        # cache: numba's index files are pickles, read before their contents are checked)
        pycache = os.path.join(path, "__pycache__")
        try:
            _make_private_dirs(pycache)
            reason = _refusal(pycache)
        except OSError:
            reason = None
        if reason is not None:
            path = pycache
    if reason is not None:
        warn_once("refused", path, f"kernel cache directory {path} {reason}: not used, the kernel "
                   "is compiled in memory (make it a directory of your own with mode 0700, or "
                   "set IMAGESPACE_CACHE)")
    return path if reason is None else None


def read_regular_file(path):
    """The bytes of the regular file ``path``, never following a symbolic link; None when it is
    missing, a symbolic link or not a regular file.

    Examples
    --------
    >>> from imagespace.core.codegen import read_regular_file
    >>> read_regular_file("/nonexistent/file") is None
    True
    """
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return None
    if not stat.S_ISREG(st.st_mode):
        return None
    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    try:
        fd = os.open(path, flags)
    except OSError:
        return None
    with os.fdopen(fd, "rb") as fh:
        if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):
            return None
        return fh.read()


def load_cached_module(folder, key, source):
    """The generated module anchored at ``folder/k_<key>.py`` (numba caches its machine code next
    to it). The file is compared with ``source`` and rewritten when it differs (one warning
    unless it was missing); what is executed is always ``source`` itself.

    Examples
    --------
    >>> import tempfile
    >>> from imagespace.core.codegen import load_cached_module
    >>> load_cached_module(tempfile.mkdtemp(), "doc", "answer = 42").answer
    42
    """
    path = os.path.join(folder, f"k_{key}.py")
    data = source.encode()
    current = read_regular_file(path)
    if current != data:
        if os.path.lexists(path):
            warn_once("rewritten", path, f"kernel cache file {path} did not match the generated "
                       "source (or was not a regular file): rewritten")
            st = os.lstat(path)
            if not stat.S_ISREG(st.st_mode) and not stat.S_ISDIR(st.st_mode):
                os.unlink(path)         # a planted link or special file in our private folder: removed, not followed
        atomic_write(path, lambda f: f.write(data), mode=0o600)     # private, like the folder
    name = f"imagespace_kernel_{key}"
    mod = types.ModuleType(name)
    mod.__file__ = path
    sys.modules[name] = mod   # numba's cache finds the module again by its name
    exec(compile(source, path, "exec"), mod.__dict__)
    return mod
