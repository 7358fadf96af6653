"""Paths in image space: curves, their exact check against the singularity surface, mode changes,
backlash. ``imagespace.paths`` keeps the names of :mod:`imagespace.paths.check` (its old home).

Imports ``core``, ``solve`` and ``singular``.
"""

from .check import *  # noqa: F401,F403  (the public names of the former module imagespace.paths)
from .check import __all__  # noqa: F401
