"""Short path kept for existing code: this module *is* :mod:`imagespace.spatial.screws` (the same module
object, registered under both names)."""

import importlib as _importlib
import sys as _sys

_sys.modules[__name__] = _importlib.import_module("imagespace.spatial.screws")
