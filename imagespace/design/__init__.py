"""Design: workspaces, performance indices, mobility, parameter sweeps and the fuzzy min-max
choice. ``imagespace.design`` keeps the names of :mod:`imagespace.design.sweep` (its old home).

Imports ``core``, ``solve`` and ``singular``.
"""

from .sweep import *  # noqa: F401,F403  (the public names of the former module imagespace.design)
from .sweep import __all__  # noqa: F401
