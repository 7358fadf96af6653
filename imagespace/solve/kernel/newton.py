"""The safeguarded Newton iteration (:func:`_monotone_root`) that refines each isolated root of the
batch kernel's rows, and Horner's rule (:func:`_horner`) for the signs at the ends of its bracket."""

from __future__ import annotations

from ...core._numba import njit

# constants of the bracketed Newton iteration (numerical-method knobs, not read from Tolerances:
# the root is isolated already, and the row's later decisions check the refined point)
_HORNER_ZERO = 4.5e-16       # |p(t)| below this * deg * sum|c_k||t|^k is zero within Horner's rounding
_BISECT_WIDTH = 4e-16        # a bracket narrower than this (relative) has converged: stopping width
_NEWTON_STEPS = 400          # most steps of the bracketed Newton iteration (bisection guarantees far fewer)


@njit(cache=True)
def _horner(c, deg, t):
    """``c[0] + c[1] t + ... + c[deg] t**deg`` by Horner's rule."""
    v = c[deg]
    for k in range(deg - 1, -1, -1):
        v = v * t + c[k]
    return v


@njit(cache=True)
def _monotone_root(c, deg, a, b, fa, fb):
    """The root of a polynomial monotone on [a, b] with fa * fb < 0: Newton from the secant's
    zero, kept inside the bracket (a step leaving it, or four steps that do not halve it, give way
    to bisection, so it always converges), stopped once ``|p(t)|`` is within the rounding error of
    its evaluation or the bracket is a few ulps wide."""
    t = a - fa * (b - a) / (fb - fa)
    if not (a < t < b):
        t = 0.5 * (a + b)
    return _bracketed_newton(c, deg, a, b, fa, fb, t, b - a, 0)


@njit(cache=True)
def _bracketed_newton(c, deg, a, b, fa, fb, t, width, it0):
    """The iteration of :func:`_monotone_root` from its step ``it0`` on, at the point ``t`` of the
    bracket ``[a, b]`` (``width``: the bracket's width at the last safeguard check): the lockstep
    kernel runs the first steps of every root of a block together and finishes the few slow ones
    here."""
    for it in range(it0, _NEWTON_STEPS):
        f = c[deg]
        d = 0.0
        e = abs(c[deg])
        at = abs(t)
        for k in range(deg - 1, -1, -1):
            d = d * t + f
            f = f * t + c[k]
            e = e * at + abs(c[k])
        if abs(f) <= _HORNER_ZERO * deg * e:
            return t
        if (f < 0.0) == (fa < 0.0):
            a, fa = t, f
        else:
            b, fb = t, f
        if b - a <= _BISECT_WIDTH * max(1.0, abs(a), abs(b)):
            return t
        tn = t - f / d if d != 0.0 else 0.5 * (a + b)
        if it % 4 == 3:
            # safeguard: a Newton run that has not halved the bracket in four steps is crawling
            # (far from the root, or a near-flat stretch): bisect
            if b - a > 0.5 * width:
                tn = 0.5 * (a + b)
            width = b - a
        if not (a < tn < b):
            tn = 0.5 * (a + b)
        t = tn
    return t
