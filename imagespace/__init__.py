"""imagespace: algebraic kinematics of planar parallel manipulators in the kinematic image space.

The public API (loaded lazily); see README.md for the feature table,
docs/conventions.md for the conventions and docs/references.md for the papers.
"""

import sys as _sys
import types as _types

import lazy_loader as _lazy

# short names of modules that live in the layered packages (ARCHITECTURE.md), e.g. isp.screws
_MODULE_ALIASES = {
    "kinematic_map": "core.kinematic_map", "constraints": "core.quadrics", "legs": "core.legs",
    "elimination": "core.elimination", "roots": "core.roots", "certify": "core.certify",
    "codegen": "core.codegen", "certified_dk": "solve.certified", "fastdk": "solve.kernel",
    "singularities": "singular.surface", "meshing": "singular.meshing",
    "modechange": "paths.modechange", "clearance": "paths.backlash", "workspace": "design.workspace",
    "indices": "design.indices", "mobility": "design.mobility", "screws": "spatial.screws",
}

# Nothing is imported until it is used (PEP 562, through scientific-python's lazy_loader):
# ``import imagespace`` takes milliseconds, sympy/flint load on the first use of a function and
# numba, matplotlib, trimesh, scikit-image, scipy and dask only where a feature needs them.
# The submodules and public names are listed once, in imagespace/__init__.pyi: the stub a type
# checker reads is the list lazy_loader.attach_stub reads (the stub also types the aliases above;
# tests/test_typing.py holds the two equal).
_lazy_getattr, _lazy_dir, _ = _lazy.attach_stub(__name__, __file__)


def __getattr__(name):
    if name in _MODULE_ALIASES:
        import importlib

        return importlib.import_module(f"{__name__}.{_MODULE_ALIASES[name]}")
    return _lazy_getattr(name)


def __dir__():
    return sorted(set(_lazy_dir()) | set(_MODULE_ALIASES))


class _Package(_types.ModuleType):
    """``isp.cusps`` is the function :func:`imagespace.singular.cusps.cusps`, as it always was. The import
    system binds a loaded submodule on its package, which would shadow the function by the module
    of the same name; that one binding is skipped (``from imagespace.singular.cusps import ...`` and
    ``sys.modules`` still reach the module)."""

    def __setattr__(self, name, value):
        if name == "cusps" and isinstance(value, _types.ModuleType):
            return
        super().__setattr__(name, value)

    def __reduce__(self):
        # pickled by name, like any module (cloudpickle dispatches modules on the exact type, so
        # without this a function using ``isp`` could not be sent to a dask worker or a process)
        import importlib

        return importlib.import_module, (self.__name__,)


_sys.modules[__name__].__class__ = _Package

__version__ = "0.1.0"

__all__ = [
    "examples",
    "image_point", "pose_of", "normalize", "transform_matrix", "transform_points", "compose", "inverse",
    "Quadric", "image_symbols", "rr_quadric", "pr_quadric", "rp_quadric", "pp_quadric",
    "Leg", "RPR", "RRR", "PRR", "RRP", "RPP", "PRP", "PPR",
    "PlanarParallel", "AssemblyMode", "AssemblyModes", "DKBatchResult", "CertifiedModes",
    "SingularitySurface", "PoseJacobians", "ConicSection", "singularity_surface", "singularity_surfaces",
    "jacobians", "mesh_surface", "mesh_implicit", "export_mesh",
    "ImagePath", "PathCheck", "check_path", "segments_free", "segment", "polyline", "polynomial_curve",
    "rational_curve", "pose_segment", "ModeChangePlan", "plan_mode_change", "joint_trajectory",
    "mode_count_map", "cusps", "cusp_loop", "cusp_edges", "linking_number", "backlash",
    "gruebler", "manipulator_mobility", "mechanism_mobility", "sweep", "fuzzy_minmax",
    "RealRootCertificate", "certify_real_roots", "certify_real_roots_batch",
    "ImageSpaceError", "InputError", "InputTypeError", "RowIndexError", "DegenerateDesignError", "EliminationError",
    "NearSingularWarning",
    "AngleUnitWarning", "RepeatedLegWarning",
    "Tolerances", "TOLERANCES",
    "GoughStewart", "ThreeRPS",
    "JointAtlas", "joint_atlas", "is_cuspidal", "CuspidalityResult", "atlas_figure",
]
