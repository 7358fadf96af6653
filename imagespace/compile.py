"""The only bridge from a sympy derivation to a numpy evaluator: lambdify with common
subexpression elimination, cached.

A derivation is paid for once per design: :meth:`PlanarParallel.compiled` derives the kinematic
polynomial general in the joint values and compiles its coefficients here, so evaluating them for
a batch of joint vectors is one vectorised numpy call.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import sympy as sp

from ._validate import as_float_array

__all__ = ["compile_exprs", "CompiledPolynomial"]


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
    >>> from imagespace.compile import compile_exprs
    >>> a, b = sp.symbols("a b")
    >>> compile_exprs([a * b, a + 1, sp.Integer(2)], [a, b])(np.array([1.0, 2.0]), np.array([3.0, 4.0]))
    array([[3., 2., 2.],
           [8., 3., 2.]])
    """
    exprs = [sp.sympify(e) for e in exprs]
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
