"""Short path kept for existing code: the cusp tools of :mod:`imagespace.singular.cusps` and the
cusp loops of :mod:`imagespace.paths.cusp_loops`, under their former common name."""

from .paths.cusp_loops import MAX_STEPS, CuspLoop, cusp_loop  # noqa: F401
from .singular.cusps import *  # noqa: F401,F403
from .singular.cusps import __all__ as _cusps_all

__all__ = list(_cusps_all) + ["CuspLoop", "cusp_loop", "MAX_STEPS"]
