"""imagespace: algebraic kinematics of planar parallel manipulators in the kinematic image space.

The public API; see README.md for the feature table and DESIGN.md for the conventions.
"""

from . import examples
from .constraints import Quadric, image_symbols, pp_quadric, pr_quadric, rp_quadric, rr_quadric
from .exceptions import (DegenerateDesignError, EliminationError, ImageSpaceError, InputError,
                         NearSingularWarning)
from .kinematic_map import compose, image_point, inverse, normalize, pose_of, transform_matrix, transform_points
from .legs import PPR, PRP, PRR, RPP, RPR, RRP, RRR, Leg
from .certify import RealRootCertificate, certify_real_roots, certify_real_roots_batch
from .manipulator import AssemblyMode, CertifiedModes, DKBatchResult, PlanarParallel
from .singularities import (ConicSection, PoseJacobians, SingularitySurface, jacobians,
                            singularity_surface, singularity_surfaces)
from .meshing import export_mesh, mesh_implicit, mesh_surface
from .paths import (ImagePath, PathCheck, check_path, polyline, polynomial_curve, pose_segment,
                    rational_curve, segment, segments_free)
from .modechange import ModeChangePlan, joint_trajectory, plan_mode_change
from .cusps import cusp_edges, cusp_loop, cusps, linking_number, mode_count_map
from .clearance import backlash
from .mobility import gruebler, manipulator_mobility, mechanism_mobility
from .design import fuzzy_minmax, sweep
from .tolerances import TOLERANCES, Tolerances

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
