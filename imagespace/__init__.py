"""imagespace: algebraic kinematics of planar parallel manipulators in the kinematic image space.

The public API (loaded lazily); see README.md for the feature table,
docs/conventions.md for the conventions and docs/references.md for the papers.
"""

import sys as _sys
import types as _types

import lazy_loader as _lazy

# Nothing is imported until it is used (PEP 562, through scientific-python's lazy_loader):
# ``import imagespace`` takes milliseconds, sympy/flint load on the first use of a function and
# numba, matplotlib, trimesh, scikit-image, scipy and dask only where a feature needs them.
_SUBMODULES = [
    "examples", "kinematic_map", "constraints", "legs", "manipulator", "certify", "certified_dk",
    "compile", "elimination", "roots", "fastdk", "singularities", "meshing", "paths", "modechange",
    "clearance", "mobility", "design", "tolerances", "exceptions", "plotting", "screws",
    "workspace", "indices", "dynamics", "cli",
]
_ATTRIBUTES = {
    "constraints": ["Quadric", "image_symbols", "pp_quadric", "pr_quadric", "rp_quadric", "rr_quadric"],
    "exceptions": ["DegenerateDesignError", "EliminationError", "ImageSpaceError", "InputError",
                   "NearSingularWarning"],
    "kinematic_map": ["compose", "image_point", "inverse", "normalize", "pose_of", "transform_matrix",
                      "transform_points"],
    "legs": ["PPR", "PRP", "PRR", "RPP", "RPR", "RRP", "RRR", "Leg"],
    "certify": ["RealRootCertificate", "certify_real_roots", "certify_real_roots_batch"],
    "manipulator": ["AssemblyMode", "CertifiedModes", "DKBatchResult", "PlanarParallel"],
    "singularities": ["ConicSection", "PoseJacobians", "SingularitySurface", "jacobians",
                      "singularity_surface", "singularity_surfaces"],
    "meshing": ["export_mesh", "mesh_implicit", "mesh_surface"],
    "paths": ["ImagePath", "PathCheck", "check_path", "polyline", "polynomial_curve", "pose_segment",
              "rational_curve", "segment", "segments_free"],
    "modechange": ["ModeChangePlan", "joint_trajectory", "plan_mode_change"],
    "cusps": ["cusp_edges", "cusp_loop", "cusps", "linking_number", "mode_count_map"],
    "clearance": ["backlash"],
    "mobility": ["gruebler", "manipulator_mobility", "mechanism_mobility"],
    "design": ["fuzzy_minmax", "sweep"],
    "tolerances": ["TOLERANCES", "Tolerances"],
}
__getattr__, __dir__, _ = _lazy.attach(__name__, submodules=_SUBMODULES, submod_attrs=_ATTRIBUTES)


class _Package(_types.ModuleType):
    """``isp.cusps`` is the function :func:`imagespace.cusps.cusps`, as it always was. The import
    system binds a loaded submodule on its package, which would shadow the function by the module
    of the same name; that one binding is skipped (``from imagespace.cusps import ...`` and
    ``sys.modules`` still reach the module)."""

    def __setattr__(self, name, value):
        if name == "cusps" and isinstance(value, _types.ModuleType):
            return
        super().__setattr__(name, value)


_sys.modules[__name__].__class__ = _Package

__version__ = "0.1.0"

__all__ = [
    "examples",
    "image_point", "pose_of", "normalize", "transform_matrix", "transform_points", "compose", "inverse",
    "Quadric", "image_symbols", "rr_quadric", "pr_quadric", "rp_quadric", "pp_quadric",
    "Leg", "RPR", "RRR", "PRR", "RRP", "RPP", "PRP", "PPR",
    "PlanarParallel", "AssemblyMode", "DKBatchResult", "CertifiedModes",
    "SingularitySurface", "PoseJacobians", "ConicSection", "singularity_surface", "singularity_surfaces",
    "jacobians", "mesh_surface", "mesh_implicit", "export_mesh",
    "ImagePath", "PathCheck", "check_path", "segments_free", "segment", "polyline", "polynomial_curve",
    "rational_curve", "pose_segment", "ModeChangePlan", "plan_mode_change", "joint_trajectory",
    "mode_count_map", "cusps", "cusp_loop", "cusp_edges", "linking_number", "backlash",
    "gruebler", "manipulator_mobility", "mechanism_mobility", "sweep", "fuzzy_minmax",
    "RealRootCertificate", "certify_real_roots", "certify_real_roots_batch",
    "ImageSpaceError", "InputError", "DegenerateDesignError", "EliminationError", "NearSingularWarning",
    "Tolerances", "TOLERANCES",
]
