"""The spatial side: screw theory (:mod:`~imagespace.spatial.screws`) and the spatial kinematic image
space: Study's map (:mod:`~imagespace.spatial.study`), constraint quadrics in ``P^7``
(:mod:`~imagespace.spatial.quadrics`), the Gough-Stewart platform
(:mod:`~imagespace.spatial.gough_stewart`) and the 3-RPS (:mod:`~imagespace.spatial.three_rps`),
their direct kinematics (:mod:`~imagespace.spatial.homotopy`, :mod:`~imagespace.spatial.certify`,
:mod:`~imagespace.spatial.fastcert`, :mod:`~imagespace.spatial.exact`) and singularities (:mod:`~imagespace.spatial.singularities`; the
meshes of :mod:`imagespace.spatial_surfaces`). Imports ``core`` only.
"""

import lazy_loader as _lazy

_ATTRIBUTES = {
    "study": ["study_symbols", "quaternion_multiply", "quaternion_conjugate", "quaternion_from_matrix",
              "matrix_from_quaternion", "study_point", "rotation_matrix", "translation",
              "transform_matrix", "transform_points", "study_condition", "normalize_study",
              "compose_study", "inverse_study", "planar_to_study", "study_to_planar"],
    "quadrics": ["study_quadric_matrix", "form_matrix", "quadric_value", "sphere_quadric_symbolic",
                 "sphere_quadric", "point_on_plane_quadric", "point_on_line_quadrics",
                 "landed_point_times_n"],
    "poses": ["pose_from_rotation", "pose_from_quaternion", "pose_from_rpy", "pose_from_matrix"],
    "gough_stewart": ["GoughStewart", "GOUGH_STEWART_BOUND", "PAIRED_BOUND"],
    "three_rps": ["ThreeRPS", "THREE_RPS_BOUND"],
    "platform": ["QuadricPlatform", "check_lengths"],
    "singularities": ["leg_line_forms", "jacobian_matrix", "jacobian_determinant", "aspect",
                      "constant_orientation_singularity", "ConstantOrientationSingularity"],
    "results": ["SpatialDKResult", "SpatialDKBatch"],
    "exact": ["exact_real_study_points", "ExactStudyResult"],
    "certify": ["krawczyk_certify", "KrawczykResult"],
    "fastcert": ["certify_endpoints", "FastCertificate"],
    "solver": ["QuadricFamily"],
    "homotopy": ["StartSystem", "solve_start_system", "track_parameters"],
}
__getattr__, __dir__, _ = _lazy.attach(__name__, submodules=["screws", "study", "poses", "quadrics", "gough_stewart", "results", "exact", "certify", "solver",
                                                                   "three_rps", "platform", "singularities",
                                                                   "homotopy", "fastcert"],
                                       submod_attrs=_ATTRIBUTES)
__all__ = sorted({n for names in _ATTRIBUTES.values() for n in names})
