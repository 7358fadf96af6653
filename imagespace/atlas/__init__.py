"""The atlas: certified regions of joint space by number of assembly modes, the singularity
surface and cusp curves in joint space, aspects and uniqueness domains, and whether a design is
cuspidal.

Imports ``core``, ``solve``, ``singular``, ``paths`` and ``design`` (the layer above them).
"""

from .cuspidal import CuspidalityResult, CuspWitness, default_joint_box, is_cuspidal, verify_cusp
from .curves import cusp_curves
from .domains import UniquenessDomains, plot_uniqueness_domains, uniqueness_domains, workspace_box
from .figures import (atlas_figure, atlas_sheets, atlas_traces, box_edges, cusp_polyline, plot_atlas,
                      plot_atlas_section, q_marker_text)
from .boxes import check_joint_box
from .jointspace import AtlasRegion, JointAtlas, joint_atlas

__all__ = ["AtlasRegion", "JointAtlas", "check_joint_box", "joint_atlas", "cusp_curves", "atlas_figure",
           "atlas_traces", "atlas_sheets", "cusp_polyline", "box_edges", "q_marker_text", "plot_atlas",
           "plot_atlas_section", "is_cuspidal", "verify_cusp",
           "default_joint_box", "CuspidalityResult", "CuspWitness", "UniquenessDomains", "uniqueness_domains",
           "plot_uniqueness_domains", "workspace_box"]
